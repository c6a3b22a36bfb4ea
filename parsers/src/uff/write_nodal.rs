//! Writing dataset 55 (data at nodes: mode shapes), 15 (nodes) and 82
//! (trace lines), in the layouts [`super::other`] and [`super::geometry`]
//! read and pyuff reads and writes:
//!
//! - 55: records 1–5 `80A1`; 6 `6I10`; 7 `8I10` (integer count, real count,
//!   integers, continued on further lines); 8 `6E13.5` reals; per node `I10`
//!   then its values `6E13.5` (complex values as real, imaginary pairs). pyuff
//!   reads a node's values from one line only: 3 values (real or complex) or
//!   6 real ones, which is what mode shapes at translational DOFs need.
//! - 15: one line per node `4I10,1P3E13.5`.
//! - 82: `3I10` number, node count, color; `80A1` id; nodes `8I10`.
//!
//! Lines end with LF; output bytes depend only on the input.

use std::fmt::Write as _;
use std::io::{self, Write};

use super::write::{cut, field_e, int_field, invalid};
use super::{NodalData55, Node, Ordinate, TraceLine};

fn text_record(out: &mut String, s: &str) {
    let s = cut(s, 80);
    let s = if s.trim().is_empty() { "NONE" } else { s };
    let _ = writeln!(out, "{s:<80}");
}

fn ints_8(out: &mut String, values: &[i64], what: &str) -> io::Result<()> {
    for chunk in values.chunks(8) {
        for v in chunk {
            int_field(out, *v, 10, what)?;
        }
        out.push('\n');
    }
    Ok(())
}

fn reals_6(out: &mut String, values: &[f64], what: &str) -> io::Result<()> {
    if let Some(x) = values.iter().find(|x| !x.is_finite()) {
        return Err(invalid(format!("{what}: {x} is not a finite number")));
    }
    for chunk in values.chunks(6) {
        for v in chunk {
            field_e(out, *v, 13, 5);
        }
        out.push('\n');
    }
    Ok(())
}

fn node_values(d: &NodalData55, values: &Ordinate) -> io::Result<Vec<f64>> {
    let complex = d.data_type == 5;
    let n = values.len();
    if n != d.values_per_node || values.is_complex() != complex {
        return Err(invalid(format!(
            "dataset 55: a node has {n} {} values, the header says {} {}",
            if values.is_complex() {
                "complex"
            } else {
                "real"
            },
            d.values_per_node,
            if complex { "complex" } else { "real" }
        )));
    }
    Ok((0..n)
        .flat_map(|i| {
            let (re, im) = values.at(i);
            if complex {
                vec![re, im]
            } else {
                vec![re]
            }
        })
        .collect())
}

/// Writes one dataset 55.
pub fn write_nodal_data<W: Write>(out: &mut W, d: &NodalData55) -> io::Result<()> {
    if !matches!(d.data_type, 2 | 5) {
        return Err(invalid(format!(
            "dataset 55: data type must be 2 (real) or 5 (complex), not {}",
            d.data_type
        )));
    }
    let mut s = String::with_capacity(1024 + d.nodes.len() * 100);
    s.push_str("    -1\n    55\n");
    for id in &d.id_lines {
        text_record(&mut s, id);
    }
    let r6 = [
        d.model_type,
        d.analysis_type,
        d.data_characteristic,
        d.specific_data_type,
        d.data_type,
        d.values_per_node as i64,
    ];
    for v in r6 {
        int_field(&mut s, v, 10, "dataset 55 record 6")?;
    }
    s.push('\n');
    let mut r7 = vec![d.integers.len() as i64, d.reals.len() as i64];
    r7.extend(&d.integers);
    ints_8(&mut s, &r7, "dataset 55 record 7")?;
    reals_6(&mut s, &d.reals, "dataset 55 record 8")?;
    for nv in &d.nodes {
        int_field(&mut s, nv.node, 10, "dataset 55 node")?;
        s.push('\n');
        reals_6(
            &mut s,
            &node_values(d, &nv.values)?,
            "dataset 55 node values",
        )?;
    }
    s.push_str("    -1\n");
    out.write_all(s.as_bytes())
}

/// Writes nodes as one dataset 15.
pub fn write_nodes15<W: Write>(out: &mut W, nodes: &[Node]) -> io::Result<()> {
    let mut s = String::with_capacity(64 + nodes.len() * 80);
    s.push_str("    -1\n    15\n");
    for n in nodes {
        for v in [n.label, n.definition_cs, n.displacement_cs, n.color] {
            int_field(&mut s, v, 10, "dataset 15 field")?;
        }
        for x in n.coordinates {
            if !x.is_finite() {
                return Err(invalid(format!(
                    "dataset 15: node {} coordinate {x}",
                    n.label
                )));
            }
            field_e(&mut s, x, 13, 5);
        }
        s.push('\n');
    }
    s.push_str("    -1\n");
    out.write_all(s.as_bytes())
}

/// Writes one trace line as dataset 82.
pub fn write_trace_line82<W: Write>(out: &mut W, t: &TraceLine) -> io::Result<()> {
    let mut s = String::with_capacity(256 + t.nodes.len() * 10);
    s.push_str("    -1\n    82\n");
    for v in [t.number, t.nodes.len() as i64, t.color] {
        int_field(&mut s, v, 10, "dataset 82 field")?;
    }
    s.push('\n');
    text_record(&mut s, &t.id);
    ints_8(&mut s, &t.nodes, "dataset 82 node")?;
    s.push_str("    -1\n");
    out.write_all(s.as_bytes())
}
