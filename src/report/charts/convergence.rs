//! `convergence.svg`: each parameter p̄_j against iteration, and the mean and
//! minimum SFDAC on a second panel (the paper's Figs. 3, 5, 7, 11).

use plotters::prelude::*;

use super::{
    draw_legend, draw_markers, draw_mesh, draw_no_data, draw_title, finite_range, finite_runs,
    hline, integer_label, legend_height, padded_range, series_color, series_marker, svg,
    tick_label, title_height, vline, Axes, ChartError, LegendEntry, Swatch, GREY,
};

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
}

const WIDTH: u32 = 960;

/// Render the chart as SVG text.
pub fn render(c: &ConvergenceChart) -> Result<String, ChartError> {
    let n = c.iterations.len();
    if n == 0 {
        return svg((WIDTH, 400), |root| {
            draw_no_data(root, &c.title, "no iterations")
        });
    }
    let xs: Vec<f64> = c.iterations.iter().map(|&i| i as f64).collect();
    let (x0, x1) = finite_range(&xs).unwrap_or((0.0, 1.0));
    let x_range = (x0 - 0.3, x1.max(x0 + 1.0) + 0.3);
    let x_labels = ((x1 - x0) as usize + 2).min(14);

    let param_entries: Vec<LegendEntry> = c
        .parameter_names
        .iter()
        .enumerate()
        .map(|(j, name)| {
            LegendEntry::new(
                name.clone(),
                series_color(j),
                Swatch::LineMarker(series_marker(j)),
            )
        })
        .collect();
    let mut sfdac_entries = vec![
        LegendEntry::new(
            "mean SFDAC",
            RGBColor(0, 100, 200),
            Swatch::LineMarker(super::Marker::Circle),
        ),
        LegendEntry::new(
            "minimum SFDAC",
            RGBColor(213, 94, 0),
            Swatch::LineMarker(super::Marker::Triangle),
        ),
    ];
    if let Some(s) = c.selected {
        sfdac_entries.push(LegendEntry::new(
            format!("returned model (iteration {s})"),
            GREY,
            Swatch::VMark { dashed: true },
        ));
    }
    let w = WIDTH as i32 - 40;
    let top_legend = legend_height(&param_entries, w);
    let bottom_legend = legend_height(&sfdac_entries, w);
    let th = title_height(c.subtitle.is_some());
    let top_h = 380;
    let bottom_h = 280;
    let height = (th + top_legend + top_h + bottom_legend + bottom_h + 10) as u32;

    svg((WIDTH, height), |root| {
        draw_title(root, &c.title, c.subtitle.as_deref())?;
        let (_, rest) = root.split_vertically(th);
        let (legend_a, rest) = rest.split_vertically(top_legend);
        draw_legend(&legend_a.margin(0, 0, 20, 20), &param_entries)?;
        let (top, rest) = rest.split_vertically(top_h);
        let (legend_b, bottom) = rest.split_vertically(bottom_legend);
        draw_legend(&legend_b.margin(0, 0, 20, 20), &sfdac_entries)?;

        // Parameters.
        let all_p: Vec<f64> = c
            .parameters
            .iter()
            .flatten()
            .copied()
            .chain([0.0])
            .collect();
        let (plo, phi) = finite_range(&all_p).unwrap_or((-0.1, 0.1));
        let y_range = padded_range(plo, phi, 0.05);
        let mut chart = ChartBuilder::on(&top)
            .margin_left(10)
            .margin_right(25)
            .margin_top(6)
            .x_label_area_size(44)
            .y_label_area_size(78)
            .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)?;
        let yfmt = tick_label(y_range, 8);
        draw_mesh(
            &mut chart,
            &Axes {
                x_desc: "iteration n",
                y_desc: "relative parameter change p̄ (dimensionless)",
                x_fmt: &integer_label,
                y_fmt: &yfmt,
                x_labels,
                y_labels: 9,
            },
        )?;
        hline(&mut chart, 0.0, x_range, GREY.stroke_width(1))?;
        if let Some(s) = c.selected {
            vline(&mut chart, s as f64, y_range, GREY)?;
        }
        for j in 0..c.parameter_names.len() {
            let color = series_color(j);
            let pts: Vec<(f64, f64)> = xs
                .iter()
                .zip(&c.parameters)
                .map(|(&x, p)| (x, p.get(j).copied().unwrap_or(f64::NAN)))
                .collect();
            for run in finite_runs(pts.iter().copied()) {
                chart.draw_series(LineSeries::new(run, color.stroke_width(2)))?;
            }
            draw_markers(&mut chart, series_marker(j), &pts, 4, color)?;
        }

        // SFDAC.
        let y_range = (-1.05, 1.05);
        let mut chart = ChartBuilder::on(&bottom)
            .margin_left(10)
            .margin_right(25)
            .margin_top(6)
            .margin_bottom(6)
            .x_label_area_size(44)
            .y_label_area_size(78)
            .build_cartesian_2d(x_range.0..x_range.1, y_range.0..y_range.1)?;
        let yfmt = tick_label((-1.0, 1.0), 4);
        draw_mesh(
            &mut chart,
            &Axes {
                x_desc: "iteration n",
                y_desc: "SFDAC (dimensionless)",
                x_fmt: &integer_label,
                y_fmt: &yfmt,
                x_labels,
                y_labels: 9,
            },
        )?;
        hline(&mut chart, 1.0, x_range, GREY.stroke_width(1))?;
        if let Some(s) = c.selected {
            vline(&mut chart, s as f64, y_range, GREY)?;
        }
        for (k, (vals, entry)) in [&c.sfdac_mean, &c.sfdac_min]
            .into_iter()
            .zip(&sfdac_entries)
            .enumerate()
        {
            let pts: Vec<(f64, f64)> = xs
                .iter()
                .zip(vals)
                .map(|(&x, &v)| (x, v.clamp(-1.05, 1.05)))
                .collect();
            for run in finite_runs(pts.iter().copied()) {
                chart.draw_series(LineSeries::new(run, entry.color.stroke_width(2)))?;
            }
            let m = if k == 0 {
                super::Marker::Circle
            } else {
                super::Marker::Triangle
            };
            draw_markers(&mut chart, m, &pts, 4, entry.color)?;
        }
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::super::test_util::assert_svg;
    use super::*;

    fn sample() -> ConvergenceChart {
        ConvergenceChart {
            title: "Convergence of the updating parameters".into(),
            subtitle: Some("converged after 3 iterations".into()),
            parameter_names: vec!["EI_root".into(), "mass_tip".into(), "k_joint".into()],
            iterations: vec![0, 1, 2, 3],
            parameters: vec![
                vec![0.0, 0.0, 0.0],
                vec![0.3, -0.1, 0.05],
                vec![0.45, -0.12, f64::NAN],
                vec![0.5, -0.12, 0.02],
            ],
            sfdac_mean: vec![-0.35, 0.5, 0.85, 0.89],
            sfdac_min: vec![-0.96, 0.1, 0.6, 0.67],
            selected: Some(3),
        }
    }

    #[test]
    fn has_title_axes_legend_and_is_deterministic() {
        let c = sample();
        let a = render(&c).unwrap();
        assert_svg(&a);
        for t in [
            "Convergence of the updating parameters",
            "iteration n",
            "SFDAC (dimensionless)",
            "EI_root",
            "k_joint",
            "mean SFDAC",
            "minimum SFDAC",
            "returned model (iteration 3)",
        ] {
            assert!(a.contains(t), "missing {t}");
        }
        assert_eq!(a, render(&c).unwrap());
    }

    #[test]
    fn odd_data_does_not_panic() {
        let mut c = sample();
        c.iterations.clear();
        c.parameters.clear();
        assert!(render(&c).unwrap().contains("no iterations"));
        let mut c = sample();
        c.iterations = vec![0];
        c.parameters = vec![vec![f64::NAN, f64::INFINITY, 0.0]];
        c.sfdac_mean = vec![f64::NAN];
        c.sfdac_min = vec![];
        c.selected = None;
        assert_svg(&render(&c).unwrap());
        let mut c = sample();
        c.parameter_names = (0..40)
            .map(|i| format!("a rather long parameter name {i}"))
            .collect();
        assert_svg(&render(&c).unwrap());
    }
}
