//! `convergence.svg`: each parameter p̄_j against iteration, and the SFDAC on
//! a second panel (the paper's Figs. 3, 5, 7, 11).
//!
//! Up to [`SINGLE_PANEL_MAX`] parameters share one panel, each line named at
//! its end; more get one small panel each (small multiples, each on its own
//! scale, the returned value in its title), so that no two parameters are
//! told apart by colour alone. The SFDAC panel plots −log₁₀(1 − SFDAC),
//! labelled in SFDAC: 0.9, 0.99, 0.999 are equally spaced, so the approach to
//! 1 stays visible after the first iterations. Stage changes (e.g. the
//! full-band estimate after the paper's iteration) are marked on both panels.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{
    bold, draw_legend, draw_markers, draw_mesh, draw_no_data, draw_title, finite_range,
    finite_runs, font, hline, integer_label, legend_height, padded_range, series_color,
    series_marker, svg, text_width, tick_label, title_height, vline, Area, Axes, Chart2d,
    ChartError, LegendEntry, Marker, Swatch, GREY,
};

/// A change of stage before iteration `at` (drawn between `at − 1` and `at`).
#[derive(Clone, Debug, PartialEq)]
pub struct StageMark {
    pub at: usize,
    /// e.g. "full-band estimate".
    pub label: String,
}

/// The history of an iteration.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvergenceChart {
    pub title: String,
    pub subtitle: Option<String>,
    pub parameter_names: Vec<String>,
    /// Iteration numbers n (x axis), 0 = initial model.
    pub iterations: Vec<usize>,
    /// p̄^n per iteration, aligned with `parameter_names`.
    pub parameters: Vec<Vec<f64>>,
    /// Mean SFDAC (Eq. 46) per iteration.
    pub sfdac_mean: Vec<f64>,
    /// Minimum SFDAC_i per iteration.
    pub sfdac_min: Vec<f64>,
    /// The iteration returned as the updated model, if any.
    pub selected: Option<usize>,
    /// Where the method changes stage.
    pub stages: Vec<StageMark>,
    /// Per parameter: the data did not identify it (its returned value is
    /// the deck's, titled "not identified" instead of a number).
    pub not_identified: Vec<bool>,
}

const WIDTH: u32 = 960;
/// Most parameters drawn on one shared panel.
pub const SINGLE_PANEL_MAX: usize = 8;
/// Columns of the small multiples.
const COLUMNS: usize = 4;
const CELL_H: i32 = 160;
const MEAN_COLOR: RGBColor = RGBColor(0, 100, 200);
const MIN_COLOR: RGBColor = RGBColor(213, 94, 0);
const STAGE_COLOR: RGBColor = RGBColor(120, 60, 160);
/// 1 − SFDAC below this is drawn at it (SFDAC 0.999999).
const FLOOR: f64 = 1e-6;

/// The x axis: iterations, padded.
struct XAxis {
    xs: Vec<f64>,
    range: (f64, f64),
    labels: usize,
}

fn x_axis(c: &ConvergenceChart) -> XAxis {
    let xs: Vec<f64> = c.iterations.iter().map(|&i| i as f64).collect();
    let (x0, x1) = finite_range(&xs).unwrap_or((0.0, 1.0));
    XAxis {
        range: (x0 - 0.3, x1.max(x0 + 1.0) + 0.3),
        labels: ((x1 - x0) as usize + 2).min(14),
        xs,
    }
}

fn sfdac_entries(c: &ConvergenceChart) -> Vec<LegendEntry> {
    let mut e = vec![
        LegendEntry::new("mean SFDAC", MEAN_COLOR, Swatch::LineMarker(Marker::Circle)),
        LegendEntry::new(
            "minimum SFDAC",
            MIN_COLOR,
            Swatch::LineMarker(Marker::Triangle),
        ),
    ];
    if let Some(s) = c.selected {
        e.push(LegendEntry::new(
            format!("returned model (iteration {s})"),
            GREY,
            Swatch::VMark { dashed: true },
        ));
    }
    for s in &c.stages {
        e.push(LegendEntry::new(
            format!("{} from iteration {}", s.label, s.at),
            STAGE_COLOR,
            Swatch::VMark { dashed: false },
        ));
    }
    e
}

/// Height of the parameter panel(s).
fn parameters_height(c: &ConvergenceChart) -> i32 {
    let n = c.parameter_names.len();
    if n <= SINGLE_PANEL_MAX {
        400
    } else {
        n.div_ceil(COLUMNS) as i32 * CELL_H + 40
    }
}

/// Render the chart as SVG text.
pub fn render(c: &ConvergenceChart) -> Result<String, ChartError> {
    if c.iterations.is_empty() {
        return svg((WIDTH, 400), |root| {
            draw_no_data(root, &c.title, "no iterations")
        });
    }
    let x = x_axis(c);
    let entries = sfdac_entries(c);
    let legend_h = legend_height(&entries, WIDTH as i32 - 40);
    let th = title_height(c.subtitle.is_some());
    let top_h = parameters_height(c);
    let bottom_h = 300;
    let height = (th + legend_h + top_h + bottom_h + 10) as u32;

    svg((WIDTH, height), |root| {
        draw_title(root, &c.title, c.subtitle.as_deref())?;
        let (_, rest) = root.split_vertically(th);
        let (top, rest) = rest.split_vertically(top_h);
        let right = if c.parameter_names.len() <= SINGLE_PANEL_MAX {
            let right = end_label_width(c);
            shared_panel(root, &top, c, &x, right)?;
            right
        } else {
            small_multiples(root, &top, c, &x)?;
            25
        };
        let (legend_b, bottom) = rest.split_vertically(legend_h);
        draw_legend(&legend_b.margin(0, 0, 20, 20), &entries)?;
        sfdac_panel(root, &bottom, c, &x, right)
    })
}

/// The iteration's marks: returned model (dashed grey), stage changes (purple).
fn marks(
    root: &Area,
    chart: &mut Chart2d,
    c: &ConvergenceChart,
    y_range: (f64, f64),
    label_stages: bool,
) -> Result<(), ChartError> {
    if let Some(s) = c.selected {
        vline(chart, s as f64, y_range, GREY)?;
    }
    for s in &c.stages {
        let xm = s.at as f64 - 0.5;
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(xm, y_range.0), (xm, y_range.1)],
            STAGE_COLOR.stroke_width(2),
        )))?;
        if label_stages {
            let (px, py) = chart.backend_coord(&(xm, y_range.1));
            root.draw_text(
                &s.label,
                &font(11.0)
                    .color(&STAGE_COLOR)
                    .pos(Pos::new(HPos::Right, VPos::Top)),
                (px - 4, py + 4),
            )?;
        }
    }
    Ok(())
}

/// The values of parameter `j` per iteration.
fn parameter_points(c: &ConvergenceChart, x: &XAxis, j: usize) -> Vec<(f64, f64)> {
    x.xs.iter()
        .zip(&c.parameters)
        .map(|(&x, p)| (x, p.get(j).copied().unwrap_or(f64::NAN)))
        .collect()
}

fn draw_line(
    chart: &mut Chart2d,
    pts: &[(f64, f64)],
    color: RGBColor,
    marker: Marker,
    r: i32,
) -> Result<(), ChartError> {
    for run in finite_runs(pts.iter().copied()) {
        chart.draw_series(LineSeries::new(run, color.stroke_width(2)))?;
    }
    draw_markers(chart, marker, pts, r, color)
}

/// Room (px) right of the plot for the names at the line ends.
fn end_label_width(c: &ConvergenceChart) -> i32 {
    c.parameter_names
        .iter()
        .map(|n| text_width(n, 12.0))
        .fold(0.0, f64::max)
        .min(200.0) as i32
        + 16
}

/// Few parameters: one panel, each line named at its right end.
fn shared_panel(
    root: &Area,
    area: &Area,
    c: &ConvergenceChart,
    x: &XAxis,
    label_w: i32,
) -> Result<(), ChartError> {
    let all_p: Vec<f64> = c
        .parameters
        .iter()
        .flatten()
        .copied()
        .chain([0.0])
        .collect();
    let (plo, phi) = finite_range(&all_p).unwrap_or((-0.1, 0.1));
    let y_range = padded_range(plo, phi, 0.05);
    let mut chart = ChartBuilder::on(area)
        .margin_left(10)
        .margin_right(label_w)
        .margin_top(10)
        .x_label_area_size(44)
        .y_label_area_size(78)
        .build_cartesian_2d(x.range.0..x.range.1, y_range.0..y_range.1)?;
    let yfmt = tick_label(y_range, 8);
    draw_mesh(
        &mut chart,
        &Axes {
            x_desc: "iteration n",
            y_desc: "relative parameter change p̄ (dimensionless)",
            x_fmt: &integer_label,
            y_fmt: &yfmt,
            x_labels: x.labels,
            y_labels: 9,
        },
    )?;
    hline(&mut chart, 0.0, x.range, GREY.stroke_width(1))?;
    marks(root, &mut chart, c, y_range, true)?;
    let mut ends = Vec::new();
    for j in 0..c.parameter_names.len() {
        let pts = parameter_points(c, x, j);
        draw_line(&mut chart, &pts, series_color(j), series_marker(j), 4)?;
        if let Some(&(px, py)) = pts.iter().rev().find(|p| p.1.is_finite()) {
            let (bx, by) = chart.backend_coord(&(px, py.clamp(y_range.0, y_range.1)));
            ends.push((j, bx, by));
        }
    }
    end_labels(root, c, &chart, &mut ends)
}

/// Each line's name at its end, pushed apart vertically so none overlap.
fn end_labels(
    root: &Area,
    c: &ConvergenceChart,
    chart: &Chart2d,
    ends: &mut [(usize, i32, i32)],
) -> Result<(), ChartError> {
    const ROW: i32 = 14;
    ends.sort_by_key(|e| (e.2, e.0));
    let mut ys: Vec<i32> = ends.iter().map(|e| e.2).collect();
    for k in 1..ys.len() {
        ys[k] = ys[k].max(ys[k - 1] + ROW);
    }
    // Shift the whole column up if it ran below the plot.
    let (_, py) = chart.plotting_area().get_pixel_range();
    if let Some(&last) = ys.last() {
        let over = (last - py.end).max(0);
        ys.iter_mut().for_each(|y| *y -= over);
    }
    let right = chart.plotting_area().get_pixel_range().0.end;
    for (e, y) in ends.iter().zip(ys) {
        let (j, bx, by) = *e;
        let x0 = right + 6;
        root.draw(&PathElement::new(
            vec![(bx, by), (x0, y)],
            series_color(j).stroke_width(1),
        ))?;
        root.draw_text(
            &super::abbreviate(&c.parameter_names[j], 12.0, 200.0),
            &font(12.0)
                .color(&series_color(j))
                .pos(Pos::new(HPos::Left, VPos::Center)),
            (x0 + 3, y),
        )?;
    }
    Ok(())
}

/// Many parameters: one small panel each, own scale, returned value in the title.
fn small_multiples(
    root: &Area,
    area: &Area,
    c: &ConvergenceChart,
    x: &XAxis,
) -> Result<(), ChartError> {
    let (head, grid) = area.split_vertically(30);
    let (w, _) = head.dim_in_pixel();
    head.draw_text(
        "relative parameter change p̄ (dimensionless) against iteration n, each on its own scale",
        &font(13.0).pos(Pos::new(HPos::Center, VPos::Top)),
        (w as i32 / 2, 8),
    )?;
    let rows = c.parameter_names.len().div_ceil(COLUMNS);
    let cells = grid.split_evenly((rows, COLUMNS));
    for (j, cell) in cells.iter().enumerate().take(c.parameter_names.len()) {
        small_panel(root, cell, c, x, j)?;
    }
    Ok(())
}

fn small_panel(
    root: &Area,
    cell: &Area,
    c: &ConvergenceChart,
    x: &XAxis,
    j: usize,
) -> Result<(), ChartError> {
    let pts = parameter_points(c, x, j);
    let last = c.selected.and_then(|s| pts.get(s)).map(|p| p.1);
    let value = if c.not_identified.get(j).copied().unwrap_or(false) {
        ": not identified".to_string()
    } else {
        last.filter(|v| v.is_finite())
            .map(|v| format!(" = {}", super::fmt_fixed(v, 4)))
            .unwrap_or_default()
    };
    let (w, _) = cell.dim_in_pixel();
    let title = super::abbreviate(
        &format!("{}{value}", c.parameter_names[j]),
        12.0,
        w as f64 - 60.0,
    );
    let (head, body) = cell.split_vertically(20);
    head.draw_text(
        &title,
        &bold(12.0).pos(Pos::new(HPos::Center, VPos::Top)),
        (w as i32 / 2 + 20, 4),
    )?;
    let vals: Vec<f64> = pts.iter().map(|p| p.1).chain([0.0]).collect();
    let (lo, hi) = finite_range(&vals).unwrap_or((-0.1, 0.1));
    let y_range = padded_range(lo, hi.max(lo + 1e-6), 0.08);
    let mut chart = ChartBuilder::on(&body)
        .margin_left(4)
        .margin_right(10)
        .margin_top(4)
        .x_label_area_size(20)
        .y_label_area_size(58)
        .build_cartesian_2d(x.range.0..x.range.1, y_range.0..y_range.1)?;
    let yfmt = compact_tick_label(y_range, 3);
    draw_mesh(
        &mut chart,
        &Axes {
            x_desc: "",
            y_desc: "",
            x_fmt: &integer_label,
            y_fmt: &yfmt,
            x_labels: x.labels.min(6),
            y_labels: 4,
        },
    )?;
    hline(&mut chart, 0.0, x.range, GREY.stroke_width(1))?;
    marks(root, &mut chart, c, y_range, false)?;
    draw_line(&mut chart, &pts, series_color(0), Marker::Circle, 2)
}

/// Tick labels of a small panel: fixed decimals, or `2.5e-5` when the
/// ticks are closer than 0.001 (fixed decimals would not fit the panel).
pub fn compact_tick_label(range: (f64, f64), n: usize) -> Box<dyn Fn(&f64) -> String> {
    let step = super::nice_step((range.1 - range.0).abs() / n.max(1) as f64);
    if step >= 1e-3 {
        Box::new(tick_label(range, n))
    } else {
        Box::new(move |v: &f64| {
            if v.abs() < step * 1e-6 {
                "0".into()
            } else {
                format!("{v:.1e}")
            }
        })
    }
}

/// −log₁₀(1 − s), with 1 − s floored at [`FLOOR`].
pub fn nines(s: f64) -> f64 {
    -(1.0 - s).max(FLOOR).log10()
}

/// The SFDAC tick label of −log₁₀(1 − s) = v: 0 → "0", 1 → "0.9", 2 → "0.99".
pub fn nines_label(v: &f64) -> String {
    let k = v.round();
    if (v - k).abs() > 1e-6 {
        return String::new();
    }
    match k as i64 {
        i64::MIN..=-1 => String::new(),
        0 => "0".into(),
        n => format!("0.{}", "9".repeat(n as usize)),
    }
}

fn sfdac_panel(
    root: &Area,
    area: &Area,
    c: &ConvergenceChart,
    x: &XAxis,
    right: i32,
) -> Result<(), ChartError> {
    let all: Vec<f64> = c
        .sfdac_mean
        .iter()
        .chain(&c.sfdac_min)
        .filter(|v| v.is_finite())
        .map(|&v| nines(v))
        .collect();
    let top = finite_range(&all).map_or(2.0, |r| r.1).max(2.0).ceil() + 0.3;
    // SFDAC = −1 (1 − s = 2) at the bottom.
    let y_range = (nines(-1.0) - 0.1, top);
    let mut chart = ChartBuilder::on(area)
        .margin_left(10)
        .margin_right(right)
        .margin_top(6)
        .margin_bottom(6)
        .x_label_area_size(44)
        .y_label_area_size(78)
        .build_cartesian_2d(x.range.0..x.range.1, y_range.0..y_range.1)?;
    draw_mesh(
        &mut chart,
        &Axes {
            x_desc: "iteration n",
            y_desc: "SFDAC (scale of 1 − SFDAC, log)",
            x_fmt: &integer_label,
            y_fmt: &nines_label,
            x_labels: x.labels,
            y_labels: (top.floor() as usize + 2).max(3),
        },
    )?;
    marks(root, &mut chart, c, y_range, true)?;
    for (vals, color, marker) in [
        (&c.sfdac_mean, MEAN_COLOR, Marker::Circle),
        (&c.sfdac_min, MIN_COLOR, Marker::Triangle),
    ] {
        let pts: Vec<(f64, f64)> =
            x.xs.iter()
                .zip(vals)
                .map(|(&x, &v)| (x, if v.is_finite() { nines(v) } else { v }))
                .collect();
        draw_line(&mut chart, &pts, color, marker, 4)?;
    }
    Ok(())
}
