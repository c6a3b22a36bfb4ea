//! `stabilisation.svg`: the poles of every model order over the band
//! (x: frequency, y: model order), marked by their stability against the
//! order below, the selected modes ringed on their clusters' poles and
//! marked by a dashed line, over the weighted summed FRF (log scale, right
//! in the chart, drawn in grey across the order axis).

use plotters::prelude::*;

use crate::identification::{Diagram, Identification, Stability};
use crate::report::charts::{
    draw_legend, draw_mesh, draw_title, legend_height, svg, tick_label, title_height, Axes,
    Chart2d, ChartError, LegendEntry, Marker, Swatch, DARK, GREY, LIGHT_GREY,
};

const WIDTH: u32 = 960;
const HEIGHT: u32 = 600;

fn style_of(s: Stability) -> (RGBColor, Marker, i32, &'static str) {
    match s {
        Stability::Stable => (DARK, Marker::Circle, 4, "stable: frequency, damping, shape"),
        Stability::Damping => (
            RGBColor(0, 100, 200),
            Marker::Square,
            3,
            "stable: frequency, damping",
        ),
        Stability::Vector => (
            RGBColor(0, 158, 115),
            Marker::Triangle,
            3,
            "stable: frequency, shape",
        ),
        Stability::Frequency => (
            RGBColor(230, 120, 0),
            Marker::Triangle,
            3,
            "stable: frequency",
        ),
        Stability::New => (GREY, Marker::Cross, 3, "new / unstable"),
        Stability::Unphysical => (LIGHT_GREY, Marker::Cross, 2, "unphysical damping"),
    }
}

const ORDERED: [Stability; 6] = [
    Stability::Stable,
    Stability::Damping,
    Stability::Vector,
    Stability::Frequency,
    Stability::New,
    Stability::Unphysical,
];

/// The summed FRF, log-scaled onto [0, ymax], at most 2000 points (the
/// largest of each run of lines: peaks survive).
fn draw_indicator(chart: &mut Chart2d, d: &Diagram, ymax: f64) -> Result<(), ChartError> {
    let step = d.indicator.len().div_ceil(2000).max(1);
    let freqs: Vec<f64> = d.frequencies_hz.chunks(step).map(|c| c[0]).collect();
    let logs: Vec<f64> = d
        .indicator
        .chunks(step)
        .map(|c| c.iter().fold(1e-300f64, |a, &b| a.max(b)).log10())
        .collect();
    let (lo, hi) = logs
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| {
            (a.min(v), b.max(v))
        });
    if hi > lo {
        let pts = freqs
            .iter()
            .zip(&logs)
            .map(|(&f, &l)| (f, 0.02 * ymax + 0.96 * ymax * (l - lo) / (hi - lo)));
        chart.draw_series(std::iter::once(PathElement::new(
            pts.collect::<Vec<_>>(),
            GREY.stroke_width(1),
        )))?;
    }
    Ok(())
}

/// The chart's SVG text.
pub fn render(id: &Identification, title: &str) -> Result<String, ChartError> {
    let d = &id.diagram;
    let ring = RGBColor(213, 94, 0);
    let mut legend: Vec<LegendEntry> = ORDERED
        .iter()
        .map(|&s| {
            let (c, m, _, label) = style_of(s);
            LegendEntry::new(label, c, Swatch::Marker(m))
        })
        .collect();
    legend.push(LegendEntry::new(
        "selected mode",
        ring,
        Swatch::VMark { dashed: true },
    ));
    legend.push(LegendEntry::new(
        "summed |FRF| (log)",
        GREY,
        Swatch::Line { width: 1 },
    ));
    let subtitle = format!(
        "{} modes selected of {} poles, orders 1–{}",
        id.modes.len(),
        d.poles.len(),
        d.max_order
    );
    svg((WIDTH, HEIGHT), |root| {
        let th = title_height(true);
        let lh = legend_height(&legend, WIDTH as i32 - 20);
        let (top, rest) = root.split_vertically(th);
        draw_title(&top, title, Some(&subtitle))?;
        let (plot, bottom) = rest.split_vertically(HEIGHT as i32 - th - lh);
        let f0 = d.frequencies_hz.first().copied().unwrap_or(0.0);
        let f1 = d
            .frequencies_hz
            .last()
            .copied()
            .unwrap_or(1.0)
            .max(f0 + 1e-9);
        let ymax = d.max_order as f64 + 1.0;
        let mut chart = ChartBuilder::on(&plot)
            .margin(10)
            .x_label_area_size(42)
            .y_label_area_size(56)
            .build_cartesian_2d(f0..f1, 0.0..ymax)?;
        let xfmt = tick_label((f0, f1), 10);
        let yfmt = |v: &f64| format!("{}", v.round() as i64);
        draw_mesh(
            &mut chart,
            &Axes {
                x_desc: "frequency (Hz)",
                y_desc: "model order",
                x_fmt: &xfmt,
                y_fmt: &yfmt,
                x_labels: 10,
                y_labels: 8,
            },
        )?;
        draw_indicator(&mut chart, d, ymax)?;
        for m in &id.modes {
            chart.draw_series(std::iter::once(plotters::element::DashedPathElement::new(
                vec![(m.frequency_hz, 0.0), (m.frequency_hz, ymax)],
                4,
                3,
                ring.stroke_width(1),
            )))?;
        }
        for &s in ORDERED.iter().rev() {
            let (c, m, r, _) = style_of(s);
            let pts = d
                .poles
                .iter()
                .filter(|p| p.stability == s)
                .map(|p| (p.frequency_hz, p.order as f64));
            match m {
                Marker::Circle => {
                    chart.draw_series(pts.map(|p| Circle::new(p, r, c.filled())))?;
                }
                Marker::Square => {
                    chart.draw_series(pts.map(|p| {
                        EmptyElement::at(p) + Rectangle::new([(-r, -r), (r, r)], c.stroke_width(1))
                    }))?;
                }
                Marker::Triangle => {
                    chart.draw_series(
                        pts.map(|p| TriangleMarker::new(p, r + 1, c.stroke_width(1))),
                    )?;
                }
                Marker::Cross => {
                    chart.draw_series(pts.map(|p| Cross::new(p, r, c.stroke_width(1))))?;
                }
            }
        }
        for m in &id.modes {
            chart.draw_series(m.cluster.iter().map(|&k| {
                let p = &d.poles[k];
                Circle::new((p.frequency_hz, p.order as f64), 7, ring.stroke_width(1))
            }))?;
        }
        draw_legend(&bottom, &legend)?;
        Ok(())
    })
}
