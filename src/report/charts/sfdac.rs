//! `sfdac.svg`: SFDAC_i at each updating frequency, one bar per model
//! (initial vs updated; the paper's Table 6), with each model's mean as a
//! dashed line.

use plotters::prelude::*;

use super::{
    category_layout, comparison_color, draw_category_labels, draw_category_mesh, draw_grouped_bars,
    draw_legend, draw_no_data, draw_title, draw_x_desc, fmt_fixed, hline, legend_height,
    tick_label, title_height, ChartError, LegendEntry, NamedSeries, Swatch, GREY,
};

/// SFDAC per updating frequency for one or more models.
#[derive(Clone, Debug, PartialEq)]
pub struct SfdacChart {
    pub title: String,
    pub subtitle: Option<String>,
    /// The updating frequencies ω_i (Hz), one bar group each.
    pub frequencies_hz: Vec<f64>,
    /// One series per model (e.g. "initial model", "updated model"), aligned
    /// with `frequencies_hz`.
    pub series: Vec<NamedSeries>,
}

const WIDTH: u32 = 960;
const PLOT_H: i32 = 420;

fn model_color(i: usize) -> RGBColor {
    comparison_color(i + 1)
}

/// Relative error a frequency label may have (2.75 Hz must not read "2.8").
const LABEL_RELATIVE_ERROR: f64 = 1e-3;

/// Frequency labels with enough decimals to tell neighbours apart, and to
/// give each frequency within [`LABEL_RELATIVE_ERROR`] of its value.
pub fn frequency_labels(hz: &[f64]) -> Vec<String> {
    let mut min_gap = f64::INFINITY;
    for w in hz.windows(2) {
        let d = (w[1] - w[0]).abs();
        if d > 0.0 {
            min_gap = min_gap.min(d);
        }
    }
    let apart = if min_gap.is_finite() {
        super::decimals_for(min_gap).clamp(1, 4)
    } else {
        2
    };
    let close = |d: usize| {
        let scale = 10f64.powi(d as i32);
        hz.iter()
            .all(|f| ((f * scale).round() / scale - f).abs() <= LABEL_RELATIVE_ERROR * f.abs())
    };
    let d = (apart..4).find(|&d| close(d)).unwrap_or(4);
    hz.iter().map(|f| fmt_fixed(*f, d)).collect()
}

/// Render the chart as SVG text.
pub fn render(c: &SfdacChart) -> Result<String, ChartError> {
    let n = c.frequencies_hz.len();
    if n == 0 || c.series.is_empty() {
        return svg_no_data(c);
    }
    let mut entries: Vec<LegendEntry> = c
        .series
        .iter()
        .enumerate()
        .map(|(s, ser)| {
            let label = match (mean(&ser.values), min(&ser.values)) {
                (Some(m), Some(lo)) => format!(
                    "{} (mean {}, min {})",
                    ser.label,
                    fmt_fixed(m, 3),
                    fmt_fixed(lo, 3)
                ),
                _ => ser.label.clone(),
            };
            LegendEntry::new(label, model_color(s), Swatch::Bar)
        })
        .collect();
    entries.push(LegendEntry::new(
        "mean (dashed)",
        GREY,
        Swatch::Line { width: 1 },
    ));
    let labels = frequency_labels(&c.frequencies_hz);
    let plot_w = WIDTH as f64 - 120.0;
    let layout = category_layout(&labels, plot_w / n as f64);
    let lh = legend_height(&entries, WIDTH as i32 - 40);
    let th = title_height(c.subtitle.is_some());
    let height = (th + lh + PLOT_H + layout.height + 10) as u32;

    super::svg((WIDTH, height), |root| {
        draw_title(root, &c.title, c.subtitle.as_deref())?;
        let (_, rest) = root.split_vertically(th);
        let (legend_a, plot) = rest.split_vertically(lh);
        draw_legend(&legend_a.margin(0, 0, 20, 20), &entries)?;
        let y_range = (-1.05, 1.05);
        let x_range = (-0.6, n as f64 - 0.4);
        let mut chart = ChartBuilder::on(&plot)
            .margin_left(10)
            .margin_right(25)
            .margin_top(6)
            .x_label_area_size(layout.height)
            .y_label_area_size(78)
            .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)?;
        let yfmt = tick_label((-1.0, 1.0), 4);
        draw_category_mesh(&mut chart, "SFDAC_i (dimensionless)", &yfmt, 9)?;
        hline(&mut chart, 0.0, x_range, GREY.stroke_width(1))?;
        let colors: Vec<RGBColor> = (0..c.series.len()).map(model_color).collect();
        draw_grouped_bars(&mut chart, &c.series, &colors, y_range)?;
        for (s, ser) in c.series.iter().enumerate() {
            if let Some(m) = mean(&ser.values) {
                chart.draw_series(std::iter::once(plotters::element::DashedPathElement::new(
                    vec![(x_range.0, m), (x_range.1, m)],
                    6,
                    4,
                    model_color(s).stroke_width(2),
                )))?;
            }
        }
        draw_category_labels(root, &chart, &labels, y_range.0, &layout)?;
        draw_x_desc(root, &chart, "updating frequency (Hz)", height as i32 - 10)?;
        Ok(())
    })
}

fn svg_no_data(c: &SfdacChart) -> Result<String, ChartError> {
    super::svg((WIDTH, 400), |root| {
        draw_no_data(root, &c.title, "no updating frequencies")
    })
}

fn finite(v: &[f64]) -> impl Iterator<Item = f64> + '_ {
    v.iter().copied().filter(|x| x.is_finite())
}

fn mean(v: &[f64]) -> Option<f64> {
    let n = finite(v).count();
    (n > 0).then(|| finite(v).sum::<f64>() / n as f64)
}

fn min(v: &[f64]) -> Option<f64> {
    finite(v).reduce(f64::min)
}
