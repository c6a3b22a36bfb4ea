//! FRF overlays: per channel, the magnitude of each series (e.g. measured,
//! initial model, updated model) on a log axis against frequency, with marked
//! frequencies (the updating frequencies) and labelled resonances, and the
//! phase below (`frf/NN-LABEL.svg`); and a contact sheet of the magnitudes of
//! every channel (`frf-overlay.svg`).
//!
//! Generic over the series: the first is drawn as the reference (dark), the
//! others as models; any labels work ("before"/"after", "test"/"model", …).

use num_complex::Complex64;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use rayon::prelude::*;

use super::{
    abbreviate, bold, comparison_color, draw_legend, draw_mesh, draw_no_data, draw_title,
    finite_range, finite_runs, font, legend_height, nice_step, pow10_label, stagger, text_width,
    tick_label, title_height, Area, Axes, Chart2d, ChartError, LegendEntry, Marker, Swatch, GREY,
    LIGHT_GREY,
};

/// A labelled resonance (e.g. "R3" at 33.125 Hz).
#[derive(Clone, Debug, PartialEq)]
pub struct ResonanceMark {
    pub hz: f64,
    pub label: String,
}

/// One channel: a value per frequency line for each series.
#[derive(Clone, Debug, PartialEq)]
pub struct FrfChannel {
    /// e.g. "112+z/112+z".
    pub label: String,
    /// values[series][line], aligned with [`FrfOverlay::series_labels`] and
    /// [`FrfOverlay::frequencies_hz`].
    pub values: Vec<Vec<Complex64>>,
}

/// FRFs of several series on shared frequency lines.
#[derive(Clone, Debug, PartialEq)]
pub struct FrfOverlay {
    pub title: String,
    pub subtitle: Option<String>,
    /// The FRF kind, e.g. "accelerance".
    pub quantity: String,
    /// Its units, e.g. "m/s²/N".
    pub units: String,
    pub frequencies_hz: Vec<f64>,
    /// e.g. ["measured", "initial model", "updated model"].
    pub series_labels: Vec<String>,
    pub channels: Vec<FrfChannel>,
    /// Frequencies marked by dashed vertical lines (Hz).
    pub marks_hz: Vec<f64>,
    /// Legend text of the marks, e.g. "updating frequency".
    pub mark_label: String,
    pub resonances: Vec<ResonanceMark>,
}

const WIDTH: u32 = 960;

fn series_style(s: usize) -> ShapeStyle {
    match s {
        0 => RGBColor(70, 70, 70).stroke_width(2),
        k => comparison_color(k).stroke_width(if k == 1 { 1 } else { 2 }),
    }
}

fn legend_entries(o: &FrfOverlay) -> Vec<LegendEntry> {
    let mut e: Vec<LegendEntry> = o
        .series_labels
        .iter()
        .enumerate()
        .map(|(s, l)| {
            let st = series_style(s);
            let c = st.color.to_rgba();
            LegendEntry::new(
                l.clone(),
                RGBColor(c.0, c.1, c.2),
                Swatch::Line {
                    width: st.stroke_width.max(2),
                },
            )
        })
        .collect();
    if !o.marks_hz.is_empty() {
        e.push(LegendEntry::new(
            o.mark_label.clone(),
            // The translucent mark colour as seen on white.
            RGBColor(115, 202, 178),
            Swatch::VMark { dashed: false },
        ));
    }
    if !o.resonances.is_empty() {
        e.push(LegendEntry::new(
            "test resonance",
            GREY,
            Swatch::Marker(Marker::Triangle),
        ));
    }
    e
}

fn mark_color() -> RGBColor {
    RGBColor(0, 158, 115)
}

/// A marked frequency: a thin translucent solid line (one SVG element, where
/// a dashed line would be hundreds).
fn mark_line(chart: &mut Chart2d, f: f64, (y0, y1): (f64, f64)) -> Result<(), ChartError> {
    chart.draw_series(std::iter::once(PathElement::new(
        vec![(f, y0), (f, y1)],
        mark_color().mix(0.55).stroke_width(1),
    )))?;
    Ok(())
}

/// The x range of the overlay (Hz); never empty.
fn x_range(o: &FrfOverlay) -> (f64, f64) {
    let (a, b) = finite_range(&o.frequencies_hz).unwrap_or((0.0, 1.0));
    if b > a {
        (a, b)
    } else {
        (a - 0.5, a + 0.5)
    }
}

/// Decades (integer log10 bounds) covering the magnitudes of `ch` at lines
/// above 0 Hz: from the 0.5 % quantile (single deep notches and the 0 Hz line
/// do not stretch the axis) to above the largest value, at most `max_decades`.
fn decades(o: &FrfOverlay, ch: &FrfChannel, max_decades: i32) -> (i32, i32) {
    // The quantile and the largest of |v|² (the same order as log10 |v|):
    // two logarithms instead of one per value.
    let mut squares: Vec<f64> = ch
        .values
        .iter()
        .flat_map(|series| series.iter().zip(&o.frequencies_hz))
        .filter(|(_, f)| **f > 0.0)
        .map(|(v, _)| v.norm_sqr())
        .filter(|m2| *m2 > 0.0 && m2.is_finite())
        .collect();
    if squares.is_empty() {
        return (-1, 0);
    }
    let top2 = squares.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let q = (squares.len() as f64 * 0.005) as usize;
    let (_, &mut lo2, _) = squares.select_nth_unstable_by(q, f64::total_cmp);
    crate::solvers::vector_state::clear();
    let (hi, lo) = (0.5 * top2.log10(), 0.5 * lo2.log10());
    let top = hi.ceil() as i32;
    let top = if top as f64 - hi < 0.05 { top + 1 } else { top };
    let bottom = (lo.floor() as i32).max(top - max_decades).min(top - 1);
    (bottom, top)
}

/// (f, y) points of one series, reduced to the extremes per pixel bucket when
/// there are many more lines than pixels.
pub fn decimate(points: Vec<(f64, f64)>, x: (f64, f64), buckets: usize) -> Vec<(f64, f64)> {
    if points.len() <= 4 * buckets || buckets == 0 {
        return points;
    }
    let mut out = Vec::with_capacity(2 * buckets + 2);
    let width = (x.1 - x.0).max(f64::MIN_POSITIVE);
    let bucket_of =
        |f: f64| (((f - x.0) / width * buckets as f64).floor().max(0.0) as usize).min(buckets - 1);
    let mut i = 0;
    while i < points.len() {
        let b = bucket_of(points[i].0);
        let mut j = i;
        let (mut lo, mut hi) = (i, i);
        while j < points.len() && bucket_of(points[j].0) == b {
            // NaN breaks lines: keep it as its own point.
            if !points[j].1.is_finite() {
                break;
            }
            if points[j].1 < points[lo].1 {
                lo = j;
            }
            if points[j].1 > points[hi].1 {
                hi = j;
            }
            j += 1;
        }
        if j == i {
            out.push(points[i]);
            i += 1;
            continue;
        }
        let (a, b2) = if lo <= hi { (lo, hi) } else { (hi, lo) };
        out.push(points[a]);
        if b2 != a {
            out.push(points[b2]);
        }
        i = j;
    }
    out
}

fn magnitude_points(o: &FrfOverlay, values: &[Complex64], floor: f64) -> Vec<(f64, f64)> {
    log_magnitudes(squared_magnitude_points(o, values), floor)
}

/// (f, |v|²) per line, NaN where v is not finite (the line breaks there).
/// |v|² orders the lines as log10 |v| does, so a series can be reduced to
/// its pixel extremes ([`decimate`]) before the logarithms are taken.
fn squared_magnitude_points(o: &FrfOverlay, values: &[Complex64]) -> Vec<(f64, f64)> {
    o.frequencies_hz
        .iter()
        .zip(values)
        .map(|(&f, v)| {
            let finite = v.re.is_finite() && v.im.is_finite();
            (f, if finite { v.norm_sqr() } else { f64::NAN })
        })
        .collect()
}

/// (f, |v|²) → (f, log10 |v|), not below `floor` (|v| = 0 at it).
fn log_magnitudes(points: Vec<(f64, f64)>, floor: f64) -> Vec<(f64, f64)> {
    // A log10 per point: libm at full speed.
    crate::solvers::vector_state::clear();
    points
        .into_iter()
        .map(|(f, m2)| {
            let y = if m2 > 0.0 {
                (0.5 * m2.log10()).max(floor)
            } else if m2 == 0.0 {
                floor
            } else {
                f64::NAN
            };
            (f, y)
        })
        .collect()
}

fn phase_points(o: &FrfOverlay, values: &[Complex64]) -> Vec<(f64, f64)> {
    // Break the line where the phase wraps.
    let mut out = Vec::with_capacity(values.len());
    let mut prev: Option<f64> = None;
    for (&f, v) in o.frequencies_hz.iter().zip(values) {
        let p = if v.norm() > 0.0 && v.norm().is_finite() {
            v.arg().to_degrees()
        } else {
            f64::NAN
        };
        if let (Some(q), true) = (prev, p.is_finite()) {
            if (p - q).abs() > 180.0 {
                out.push((f, f64::NAN));
            }
        }
        prev = p.is_finite().then_some(p);
        out.push((f, p));
    }
    out
}

fn log_label(v: &f64) -> String {
    if (v - v.round()).abs() < 1e-6 {
        pow10_label(v.round() as i32)
    } else {
        String::new()
    }
}

fn draw_series_lines(
    chart: &mut Chart2d,
    pts: Vec<(f64, f64)>,
    style: ShapeStyle,
    x: (f64, f64),
    buckets: usize,
) -> Result<(), ChartError> {
    draw_decimated(chart, decimate(pts, x, buckets), style)
}

/// Draws points already reduced to the panel's pixels.
fn draw_decimated(
    chart: &mut Chart2d,
    pts: Vec<(f64, f64)>,
    style: ShapeStyle,
) -> Result<(), ChartError> {
    for run in finite_runs(pts) {
        if run.len() == 1 {
            chart.draw_series(std::iter::once(Circle::new(run[0], 1, style.filled())))?;
        } else {
            chart.draw_series(LineSeries::new(run, style))?;
        }
    }
    Ok(())
}

const LABEL_PX: f64 = 12.0;

/// Rows the resonance labels need above a plot spanning `plot_px` (left,
/// right) pixels over the x range `x` (at most 3).
fn resonance_label_rows(o: &FrfOverlay, x: (f64, f64), plot_px: (f64, f64)) -> usize {
    let sizes: Vec<(f64, f64)> = o
        .resonances
        .iter()
        .filter(|r| r.hz.is_finite() && r.hz >= x.0 && r.hz <= x.1)
        .map(|r| {
            let t = (r.hz - x.0) / (x.1 - x.0).max(f64::MIN_POSITIVE);
            (
                plot_px.0 + t * (plot_px.1 - plot_px.0),
                text_width(&r.label, LABEL_PX),
            )
        })
        .collect();
    stagger(&sizes, 3.0, 3)
        .into_iter()
        .max()
        .map_or(0, |r| r + 1)
}

/// Dashed marks and resonance labels (above the plot) on a magnitude panel.
fn draw_marks(
    root: &Area,
    chart: &mut Chart2d,
    o: &FrfOverlay,
    y: (f64, f64),
    label_rows: usize,
    label_px: f64,
) -> Result<(), ChartError> {
    let x = chart.x_range();
    for &f in &o.marks_hz {
        if f.is_finite() && f >= x.start && f <= x.end {
            mark_line(chart, f, y)?;
        }
    }
    let visible: Vec<&ResonanceMark> = o
        .resonances
        .iter()
        .filter(|r| r.hz.is_finite() && r.hz >= x.start && r.hz <= x.end)
        .collect();
    if visible.is_empty() {
        return Ok(());
    }
    let pos: Vec<(i32, i32)> = visible
        .iter()
        .map(|r| chart.backend_coord(&(r.hz, y.1)))
        .collect();
    for &(px, py) in &pos {
        root.draw(&Polygon::new(
            vec![(px - 4, py), (px + 4, py), (px, py + 6)],
            GREY.filled(),
        ))?;
    }
    if label_rows > 0 {
        let sizes: Vec<(f64, f64)> = visible
            .iter()
            .zip(&pos)
            .map(|(r, p)| (p.0 as f64, text_width(&r.label, label_px)))
            .collect();
        let rows = stagger(&sizes, 3.0, label_rows);
        for ((r, &(px, py)), row) in visible.iter().zip(&pos).zip(rows) {
            root.draw_text(
                &r.label,
                &font(label_px)
                    .color(&RGBColor(80, 80, 80))
                    .pos(Pos::new(HPos::Center, VPos::Bottom)),
                (px, py - 3 - row as i32 * (label_px as i32 + 2)),
            )?;
        }
    }
    Ok(())
}

/// Render channel `index` (magnitude and phase) as SVG text.
pub fn render_channel(o: &FrfOverlay, index: usize) -> Result<String, ChartError> {
    let Some(ch) = o.channels.get(index) else {
        return super::svg((WIDTH, 400), |root| {
            draw_no_data(root, &o.title, "no such channel")
        });
    };
    let title = format!("{} — {}", o.title, ch.label);
    if o.frequencies_hz.is_empty() {
        return super::svg((WIDTH, 400), |root| {
            draw_no_data(root, &title, "no frequency lines")
        });
    }
    let entries = legend_entries(o);
    let lh = legend_height(&entries, WIDTH as i32 - 40);
    let th = title_height(o.subtitle.is_some());
    let (mag_h, phase_h) = (420, 250);
    let height = (th + lh + mag_h + phase_h + 10) as u32;
    let x = x_range(o);
    let (d0, d1) = decades(o, ch, 8);
    let floor = d0 as f64;
    let buckets = 2 * (WIDTH as usize - 110);
    let label_rows = resonance_label_rows(o, x, (88.0, WIDTH as f64 - 25.0));
    super::svg((WIDTH, height), |root| {
        draw_title(root, &title, o.subtitle.as_deref())?;
        let (_, rest) = root.split_vertically(th);
        let (legend_a, rest) = rest.split_vertically(lh);
        draw_legend(&legend_a.margin(0, 0, 20, 20), &entries)?;
        let (top, bottom) = rest.split_vertically(mag_h);

        let y = (floor, d1 as f64);
        let mut chart = ChartBuilder::on(&top)
            .margin_left(10)
            .margin_right(25)
            .margin_top(6 + label_rows as i32 * (LABEL_PX as i32 + 2))
            .x_label_area_size(30)
            .y_label_area_size(78)
            .build_cartesian_2d(x.0..x.1, y.0..y.1)?;
        let xfmt = tick_label(x, 10);
        let ydesc = format!("|{}| ({}, log scale)", o.quantity, o.units);
        draw_mesh(
            &mut chart,
            &Axes {
                x_desc: "",
                y_desc: &ydesc,
                x_fmt: &xfmt,
                y_fmt: &log_label,
                x_labels: 12,
                y_labels: (d1 - d0 + 1).clamp(2, 9) as usize,
            },
        )?;
        draw_marks(root, &mut chart, o, y, label_rows, LABEL_PX)?;
        for (s, vals) in ch.values.iter().enumerate() {
            draw_series_lines(
                &mut chart,
                magnitude_points(o, vals, floor),
                series_style(s),
                x,
                buckets,
            )?;
        }

        // Phase, plotted in quarter turns so that the ticks fall on multiples of 90°.
        let q = (-2.2, 2.2);
        let mut chart = ChartBuilder::on(&bottom)
            .margin_left(10)
            .margin_right(25)
            .margin_top(4)
            .margin_bottom(6)
            .x_label_area_size(48)
            .y_label_area_size(78)
            .build_cartesian_2d(x.0..x.1, q.0..q.1)?;
        let quarter = |v: &f64| format!("{}", (v * 90.0).round() as i64);
        draw_mesh(
            &mut chart,
            &Axes {
                x_desc: "frequency (Hz)",
                y_desc: "phase (°)",
                x_fmt: &xfmt,
                y_fmt: &quarter,
                x_labels: 12,
                y_labels: 5,
            },
        )?;
        for &f in &o.marks_hz {
            if f.is_finite() && f >= x.0 && f <= x.1 {
                mark_line(&mut chart, f, q)?;
            }
        }
        for (s, vals) in ch.values.iter().enumerate() {
            let pts: Vec<(f64, f64)> = phase_points(o, vals)
                .into_iter()
                .map(|(f, p)| (f, p / 90.0))
                .collect();
            draw_series_lines(&mut chart, pts, series_style(s), x, buckets)?;
        }
        Ok(())
    })
}

/// Columns of the contact sheet for `n` channels.
fn sheet_columns(n: usize) -> usize {
    match n {
        0..=1 => 1,
        2 | 4 => 2,
        3 | 5 | 6 | 9 => 3,
        _ => 4,
    }
}

/// A panel's decades (log10 bounds) and its series reduced to pixels.
type Panel = ((i32, i32), Vec<Vec<(f64, f64)>>);

/// Render every channel's magnitude as a grid of small panels with one legend.
pub fn render_contact_sheet(o: &FrfOverlay) -> Result<String, ChartError> {
    let n = o.channels.len();
    if n == 0 || o.frequencies_hz.is_empty() {
        return super::svg((WIDTH, 400), |root| {
            draw_no_data(root, &o.title, "no channels or no frequency lines")
        });
    }
    let cols = sheet_columns(n);
    let rows = n.div_ceil(cols);
    let width: u32 = if cols >= 4 { 1280 } else { WIDTH };
    let cell_h: u32 = if cols == 1 { 420 } else { 260 };
    let entries = legend_entries(o);
    let lh = legend_height(&entries, width as i32 - 40);
    let th = title_height(o.subtitle.is_some());
    let height = th as u32 + lh as u32 + rows as u32 * cell_h + 10;
    let x = x_range(o);
    let cell_w = width as usize / cols;
    let buckets = cell_w / 2;
    // Each panel's axis range and pixel-reduced series, on all cores (a
    // long record has 10⁵–10⁶ values per sheet); drawn in order below.
    let panels: Vec<Panel> = o
        .channels
        .par_iter()
        .map(|ch| {
            let (d0, d1) = decades(o, ch, 7);
            let series = ch
                .values
                .iter()
                .map(|vals| {
                    let reduced = decimate(squared_magnitude_points(o, vals), x, buckets);
                    log_magnitudes(reduced, d0 as f64)
                })
                .collect();
            ((d0, d1), series)
        })
        .collect();
    super::svg((width, height), |root| {
        draw_title(root, &o.title, o.subtitle.as_deref())?;
        let (_, rest) = root.split_vertically(th);
        let (legend_a, grid) = rest.split_vertically(lh);
        draw_legend(&legend_a.margin(0, 0, 20, 20), &entries)?;
        let grid = grid.margin(0, 10, 4, 4);
        let cells = grid.split_evenly((rows, cols));
        let xfmt_n = if cols >= 3 { 5 } else { 8 };
        let xfmt = sheet_tick_label(x, xfmt_n);
        let ydesc = format!("|H| ({})", o.units);
        for ((ch, cell), ((d0, d1), series)) in o.channels.iter().zip(&cells).zip(&panels) {
            let (d0, d1) = (*d0, *d1);
            let (cw, _) = cell.dim_in_pixel();
            let label = abbreviate(&ch.label, 12.0, cw as f64 - 20.0);
            cell.draw_text(
                &label,
                &bold(12.0).pos(Pos::new(HPos::Center, VPos::Top)),
                (cw as i32 / 2 + 20, 4),
            )?;
            let y = (d0 as f64, d1 as f64);
            let mut chart = ChartBuilder::on(cell)
                .margin_top(22)
                .margin_right(12)
                .margin_left(4)
                .x_label_area_size(36)
                .y_label_area_size(56)
                .build_cartesian_2d(x.0..x.1, y.0..y.1)?;
            chart
                .configure_mesh()
                .x_desc("frequency (Hz)")
                .y_desc(ydesc.as_str())
                .x_label_formatter(&xfmt)
                .y_label_formatter(&log_label)
                .x_labels(xfmt_n)
                // Every decade labelled (at most 8 in a 260 px panel).
                .y_labels((d1 - d0 + 1).clamp(3, 8) as usize)
                .label_style(font(10.0))
                .axis_desc_style(font(10.0))
                .bold_line_style(LIGHT_GREY.stroke_width(1))
                .max_light_lines(0)
                .axis_style(GREY.stroke_width(1))
                .draw()?;
            draw_marks(root, &mut chart, o, y, 0, 10.0)?;
            for (s, pts) in series.iter().enumerate() {
                let st = series_style(s);
                let st = if s == 0 { st.color.stroke_width(1) } else { st };
                draw_decimated(&mut chart, pts.clone(), st)?;
            }
        }
        Ok(())
    })
}

/// Tick labels for small panels: like [`tick_label`] but coarser.
fn sheet_tick_label(range: (f64, f64), n: usize) -> impl Fn(&f64) -> String {
    let d = super::decimals_for(nice_step((range.1 - range.0).abs() / n.max(1) as f64));
    move |v: &f64| super::fmt_fixed(*v, d)
}

/// A file-name-safe form of a channel label (`112+z/112+z` → `112+z_112+z`).
pub fn file_stem(label: &str) -> String {
    label
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '+' || c == '-' || c == '.' {
                c
            } else {
                '_'
            }
        })
        .collect()
}
