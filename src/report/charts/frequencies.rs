//! `frequencies.svg`: test vs model resonance frequencies (the paper's
//! Table 7). Top panel: the frequencies (Hz) per test resonance; bottom panel:
//! the deviation (f_model − f_test)/f_test in % as grouped bars.

use plotters::prelude::*;

use super::font;
use super::{
    category_layout, comparison_color, draw_category_labels, draw_category_mesh, draw_grouped_bars,
    draw_legend, draw_markers, draw_no_data, draw_title, draw_x_desc, finite_range, fmt_fixed,
    hline, legend_height, padded_range, tick_label, title_height, ChartError, LegendEntry, Marker,
    NamedSeries, Swatch, GREY,
};
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// One test resonance and the frequency of its partner mode in each model.
#[derive(Clone, Debug, PartialEq)]
pub struct ModeFrequencies {
    /// Short label, e.g. "1".
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
}

/// Render the chart as SVG text.
pub fn render(c: &FrequencyChart) -> Result<String, ChartError> {
    let n = c.modes.len();
    if n == 0 {
        return super::svg((WIDTH, 400), |root| {
            draw_no_data(root, &c.title, "no test resonances")
        });
    }
    let model_color = |m: usize| comparison_color(m + 1);
    let model_marker = |m: usize| {
        if m % 2 == 0 {
            Marker::Circle
        } else {
            Marker::Triangle
        }
    };
    let mut entries = vec![LegendEntry::new(
        c.reference_label.clone(),
        comparison_color(0),
        Swatch::Marker(Marker::Cross),
    )];
    for (m, l) in c.model_labels.iter().enumerate() {
        let label = match c.mean_abs_deviation_pct(m) {
            Some(d) => format!("{l} (mean |Δf| {} %)", fmt_fixed(d, 2)),
            None => l.clone(),
        };
        entries.push(LegendEntry::new(
            label,
            model_color(m),
            Swatch::Marker(model_marker(m)),
        ));
    }
    let mode_labels: Vec<String> = c.modes.iter().map(|r| r.label.clone()).collect();
    let hz_labels: Vec<String> =
        super::sfdac::frequency_labels(&c.modes.iter().map(|r| r.reference_hz).collect::<Vec<_>>());
    let plot_w = WIDTH as f64 - 120.0;
    let top_layout = category_layout(&mode_labels, plot_w / n as f64);
    let bottom_layout = category_layout(&hz_labels, plot_w / n as f64);
    let lh = legend_height(&entries, WIDTH as i32 - 40);
    let th = title_height(c.subtitle.is_some());
    let (top_h, bottom_h) = (300 + top_layout.height, 300 + bottom_layout.height);
    let height = (th + lh + top_h + bottom_h + 10) as u32;

    super::svg((WIDTH, height), |root| {
        draw_title(root, &c.title, c.subtitle.as_deref())?;
        let (_, rest) = root.split_vertically(th);
        let (legend_a, rest) = rest.split_vertically(lh);
        draw_legend(&legend_a.margin(0, 0, 20, 20), &entries)?;
        let (top, bottom) = rest.split_vertically(top_h);
        let x_range = (-0.6, n as f64 - 0.4);

        // Frequencies.
        let all: Vec<f64> = c
            .modes
            .iter()
            .flat_map(|r| {
                std::iter::once(r.reference_hz).chain(r.models_hz.iter().flatten().copied())
            })
            .collect();
        let (lo, hi) = finite_range(&all).unwrap_or((0.0, 1.0));
        // A far-off partner (a poor pairing) would squash the others: clip.
        let ref_hi = finite_range(c.modes.iter().map(|r| &r.reference_hz)).map_or(hi, |r| r.1);
        let hi = if ref_hi > 0.0 {
            hi.min(1.5 * ref_hi)
        } else {
            hi
        };
        let y_range = padded_range(lo.min(0.0), hi, 0.05);
        let y_range = (
            if lo >= 0.0 {
                y_range.0.max(0.0)
            } else {
                y_range.0
            },
            y_range.1,
        );
        let mut chart = ChartBuilder::on(&top)
            .margin_left(10)
            .margin_right(25)
            .margin_top(6)
            .x_label_area_size(top_layout.height)
            .y_label_area_size(78)
            .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)?;
        let yfmt = tick_label(y_range, 8);
        draw_category_mesh(&mut chart, "frequency (Hz)", &yfmt, 9)?;
        let reference: Vec<(f64, f64)> = c
            .modes
            .iter()
            .enumerate()
            .map(|(i, r)| (i as f64, r.reference_hz))
            .collect();
        draw_markers(
            &mut chart,
            Marker::Cross,
            &reference,
            6,
            comparison_color(0),
        )?;
        for m in 0..c.model_labels.len() {
            let dx = 0.12 * (m as f64 + 1.0) * if m % 2 == 0 { -1.0 } else { 1.0 };
            let pts: Vec<(f64, f64)> = c
                .modes
                .iter()
                .enumerate()
                .filter_map(|(i, r)| Some((i as f64 + dx, r.models_hz.get(m).copied().flatten()?)))
                .collect();
            let inside: Vec<(f64, f64)> = pts.iter().map(|&(x, f)| (x, f.min(y_range.1))).collect();
            draw_markers(&mut chart, model_marker(m), &inside, 5, model_color(m))?;
            for &(x, f) in pts.iter().filter(|p| p.1 > y_range.1) {
                let (px, py) = chart.backend_coord(&(x, y_range.1));
                root.draw_text(
                    &format!("{} Hz ↑", fmt_fixed(f, 1)),
                    &font(10.0)
                        .color(&model_color(m))
                        .pos(Pos::new(HPos::Center, VPos::Top)),
                    (px, py + 8 + 12 * m as i32),
                )?;
            }
        }
        draw_category_labels(root, &chart, &mode_labels, y_range.0, &top_layout)?;
        let (_, py) = chart.plotting_area().get_pixel_range();
        draw_x_desc(
            root,
            &chart,
            "test resonance",
            py.end + top_layout.height - 4,
        )?;

        // Deviations.
        let series: Vec<NamedSeries> = c
            .model_labels
            .iter()
            .enumerate()
            .map(|(m, l)| NamedSeries::new(l.clone(), c.deviations_pct(m)))
            .collect();
        let devs: Vec<f64> = series
            .iter()
            .flat_map(|s| s.values.iter().copied())
            .chain([0.0])
            .collect();
        let (lo, hi) = finite_range(&devs).unwrap_or((-1.0, 1.0));
        let limit = clip_limit(&devs);
        let (lo, hi) = (lo.max(-limit), hi.min(limit));
        let y_range = padded_range(lo, hi.max(lo + 0.5), 0.08);
        let mut chart = ChartBuilder::on(&bottom)
            .margin_left(10)
            .margin_right(25)
            .margin_top(10)
            .x_label_area_size(bottom_layout.height)
            .y_label_area_size(78)
            .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)?;
        let yfmt = tick_label(y_range, 8);
        draw_category_mesh(
            &mut chart,
            "deviation (f_model − f_test)/f_test (%)",
            &yfmt,
            9,
        )?;
        hline(&mut chart, 0.0, x_range, GREY.stroke_width(1))?;
        let colors: Vec<RGBColor> = (0..series.len()).map(model_color).collect();
        draw_grouped_bars(&mut chart, &series, &colors, y_range)?;
        // Value of each clipped bar, at its end.
        let k = series.len().max(1) as f64;
        for (m, ser) in series.iter().enumerate() {
            for (i, &v) in ser.values.iter().enumerate() {
                if v.is_finite() && (v > y_range.1 || v < y_range.0) {
                    let x = i as f64 - 0.4 + (m as f64 + 0.5) * 0.8 / k;
                    let edge = if v > 0.0 { y_range.1 } else { y_range.0 };
                    let (px, py) = chart.backend_coord(&(x, edge));
                    // Written along the bar, in white, from its clipped end.
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
        }
        draw_category_labels(root, &chart, &hz_labels, y_range.0, &bottom_layout)?;
        draw_x_desc(
            root,
            &chart,
            "test resonance frequency (Hz)",
            height as i32 - 10,
        )?;
        Ok(())
    })
}

/// Deviation axis limit (%): the largest |value| unless it is an outlier
/// (beyond 4× the median |value| and 20 %), which is then clipped.
fn clip_limit(values: &[f64]) -> f64 {
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

#[cfg(test)]
mod tests {
    use super::super::test_util::assert_svg;
    use super::*;

    fn sample() -> FrequencyChart {
        let test = [6.376, 16.104, 33.125, 33.531, 35.647];
        FrequencyChart {
            title: "Resonance frequencies: test vs models".into(),
            subtitle: None,
            reference_label: "test".into(),
            model_labels: vec!["initial model".into(), "updated model".into()],
            modes: test
                .iter()
                .enumerate()
                .map(|(i, &f)| ModeFrequencies {
                    label: format!("{}", i + 1),
                    reference_hz: f,
                    models_hz: vec![Some(f * 1.06), if i == 2 { None } else { Some(f * 0.99) }],
                })
                .collect(),
        }
    }

    #[test]
    fn has_title_axes_legend_and_is_deterministic() {
        let c = sample();
        let a = render(&c).unwrap();
        assert_svg(&a);
        for t in [
            "Resonance frequencies: test vs models",
            "frequency (Hz)",
            "(%)",
            "test resonance frequency (Hz)",
            "initial model (mean |Δf| 6.00 %)",
            "updated model",
            "33.5",
        ] {
            assert!(a.contains(t), "missing {t}");
        }
        assert_eq!(a, render(&c).unwrap());
        assert!((c.mean_abs_deviation_pct(1).unwrap() - 1.0).abs() < 1e-9);
    }

    #[test]
    fn outliers_are_clipped_and_labelled() {
        let mut c = sample();
        c.modes[0].reference_hz = 0.1;
        c.modes[0].models_hz = vec![Some(645.0), Some(645.0)];
        let a = render(&c).unwrap();
        assert_svg(&a);
        assert!(a.contains("+6.4e5 % (clipped)"), "clipped bar label");
        assert!(a.contains("645.0 Hz ↑"));
        assert_eq!(clip_limit(&[1.0, -2.0, 3.0]), 3.0);
        assert_eq!(clip_limit(&[1.0, 2.0, 5000.0]), 20.0);
        assert_eq!(clip_limit(&[f64::NAN]), 1.0);
    }

    #[test]
    fn odd_data_does_not_panic() {
        let mut c = sample();
        c.modes.clear();
        assert!(render(&c).unwrap().contains("no test resonances"));
        let mut c = sample();
        c.modes[0].reference_hz = 0.0;
        c.modes[1].reference_hz = f64::NAN;
        c.modes[2].models_hz = vec![];
        assert_svg(&render(&c).unwrap());
    }
}
