//! Datasets other than 58: typed content, dispatch and one-line summaries.
//!
//! - 151 (header), 7 or 8 `80A1` records: model name, description, program
//!   that created the database, its dates, program that wrote the file, date.
//! - 55 (data at nodes): records 1–5 `80A1` ids; 6 `6I10` model type,
//!   analysis type, data characteristic, specific data type, data type
//!   (2 real, 5 complex), values per node; 7 `8I10` integer count, real count,
//!   then the integers (load case, mode, ...); 8 `6E13.5` the reals
//!   (frequency, modal mass, damping, eigenvalue, ...); then per node `I10`
//!   node and `6E13.5` its values.
//! - 1858 (58 qualifiers): 12 short records of codes and reals, kept as text.

use super::geometry::{self, CoordinateSystem, Node, Part, TraceLine};
use super::split::Block;
use super::text::{self, Line, Lines};
use super::units::{self, Units164};
use super::{Complex64, Ordinate, OtherDataset, UffError};

/// Typed content of a dataset other than 58.
#[derive(Clone, Debug, PartialEq)]
pub enum OtherKind {
    /// 151.
    Header(Header151),
    /// 164.
    Units(Units164),
    /// 15 and 2411.
    Nodes(Vec<Node>),
    /// 18 (no part) and 2420 (with its part).
    CoordinateSystems {
        part: Option<Part>,
        systems: Vec<CoordinateSystem>,
    },
    /// 82.
    TraceLine(TraceLine),
    /// 55.
    NodalData(Box<NodalData55>),
    /// 1858: the records as text.
    Qualifiers(Vec<String>),
    /// Not read (2412, 2414, unknown numbers); a note says so.
    Skipped,
}

/// Dataset 151: header records as text.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct Header151 {
    pub records: Vec<String>,
}

impl Header151 {
    fn record(&self, k: usize) -> &str {
        self.records.get(k).map_or("", String::as_str)
    }
    /// Record 1: model file name.
    pub fn model_name(&self) -> &str {
        self.record(0)
    }
    /// Record 2: model file description.
    pub fn description(&self) -> &str {
        self.record(1)
    }
    /// Record 3: program which created the database.
    pub fn database_program(&self) -> &str {
        self.record(2)
    }
    /// Record 6: program which created the universal file (7-record form).
    pub fn file_program(&self) -> &str {
        self.record(5)
    }
}

/// Values of one node in dataset 55.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeValues {
    pub node: i64,
    pub values: Ordinate,
}

/// Dataset 55: data at nodes (mode shapes, ...).
#[derive(Clone, Debug, PartialEq)]
pub struct NodalData55 {
    pub id_lines: [String; 5],
    pub model_type: i64,
    /// 1 static, 2 normal mode, 3 complex eigenvalue (first order), ...
    pub analysis_type: i64,
    /// 1 scalar, 2 translation (3 DOF), 3 translation and rotation (6 DOF), ...
    pub data_characteristic: i64,
    pub specific_data_type: i64,
    /// 2 real, 5 complex.
    pub data_type: i64,
    pub values_per_node: usize,
    /// Record 7 after the two counts (load case, mode number, ...).
    pub integers: Vec<i64>,
    /// Record 8 (normal mode: frequency, modal mass, viscous and hysteretic damping).
    pub reals: Vec<f64>,
    pub nodes: Vec<NodeValues>,
}

type Failure = (usize, String);

fn header151(lines: &[Line<'_>]) -> Header151 {
    Header151 {
        records: lines.iter().map(|l| text::text_field(l.text)).collect(),
    }
}

fn ints(line: Option<&Line<'_>>, k: usize, count: usize, what: &str) -> Result<Vec<i64>, Failure> {
    let line = line.ok_or((
        k.saturating_sub(1),
        format!("dataset ends early: expected {what}"),
    ))?;
    let v: Vec<i64> = text::tokens(line.text)
        .map(text::parse_int)
        .collect::<Option<_>>()
        .ok_or((
            k,
            format!("expected {what}, found '{}'", text::excerpt(line.text)),
        ))?;
    if v.len() < count {
        return Err((
            k,
            format!("expected {what} ({count} integers), found {}", v.len()),
        ));
    }
    Ok(v)
}

/// Reads `count` reals over lines starting at `*k` (fields of `width`).
fn reals_over_lines(
    lines: &[Line<'_>],
    k: &mut usize,
    count: usize,
    width: usize,
    what: &str,
) -> Result<Vec<f64>, Failure> {
    let mut v = Vec::with_capacity(count.min(lines.len() * 8));
    while v.len() < count {
        let line = lines.get(*k).ok_or((
            k.saturating_sub(1),
            format!(
                "dataset ends early: expected {count} values ({what}), found {}",
                v.len()
            ),
        ))?;
        text::reals_by_width_or_tokens(line.text, width, &mut v)
            .map_err(|m| (*k, format!("{what}: {m}")))?;
        if let Some((i, x)) = text::first_non_finite(&v) {
            return Err((
                *k,
                format!("{what}: value {} is {x}; expected a finite number", i + 1),
            ));
        }
        *k += 1;
    }
    if v.len() > count {
        return Err((
            *k - 1,
            format!("expected {count} values ({what}), found {}", v.len()),
        ));
    }
    Ok(v)
}

fn nodal_data55(lines: &[Line<'_>]) -> Result<NodalData55, Failure> {
    if lines.len() < 8 {
        return Err((
            lines.len().saturating_sub(1),
            format!("dataset 55 needs 8 header records, found {}", lines.len()),
        ));
    }
    let id_lines: [String; 5] = std::array::from_fn(|k| text::text_field(lines[k].text));
    let r6 = ints(lines.get(5), 5, 6, "record 6 (6I10: model type, analysis type, data characteristic, specific data type, data type, values per node)")?;
    let r7 = ints(
        lines.get(6),
        6,
        2,
        "record 7 (8I10: integer count, real count, integers)",
    )?;
    let data_type = r6[4];
    let complex = match data_type {
        2 => false,
        5 => true,
        d => {
            return Err((
                5,
                format!("record 6: data type must be 2 (real) or 5 (complex), found {d}"),
            ))
        }
    };
    let values_per_node = usize::try_from(r6[5]).ok().filter(|&n| n <= 1000).ok_or((
        5,
        format!("record 6: values per node must be 0..1000, found {}", r6[5]),
    ))?;
    let int_count = usize::try_from(r7[0]).ok().filter(|&n| n <= 1000).ok_or((
        6,
        format!("record 7: integer count must be 0..1000, found {}", r7[0]),
    ))?;
    let real_count = usize::try_from(r7[1]).ok().filter(|&n| n <= 1000).ok_or((
        6,
        format!("record 7: real count must be 0..1000, found {}", r7[1]),
    ))?;
    // Record 7 may continue on further lines (8I10).
    let mut integers: Vec<i64> = r7[2..].to_vec();
    let mut k = 7;
    while integers.len() < int_count {
        let more = ints(lines.get(k), k, 1, "record 7 integers (8I10)")?;
        integers.extend(more);
        k += 1;
    }
    integers.truncate(int_count);
    let reals = reals_over_lines(lines, &mut k, real_count, 13, "record 8")?;
    let per_node = values_per_node * if complex { 2 } else { 1 };
    let mut nodes = Vec::new();
    while k < lines.len() {
        if text::is_blank_line(lines[k].text) {
            k += 1;
            continue;
        }
        let node = ints(lines.get(k), k, 1, "node number (I10)")?[0];
        k += 1;
        let v = reals_over_lines(lines, &mut k, per_node, 13, "node values (6E13.5)")?;
        let values = if complex {
            Ordinate::Complex(
                v.chunks_exact(2)
                    .map(|c| Complex64::new(c[0], c[1]))
                    .collect(),
            )
        } else {
            Ordinate::Real(v)
        };
        nodes.push(NodeValues { node, values });
    }
    Ok(NodalData55 {
        id_lines,
        model_type: r6[0],
        analysis_type: r6[1],
        data_characteristic: r6[2],
        specific_data_type: r6[3],
        data_type,
        values_per_node,
        integers,
        reals,
        nodes,
    })
}

fn summary(number: u32, kind: &OtherKind) -> String {
    match kind {
        OtherKind::Header(h) => format!(
            "151 header: model '{}', written by '{}'",
            h.model_name(),
            h.file_program()
        ),
        OtherKind::Units(u) => format!(
            "164 units: code {} ({}), length {} /m, force {} /N, temperature {} /K, offset {}",
            u.code, u.description, u.length, u.force, u.temperature, u.temperature_offset
        ),
        OtherKind::Nodes(n) => format!("{number} nodes: {}", n.len()),
        OtherKind::CoordinateSystems { systems, .. } => {
            format!("{number} coordinate systems: {}", systems.len())
        }
        OtherKind::TraceLine(t) => format!(
            "82 trace line {} '{}': {} nodes",
            t.number,
            t.id,
            t.nodes.len()
        ),
        OtherKind::NodalData(d) => format!(
            "55 data at nodes: analysis type {}, {} nodes x {} values{}",
            d.analysis_type,
            d.nodes.len(),
            d.values_per_node,
            if d.data_type == 5 { " (complex)" } else { "" }
        ),
        OtherKind::Qualifiers(r) => {
            format!("1858 function qualifiers: {} records kept as text", r.len())
        }
        OtherKind::Skipped => format!("{number}: not read"),
    }
}

/// Parses a block that is not dataset 58.
pub(crate) fn parse(
    bytes: &[u8],
    block: &Block,
    notes: &mut Vec<String>,
) -> Result<OtherDataset, UffError> {
    let number = block.number;
    let lines: Vec<Line<'_>> = Lines::new(bytes, block.text.clone(), block.line + 1).collect();
    let fail = |(k, message): Failure| {
        let (line, offset) = lines
            .get(k)
            .map_or((block.close_line, block.close_offset), |l| {
                (l.number, l.start)
            });
        UffError {
            line: Some(line),
            byte_offset: offset,
            dataset_index: Some(block.index),
            dataset_number: Some(number),
            message: format!("dataset {number}: {message}"),
        }
    };
    let kind = match number {
        151 => OtherKind::Header(header151(&lines)),
        164 => OtherKind::Units(units::parse(&lines).map_err(fail)?),
        15 => OtherKind::Nodes(geometry::nodes15(&lines).map_err(fail)?),
        2411 => OtherKind::Nodes(geometry::nodes2411(&lines).map_err(fail)?),
        18 => OtherKind::CoordinateSystems {
            part: None,
            systems: geometry::systems18(&lines).map_err(fail)?,
        },
        2420 => {
            let (part, systems) = geometry::systems2420(&lines).map_err(fail)?;
            OtherKind::CoordinateSystems {
                part: Some(part),
                systems,
            }
        }
        82 => OtherKind::TraceLine(geometry::trace_line(&lines).map_err(fail)?),
        55 => OtherKind::NodalData(Box::new(nodal_data55(&lines).map_err(fail)?)),
        1858 => OtherKind::Qualifiers(lines.iter().map(|l| text::text_field(l.text)).collect()),
        2412 | 2414 => {
            notes.push(format!(
                "line {}: dataset {number} (elements/results) skipped",
                block.line
            ));
            OtherKind::Skipped
        }
        _ => {
            notes.push(format!(
                "line {}: unknown dataset {number} skipped",
                block.line
            ));
            OtherKind::Skipped
        }
    };
    Ok(OtherDataset {
        number,
        line: block.line,
        summary: summary(number, &kind),
        kind,
    })
}
