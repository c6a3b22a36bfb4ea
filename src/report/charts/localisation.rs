//! The localisation map of a diagnosis (`localisation.svg`): the model's
//! geometry (beams as lines between nodes, already projected on a plane) with
//! the scored nodes drawn as discs whose colour and size give their score,
//! the best nodes labelled, a colour scale, the measured nodes and the fixed
//! supports. Equal scales on both axes, so the structure keeps its shape.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{
    draw_legend, draw_mesh, draw_no_data, draw_title, finite_range, fmt_fixed, font, legend_height,
    nice_step, text_width, tick_label, title_height, Axes, ChartError, LegendEntry, Marker, Swatch,
    DARK, GREY,
};

/// One node of the map (projected coordinates, m).
#[derive(Clone, Debug, PartialEq)]
pub struct MapNode {
    pub id: u32,
    pub x: f64,
    pub y: f64,
    /// Localisation score (share of the remaining error, 0–1), if scored.
    pub score: Option<f64>,
    /// Label of the best candidate at this node (shown for the top nodes).
    pub candidate: Option<String>,
    /// A measured channel sits on this node.
    pub measured: bool,
    /// The node has fixed DOFs.
    pub fixed: bool,
}

/// The data of the map.
#[derive(Clone, Debug, PartialEq)]
pub struct LocalisationMap {
    pub title: String,
    pub subtitle: Option<String>,
    /// Axis descriptions, e.g. "x (m)" and "z (m)".
    pub x_desc: String,
    pub y_desc: String,
    pub nodes: Vec<MapNode>,
    /// Lines between nodes (indices into `nodes`): the beams.
    pub lines: Vec<(usize, usize)>,
    /// How many of the best-scored nodes get a text label.
    pub labelled: usize,
    /// The accepted findings, each ringed in its own colour at its nodes.
    pub findings: Vec<MapFinding>,
}

/// An accepted finding of the diagnosis on the map.
#[derive(Clone, Debug, PartialEq)]
pub struct MapFinding {
    /// e.g. "support-flexibility at node 1 (ry)".
    pub label: String,
    /// Indices into [`LocalisationMap::nodes`].
    pub nodes: Vec<usize>,
}

/// Ring colours of the findings (blue, green, purple, teal): none on the
/// yellow–red score scale.
const FINDING_COLORS: [RGBColor; 4] = [
    RGBColor(0, 90, 200),
    RGBColor(0, 140, 70),
    RGBColor(120, 60, 170),
    RGBColor(0, 130, 140),
];

fn finding_color(i: usize) -> RGBColor {
    FINDING_COLORS[i % FINDING_COLORS.len()]
}

const WIDTH: u32 = 960;
const BAR_W: i32 = 150;
const LABEL_PX: f64 = 12.0;

/// Sequential colour of `t` in [0, 1]: pale yellow → orange → red → dark red.
pub fn score_color(t: f64) -> RGBColor {
    const STOPS: [(f64, (f64, f64, f64)); 4] = [
        (0.0, (255.0, 237.0, 160.0)),
        (0.35, (253.0, 141.0, 60.0)),
        (0.7, (227.0, 26.0, 28.0)),
        (1.0, (128.0, 0.0, 38.0)),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    for w in STOPS.windows(2) {
        let ((t0, a), (t1, b)) = (w[0], w[1]);
        if t <= t1 {
            let u = (t - t0) / (t1 - t0);
            let mix = |p: f64, q: f64| (p + u * (q - p)).round() as u8;
            return RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2));
        }
    }
    RGBColor(128, 0, 38)
}

/// Top of the colour scale: the best score rounded up to a nice share.
fn scale_top(m: &LocalisationMap) -> f64 {
    let best = m
        .nodes
        .iter()
        .filter_map(|n| n.score)
        .filter(|s| s.is_finite())
        .fold(0.0f64, f64::max);
    if best <= 0.0 {
        return 1.0;
    }
    let step = nice_step(best / 4.0);
    ((best / step).ceil() * step).min(1.0).max(best)
}

fn radius(score: f64, top: f64) -> i32 {
    (4.0 + 9.0 * (score / top).clamp(0.0, 1.0).sqrt()).round() as i32
}

fn legend_entries(m: &LocalisationMap) -> Vec<LegendEntry> {
    let mut e = vec![
        LegendEntry::new("beam", GREY, Swatch::Line { width: 3 }),
        LegendEntry::new("node", RGBColor(90, 90, 90), Swatch::Marker(Marker::Circle)),
        LegendEntry::new(
            "measured node (sensor)",
            DARK,
            Swatch::Marker(Marker::Triangle),
        ),
        LegendEntry::new("fixed support", DARK, Swatch::Bar),
        LegendEntry::new(
            "localisation score of a node (colour and size)",
            score_color(0.75),
            Swatch::Marker(Marker::Circle),
        ),
    ];
    for (i, f) in m.findings.iter().enumerate() {
        e.push(LegendEntry::new(
            format!("accepted: {}", f.label),
            finding_color(i),
            Swatch::Line { width: 4 },
        ));
    }
    e
}

/// Data ranges with equal scales for a plot of `pw` px wide; returns the
/// ranges and the plot height (px).
fn ranges(m: &LocalisationMap, pw: f64) -> ((f64, f64), (f64, f64), f64) {
    let (x0, x1) = finite_range(m.nodes.iter().map(|n| &n.x)).unwrap_or((0.0, 1.0));
    let (y0, y1) = finite_range(m.nodes.iter().map(|n| &n.y)).unwrap_or((0.0, 1.0));
    let span = (x1 - x0).max(y1 - y0).max(1e-9);
    // Room around the structure for the discs and labels.
    let pad = 0.08 * span;
    let (mut xa, mut xb) = (x0 - pad, x1 + pad);
    let (mut ya, mut yb) = (y0 - pad, y1 + pad);
    // Plot height from the aspect ratio, within bounds; then widen the
    // narrower range so that a metre is as long on both axes.
    let aspect = (yb - ya) / (xb - xa);
    let ph = (pw * aspect).clamp(260.0, 560.0);
    let per_px = ((xb - xa) / pw).max((yb - ya) / ph);
    let (cx, cy) = ((xa + xb) / 2.0, (ya + yb) / 2.0);
    xa = cx - per_px * pw / 2.0;
    xb = cx + per_px * pw / 2.0;
    ya = cy - per_px * ph / 2.0;
    yb = cy + per_px * ph / 2.0;
    ((xa, xb), (ya, yb), ph)
}

type Rect = (f64, f64, f64, f64);

fn overlaps(a: Rect, b: Rect) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// Render the map as SVG text.
pub fn render(m: &LocalisationMap) -> Result<String, ChartError> {
    if m.nodes.is_empty() {
        return super::svg((WIDTH, 400), |root| {
            draw_no_data(root, &m.title, "the deck has no nodes")
        });
    }
    let entries = legend_entries(m);
    let lh = legend_height(&entries, WIDTH as i32 - 40);
    let th = title_height(m.subtitle.is_some());
    let (left, right, top_m, bottom) = (72, BAR_W + 20, 10, 46);
    let pw = (WIDTH as i32 - left - right - 10) as f64;
    let (xr, yr, ph) = ranges(m, pw);
    let height = (th + lh + top_m + ph.round() as i32 + bottom + 12) as u32;
    let top = scale_top(m);
    super::svg((WIDTH, height), |root| {
        draw_title(root, &m.title, m.subtitle.as_deref())?;
        let (_, rest) = root.split_vertically(th);
        let (legend_a, rest) = rest.split_vertically(lh);
        draw_legend(&legend_a.margin(0, 0, 20, 20), &entries)?;
        let (plot_a, bar_a) = rest.split_horizontally(WIDTH as i32 - right);
        let mut chart = ChartBuilder::on(&plot_a)
            .margin_left(10)
            .margin_right(0)
            .margin_top(top_m)
            .x_label_area_size(bottom)
            .y_label_area_size(left - 10)
            .build_cartesian_2d(xr.0..xr.1, yr.0..yr.1)?;
        let xfmt = tick_label(xr, 8);
        let yfmt = tick_label(yr, 6);
        draw_mesh(
            &mut chart,
            &Axes {
                x_desc: &m.x_desc,
                y_desc: &m.y_desc,
                x_fmt: &xfmt,
                y_fmt: &yfmt,
                x_labels: 10,
                y_labels: 7,
            },
        )?;
        for &(a, b) in &m.lines {
            if let (Some(p), Some(q)) = (m.nodes.get(a), m.nodes.get(b)) {
                chart.draw_series(std::iter::once(PathElement::new(
                    vec![(p.x, p.y), (q.x, q.y)],
                    GREY.stroke_width(3),
                )))?;
            }
        }
        let scored = draw_nodes(root, &chart, m, top)?;
        draw_findings(root, &chart, m, top)?;
        draw_labels(root, &chart, m, top, &scored)?;
        let (_, pyr) = chart.plotting_area().get_pixel_range();
        draw_colour_bar(&bar_a, top, (pyr.start, pyr.end), th + lh)?;
        Ok(())
    })
}

/// Radius (px) a node takes on the map: its disc, or the plain dot.
fn node_radius(n: &MapNode, top: f64) -> i32 {
    n.score
        .filter(|s| s.is_finite() && *s > 0.0)
        .map_or(3, |s| radius(s, top))
}

/// Plain nodes, scored discs (best on top), sensors and supports; returns
/// the scored nodes, best last.
fn draw_nodes<'m>(
    root: &super::Area,
    chart: &super::Chart2d,
    m: &'m LocalisationMap,
    top: f64,
) -> Result<Vec<&'m MapNode>, ChartError> {
    let px = |n: &MapNode| chart.backend_coord(&(n.x, n.y));
    for n in &m.nodes {
        root.draw(&Circle::new(px(n), 3, RGBColor(90, 90, 90).filled()))?;
    }
    let mut scored: Vec<&MapNode> = m
        .nodes
        .iter()
        .filter(|n| n.score.is_some_and(|s| s.is_finite() && s > 0.0))
        .collect();
    scored.sort_by(|a, b| {
        a.score
            .unwrap_or(0.0)
            .total_cmp(&b.score.unwrap_or(0.0))
            .then(b.id.cmp(&a.id))
    });
    for n in &scored {
        let s = n.score.unwrap_or(0.0);
        let r = radius(s, top);
        root.draw(&Circle::new(px(n), r, score_color(s / top).filled()))?;
        root.draw(&Circle::new(px(n), r, DARK.stroke_width(1)))?;
    }
    // Sensors: a small triangle above the node; supports: a ground bar
    // below it (both outside the disc, so neither hides the other).
    for n in &m.nodes {
        let (x, y) = px(n);
        let r = node_radius(n, top);
        if n.measured {
            let base = y - r - 2;
            root.draw(&Polygon::new(
                vec![(x - 5, base), (x + 5, base), (x, base - 8)],
                DARK.filled(),
            ))?;
        }
        if n.fixed {
            root.draw(&Rectangle::new(
                [(x - 10, y + r + 2), (x + 10, y + r + 7)],
                DARK.filled(),
            ))?;
        }
    }
    Ok(scored)
}

/// A thick ring around each node of each accepted finding, outside the
/// score disc (a second finding at the same node gets a wider ring).
fn draw_findings(
    root: &super::Area,
    chart: &super::Chart2d,
    m: &LocalisationMap,
    top: f64,
) -> Result<(), ChartError> {
    let mut rings: Vec<(usize, i32)> = Vec::new();
    for (i, f) in m.findings.iter().enumerate() {
        for &k in &f.nodes {
            let Some(n) = m.nodes.get(k) else { continue };
            let before = rings.iter().filter(|r| r.0 == k).count() as i32;
            let r = node_radius(n, top) + 6 + 6 * before;
            rings.push((k, r));
            let c = chart.backend_coord(&(n.x, n.y));
            root.draw(&Circle::new(c, r, finding_color(i).stroke_width(3)))?;
        }
    }
    Ok(())
}

/// Labels of the best nodes, placed where they overlap nothing.
fn draw_labels(
    root: &super::Area,
    chart: &super::Chart2d,
    m: &LocalisationMap,
    top: f64,
    scored: &[&MapNode],
) -> Result<(), ChartError> {
    let px = |n: &MapNode| chart.backend_coord(&(n.x, n.y));
    let (pxr, pyr) = chart.plotting_area().get_pixel_range();
    let bounds = (
        pxr.start as f64,
        pyr.start as f64,
        pxr.end as f64,
        pyr.end as f64,
    );
    let mut taken: Vec<Rect> = Vec::new();
    for n in &m.nodes {
        let (x, y) = px(n);
        let (x, y) = (x as f64, y as f64);
        let r = node_radius(n, top).max(4) as f64;
        taken.push((x - r, y - r, x + r, y + r));
        if n.measured {
            taken.push((x - 6.0, y - r - 11.0, x + 6.0, y - r));
        }
        if n.fixed {
            taken.push((x - 11.0, y + r, x + 11.0, y + r + 8.0));
        }
    }
    for n in scored.iter().rev().take(m.labelled) {
        let s = n.score.unwrap_or(0.0);
        let text = format!("node {}: {} %", n.id, fmt_fixed(100.0 * s, 0));
        let w = text_width(&text, LABEL_PX) + 4.0;
        let h = LABEL_PX + 4.0;
        let (x, y) = px(n);
        let r = radius(s, top) as f64 + 4.0;
        let cands = label_candidates((x as f64, y as f64), r, (w, h));
        let inside =
            |b: Rect| b.0 >= bounds.0 && b.1 >= bounds.1 && b.2 <= bounds.2 && b.3 <= bounds.3;
        let pick = cands
            .iter()
            .copied()
            .find(|&b| inside(b) && !taken.iter().any(|&o| overlaps(b, o)))
            .or_else(|| cands.iter().copied().find(|&b| inside(b)));
        let Some(b) = pick else { continue };
        taken.push(b);
        root.draw(&Rectangle::new(
            [
                (b.0.round() as i32, b.1.round() as i32),
                (b.2.round() as i32, b.3.round() as i32),
            ],
            WHITE.mix(0.85).filled(),
        ))?;
        root.draw_text(
            &text,
            &font(LABEL_PX).pos(Pos::new(HPos::Left, VPos::Center)),
            (
                (b.0 + 2.0).round() as i32,
                ((b.1 + b.3) / 2.0).round() as i32,
            ),
        )?;
    }
    Ok(())
}

/// Candidate label boxes around a disc at (x, y) of radius r: above, below,
/// right, left, diagonals, then further away.
fn label_candidates((x, y): (f64, f64), r: f64, (w, h): (f64, f64)) -> Vec<Rect> {
    let mut cands: Vec<(f64, f64)> = Vec::new();
    for k in [1.0, 2.2, 3.4] {
        let d = r * k;
        cands.extend([
            (x - w / 2.0, y - d - h - 10.0),
            (x - w / 2.0, y + d),
            (x + d, y - h / 2.0),
            (x - d - w, y - h / 2.0),
            (x + d * 0.7, y - d * 0.7 - h),
            (x - d * 0.7 - w, y - d * 0.7 - h),
            (x + d * 0.7, y + d * 0.7),
            (x - d * 0.7 - w, y + d * 0.7),
        ]);
    }
    cands
        .into_iter()
        .map(|(l, t)| (l, t, l + w, t + h))
        .collect()
}

/// The colour scale: a vertical bar with ticks in %, its description beside.
fn draw_colour_bar(
    area: &super::Area,
    top: f64,
    (py0, py1): (i32, i32),
    offset: i32,
) -> Result<(), ChartError> {
    // `area` starts `offset` px below the root's top: convert.
    let (y0, y1) = (py0 - offset, py1 - offset);
    let h = (y1 - y0).clamp(120, 320);
    let yc = (y0 + y1) / 2;
    let (bt, bb) = (yc - h / 2, yc + h / 2);
    let (bx0, bx1) = (24, 42);
    let steps = 64;
    for i in 0..steps {
        let t0 = i as f64 / steps as f64;
        let a = bb - ((h as f64) * t0).round() as i32;
        let b = bb - ((h as f64) * (t0 + 1.0 / steps as f64)).round() as i32;
        area.draw(&Rectangle::new(
            [(bx0, b), (bx1, a)],
            score_color(t0 + 0.5 / steps as f64).filled(),
        ))?;
    }
    area.draw(&Rectangle::new(
        [(bx0, bt), (bx1, bb)],
        GREY.stroke_width(1),
    ))?;
    let step = nice_step(top / 4.0);
    let d = super::decimals_for(100.0 * step);
    let mut v = 0.0;
    while v <= top * (1.0 + 1e-9) {
        let y = bb - ((h as f64) * v / top).round() as i32;
        area.draw(&PathElement::new(
            vec![(bx1, y), (bx1 + 5, y)],
            GREY.stroke_width(1),
        ))?;
        area.draw_text(
            &fmt_fixed(100.0 * v, d),
            &font(12.0).pos(Pos::new(HPos::Left, VPos::Center)),
            (bx1 + 8, y),
        )?;
        v += step;
    }
    // Description, read upwards, right of the tick labels.
    let style = font(13.0)
        .transform(FontTransform::Rotate270)
        .pos(Pos::new(HPos::Center, VPos::Top));
    area.draw_text("share of FRF error removed (%)", &style, (bx1 + 48, yc))?;
    Ok(())
}
