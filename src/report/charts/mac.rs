//! `mac.svg`: MAC matrices (the test shapes that paired the resonances, as the
//! title names them, vs FE modes) as heat maps, one panel per model, with a shared colour scale;
//! paired cells are outlined.

use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

use super::{
    abbreviate, bold, draw_no_data, draw_title, fmt_fixed, font, text_width, title_height, Area,
    ChartError, DARK, GREY,
};

/// One MAC matrix: rows are the chart's rows (test resonances), columns the
/// modes of one model.
#[derive(Clone, Debug, PartialEq)]
pub struct MacPanel {
    /// e.g. "updated model".
    pub label: String,
    /// One label per column (e.g. the FE mode frequency in Hz).
    pub column_labels: Vec<String>,
    /// MAC[row][column] in [0, 1].
    pub values: Vec<Vec<f64>>,
    /// (row, column) cells to outline (the pairing).
    pub pairs: Vec<(usize, usize)>,
}

/// MAC heat maps sharing their rows.
#[derive(Clone, Debug, PartialEq)]
pub struct MacChart {
    pub title: String,
    pub subtitle: Option<String>,
    /// One label per row (e.g. the test resonance frequency in Hz).
    pub row_labels: Vec<String>,
    /// Description of the rows, e.g. "test resonance (Hz)".
    pub row_axis: String,
    /// Description of the columns, e.g. "FE mode (Hz)".
    pub column_axis: String,
    /// The colour scale's label, naming the test shapes, e.g. "MAC of the
    /// fitted mode shapes (dimensionless)".
    pub scale_label: String,
    pub panels: Vec<MacPanel>,
}

const WIDTH: u32 = 960;
const LABEL_PX: f64 = 12.0;
const BAR_W: i32 = 110;

/// Sequential colour map (light → dark blue) of v ∈ [0, 1].
pub fn mac_color(v: f64) -> RGBColor {
    const STOPS: [(f64, [f64; 3]); 5] = [
        (0.0, [247.0, 251.0, 255.0]),
        (0.25, [198.0, 219.0, 239.0]),
        (0.5, [107.0, 174.0, 214.0]),
        (0.75, [33.0, 113.0, 181.0]),
        (1.0, [8.0, 48.0, 107.0]),
    ];
    if !v.is_finite() {
        return RGBColor(220, 220, 220);
    }
    let v = v.clamp(0.0, 1.0);
    for w in STOPS.windows(2) {
        let (a, ca) = w[0];
        let (b, cb) = w[1];
        if v <= b {
            let t = (v - a) / (b - a);
            let c = |k: usize| (ca[k] + t * (cb[k] - ca[k])).round() as u8;
            return RGBColor(c(0), c(1), c(2));
        }
    }
    RGBColor(8, 48, 107)
}

struct Geometry {
    row_label_w: i32,
    cell_w: i32,
    cell_h: i32,
    rotated: bool,
    col_label_h: i32,
    panel_w: i32,
}

fn geometry(c: &MacChart) -> Geometry {
    let np = c.panels.len().max(1) as i32;
    let ncols = c
        .panels
        .iter()
        .map(|p| p.column_labels.len())
        .max()
        .unwrap_or(1)
        .max(1) as i32;
    let nrows = c.row_labels.len().max(1) as i32;
    let row_label_w = c
        .row_labels
        .iter()
        .map(|l| text_width(l, LABEL_PX))
        .fold(0.0, f64::max)
        .min(120.0) as i32
        + 34;
    let panel_w = (WIDTH as i32 - BAR_W - 20) / np;
    let cell_w = ((panel_w - row_label_w - 16) / ncols).clamp(6, 60);
    // Rows get their own height (≈ 300 px in all, 14–40 px each): narrow
    // columns must not squash them.
    let cell_h = (300 / nrows).clamp(14, 40).max(cell_w.min(40));
    let widest = c
        .panels
        .iter()
        .flat_map(|p| p.column_labels.iter())
        .map(|l| text_width(l, LABEL_PX))
        .fold(0.0, f64::max);
    let rotated = widest + 4.0 > cell_w as f64;
    let col_label_h = if rotated {
        widest.min(100.0) as i32 + 12
    } else {
        22
    };
    Geometry {
        row_label_w,
        cell_w,
        cell_h,
        rotated,
        col_label_h,
        panel_w,
    }
}

/// Render the chart as SVG text.
pub fn render(c: &MacChart) -> Result<String, ChartError> {
    let nrows = c.row_labels.len();
    if nrows == 0 || c.panels.is_empty() || c.panels.iter().all(|p| p.column_labels.is_empty()) {
        return super::svg((WIDTH, 400), |root| {
            draw_no_data(root, &c.title, "no test resonances or no FE modes")
        });
    }
    let g = geometry(c);
    let th = title_height(c.subtitle.is_some());
    let grid_top = th + 30;
    let grid_h = g.cell_h * nrows as i32;
    let height = (grid_top + grid_h.max(120) + g.col_label_h + 40) as u32;
    super::svg((WIDTH, height), |root| {
        draw_title(root, &c.title, c.subtitle.as_deref())?;
        for (k, p) in c.panels.iter().enumerate() {
            draw_panel(root, c, p, &g, 10 + k as i32 * g.panel_w, grid_top)?;
        }
        draw_color_bar(
            root,
            &c.scale_label,
            WIDTH as i32 - BAR_W + 10,
            grid_top,
            grid_h.max(120),
        )?;
        Ok(())
    })
}

fn draw_panel(
    root: &Area,
    c: &MacChart,
    p: &MacPanel,
    g: &Geometry,
    x0: i32,
    y0: i32,
) -> Result<(), ChartError> {
    let gx = x0 + g.row_label_w;
    let ncols = p.column_labels.len() as i32;
    let nrows = c.row_labels.len() as i32;
    let grid_w = g.cell_w * ncols;
    let grid_h = g.cell_h * nrows;
    let title = abbreviate(&p.label, 14.0, g.panel_w as f64 - 20.0);
    root.draw_text(
        &title,
        &bold(14.0).pos(Pos::new(HPos::Center, VPos::Bottom)),
        (gx + grid_w / 2, y0 - 8),
    )?;
    let show_values = g.cell_w >= 34 && g.cell_h >= 18;
    for r in 0..nrows {
        for col in 0..ncols {
            let v = p
                .values
                .get(r as usize)
                .and_then(|row| row.get(col as usize))
                .copied()
                .unwrap_or(f64::NAN);
            let (x, y) = (gx + col * g.cell_w, y0 + r * g.cell_h);
            root.draw(&Rectangle::new(
                [(x, y), (x + g.cell_w, y + g.cell_h)],
                mac_color(v).filled(),
            ))?;
            if show_values && v.is_finite() {
                let color = if v > 0.55 { WHITE } else { DARK };
                root.draw_text(
                    &fmt_fixed(v, 2),
                    &font(11.0)
                        .color(&color)
                        .pos(Pos::new(HPos::Center, VPos::Center)),
                    (x + g.cell_w / 2, y + g.cell_h / 2),
                )?;
            }
        }
    }
    root.draw(&Rectangle::new(
        [(gx, y0), (gx + grid_w, y0 + grid_h)],
        GREY.stroke_width(1),
    ))?;
    for &(r, col) in &p.pairs {
        if (r as i32) < nrows && (col as i32) < ncols {
            let (x, y) = (gx + col as i32 * g.cell_w, y0 + r as i32 * g.cell_h);
            root.draw(&Rectangle::new(
                [(x + 1, y + 1), (x + g.cell_w - 1, y + g.cell_h - 1)],
                RGBColor(213, 94, 0).stroke_width(2),
            ))?;
        }
    }
    // Row labels and description.
    for (r, l) in c.row_labels.iter().enumerate() {
        let l = abbreviate(l, LABEL_PX, 120.0);
        let y = y0 + r as i32 * g.cell_h + g.cell_h / 2;
        root.draw_text(
            &l,
            &font(LABEL_PX).pos(Pos::new(HPos::Right, VPos::Center)),
            (gx - 5, y),
        )?;
    }
    let desc = abbreviate(&c.row_axis, 13.0, grid_h.max(60) as f64);
    root.draw_text(
        &desc,
        &font(13.0)
            .transform(FontTransform::Rotate270)
            .pos(Pos::new(HPos::Center, VPos::Top)),
        (x0 + 2, y0 + grid_h / 2),
    )?;
    // Column labels and description.
    for (col, l) in p.column_labels.iter().enumerate() {
        let x = gx + col as i32 * g.cell_w + g.cell_w / 2;
        let y = y0 + grid_h + 4;
        if g.rotated {
            let l = abbreviate(l, LABEL_PX, 100.0);
            root.draw_text(
                &l,
                &font(LABEL_PX)
                    .transform(FontTransform::Rotate270)
                    .pos(Pos::new(HPos::Right, VPos::Center)),
                (x, y),
            )?;
        } else {
            root.draw_text(
                l,
                &font(LABEL_PX).pos(Pos::new(HPos::Center, VPos::Top)),
                (x, y),
            )?;
        }
    }
    let desc = abbreviate(&c.column_axis, 13.0, (g.panel_w - g.row_label_w) as f64);
    root.draw_text(
        &desc,
        &font(13.0).pos(Pos::new(HPos::Center, VPos::Top)),
        (gx + grid_w / 2, y0 + grid_h + g.col_label_h + 6),
    )?;
    Ok(())
}

fn draw_color_bar(root: &Area, label: &str, x: i32, y0: i32, h: i32) -> Result<(), ChartError> {
    let w = 18;
    let steps = 50;
    for i in 0..steps {
        let v0 = i as f64 / steps as f64;
        let ya = y0 + h - ((i + 1) * h) / steps;
        let yb = y0 + h - (i * h) / steps;
        root.draw(&Rectangle::new(
            [(x, ya), (x + w, yb)],
            mac_color(v0 + 0.5 / steps as f64).filled(),
        ))?;
    }
    root.draw(&Rectangle::new(
        [(x, y0), (x + w, y0 + h)],
        GREY.stroke_width(1),
    ))?;
    for k in 0..=5 {
        let v = k as f64 / 5.0;
        let y = y0 + h - (v * h as f64).round() as i32;
        root.draw(&PathElement::new(
            vec![(x + w, y), (x + w + 4, y)],
            GREY.stroke_width(1),
        ))?;
        root.draw_text(
            &fmt_fixed(v, 1),
            &font(11.0).pos(Pos::new(HPos::Left, VPos::Center)),
            (x + w + 7, y),
        )?;
    }
    root.draw_text(
        label,
        &font(13.0)
            .transform(FontTransform::Rotate270)
            .pos(Pos::new(HPos::Center, VPos::Top)),
        (x + w + 40, y0 + h / 2),
    )?;
    Ok(())
}
