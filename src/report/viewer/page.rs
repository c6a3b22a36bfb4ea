//! The viewer's HTML section: a select of the pairs, play/pause, amplitude
//! and view-angle sliders, one canvas for the test shape and one for its FE
//! partner, the still images (shown when printing), the data as one JSON
//! blob and the script (`viewer.js`). Numbers are written with a fixed
//! number of decimals: the same data give the same bytes.

use std::fmt::Write as _;

use super::{ViewerData, STILL_FILE};
use crate::report::charts::fmt_fixed;
use crate::report::html::esc;

/// The script: reads the JSON blob, draws and animates.
const SCRIPT: &str = include_str!("viewer.js");

/// Node coordinates are centred on the model's bounding box and divided by
/// its largest extent (written as `size_m`): (centre, size).
pub fn frame(xyz: &[[f64; 3]]) -> ([f64; 3], f64) {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in xyz {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    if xyz.is_empty() {
        return ([0.0; 3], 1.0);
    }
    let size = (0..3).map(|k| hi[k] - lo[k]).fold(0.0f64, f64::max);
    let centre = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    (centre, if size > 0.0 { size } else { 1.0 })
}

fn json_str(s: &str) -> String {
    let mut o = String::from("\"");
    for c in s.chars() {
        match c {
            '"' => o.push_str("\\\""),
            '\\' => o.push_str("\\\\"),
            // Never `</script>` inside the blob.
            '<' => o.push_str("\\u003c"),
            c if (c as u32) < 0x20 => {
                let _ = write!(o, "\\u{:04x}", c as u32);
            }
            c => o.push(c),
        }
    }
    o.push('"');
    o
}

fn num(v: f64, d: usize) -> String {
    if v.is_finite() {
        fmt_fixed(v, d)
    } else {
        "null".into()
    }
}

fn triples(v: &[[f64; 3]], d: usize) -> String {
    let items: Vec<String> = v
        .iter()
        .map(|p| format!("[{},{},{}]", num(p[0], d), num(p[1], d), num(p[2], d)))
        .collect();
    format!("[{}]", items.join(","))
}

/// The label of a pair in the select and the still images.
pub fn pair_label(v: &ViewerData, k: usize) -> String {
    let p = &v.pairs[k];
    format!(
        "test {} · {} Hz  ↔  FE {} · {} Hz  ·  MAC {}",
        p.test_mode,
        fmt_fixed(p.test_hz, 3),
        p.fe_mode,
        fmt_fixed(p.fe_hz, 3),
        fmt_fixed(p.mac, 3)
    )
}

/// The JSON blob: geometry (normalised), which translations were measured
/// and each pair's shapes (largest translation 1).
pub fn viewer_json(v: &ViewerData) -> String {
    let (centre, size) = frame(&v.xyz);
    let xyz: Vec<[f64; 3]> = v
        .xyz
        .iter()
        .map(|p| [0, 1, 2].map(|k| (p[k] - centre[k]) / size))
        .collect();
    let ids: Vec<String> = v.ids.iter().map(|i| i.to_string()).collect();
    let beams: Vec<String> = v
        .beams
        .iter()
        .map(|b| format!("[{},{}]", b[0], b[1]))
        .collect();
    let measured: Vec<String> = v
        .measured
        .iter()
        .map(|m| format!("[{},{},{}]", m[0] as u8, m[1] as u8, m[2] as u8))
        .collect();
    let mut s = format!(
        "{{\"test_kind\":{},\"fe_kind\":{},\"plane\":{},\"size_m\":{:.6e},\"ids\":[{}],\"xyz\":{},\"beams\":[{}],\"measured\":[{}],\"pairs\":[",
        json_str(&v.test_kind),
        json_str(&v.fe_kind),
        v.plane,
        size,
        ids.join(","),
        triples(&xyz, 5),
        beams.join(","),
        measured.join(",")
    );
    for (k, p) in v.pairs.iter().enumerate() {
        let _ = write!(
            s,
            "{}\n{{\"label\":{},\"test_mode\":{},\"fe_mode\":{},\"test_hz\":{},\"fe_hz\":{},\"mac\":{},\"test\":{},\"fe\":{}}}",
            if k == 0 { "" } else { "," },
            json_str(&pair_label(v, k)),
            p.test_mode,
            p.fe_mode,
            num(p.test_hz, 4),
            num(p.fe_hz, 4),
            num(p.mac, 4),
            triples(&p.test, 4),
            triples(&p.fe, 4)
        );
    }
    s.push_str("]}");
    s
}

/// The section (heading `id="shapes"`); `intro` is HTML saying where the
/// shapes come from, `still` the SVG of [`super::still_svg`] (shown when
/// the page is printed, in place of the canvases).
pub fn section(v: &ViewerData, intro: &str, still: &str) -> String {
    let mut s = String::from("<h2 id=\"shapes\">Mode shapes</h2>\n");
    let _ = writeln!(s, "<p>{intro}</p>");
    if v.pairs.is_empty() {
        s.push_str(
            "<p class=\"muted\">No test mode is paired with an FE mode: nothing to animate.</p>\n",
        );
        return s;
    }
    let _ = writeln!(
        s,
        "<p class=\"muted\">Left: the {} at the measured nodes (dots), moved by the directions measured there; the other nodes interpolated linearly along the beams, directions never measured at rest. Right: the {} at every node. Each shape scaled to the amplitude below; the test shape's sign is the one that agrees with its partner. Grey: the model at rest. Drag a picture to turn the view.</p>",
        esc(&v.test_kind),
        esc(&v.fe_kind)
    );
    s.push_str("<div id=\"frfup-viewer\" class=\"viewer\">\n<div class=\"viewer-live\">\n<p class=\"viewer-controls\">");
    s.push_str("<label class=\"pick\">pair <select data-v=\"pair\"></select></label> <button type=\"button\" data-v=\"play\">pause</button> ");
    s.push_str("<label>amplitude (% of size) <input type=\"range\" data-v=\"amp\" min=\"0\" max=\"30\" step=\"1\" value=\"10\"></label> ");
    let (az, el) = super::still::first_view(v.plane);
    let _ = write!(
        s,
        "<label>azimuth <input type=\"range\" data-v=\"az\" min=\"-180\" max=\"180\" step=\"1\" value=\"{az}\"></label> <label>elevation <input type=\"range\" data-v=\"el\" min=\"-90\" max=\"90\" step=\"1\" value=\"{el}\"></label></p>"
    );
    let _ = writeln!(
        s,
        "<div class=\"viewer-pair\"><figure><canvas data-v=\"test\" width=\"600\" height=\"420\"></canvas><figcaption data-v=\"test-caption\">{}</figcaption></figure><figure><canvas data-v=\"fe\" width=\"600\" height=\"420\"></canvas><figcaption data-v=\"fe-caption\">{}</figcaption></figure></div>\n</div>",
        esc(&v.test_kind),
        esc(&v.fe_kind)
    );
    let _ = writeln!(
        s,
        "<p class=\"muted\">Still images of every pair (undeformed and at the extreme of the swing): <a href=\"{STILL_FILE}\">{STILL_FILE}</a>.</p>"
    );
    let _ = writeln!(
        s,
        "<div class=\"viewer-still chart\">{}</div>",
        still.trim()
    );
    let _ = writeln!(
        s,
        "<script type=\"application/json\" id=\"frfup-viewer-data\">{}</script>\n<script>{}</script>\n</div>",
        viewer_json(v),
        SCRIPT.trim()
    );
    s
}

/// The section when there is nothing to draw, and why.
pub fn unavailable(why: &str) -> String {
    format!(
        "<h2 id=\"shapes\">Mode shapes</h2>\n<p class=\"muted\">No mode-shape viewer: {}.</p>\n",
        esc(why)
    )
}
