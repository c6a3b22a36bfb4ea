//! `mode-shapes.svg`: every pair as two small pictures (test shape, FE
//! partner), two pairs to a row, in the viewer's first view: the model at
//! rest in grey, the shape at the extreme of its swing (largest translation
//! [`AMPLITUDE`] of the model's size) in colour, measured nodes dotted.

use std::fmt::Write as _;

use super::page::{frame, pair_label};
use super::ViewerData;
use crate::report::charts::FONT;
use crate::report::html::esc;

/// Largest translation drawn, as a fraction of the model's size (the
/// viewer's default amplitude).
pub const AMPLITUDE: f64 = 0.1;

const WIDTH: f64 = 960.0;
const PANEL_W: f64 = 240.0;
const PANEL_H: f64 = 170.0;
const ROW_H: f64 = PANEL_H + 44.0;
const TOP: f64 = 58.0;
const TEST_COLOUR: &str = "#d55e00";
const FE_COLOUR: &str = "#0072b2";

/// Orthographic projection, z up (as `viewer.js`).
fn project(p: [f64; 3], az: f64, el: f64) -> [f64; 2] {
    let (sa, ca) = az.to_radians().sin_cos();
    let (se, ce) = el.to_radians().sin_cos();
    [
        ca * p[0] + sa * p[1],
        -se * sa * p[0] + se * ca * p[1] + ce * p[2],
    ]
}

/// The first view: face-on for a plane deck, else from the front left, above.
pub fn first_view(plane: bool) -> (f64, f64) {
    if plane {
        (0.0, 0.0)
    } else {
        (-35.0, 25.0)
    }
}

/// A wireframe as one path, in panel pixels.
fn wire(s: &mut String, pts: &[[f64; 2]], beams: &[[usize; 2]], stroke: &str, width: f64) {
    let mut d = String::new();
    for b in beams {
        let (p, q) = (pts[b[0]], pts[b[1]]);
        let _ = write!(d, "M{:.1} {:.1}L{:.1} {:.1}", p[0], p[1], q[0], q[1]);
    }
    let _ = writeln!(
        s,
        "<path d=\"{d}\" fill=\"none\" stroke=\"{stroke}\" stroke-width=\"{width}\"/>"
    );
}

/// One picture at (x0, y0): `shape` of the normalised geometry `xyz`.
fn panel(
    s: &mut String,
    v: &ViewerData,
    xyz: &[[f64; 3]],
    shape: &[[f64; 3]],
    at: (f64, f64),
    test: bool,
) {
    let (az, el) = first_view(v.plane);
    let rest: Vec<[f64; 2]> = xyz.iter().map(|&p| project(p, az, el)).collect();
    let moved: Vec<[f64; 2]> = xyz
        .iter()
        .zip(shape)
        .map(|(p, u)| project([0, 1, 2].map(|k| p[k] + AMPLITUDE * u[k]), az, el))
        .collect();
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for q in &rest {
        for k in 0..2 {
            lo[k] = lo[k].min(q[k]);
            hi[k] = hi[k].max(q[k]);
        }
    }
    let m = AMPLITUDE + 0.02;
    let scale = ((PANEL_W - 16.0) / (hi[0] - lo[0] + 2.0 * m))
        .min((PANEL_H - 16.0) / (hi[1] - lo[1] + 2.0 * m));
    let (cx, cy) = (0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]));
    let px = |q: &[f64; 2]| {
        [
            at.0 + PANEL_W / 2.0 + (q[0] - cx) * scale,
            at.1 + PANEL_H / 2.0 - (q[1] - cy) * scale,
        ]
    };
    let rest: Vec<[f64; 2]> = rest.iter().map(px).collect();
    let moved: Vec<[f64; 2]> = moved.iter().map(px).collect();
    let _ = writeln!(
        s,
        "<rect x=\"{:.1}\" y=\"{:.1}\" width=\"{PANEL_W}\" height=\"{PANEL_H}\" fill=\"none\" stroke=\"#eeeeee\"/>",
        at.0, at.1
    );
    wire(s, &rest, &v.beams, "#c8c8c8", 1.0);
    let colour = if test { TEST_COLOUR } else { FE_COLOUR };
    wire(s, &moved, &v.beams, colour, 1.5);
    if test {
        for (q, m) in moved.iter().zip(&v.measured) {
            if m.iter().any(|&b| b) {
                let _ = writeln!(
                    s,
                    "<circle cx=\"{:.1}\" cy=\"{:.1}\" r=\"2.5\" fill=\"{colour}\"/>",
                    q[0], q[1]
                );
            }
        }
    }
}

fn text(s: &mut String, x: f64, y: f64, size: u32, anchor: &str, body: &str) {
    let _ = writeln!(
        s,
        "<text x=\"{x:.1}\" y=\"{y:.1}\" font-family=\"{FONT}\" font-size=\"{size}\" text-anchor=\"{anchor}\" fill=\"#222222\">{}</text>",
        esc(body)
    );
}

/// The SVG text.
pub fn render(v: &ViewerData) -> String {
    let (centre, size) = frame(&v.xyz);
    let xyz: Vec<[f64; 3]> = v
        .xyz
        .iter()
        .map(|p| [0, 1, 2].map(|k| (p[k] - centre[k]) / size))
        .collect();
    let rows = v.pairs.len().div_ceil(2).max(1);
    let height = TOP + rows as f64 * ROW_H + 8.0;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{WIDTH}\" height=\"{height}\" viewBox=\"0 0 {WIDTH} {height}\">\n<rect width=\"100%\" height=\"100%\" fill=\"#ffffff\"/>\n"
    );
    text(
        &mut s,
        WIDTH / 2.0,
        24.0,
        18,
        "middle",
        "Mode shapes: test (left) and FE partner (right)",
    );
    let sub = format!(
        "{} / {}; grey: at rest; colour: at the extreme (largest translation {} % of the model's size); dots: measured nodes",
        v.test_kind,
        v.fe_kind,
        (AMPLITUDE * 100.0).round()
    );
    text(&mut s, WIDTH / 2.0, 44.0, 12, "middle", &sub);
    if v.pairs.is_empty() {
        text(
            &mut s,
            WIDTH / 2.0,
            TOP + 40.0,
            14,
            "middle",
            "no pair to draw",
        );
    }
    for (k, p) in v.pairs.iter().enumerate() {
        let x0 = (k % 2) as f64 * 2.0 * PANEL_W;
        let y0 = TOP + (k / 2) as f64 * ROW_H;
        text(
            &mut s,
            x0 + PANEL_W,
            y0 + 14.0,
            12,
            "middle",
            &pair_label(v, k),
        );
        panel(&mut s, v, &xyz, &p.test, (x0, y0 + 22.0), true);
        panel(&mut s, v, &xyz, &p.fe, (x0 + PANEL_W, y0 + 22.0), false);
    }
    s.push_str("</svg>\n");
    s
}
