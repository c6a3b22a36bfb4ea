//! Mode shapes out of the program, for any modal viewer: the deck's geometry
//! as UFF 15 (nodes) and UFF 82 (one trace line through every beam), modes
//! as UFF 55 (normal modes: frequency, unit modal mass, viscous damping
//! ratio; three real translations per node, in the global axes), and the
//! same shapes as CSV (one row per node and direction, one column per mode).

use frfup_parsers::deck::Deck;
use frfup_parsers::uff::{self, NodalData55, NodeValues, Ordinate, TraceLine};

use crate::fsio::csv_number;
use crate::report::tables::csv_text;
use crate::solvers::eigen::nodal::NodalModes;

/// UFF 15 (every node of the deck) and UFF 82 (the beams as one trace line,
/// the pen lifted between beams that do not continue each other).
pub fn geometry_uff(deck: &Deck) -> std::io::Result<Vec<u8>> {
    let mut out = Vec::new();
    let nodes: Vec<uff::Node> = deck
        .nodes
        .iter()
        .map(|n| uff::Node {
            label: i64::from(n.id),
            definition_cs: 0,
            displacement_cs: 0,
            color: 8,
            coordinates: n.xyz,
        })
        .collect();
    uff::write_nodes15(&mut out, &nodes)?;
    let mut line: Vec<i64> = Vec::new();
    for b in &deck.beams {
        let [a, c] = b.nodes.map(i64::from);
        if line.last() != Some(&a) {
            if !line.is_empty() {
                line.push(0);
            }
            line.push(a);
        }
        line.push(c);
    }
    if !line.is_empty() {
        let trace = TraceLine {
            number: 1,
            color: 8,
            id: format!("{}: beams", deck.title()),
            nodes: line,
        };
        uff::write_trace_line82(&mut out, &trace)?;
    }
    Ok(out)
}

/// One UFF 55 dataset per mode.
pub fn modes_uff(set: &NodalModes) -> std::io::Result<Vec<u8>> {
    let mut out = Vec::new();
    for (r, values) in set.values.iter().enumerate() {
        let f = set.frequencies_hz.get(r).copied().unwrap_or(0.0);
        let zeta = set
            .damping_ratios
            .as_ref()
            .and_then(|z| z.get(r).copied())
            .unwrap_or(0.0);
        let id_lines = [
            format!("{} {}", set.kind, r + 1),
            format!("frfup {}", env!("CARGO_PKG_VERSION")),
            format!("from {}", set.source),
            format!("f = {f:.6} Hz, damping ratio = {zeta:.6}"),
            "NONE".into(),
        ];
        let nodes = set
            .nodes
            .iter()
            .zip(values)
            .map(|(&n, v)| (i64::from(n), *v));
        let d = normal_mode(id_lines, r + 1, f, zeta, nodes);
        uff::write_nodal_data(&mut out, &d)?;
    }
    Ok(out)
}

/// One UFF 55 normal mode (analysis type 2, real translations, 3 values per
/// node): record 7 the load case 1 and `mode`, record 8 f (Hz), unit modal
/// mass, viscous damping ratio `zeta`, no hysteretic damping.
pub fn normal_mode(
    id_lines: [String; 5],
    mode: usize,
    f: f64,
    zeta: f64,
    nodes: impl Iterator<Item = (i64, [f64; 3])>,
) -> NodalData55 {
    NodalData55 {
        id_lines,
        model_type: 1,
        analysis_type: 2,
        data_characteristic: 2,
        specific_data_type: 8,
        data_type: 2,
        values_per_node: 3,
        integers: vec![1, mode as i64],
        reals: vec![f, 1.0, zeta, 0.0],
        nodes: nodes
            .map(|(node, v)| NodeValues {
                node,
                values: Ordinate::Real(v.to_vec()),
            })
            .collect(),
    }
}

/// The shapes as CSV: `node`, `direction`, then one column per mode named by
/// its kind, number and frequency (`FE mode 1 (12.345 Hz)`).
pub fn shapes_csv(sets: &[&NodalModes]) -> String {
    let mut header = vec!["node".to_string(), "direction".to_string()];
    for set in sets {
        for (r, f) in set.frequencies_hz.iter().enumerate().take(set.values.len()) {
            header.push(format!("{} {} ({f:.3} Hz)", set.kind, r + 1));
        }
    }
    let mut nodes: Vec<u32> = sets.iter().flat_map(|s| s.nodes.clone()).collect();
    nodes.sort_unstable();
    nodes.dedup();
    let mut rows = Vec::new();
    for n in nodes {
        for (a, name) in ["x", "y", "z"].iter().enumerate() {
            let mut row = vec![n.to_string(), name.to_string()];
            for set in sets {
                let i = set
                    .nodes
                    .binary_search(&n)
                    .ok()
                    .filter(|&i| set.known[i][a]);
                for v in &set.values {
                    row.push(i.map_or(String::new(), |i| csv_number(v[i][a])));
                }
            }
            rows.push(row);
        }
    }
    csv_text(std::iter::once(header).chain(rows))
}
