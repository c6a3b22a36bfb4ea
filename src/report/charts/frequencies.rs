//! `frequencies.svg`: test vs model resonance frequencies (the paper's
//! Table 7). Left: each model's partner frequency against the test frequency
//! on log–log axes, with the diagonal (equal frequencies) and ±5 % lines, so
//! that a relative error is the same distance from the diagonal at any
//! frequency. Right: the deviation (f_model − f_test)/f_test in % of each
//! model as bars, one panel per model, each on its own scale (an updated
//! model's 0.1 % stays visible next to an initial model's 10 %).

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::font;
use super::{
    category_layout, comparison_color, draw_category_labels, draw_category_mesh, draw_grouped_bars,
    draw_legend, draw_markers, draw_no_data, draw_title, finite_range, fmt_fixed, hline,
    legend_height, log_ticks, padded_range, tick_label, title_height, Area, Chart2d, ChartError,
    LegendEntry, Marker, NamedSeries, Swatch, GREY, LIGHT_GREY,
};

/// One test resonance and the frequency of its partner mode in each model.
#[derive(Clone, Debug, PartialEq)]
pub struct ModeFrequencies {
    /// Short label, e.g. "R1".
    pub label: String,
    pub reference_hz: f64,
    /// Partner frequency per model (`None`: unpaired), aligned with
    /// [`FrequencyChart::model_labels`].
    pub models_hz: Vec<Option<f64>>,
}

/// Reference (test) frequencies against one or more models.
#[derive(Clone, Debug, PartialEq)]
pub struct FrequencyChart {
    pub title: String,
    pub subtitle: Option<String>,
    /// e.g. "test".
    pub reference_label: String,
    /// e.g. ["initial model", "updated model"].
    pub model_labels: Vec<String>,
    pub modes: Vec<ModeFrequencies>,
}

const WIDTH: u32 = 960;
/// Side (px) of the square test-vs-model panel.
const DIAGONAL: i32 = 470;
/// Height (px) of one deviation panel, category labels excluded.
const DEVIATION_H: i32 = 200;
/// The relative band drawn around the diagonal.
const BAND: f64 = 0.05;

impl FrequencyChart {
    /// Deviation in % of model `m` per mode (NaN where unpaired).
    pub fn deviations_pct(&self, m: usize) -> Vec<f64> {
        self.modes
            .iter()
            .map(|r| match r.models_hz.get(m).copied().flatten() {
                Some(f) if r.reference_hz != 0.0 => 100.0 * (f - r.reference_hz) / r.reference_hz,
                _ => f64::NAN,
            })
            .collect()
    }

    /// Mean |deviation| in % of model `m` over its paired modes.
    pub fn mean_abs_deviation_pct(&self, m: usize) -> Option<f64> {
        let d: Vec<f64> = self
            .deviations_pct(m)
            .into_iter()
            .filter(|x| x.is_finite())
            .collect();
        (!d.is_empty()).then(|| d.iter().map(|x| x.abs()).sum::<f64>() / d.len() as f64)
    }

    /// "initial model (mean |Δf| 5.43 %)".
    fn model_title(&self, m: usize) -> String {
        let l = &self.model_labels[m];
        match self.mean_abs_deviation_pct(m) {
            Some(d) => format!("{l} (mean |Δf| {} %)", fmt_fixed(d, 2)),
            None => l.clone(),
        }
    }
}

fn model_color(m: usize) -> RGBColor {
    comparison_color(m + 1)
}

fn model_marker(m: usize) -> Marker {
    if m % 2 == 0 {
        Marker::Circle
    } else {
        Marker::Triangle
    }
}

fn legend(c: &FrequencyChart) -> Vec<LegendEntry> {
    let mut entries: Vec<LegendEntry> = (0..c.model_labels.len())
        .map(|m| {
            LegendEntry::new(
                c.model_title(m),
                model_color(m),
                Swatch::Marker(model_marker(m)),
            )
        })
        .collect();
    entries.push(LegendEntry::new(
        format!("model = {}", c.reference_label),
        GREY,
        Swatch::Line { width: 1 },
    ));
    entries.push(LegendEntry::new(
        format!("±{} %", fmt_fixed(100.0 * BAND, 0)),
        GREY,
        Swatch::VMark { dashed: true },
    ));
    entries
}

/// Render the chart as SVG text.
pub fn render(c: &FrequencyChart) -> Result<String, ChartError> {
    let n = c.modes.len();
    if n == 0 {
        return super::svg((WIDTH, 400), |root| {
            draw_no_data(root, &c.title, "no test resonances")
        });
    }
    let entries = legend(c);
    let mode_labels: Vec<String> = c.modes.iter().map(|r| r.label.clone()).collect();
    let right_w = WIDTH as f64 - DIAGONAL as f64 - 100.0;
    let layout = category_layout(&mode_labels, right_w / n as f64);
    let lh = legend_height(&entries, WIDTH as i32 - 40);
    let th = title_height(c.subtitle.is_some());
    let models = c.model_labels.len().max(1) as i32;
    let panel_h = DEVIATION_H + layout.height + 24;
    let body = (DIAGONAL + 60).max(models * panel_h);
    let height = (th + lh + body + 10) as u32;

    super::svg((WIDTH, height), |root| {
        draw_title(root, &c.title, c.subtitle.as_deref())?;
        let (_, rest) = root.split_vertically(th);
        let (legend_a, rest) = rest.split_vertically(lh);
        draw_legend(&legend_a.margin(0, 0, 20, 20), &entries)?;
        let (left, right) = rest.split_horizontally(DIAGONAL + 30);
        diagonal_panel(root, &left.margin(0, 0, 0, 0), c)?;
        for m in 0..c.model_labels.len() {
            let top = m as i32 * panel_h;
            let area = right
                .clone()
                .shrink((0, top), (right.dim_in_pixel().0, panel_h as u32));
            deviation_panel(root, &area, c, m, &mode_labels, &layout)?;
        }
        Ok(())
    })
}

/// Log–log axis range (Hz) of every positive frequency, partners more than a
/// factor 2 off the test range clipped.
fn log_range(c: &FrequencyChart) -> Option<(f64, f64)> {
    let refs: Vec<f64> = c
        .modes
        .iter()
        .map(|r| r.reference_hz)
        .filter(|f| *f > 0.0 && f.is_finite())
        .collect();
    let (rlo, rhi) = finite_range(&refs)?;
    let all: Vec<f64> = c
        .modes
        .iter()
        .flat_map(|r| r.models_hz.iter().flatten().copied())
        .filter(|f| *f > 0.0 && f.is_finite())
        .chain(refs.iter().copied())
        .collect();
    let (lo, hi) = finite_range(&all)?;
    let (lo, hi) = (lo.max(rlo / 2.0), hi.min(2.0 * rhi));
    // 6 % of a decade (at least) on each side.
    let pad = 0.06 * (hi.log10() - lo.log10()).max(0.3);
    Some((lo.log10() - pad, hi.log10() + pad))
}

/// The test-vs-model panel: log10 of each frequency on linear axes, ticks
/// at 1, 2, 5 × 10ᵏ Hz.
fn diagonal_panel(root: &Area, area: &Area, c: &FrequencyChart) -> Result<(), ChartError> {
    let Some((lo, hi)) = log_range(c) else {
        return Ok(());
    };
    let mut chart = ChartBuilder::on(area)
        .margin_left(10)
        .margin_right(10)
        .margin_top(6)
        .x_label_area_size(44)
        .y_label_area_size(64)
        .build_cartesian_2d(lo..hi, lo..hi)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(0)
        .y_labels(0)
        .x_desc(format!("{} frequency (Hz, log scale)", c.reference_label))
        .y_desc("model frequency (Hz, log scale)")
        .axis_desc_style(font(13.0))
        .axis_style(GREY.stroke_width(1))
        .draw()?;
    log_grid(root, &mut chart, (lo, hi))?;
    let diag = |k: f64| vec![(lo, lo + k), (hi, hi + k)];
    chart.draw_series(std::iter::once(PathElement::new(
        diag(0.0),
        GREY.stroke_width(1),
    )))?;
    for k in [(1.0 + BAND).log10(), (1.0 - BAND).log10()] {
        chart.draw_series(std::iter::once(plotters::element::DashedPathElement::new(
            diag(k),
            4,
            3,
            GREY.stroke_width(1),
        )))?;
    }
    for m in 0..c.model_labels.len() {
        let mut inside = Vec::new();
        for r in &c.modes {
            let Some(f) = r.models_hz.get(m).copied().flatten() else {
                continue;
            };
            if !(r.reference_hz > 0.0 && f > 0.0 && f.is_finite()) {
                continue;
            }
            let (x, y) = (r.reference_hz.log10(), f.log10());
            if y > hi || y < lo {
                let edge = y.clamp(lo, hi);
                let (px, py) = chart.backend_coord(&(x, edge));
                let (arrow, dy) = if y > hi { ("↑", 6) } else { ("↓", -18) };
                root.draw_text(
                    &format!("{} Hz {arrow}", fmt_fixed(f, 1)),
                    &font(10.0)
                        .color(&model_color(m))
                        .pos(Pos::new(HPos::Center, VPos::Top)),
                    (px, py + dy + 12 * m as i32),
                )?;
            } else {
                inside.push((x, y));
            }
        }
        draw_markers(&mut chart, model_marker(m), &inside, 5, model_color(m))?;
    }
    Ok(())
}

/// Grid lines and labels at 1, 2, 5 × 10ᵏ on both log10 axes.
fn log_grid(root: &Area, chart: &mut Chart2d, (lo, hi): (f64, f64)) -> Result<(), ChartError> {
    for t in log_ticks(10f64.powf(lo), 10f64.powf(hi)) {
        let v = t.log10();
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(v, lo), (v, hi)],
            LIGHT_GREY.stroke_width(1),
        )))?;
        chart.draw_series(std::iter::once(PathElement::new(
            vec![(lo, v), (hi, v)],
            LIGHT_GREY.stroke_width(1),
        )))?;
        let label = super::log_tick_label(t);
        let (px, py) = chart.backend_coord(&(v, lo));
        root.draw_text(
            &label,
            &font(12.0).pos(Pos::new(HPos::Center, VPos::Top)),
            (px, py + 6),
        )?;
        let (px, py) = chart.backend_coord(&(lo, v));
        root.draw_text(
            &label,
            &font(12.0).pos(Pos::new(HPos::Right, VPos::Center)),
            (px - 6, py),
        )?;
    }
    Ok(())
}

/// The deviations of model `m` as bars on their own scale.
fn deviation_panel(
    root: &Area,
    area: &Area,
    c: &FrequencyChart,
    m: usize,
    mode_labels: &[String],
    layout: &super::CategoryLayout,
) -> Result<(), ChartError> {
    let n = c.modes.len();
    let series = vec![NamedSeries::new(
        c.model_labels[m].clone(),
        c.deviations_pct(m),
    )];
    let (head, body) = area.split_vertically(24);
    let (w, _) = head.dim_in_pixel();
    head.draw_text(
        &format!("{}: deviation from the test", c.model_title(m)),
        &super::bold(13.0)
            .color(&model_color(m))
            .pos(Pos::new(HPos::Center, VPos::Top)),
        (w as i32 / 2, 6),
    )?;
    let devs: Vec<f64> = series[0].values.iter().copied().chain([0.0]).collect();
    let (lo, hi) = finite_range(&devs).unwrap_or((-1.0, 1.0));
    let limit = clip_limit(&devs);
    let (lo, hi) = (lo.max(-limit), hi.min(limit));
    // At least ±0.05 % shown, so that zero deviations do not fill the panel.
    let y_range = padded_range(lo.min(-0.05), hi.max(0.05), 0.08);
    let x_range = (-0.6, n as f64 - 0.4);
    let mut chart = ChartBuilder::on(&body)
        .margin_left(10)
        .margin_right(25)
        .margin_top(4)
        .x_label_area_size(layout.height)
        .y_label_area_size(64)
        .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)?;
    let yfmt = tick_label(y_range, 6);
    draw_category_mesh(&mut chart, "(f_model − f_test)/f_test (%)", &yfmt, 7)?;
    hline(&mut chart, 0.0, x_range, GREY.stroke_width(1))?;
    draw_grouped_bars(&mut chart, &series, &[model_color(m)], y_range)?;
    clipped_labels(root, &chart, &series[0].values, y_range)?;
    draw_category_labels(root, &chart, mode_labels, y_range.0, layout)?;
    Ok(())
}

/// The value of each clipped bar, written along it from its clipped end;
/// "unpaired" where the model has no partner mode.
fn clipped_labels(
    root: &Area,
    chart: &Chart2d,
    values: &[f64],
    y_range: (f64, f64),
) -> Result<(), ChartError> {
    for (i, &v) in values.iter().enumerate() {
        if v.is_nan() {
            let (px, py) = chart.backend_coord(&(i as f64, 0.0));
            root.draw_text(
                "unpaired",
                &font(10.0)
                    .color(&GREY)
                    .transform(FontTransform::Rotate270)
                    .pos(Pos::new(HPos::Left, VPos::Center)),
                (px, py - 4),
            )?;
        }
        if v.is_finite() && (v > y_range.1 || v < y_range.0) {
            let edge = if v > 0.0 { y_range.1 } else { y_range.0 };
            let (px, py) = chart.backend_coord(&(i as f64, edge));
            let (hpos, dy) = if v > 0.0 {
                (HPos::Right, 5)
            } else {
                (HPos::Left, -5)
            };
            root.draw_text(
                &format!("{} % (clipped)", clipped_value(v)),
                &font(10.0)
                    .color(&WHITE)
                    .transform(FontTransform::Rotate270)
                    .pos(Pos::new(hpos, VPos::Center)),
                (px, py + dy),
            )?;
        }
    }
    Ok(())
}

/// Deviation axis limit (%): the largest |value| unless it is an outlier
/// (beyond 4× the median |value| and 20 %), which is then clipped.
pub fn clip_limit(values: &[f64]) -> f64 {
    let mut a: Vec<f64> = values
        .iter()
        .filter(|v| v.is_finite())
        .map(|v| v.abs())
        .collect();
    a.sort_by(f64::total_cmp);
    let Some(&max) = a.last() else {
        return 1.0;
    };
    let median = a[a.len() / 2];
    let limit = (4.0 * median).max(20.0);
    if max > limit {
        limit
    } else {
        max.max(1e-9)
    }
}

fn clipped_value(v: f64) -> String {
    if v.abs() >= 1e4 {
        format!("{v:+.1e}")
    } else {
        format!("{v:+.0}")
    }
}
