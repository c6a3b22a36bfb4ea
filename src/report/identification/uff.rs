//! `modes.uff`: the identified modes as UFF 55 normal modes (analysis type
//! 2: frequency, unit modal mass, viscous damping ratio; real shapes at the
//! measured translations, 3 values per node, the direction's sign applied).

use frfup_parsers::uff::{NodalData55, NodeValues, Ordinate};

use crate::identification::Identification;

/// The file's bytes.
pub fn modes_uff(id: &Identification, test_name: &str) -> std::io::Result<Vec<u8>> {
    let mut nodes: Vec<i64> = id
        .data
        .outputs
        .iter()
        .filter(|d| (1..=3).contains(&d.direction.abs()))
        .map(|d| d.node)
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    let mut out = Vec::new();
    for (r, m) in id.modes.iter().enumerate() {
        let values: Vec<NodeValues> = nodes
            .iter()
            .map(|&n| {
                let mut v = vec![0.0; 3];
                for (o, d) in id.data.outputs.iter().enumerate() {
                    if d.node == n && (1..=3).contains(&d.direction.abs()) {
                        let k = d.direction.unsigned_abs() as usize - 1;
                        v[k] = m.shape[o].re * f64::from(d.direction.signum());
                    }
                }
                NodeValues {
                    node: n,
                    values: Ordinate::Real(v),
                }
            })
            .collect();
        let d = NodalData55 {
            id_lines: [
                format!("mode {} ({})", r + 1, m.kind.name()),
                format!("identified by frfup {}", env!("CARGO_PKG_VERSION")),
                format!("from {test_name}"),
                format!(
                    "f = {:.6} Hz, damping ratio = {:.6}, MPC = {:.4}",
                    m.frequency_hz, m.damping_ratio, m.quality.mpc
                ),
                "NONE".into(),
            ],
            model_type: 1,
            analysis_type: 2,
            data_characteristic: 2,
            specific_data_type: 8,
            data_type: 2,
            values_per_node: 3,
            integers: vec![1, r as i64 + 1],
            reals: vec![m.frequency_hz, 1.0, m.damping_ratio, 0.0],
            nodes: values,
        };
        frfup_parsers::uff::write_nodal_data(&mut out, &d)?;
    }
    Ok(out)
}
