//! Charts of an updating run, each a pure function from a plain data struct to
//! SVG text (plotters, SVG backend). Same input → same bytes.
//!
//! Shared here: the error type, fonts, colours, legends drawn in their own band
//! (never over the data), tick formatting and label placement.

pub mod convergence;
pub mod frequencies;
pub mod frf_overlay;
pub mod localisation;
pub mod mac;
pub mod sfdac;

use std::fmt;

use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

pub use convergence::{ConvergenceChart, StageMark};
pub use frequencies::{FrequencyChart, ModeFrequencies};
pub use frf_overlay::{FrfChannel, FrfOverlay, ResonanceMark};
pub use localisation::{LocalisationMap, MapFinding, MapNode};
pub use mac::{MacChart, MacPanel};
pub use sfdac::SfdacChart;

/// A chart could not be drawn (the SVG backend failed).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChartError(pub String);

impl fmt::Display for ChartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "drawing a chart: {}", self.0)
    }
}

impl std::error::Error for ChartError {}

impl<E: std::error::Error + Send + Sync> From<DrawingAreaErrorKind<E>> for ChartError {
    fn from(e: DrawingAreaErrorKind<E>) -> Self {
        ChartError(e.to_string())
    }
}

/// The drawing surface every chart draws on.
pub(crate) type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// Font family of every text (DejaVu Sans where available).
pub(crate) const FONT: &str = "DejaVu Sans, Arial, sans-serif";

/// A text style whose SVG `font-size` is `px` (plotters writes size/1.24).
pub(crate) fn font(px: f64) -> TextStyle<'static> {
    (FONT, px * 1.24).into_font().color(&BLACK)
}

pub(crate) fn bold(px: f64) -> TextStyle<'static> {
    (FONT, px * 1.24, FontStyle::Bold).into_font().color(&BLACK)
}

/// Estimated width (px) of `text` at `px` font size (DejaVu Sans averages ≈ 0.6 em).
pub(crate) fn text_width(text: &str, px: f64) -> f64 {
    text.chars()
        .map(|c| {
            if c.is_ascii_uppercase() || c == 'm' || c == 'w' {
                0.72
            } else {
                0.58
            }
        })
        .sum::<f64>()
        * px
}

/// `text` cut to at most `max_px` wide with an ellipsis.
pub fn abbreviate(text: &str, px: f64, max_px: f64) -> String {
    if text_width(text, px) <= max_px {
        return text.to_string();
    }
    let mut out = String::new();
    for c in text.chars() {
        let next = format!("{out}{c}…");
        if text_width(&next, px) > max_px {
            break;
        }
        out.push(c);
    }
    out.push('…');
    out
}

pub(crate) const GREY: RGBColor = RGBColor(150, 150, 150);
pub(crate) const LIGHT_GREY: RGBColor = RGBColor(225, 225, 225);
pub(crate) const DARK: RGBColor = RGBColor(30, 30, 30);

/// Colour-blind-friendly series colours (Okabe–Ito, then Tableau).
pub(crate) const PALETTE: [RGBColor; 12] = [
    RGBColor(0, 114, 178),   // blue
    RGBColor(230, 159, 0),   // orange
    RGBColor(0, 158, 115),   // green
    RGBColor(204, 121, 167), // purple-pink
    RGBColor(213, 94, 0),    // vermillion
    RGBColor(86, 180, 233),  // sky blue
    RGBColor(120, 94, 240),  // violet
    RGBColor(140, 86, 75),   // brown
    RGBColor(188, 189, 34),  // olive
    RGBColor(127, 127, 127), // grey
    RGBColor(23, 190, 207),  // cyan
    RGBColor(214, 39, 40),   // red
];

/// Colour of series `i` (cycles).
pub(crate) fn series_color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// Colours of a before/after comparison: reference (test) black, then the
/// models: first ("initial") orange, second ("updated") blue, then the palette.
pub(crate) fn comparison_color(i: usize) -> RGBColor {
    match i {
        0 => DARK,
        1 => RGBColor(230, 120, 0),
        2 => RGBColor(0, 100, 200),
        // Green, not the palette's vermillion (too near the orange of 1).
        3 => RGBColor(0, 158, 115),
        k => series_color(k + 1),
    }
}

/// Marker shapes cycled for series beyond the palette.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Marker {
    Circle,
    Square,
    Triangle,
    Cross,
}

pub(crate) fn series_marker(i: usize) -> Marker {
    match (i / PALETTE.len()) % 4 {
        0 => Marker::Circle,
        1 => Marker::Square,
        2 => Marker::Triangle,
        _ => Marker::Cross,
    }
}

/// How a legend entry is drawn.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Swatch {
    Line {
        width: u32,
    },
    LineMarker(Marker),
    Marker(Marker),
    Bar,
    /// A vertical line (frequency marks, the returned iteration).
    VMark {
        dashed: bool,
    },
}

#[derive(Clone, Debug)]
pub(crate) struct LegendEntry {
    pub label: String,
    pub color: RGBColor,
    pub swatch: Swatch,
}

impl LegendEntry {
    pub fn new(label: impl Into<String>, color: RGBColor, swatch: Swatch) -> Self {
        LegendEntry {
            label: label.into(),
            color,
            swatch,
        }
    }
}

const LEGEND_PX: f64 = 13.0;
const LEGEND_ROW: i32 = 20;
const SWATCH_W: i32 = 26;

fn entry_width(e: &LegendEntry) -> i32 {
    SWATCH_W + 6 + text_width(&e.label, LEGEND_PX).ceil() as i32 + 18
}

/// Entries flowed into rows that fit `width` px (each label cut to fit).
fn legend_rows(entries: &[LegendEntry], width: i32) -> Vec<Vec<LegendEntry>> {
    let max_label = (width - SWATCH_W - 30).max(40) as f64;
    let mut rows: Vec<Vec<LegendEntry>> = Vec::new();
    let mut used = 0;
    for e in entries {
        let mut e = e.clone();
        e.label = abbreviate(&e.label, LEGEND_PX, max_label);
        let w = entry_width(&e);
        match rows.last_mut() {
            Some(row) if used + w <= width => {
                row.push(e);
                used += w;
            }
            _ => {
                rows.push(vec![e]);
                used = w;
            }
        }
    }
    rows
}

/// Height (px) a legend of `entries` takes at `width`.
pub(crate) fn legend_height(entries: &[LegendEntry], width: i32) -> i32 {
    let n = legend_rows(entries, width).len() as i32;
    if n == 0 {
        0
    } else {
        n * LEGEND_ROW + 8
    }
}

fn draw_marker(
    area: &Area,
    m: Marker,
    (x, y): (i32, i32),
    r: i32,
    color: RGBColor,
) -> Result<(), ChartError> {
    let style = color.filled();
    match m {
        Marker::Circle => area.draw(&Circle::new((x, y), r, style))?,
        Marker::Square => area.draw(&Rectangle::new([(x - r, y - r), (x + r, y + r)], style))?,
        Marker::Triangle => area.draw(&Polygon::new(
            vec![(x, y - r - 1), (x - r - 1, y + r), (x + r + 1, y + r)],
            style,
        ))?,
        Marker::Cross => {
            let s = color.stroke_width(2);
            area.draw(&PathElement::new(vec![(x - r, y - r), (x + r, y + r)], s))?;
            area.draw(&PathElement::new(vec![(x - r, y + r), (x + r, y - r)], s))?;
        }
    }
    Ok(())
}

/// Draw markers at data points of a chart.
pub(crate) fn draw_markers(
    chart: &mut Chart2d,
    m: Marker,
    points: &[(f64, f64)],
    r: i32,
    color: RGBColor,
) -> Result<(), ChartError> {
    let style = color.filled();
    let pts = points
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite());
    match m {
        Marker::Circle => {
            chart.draw_series(pts.map(|p| EmptyElement::at(p) + Circle::new((0, 0), r, style)))?;
        }
        Marker::Square => {
            chart.draw_series(
                pts.map(|p| EmptyElement::at(p) + Rectangle::new([(-r, -r), (r, r)], style)),
            )?;
        }
        Marker::Triangle => {
            chart.draw_series(pts.map(|p| {
                EmptyElement::at(p)
                    + Polygon::new(vec![(0, -r - 1), (-r - 1, r), (r + 1, r)], style)
            }))?;
        }
        Marker::Cross => {
            let s = color.stroke_width(2);
            chart.draw_series(pts.map(|p| {
                EmptyElement::at(p)
                    + PathElement::new(vec![(-r, -r), (r, r)], s)
                    + PathElement::new(vec![(-r, r), (r, -r)], s)
            }))?;
        }
    }
    Ok(())
}

/// Draw the legend into `area` (rows from its top-left corner, centred).
pub(crate) fn draw_legend(area: &Area, entries: &[LegendEntry]) -> Result<(), ChartError> {
    let (w, _) = area.dim_in_pixel();
    let rows = legend_rows(entries, w as i32);
    let style = font(LEGEND_PX).pos(Pos::new(HPos::Left, VPos::Center));
    for (r, row) in rows.iter().enumerate() {
        let total: i32 = row.iter().map(entry_width).sum();
        let mut x = ((w as i32 - total) / 2).max(0);
        let y = 4 + r as i32 * LEGEND_ROW + LEGEND_ROW / 2;
        for e in row {
            let (x0, x1) = (x + 2, x + SWATCH_W - 2);
            let xm = (x0 + x1) / 2;
            match e.swatch {
                Swatch::Line { width } => area.draw(&PathElement::new(
                    vec![(x0, y), (x1, y)],
                    e.color.stroke_width(width),
                ))?,
                Swatch::LineMarker(m) => {
                    area.draw(&PathElement::new(
                        vec![(x0, y), (x1, y)],
                        e.color.stroke_width(2),
                    ))?;
                    draw_marker(area, m, (xm, y), 3, e.color)?;
                }
                Swatch::Marker(m) => draw_marker(area, m, (xm, y), 4, e.color)?,
                Swatch::Bar => area.draw(&Rectangle::new(
                    [(x0 + 4, y - 6), (x1 - 4, y + 6)],
                    e.color.filled(),
                ))?,
                Swatch::VMark { dashed: false } => {
                    area.draw(&PathElement::new(
                        vec![(xm, y - 8), (xm, y + 8)],
                        e.color.stroke_width(2),
                    ))?;
                }
                Swatch::VMark { dashed: true } => {
                    for k in 0..3 {
                        let yy = y - 8 + k * 6;
                        area.draw(&PathElement::new(
                            vec![(xm, yy), (xm, yy + 3)],
                            e.color.stroke_width(1),
                        ))?;
                    }
                }
            }
            area.draw_text(&e.label, &style, (x + SWATCH_W + 6, y))?;
            x += entry_width(e);
        }
    }
    Ok(())
}

/// Draw a centred chart title (and an optional smaller subtitle) into `area`.
pub(crate) fn draw_title(
    area: &Area,
    title: &str,
    subtitle: Option<&str>,
) -> Result<(), ChartError> {
    let (w, _) = area.dim_in_pixel();
    let t = abbreviate(title, 18.0, w as f64 - 20.0);
    area.draw_text(
        &t,
        &bold(18.0).pos(Pos::new(HPos::Center, VPos::Top)),
        (w as i32 / 2, 8),
    )?;
    if let Some(s) = subtitle {
        let s = abbreviate(s, 12.0, w as f64 - 20.0);
        area.draw_text(
            &s,
            &font(12.0)
                .color(&RGBColor(80, 80, 80))
                .pos(Pos::new(HPos::Center, VPos::Top)),
            (w as i32 / 2, 32),
        )?;
    }
    Ok(())
}

/// Height of the title band.
pub(crate) fn title_height(subtitle: bool) -> i32 {
    if subtitle {
        52
    } else {
        36
    }
}

/// A "no data" chart: title and a centred message.
pub(crate) fn draw_no_data(area: &Area, title: &str, message: &str) -> Result<(), ChartError> {
    draw_title(area, title, None)?;
    let (w, h) = area.dim_in_pixel();
    area.draw(&Rectangle::new(
        [(20, 50), (w as i32 - 20, h as i32 - 20)],
        LIGHT_GREY.stroke_width(1),
    ))?;
    area.draw_text(
        message,
        &font(15.0).pos(Pos::new(HPos::Center, VPos::Center)),
        (w as i32 / 2, h as i32 / 2),
    )?;
    Ok(())
}

/// Render `draw` into an SVG of `size` px on a white background.
pub(crate) fn svg<F>(size: (u32, u32), draw: F) -> Result<String, ChartError>
where
    F: FnOnce(&Area) -> Result<(), ChartError>,
{
    let mut s = String::new();
    {
        let root = SVGBackend::with_string(&mut s, size).into_drawing_area();
        root.fill(&WHITE)?;
        draw(&root)?;
        root.present()?;
    }
    Ok(s)
}

/// A chart with linear f64 axes.
pub(crate) type Chart2d<'a, 'b> =
    ChartContext<'a, SVGBackend<'b>, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// Axis descriptions, tick formatters and counts of one panel.
pub(crate) struct Axes<'f> {
    pub x_desc: &'f str,
    pub y_desc: &'f str,
    pub x_fmt: &'f dyn Fn(&f64) -> String,
    pub y_fmt: &'f dyn Fn(&f64) -> String,
    pub x_labels: usize,
    pub y_labels: usize,
}

/// Draw the mesh, tick labels and axis descriptions in the house style.
pub(crate) fn draw_mesh(chart: &mut Chart2d, axes: &Axes) -> Result<(), ChartError> {
    chart
        .configure_mesh()
        .x_desc(axes.x_desc)
        .y_desc(axes.y_desc)
        .x_label_formatter(axes.x_fmt)
        .y_label_formatter(axes.y_fmt)
        .x_labels(axes.x_labels)
        .y_labels(axes.y_labels)
        .label_style(font(12.0))
        .axis_desc_style(font(13.0))
        .bold_line_style(LIGHT_GREY.stroke_width(1))
        .max_light_lines(0)
        .axis_style(GREY.stroke_width(1))
        .draw()?;
    Ok(())
}

/// A dashed vertical line at x from y0 to y1 (data coordinates).
pub(crate) fn vline(
    chart: &mut Chart2d,
    x: f64,
    (y0, y1): (f64, f64),
    color: RGBColor,
) -> Result<(), ChartError> {
    if x.is_finite() {
        chart.draw_series(std::iter::once(plotters::element::DashedPathElement::new(
            vec![(x, y0), (x, y1)],
            4,
            3,
            color.stroke_width(1),
        )))?;
    }
    Ok(())
}

/// A solid horizontal line at y across the x range.
pub(crate) fn hline(
    chart: &mut Chart2d,
    y: f64,
    (x0, x1): (f64, f64),
    style: ShapeStyle,
) -> Result<(), ChartError> {
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(x0, y), (x1, y)],
        style,
    )))?;
    Ok(())
}

/// Integer tick labels (non-integers unlabelled).
pub(crate) fn integer_label(v: &f64) -> String {
    if (v - v.round()).abs() < 1e-6 {
        format!("{}", v.round() as i64)
    } else {
        String::new()
    }
}

/// One labelled series of values (e.g. the SFDAC of the initial model).
#[derive(Clone, Debug, PartialEq)]
pub struct NamedSeries {
    pub label: String,
    pub values: Vec<f64>,
}

impl NamedSeries {
    pub fn new(label: impl Into<String>, values: Vec<f64>) -> Self {
        NamedSeries {
            label: label.into(),
            values,
        }
    }
}

const CATEGORY_PX: f64 = 12.0;

/// How category labels under a bar chart are laid out.
pub(crate) struct CategoryLayout {
    pub rotated: bool,
    /// Height (px) of the label band, axis description included.
    pub height: i32,
}

/// Horizontal labels if each fits its slot, else rotated (read upwards).
pub(crate) fn category_layout(labels: &[String], slot_px: f64) -> CategoryLayout {
    let widest = labels
        .iter()
        .map(|l| text_width(l, CATEGORY_PX))
        .fold(0.0, f64::max);
    if widest + 6.0 <= slot_px {
        CategoryLayout {
            rotated: false,
            height: 48,
        }
    } else {
        CategoryLayout {
            rotated: true,
            height: widest.min(160.0).ceil() as i32 + 40,
        }
    }
}

/// Write category labels under the plotting area at data x = 0, 1, 2, …
pub(crate) fn draw_category_labels(
    root: &Area,
    chart: &Chart2d,
    labels: &[String],
    y_axis: f64,
    layout: &CategoryLayout,
) -> Result<(), ChartError> {
    for (i, l) in labels.iter().enumerate() {
        let (x, y) = chart.backend_coord(&(i as f64, y_axis));
        if layout.rotated {
            let l = abbreviate(l, CATEGORY_PX, 160.0);
            let style = font(CATEGORY_PX)
                .transform(FontTransform::Rotate270)
                .pos(Pos::new(HPos::Right, VPos::Center));
            root.draw_text(&l, &style, (x, y + 8))?;
        } else {
            root.draw_text(
                l,
                &font(CATEGORY_PX).pos(Pos::new(HPos::Center, VPos::Top)),
                (x, y + 8),
            )?;
        }
    }
    Ok(())
}

/// Bars of `series` grouped at x = 0, 1, 2, … (one colour per series).
pub(crate) fn draw_grouped_bars(
    chart: &mut Chart2d,
    series: &[NamedSeries],
    colors: &[RGBColor],
    y_clip: (f64, f64),
) -> Result<(), ChartError> {
    let k = series.len().max(1) as f64;
    let group = 0.8;
    let bar = group / k;
    for (s, ser) in series.iter().enumerate() {
        let color = colors.get(s).copied().unwrap_or_else(|| series_color(s));
        let rects = ser
            .values
            .iter()
            .enumerate()
            .filter(|(_, v)| v.is_finite())
            .map(|(i, &v)| {
                let left = i as f64 - group / 2.0 + s as f64 * bar + 0.08 * bar;
                let right = left + 0.84 * bar;
                Rectangle::new(
                    [(left, 0.0), (right, v.clamp(y_clip.0, y_clip.1))],
                    color.filled(),
                )
            });
        chart.draw_series(rects)?;
    }
    Ok(())
}

/// Draw the y-axis description and tick labels only; the x axis carries no
/// plotters labels (category labels are drawn by [`draw_category_labels`]).
pub(crate) fn draw_category_mesh(
    chart: &mut Chart2d,
    y_desc: &str,
    y_fmt: &dyn Fn(&f64) -> String,
    y_labels: usize,
) -> Result<(), ChartError> {
    chart
        .configure_mesh()
        .disable_x_mesh()
        .x_labels(0)
        .y_desc(y_desc)
        .y_label_formatter(y_fmt)
        .y_labels(y_labels)
        .label_style(font(12.0))
        .axis_desc_style(font(13.0))
        .bold_line_style(LIGHT_GREY.stroke_width(1))
        .max_light_lines(0)
        .axis_style(GREY.stroke_width(1))
        .draw()?;
    Ok(())
}

/// The x-axis description centred under the category labels.
pub(crate) fn draw_x_desc(
    root: &Area,
    chart: &Chart2d,
    text: &str,
    y_px: i32,
) -> Result<(), ChartError> {
    let (px, _) = chart.plotting_area().get_pixel_range();
    let x = (px.start + px.end) / 2;
    root.draw_text(
        text,
        &font(13.0).pos(Pos::new(HPos::Center, VPos::Bottom)),
        (x, y_px),
    )?;
    Ok(())
}

/// Finite (min, max) of `values`, or `None`.
pub(crate) fn finite_range<'a>(values: impl IntoIterator<Item = &'a f64>) -> Option<(f64, f64)> {
    let mut r: Option<(f64, f64)> = None;
    for &v in values {
        if v.is_finite() {
            r = Some(match r {
                None => (v, v),
                Some((a, b)) => (a.min(v), b.max(v)),
            });
        }
    }
    r
}

/// A "nice" step ≥ `raw` (1, 2, 2.5, 5 × 10^k).
pub fn nice_step(raw: f64) -> f64 {
    if !(raw > 0.0 && raw.is_finite()) {
        return 1.0;
    }
    let p = 10f64.powf(raw.log10().floor());
    for m in [1.0, 2.0, 2.5, 5.0, 10.0] {
        if m * p >= raw * (1.0 - 1e-9) {
            return m * p;
        }
    }
    10.0 * p
}

/// Axis range padded by `pad` (fraction) and snapped to nice steps; never empty.
pub fn padded_range(lo: f64, hi: f64, pad: f64) -> (f64, f64) {
    let (lo, hi) = if lo.is_finite() && hi.is_finite() {
        (lo.min(hi), lo.max(hi))
    } else {
        (0.0, 1.0)
    };
    let span = hi - lo;
    let span = if span > 0.0 {
        span
    } else {
        lo.abs().max(1.0) * 0.1
    };
    let step = nice_step(span / 6.0);
    let a = ((lo - pad * span) / step).floor() * step;
    let b = ((hi + pad * span) / step).ceil() * step;
    (a, b)
}

/// Number of decimals that tell apart ticks `step` apart.
pub fn decimals_for(step: f64) -> usize {
    if !(step > 0.0 && step.is_finite()) {
        return 2;
    }
    let d = -(step.log10() - 1e-9).floor();
    d.clamp(0.0, 6.0) as usize
}

/// A stable number label: `decimals` fixed digits, no "-0".
pub fn fmt_fixed(v: f64, decimals: usize) -> String {
    if !v.is_finite() {
        return "–".to_string();
    }
    let s = format!("{v:.decimals$}");
    if s.trim_start_matches('-')
        .chars()
        .all(|c| c == '0' || c == '.')
    {
        s.trim_start_matches('-').to_string()
    } else {
        s
    }
}

/// A tick label formatter for a linear axis over `range` with about `n` ticks.
pub(crate) fn tick_label(range: (f64, f64), n: usize) -> impl Fn(&f64) -> String {
    let d = decimals_for(nice_step((range.1 - range.0).abs() / n.max(1) as f64));
    move |v: &f64| fmt_fixed(*v, d)
}

/// Ticks of a log axis over [lo, hi] (both > 0): 1, 2, 5 × 10ᵏ, or
/// 1, 2, 3, 5, 7 × 10ᵏ when that gives fewer than four.
pub fn log_ticks(lo: f64, hi: f64) -> Vec<f64> {
    if !(lo > 0.0 && hi > lo && hi.is_finite()) {
        return Vec::new();
    }
    let ticks = |mantissas: &[f64]| -> Vec<f64> {
        let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
        (k0..=k1)
            .flat_map(|k| mantissas.iter().map(move |m| m * 10f64.powi(k)))
            .filter(|t| *t >= lo * (1.0 - 1e-12) && *t <= hi * (1.0 + 1e-12))
            .collect()
    };
    let t = ticks(&[1.0, 2.0, 5.0]);
    if t.len() >= 4 {
        t
    } else {
        ticks(&[1.0, 2.0, 3.0, 5.0, 7.0])
    }
}

/// A log-axis tick label: "200", "5", "0.5", "0.02".
pub fn log_tick_label(t: f64) -> String {
    if t >= 1.0 {
        format!("{}", t.round() as i64)
    } else {
        let d = (-t.log10()).ceil().max(1.0) as usize;
        fmt_fixed(t, d)
    }
}

/// `10ⁿ` in superscript digits.
pub fn pow10_label(exp: i32) -> String {
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::from("10");
    if exp < 0 {
        s.push('⁻');
    }
    for c in exp.unsigned_abs().to_string().chars() {
        s.push(SUP[c.to_digit(10).unwrap_or(0) as usize]);
    }
    s
}

/// Assign each label (centre x in px, width px) the lowest row where it does
/// not overlap the labels already placed; returns the row of each label.
pub fn stagger(labels: &[(f64, f64)], gap: f64, max_rows: usize) -> Vec<usize> {
    let mut row_ends: Vec<f64> = Vec::new();
    let mut order: Vec<usize> = (0..labels.len()).collect();
    order.sort_by(|&a, &b| labels[a].0.total_cmp(&labels[b].0).then(a.cmp(&b)));
    let mut rows = vec![0; labels.len()];
    for i in order {
        let (x, w) = labels[i];
        let left = x - w / 2.0;
        let row = row_ends.iter().position(|&end| left >= end + gap);
        let row = match row {
            Some(r) => r,
            None if row_ends.len() < max_rows.max(1) => {
                row_ends.push(f64::NEG_INFINITY);
                row_ends.len() - 1
            }
            None => {
                // Every row is full here: the row that ends first.
                (0..row_ends.len())
                    .min_by(|&a, &b| row_ends[a].total_cmp(&row_ends[b]))
                    .unwrap_or(0)
            }
        };
        row_ends[row] = x + w / 2.0;
        rows[i] = row;
    }
    rows
}

/// Split a polyline into runs of finite points (NaN/∞ break the line).
pub fn finite_runs(points: impl IntoIterator<Item = (f64, f64)>) -> Vec<Vec<(f64, f64)>> {
    let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut cur = Vec::new();
    for (x, y) in points {
        if x.is_finite() && y.is_finite() {
            cur.push((x, y));
        } else if !cur.is_empty() {
            runs.push(std::mem::take(&mut cur));
        }
    }
    if !cur.is_empty() {
        runs.push(cur);
    }
    runs
}
