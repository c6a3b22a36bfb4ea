//! Test layouts: which part of the FRF matrix H (responses × references) a
//! campaign measured, and the same data as one column (one excitation, many
//! responses), the form the updating equations take.
//!
//! - Fixed exciter: one reference, a column of H; used as it is.
//! - Roving hammer: one response (the accelerometer), many references (the
//!   hammer's points), a row of H. By Maxwell–Betti reciprocity
//!   H_ij = H_ji (K, M and C symmetric), so the row is the column of the
//!   accelerometer's DOF: each record's response and reference are swapped.
//! - Several references (MIMO) with several responses each: the reference
//!   with the most channels is used (the others are set aside, with a note).

use super::{dof_label, MeasuredFrfs};

/// What was measured, in words a test engineer uses.
#[derive(Clone, Debug, PartialEq)]
pub enum Layout {
    /// One reference: a column of the FRF matrix.
    FixedExciter { excitation: String, channels: usize },
    /// One response, several references: a row, used as the column of the
    /// response DOF by reciprocity.
    RovingHammer { response: String, impacts: usize },
    /// Several references with several responses each.
    MultiReference {
        used: String,
        channels: usize,
        references: usize,
        set_aside: usize,
    },
}

impl std::fmt::Display for Layout {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Layout::FixedExciter {
                excitation,
                channels,
            } => write!(f, "fixed exciter at {excitation}, {channels} response channel(s)"),
            Layout::RovingHammer { response, impacts } => write!(
                f,
                "roving hammer: {impacts} impact point(s), response at {response}; used as the column of {response} by reciprocity (H_ij = H_ji)"
            ),
            Layout::MultiReference {
                used,
                channels,
                references,
                set_aside,
            } => write!(
                f,
                "{references} references: the one with the most channels, {used} ({channels} channels), is used; {set_aside} record(s) of the other references set aside"
            ),
        }
    }
}

/// Count records per key in order of first appearance.
fn counts(keys: impl Iterator<Item = (i64, i32)>) -> Vec<((i64, i32), usize)> {
    let mut out: Vec<((i64, i32), usize)> = Vec::new();
    for k in keys {
        match out.iter_mut().find(|(x, _)| *x == k) {
            Some(e) => e.1 += 1,
            None => out.push((k, 1)),
        }
    }
    out
}

/// The campaign as one column of the FRF matrix, and what its layout was.
/// A row (one response DOF, several references) is transposed by
/// reciprocity; anything else is returned unchanged (the consumers use the
/// reference with the most channels).
pub fn as_column(test: &MeasuredFrfs) -> (MeasuredFrfs, Layout) {
    let refs = counts(
        test.channels
            .iter()
            .map(|c| (c.reference_node, c.reference_direction)),
    );
    let resps = counts(
        test.channels
            .iter()
            .map(|c| (c.response_node, c.response_direction)),
    );
    if refs.len() <= 1 {
        let (excitation, channels) = refs
            .first()
            .map_or((String::new(), 0), |(k, n)| (dof_label(k.0, k.1), *n));
        return (
            test.clone(),
            Layout::FixedExciter {
                excitation,
                channels,
            },
        );
    }
    if resps.len() == 1 {
        let (node, dir) = resps[0].0;
        let mut out = test.clone();
        for ch in &mut out.channels {
            std::mem::swap(&mut ch.response_node, &mut ch.reference_node);
            std::mem::swap(&mut ch.response_direction, &mut ch.reference_direction);
        }
        return (
            out,
            Layout::RovingHammer {
                response: dof_label(node, dir),
                impacts: refs.len(),
            },
        );
    }
    let best = refs
        .iter()
        .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)))
        .copied()
        .unwrap_or(((0, 0), 0));
    (
        test.clone(),
        Layout::MultiReference {
            used: dof_label(best.0 .0, best.0 .1),
            channels: best.1,
            references: refs.len(),
            set_aside: test.channels.len() - best.1,
        },
    )
}
