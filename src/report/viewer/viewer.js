// frfup's mode-shape viewer: reads the JSON blob #frfup-viewer-data and
// swings the chosen test mode (left) and its FE partner (right), in phase,
// on the model's wireframe. Orthographic view, z up: the azimuth turns the
// model about z, the elevation tilts it towards the viewer.
(function () {
  'use strict';
  var root = document.getElementById('frfup-viewer');
  var blob = document.getElementById('frfup-viewer-data');
  if (!root || !blob) {
    return;
  }
  var data = JSON.parse(blob.textContent);
  function part(name) {
    return root.querySelector('[data-v="' + name + '"]');
  }
  var pick = part('pair'), play = part('play'), amp = part('amp');
  var az = part('az'), el = part('el');
  var views = [
    {canvas: part('test'), caption: part('test-caption'), key: 'test', colour: '#d55e00', dots: true},
    {canvas: part('fe'), caption: part('fe-caption'), key: 'fe', colour: '#0072b2', dots: false}
  ];
  var PERIOD_S = 1.6;
  // The phase is the clock's: phase at `since`, plus the time played since.
  var state = {pair: 0, playing: true, phase: Math.PI / 2, since: performance.now()};
  function phase() {
    var played = state.playing ? (performance.now() - state.since) / 1000 : 0;
    return state.phase + 2 * Math.PI * played / PERIOD_S;
  }

  data.pairs.forEach(function (p, i) {
    var o = document.createElement('option');
    o.value = String(i);
    o.textContent = p.label;
    pick.appendChild(o);
  });

  function project(p, a, e) {
    var ca = Math.cos(a), sa = Math.sin(a), ce = Math.cos(e), se = Math.sin(e);
    return [ca * p[0] + sa * p[1], -se * sa * p[0] + se * ca * p[1] + ce * p[2]];
  }

  function captions() {
    var p = data.pairs[state.pair];
    views[0].caption.textContent = data.test_kind + ' ' + p.test_mode + ' · ' + p.test_hz.toFixed(3) + ' Hz';
    views[1].caption.textContent = data.fe_kind + ' ' + p.fe_mode + ' · ' + p.fe_hz.toFixed(3) + ' Hz · MAC ' + p.mac.toFixed(3);
  }

  // Canvas size follows its box (aspect 10:7), in device pixels.
  function fit(c) {
    var ratio = window.devicePixelRatio || 1;
    var w = c.clientWidth || 600, h = Math.round(w * 0.7);
    if (c.width !== Math.round(w * ratio)) {
      c.width = Math.round(w * ratio);
      c.height = Math.round(h * ratio);
    }
    var ctx = c.getContext('2d');
    ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
    return {ctx: ctx, w: w, h: h};
  }

  function draw(view) {
    var box = fit(view.canvas), ctx = box.ctx;
    var a = Number(az.value) * Math.PI / 180, e = Number(el.value) * Math.PI / 180;
    var size = Number(amp.value) / 100, s = size * Math.sin(phase());
    var shape = data.pairs[state.pair][view.key];
    var rest = data.xyz.map(function (p) { return project(p, a, e); });
    var moved = data.xyz.map(function (p, i) {
      var u = shape[i];
      return project([p[0] + s * u[0], p[1] + s * u[1], p[2] + s * u[2]], a, e);
    });
    var lo = [Infinity, Infinity], hi = [-Infinity, -Infinity];
    rest.forEach(function (q) {
      for (var k = 0; k < 2; k++) {
        lo[k] = Math.min(lo[k], q[k]);
        hi[k] = Math.max(hi[k], q[k]);
      }
    });
    var pad = 12, m = size + 0.02;
    var scale = Math.min((box.w - 2 * pad) / (hi[0] - lo[0] + 2 * m), (box.h - 2 * pad) / (hi[1] - lo[1] + 2 * m));
    var cx = (lo[0] + hi[0]) / 2, cy = (lo[1] + hi[1]) / 2;
    function x(q) { return box.w / 2 + (q[0] - cx) * scale; }
    function y(q) { return box.h / 2 - (q[1] - cy) * scale; }
    function wire(pts, colour, width) {
      ctx.strokeStyle = colour;
      ctx.lineWidth = width;
      ctx.beginPath();
      data.beams.forEach(function (b) {
        ctx.moveTo(x(pts[b[0]]), y(pts[b[0]]));
        ctx.lineTo(x(pts[b[1]]), y(pts[b[1]]));
      });
      ctx.stroke();
    }
    ctx.clearRect(0, 0, box.w, box.h);
    wire(rest, '#c8c8c8', 1);
    wire(moved, view.colour, 2);
    if (view.dots) {
      ctx.fillStyle = view.colour;
      data.measured.forEach(function (mk, i) {
        if (mk[0] || mk[1] || mk[2]) {
          ctx.beginPath();
          ctx.arc(x(moved[i]), y(moved[i]), 3, 0, 2 * Math.PI);
          ctx.fill();
        }
      });
    }
  }

  function frame() {
    redraw();
    window.requestAnimationFrame(frame);
  }

  function redraw() {
    views.forEach(draw);
  }
  pick.addEventListener('change', function () {
    state.pair = Number(pick.value);
    captions();
    redraw();
  });
  [amp, az, el].forEach(function (input) {
    input.addEventListener('input', redraw);
  });
  play.addEventListener('click', function () {
    state.phase = phase();
    state.since = performance.now();
    state.playing = !state.playing;
    play.textContent = state.playing ? 'pause' : 'play';
    redraw();
  });
  // Dragging a picture turns the view (0.5° per pixel).
  views.forEach(function (view) {
    var from = null;
    view.canvas.addEventListener('pointerdown', function (ev) {
      from = {x: ev.clientX, y: ev.clientY, az: Number(az.value), el: Number(el.value)};
      view.canvas.setPointerCapture(ev.pointerId);
    });
    view.canvas.addEventListener('pointermove', function (ev) {
      if (from) {
        var turned = from.az - 0.5 * (ev.clientX - from.x);
        az.value = String(((turned + 180) % 360 + 360) % 360 - 180);
        el.value = String(Math.max(-90, Math.min(90, from.el + 0.5 * (ev.clientY - from.y))));
      }
    });
    view.canvas.addEventListener('pointerup', function () { from = null; });
  });
  captions();
  redraw();
  window.requestAnimationFrame(frame);
})();
