//! Geometry datasets: nodes (15, 2411), coordinate systems (18, 2420) and
//! trace lines (82).
//!
//! - 15, one line per node `4I10,1P3E13.5`: label, definition CS,
//!   displacement CS, color, x, y, z.
//! - 2411, two lines per node: `4I10` label, export CS, displacement CS,
//!   color; `1P3D25.16` x, y, z.
//! - 18, per system: `5I10` label, type (0 cartesian, 1 cylindrical,
//!   2 spherical), reference CS, color, definition method; `20A1` name;
//!   `1P6E13.5` origin and a point on +x; `1P3E13.5` a point in the +xz plane.
//! - 2420: `1I10` part UID; `40A2` part name; per system: `3I10` label, type,
//!   color; `40A2` name; 4 × `1P3D25.16` transformation rows (3 axes, origin).
//! - 82: `3I10` trace line number, node count, color; `80A1` id; `8I10`
//!   nodes (0 = move without drawing).

use super::text::{self, Line};

/// A node of dataset 15 or 2411.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub label: i64,
    /// Definition (15) or export (2411) coordinate system.
    pub definition_cs: i64,
    pub displacement_cs: i64,
    pub color: i64,
    pub coordinates: [f64; 3],
}

/// How a coordinate system is given.
#[derive(Clone, Debug, PartialEq)]
pub enum CsDefinition {
    /// Dataset 18: origin, a point on +x, a point in the +xz plane.
    Points {
        origin: [f64; 3],
        x_axis_point: [f64; 3],
        xz_plane_point: [f64; 3],
    },
    /// Dataset 2420: rows 1–3 the axes, row 4 the origin.
    Matrix([[f64; 3]; 4]),
}

/// A coordinate system of dataset 18 or 2420.
#[derive(Clone, Debug, PartialEq)]
pub struct CoordinateSystem {
    pub label: i64,
    /// 0 cartesian, 1 cylindrical, 2 spherical.
    pub cs_type: i64,
    /// Dataset 18 only (0 otherwise).
    pub reference_cs: i64,
    pub color: i64,
    pub name: String,
    pub definition: CsDefinition,
}

/// Dataset 2420 part the systems belong to.
#[derive(Clone, Debug, PartialEq)]
pub struct Part {
    pub uid: i64,
    pub name: String,
}

/// Dataset 82: one trace line.
#[derive(Clone, Debug, PartialEq)]
pub struct TraceLine {
    pub number: i64,
    pub color: i64,
    pub id: String,
    /// Node labels in drawing order; 0 lifts the pen.
    pub nodes: Vec<i64>,
}

pub(crate) type Failure = (usize, String);

fn ints(
    lines: &[Line<'_>],
    k: usize,
    columns: &[(usize, usize)],
    what: &str,
) -> Result<Vec<i64>, Failure> {
    let line = lines.get(k).ok_or((
        k.saturating_sub(1),
        format!("dataset ends early: expected {what}"),
    ))?;
    text::ints_by_columns_or_tokens(line.text, columns).ok_or((
        k,
        format!("expected {what}, found '{}'", text::excerpt(line.text)),
    ))
}

fn reals(
    lines: &[Line<'_>],
    k: usize,
    width: usize,
    count: usize,
    what: &str,
) -> Result<Vec<f64>, Failure> {
    let line = lines.get(k).ok_or((
        k.saturating_sub(1),
        format!("dataset ends early: expected {what}"),
    ))?;
    let mut v = Vec::with_capacity(count);
    text::reals_by_width_or_tokens(line.text, width, &mut v)
        .map_err(|m| (k, format!("{what}: {m}")))?;
    if v.len() < count {
        return Err((
            k,
            format!("expected {count} values ({what}), found {}", v.len()),
        ));
    }
    if let Some((i, x)) = text::first_non_finite(&v) {
        return Err((
            k,
            format!("{what}: value {} is {x}; expected a finite number", i + 1),
        ));
    }
    Ok(v)
}

const I10X4: [(usize, usize); 4] = [(0, 10), (10, 20), (20, 30), (30, 40)];

/// Dataset 15.
pub(crate) fn nodes15(lines: &[Line<'_>]) -> Result<Vec<Node>, Failure> {
    let mut out = Vec::with_capacity(lines.len());
    for (k, line) in lines.iter().enumerate() {
        if text::is_blank_line(line.text) {
            continue;
        }
        let what = "node label, definition CS, displacement CS, color (4I10) and x, y, z (3E13.5)";
        let parsed = (|| {
            let i: Vec<i64> = I10X4
                .iter()
                .map(|&(s, e)| text::parse_int(text::column(line.text, s, e)))
                .collect::<Option<_>>()?;
            let mut v = Vec::with_capacity(3);
            text::reals_by_width_or_tokens(text::column_rest(line.text, 40), 13, &mut v).ok()?;
            Some((i, v))
        })()
        .or_else(|| {
            let toks: Vec<&[u8]> = text::tokens(line.text).collect();
            if toks.len() != 7 {
                return None;
            }
            let i: Vec<i64> = toks[..4]
                .iter()
                .map(|t| text::parse_int(t))
                .collect::<Option<_>>()?;
            let v: Vec<f64> = toks[4..]
                .iter()
                .map(|t| text::parse_real(t))
                .collect::<Option<_>>()?;
            Some((i, v))
        });
        let Some((i, v)) = parsed.filter(|(_, v)| v.len() == 3) else {
            return Err((
                k,
                format!("expected {what}, found '{}'", text::excerpt(line.text)),
            ));
        };
        if v.iter().any(|x| !x.is_finite()) {
            return Err((k, "node coordinates must be finite".into()));
        }
        out.push(Node {
            label: i[0],
            definition_cs: i[1],
            displacement_cs: i[2],
            color: i[3],
            coordinates: [v[0], v[1], v[2]],
        });
    }
    Ok(out)
}

/// Dataset 2411.
pub(crate) fn nodes2411(lines: &[Line<'_>]) -> Result<Vec<Node>, Failure> {
    let mut out = Vec::with_capacity(lines.len() / 2);
    let mut k = 0;
    while k < lines.len() {
        if text::is_blank_line(lines[k].text) {
            k += 1;
            continue;
        }
        let i = ints(
            lines,
            k,
            &I10X4,
            "node label, export CS, displacement CS, color (4I10)",
        )?;
        let v = reals(lines, k + 1, 25, 3, "node coordinates (3D25.16)")?;
        out.push(Node {
            label: i[0],
            definition_cs: i[1],
            displacement_cs: i[2],
            color: i[3],
            coordinates: [v[0], v[1], v[2]],
        });
        k += 2;
    }
    Ok(out)
}

/// Dataset 18.
pub(crate) fn systems18(lines: &[Line<'_>]) -> Result<Vec<CoordinateSystem>, Failure> {
    let mut out = Vec::new();
    let mut k = 0;
    while k < lines.len() {
        if text::is_blank_line(lines[k].text) {
            k += 1;
            continue;
        }
        let cols = [(0, 10), (10, 20), (20, 30), (30, 40), (40, 50)];
        let i = ints(
            lines,
            k,
            &cols,
            "CS label, type, reference CS, color, definition method (5I10)",
        )?;
        let name = lines
            .get(k + 1)
            .map(|l| text::text_field(l.text))
            .unwrap_or_default();
        // Records 3 and 4: 9 reals over one or more lines.
        let mut v = Vec::with_capacity(9);
        let mut j = k + 2;
        while v.len() < 9 {
            let more = reals(
                lines,
                j,
                13,
                1,
                "CS origin and axis points (1P6E13.5, 1P3E13.5)",
            )?;
            v.extend(more);
            j += 1;
        }
        let p = |o: usize| [v[o], v[o + 1], v[o + 2]];
        out.push(CoordinateSystem {
            label: i[0],
            cs_type: i[1],
            reference_cs: i[2],
            color: i[3],
            name,
            definition: CsDefinition::Points {
                origin: p(0),
                x_axis_point: p(3),
                xz_plane_point: p(6),
            },
        });
        k = j;
    }
    Ok(out)
}

/// Dataset 2420.
pub(crate) fn systems2420(lines: &[Line<'_>]) -> Result<(Part, Vec<CoordinateSystem>), Failure> {
    let uid = ints(lines, 0, &[(0, 10)], "part UID (I10)")?[0];
    let name = lines
        .get(1)
        .map(|l| text::text_field(l.text))
        .unwrap_or_default();
    let mut out = Vec::new();
    let mut k = 2;
    while k < lines.len() {
        if text::is_blank_line(lines[k].text) {
            k += 1;
            continue;
        }
        let i = ints(
            lines,
            k,
            &[(0, 10), (10, 20), (20, 30)],
            "CS label, type, color (3I10)",
        )?;
        let cs_name = lines
            .get(k + 1)
            .map(|l| text::text_field(l.text))
            .unwrap_or_default();
        let mut rows = [[0.0; 3]; 4];
        for (r, row) in rows.iter_mut().enumerate() {
            let v = reals(lines, k + 2 + r, 25, 3, "transformation row (1P3D25.16)")?;
            *row = [v[0], v[1], v[2]];
        }
        out.push(CoordinateSystem {
            label: i[0],
            cs_type: i[1],
            reference_cs: 0,
            color: i[2],
            name: cs_name,
            definition: CsDefinition::Matrix(rows),
        });
        k += 6;
    }
    Ok((Part { uid, name }, out))
}

/// Dataset 82.
pub(crate) fn trace_line(lines: &[Line<'_>]) -> Result<TraceLine, Failure> {
    let head = ints(
        lines,
        0,
        &[(0, 10), (10, 20), (20, 30)],
        "trace line number, node count, color (3I10)",
    )?;
    let count = usize::try_from(head[1])
        .map_err(|_| (0, format!("node count must be >= 0, found {}", head[1])))?;
    let id = lines
        .get(1)
        .map(|l| text::text_field(l.text))
        .unwrap_or_default();
    let mut nodes = Vec::with_capacity(count.min(lines.len() * 8));
    let mut k = 2;
    while nodes.len() < count {
        let line = lines.get(k).ok_or((
            k.saturating_sub(1),
            format!(
                "trace line declares {count} nodes, the dataset holds {}",
                nodes.len()
            ),
        ))?;
        for t in text::tokens(line.text) {
            if nodes.len() == count {
                break;
            }
            nodes.push(text::parse_int(t).ok_or((
                k,
                format!("expected a node label (8I10), found '{}'", text::decode(t)),
            ))?);
        }
        k += 1;
    }
    Ok(TraceLine {
        number: head[0],
        color: head[2],
        id,
        nodes,
    })
}
