//! What the loader notices in a UFF file besides its FRFs: records that are
//! not FRFs, channels named only by entity names, channels measured twice,
//! several references, and values no FRF has (a 58b byte-order flag that is
//! wrong). Each becomes a note that the commands print as a warning.

use frfup_parsers::uff::{Dataset, Function58, Ordinate, UffFile};

use super::{
    dof_label, entity_dof_label, function_type_name, node_direction_from_entity, MeasuredFrfs,
};

/// FRF magnitudes above this (in the file's units) are taken as misread data.
const IMPLAUSIBLE: f64 = 1e20;

/// Node and direction of a record-6 DOF; for node 0 with an entity name of
/// the form `.NODE.DIR` (e.g. `.1.Z-`), those of the name.
pub fn record_dof(entity: &str, node: i64, direction: i32) -> (i64, i32) {
    if node == 0 {
        if let Some(nd) = node_direction_from_entity(entity) {
            return nd;
        }
    }
    (node, direction)
}

/// The loader's notes on `file`, whose FRFs are `frfs`.
pub fn notes(file: &UffFile, frfs: &MeasuredFrfs) -> Vec<String> {
    let mut notes = Vec::new();
    let mut named = Vec::new();
    for (i, d) in file.datasets.iter().enumerate() {
        let Dataset::Function(f) = d else { continue };
        let label = format!(
            "{}/{}",
            entity_dof_label(&f.response_entity, f.response_node, f.response_direction),
            entity_dof_label(&f.reference_entity, f.reference_node, f.reference_direction)
        );
        if f.function_type != super::load::FUNCTION_TYPE_FRF {
            notes.push(format!(
                "dataset #{} ({label}) is a {} record (function type {}), not an FRF: skipped",
                i + 1,
                function_type_name(f.function_type),
                f.function_type
            ));
            continue;
        }
        if f.response_node == 0 || f.reference_node == 0 {
            named.push((i, label.clone(), f.as_ref()));
        }
        if let Some(note) = implausible_values(f) {
            notes.push(format!("dataset #{} ({label}): {note}", i + 1));
        }
    }
    notes.extend(entity_notes(&named));
    notes.extend(channel_notes(frfs));
    notes
}

fn entity_notes(named: &[(usize, String, &Function58)]) -> Vec<String> {
    let mut notes = Vec::new();
    let (mut taken, mut unusable) = (Vec::new(), Vec::new());
    for (i, label, f) in named {
        let r = record_dof(&f.response_entity, f.response_node, f.response_direction);
        let q = record_dof(&f.reference_entity, f.reference_node, f.reference_direction);
        if r.0 == 0 || q.0 == 0 {
            unusable.push(format!("#{} {label}", i + 1));
        } else {
            taken.push(format!(
                "{label} as {}/{}",
                dof_label(r.0, r.1),
                dof_label(q.0, q.1)
            ));
        }
    }
    if !taken.is_empty() {
        notes.push(format!(
            "{} FRF(s) name their DOFs only by entity names (record 6 node 0): node and direction taken from the names: {}",
            taken.len(),
            taken.join(", ")
        ));
    }
    if !unusable.is_empty() {
        notes.push(format!(
            "{} FRF(s) have node 0 and an entity name without node and direction: they match no model DOF: {}",
            unusable.len(),
            unusable.join(", ")
        ));
    }
    notes
}

fn channel_notes(frfs: &MeasuredFrfs) -> Vec<String> {
    let mut notes = Vec::new();
    let mut seen: Vec<(i64, i32, i64, i32)> = Vec::new();
    let mut references: Vec<(i64, i32)> = Vec::new();
    for c in &frfs.channels {
        let key = (
            c.response_node,
            c.response_direction,
            c.reference_node,
            c.reference_direction,
        );
        if seen.contains(&key) {
            notes.push(format!(
                "channel {}/{} is measured more than once: only the first is used",
                dof_label(key.0, key.1),
                dof_label(key.2, key.3)
            ));
        } else {
            seen.push(key);
        }
        let r = (c.reference_node, c.reference_direction);
        if !references.contains(&r) {
            references.push(r);
        }
    }
    if references.len() > 1 {
        // What the consumers do with several references, in the layout's words.
        notes.push(super::layout::as_column(frfs).1.to_string());
    }
    notes
}

/// For a record whose values no FRF has (|H| > 1e20, or not finite): what
/// the other byte order would give, when it gives plausible values.
fn implausible_values(f: &Function58) -> Option<String> {
    let (largest, swapped) = match &f.ordinate {
        Ordinate::Real(v) => extremes(v.iter().copied(), |x| {
            f64::from_bits(x.to_bits().swap_bytes())
        }),
        Ordinate::Complex(v) => extremes(v.iter().flat_map(|c| [c.re, c.im]), |x| {
            f64::from_bits(x.to_bits().swap_bytes())
        }),
        Ordinate::RealSingle(v) => extremes(v.iter().map(|&x| f64::from(x)), swap32),
        Ordinate::ComplexSingle(v) => extremes(
            v.iter().flat_map(|c| [f64::from(c.re), f64::from(c.im)]),
            swap32,
        ),
    };
    if largest <= IMPLAUSIBLE {
        return None;
    }
    let mut note = format!("values up to {largest:e}, which no FRF has");
    if f.binary && swapped <= IMPLAUSIBLE {
        note.push_str(&format!(
            "; read in the other byte order (the 58b header's byte-ordering flag reversed: {}) they are at most {swapped:e}: the flag is probably wrong",
            "1 little-endian ↔ 2 big-endian"
        ));
    } else if f.binary {
        note.push_str("; the other byte order gives no plausible values either");
    }
    Some(note)
}

fn swap32(x: f64) -> f64 {
    f64::from(f32::from_bits((x as f32).to_bits().swap_bytes()))
}

/// Largest magnitude (∞ for a non-finite value) as read and byte-swapped.
fn extremes(values: impl Iterator<Item = f64>, swap: impl Fn(f64) -> f64) -> (f64, f64) {
    let magnitude = |x: f64| {
        if x.is_finite() {
            x.abs()
        } else {
            f64::INFINITY
        }
    };
    values.fold((0.0f64, 0.0f64), |(a, b), x| {
        (a.max(magnitude(x)), b.max(magnitude(swap(x))))
    })
}
