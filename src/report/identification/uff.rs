//! `modes.uff`: the identified modes as UFF 55 normal modes (analysis type
//! 2: frequency, unit modal mass, viscous damping ratio; real shapes at the
//! measured translations, 3 values per node, the direction's sign applied).

use crate::identification::Identification;
use crate::report::shapes::normal_mode;

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
        let values = nodes.iter().map(|&n| {
            let mut v = [0.0; 3];
            for (o, d) in id.data.outputs.iter().enumerate() {
                if d.node == n && (1..=3).contains(&d.direction.abs()) {
                    let k = d.direction.unsigned_abs() as usize - 1;
                    v[k] = m.shape[o].re * f64::from(d.direction.signum());
                }
            }
            (n, v)
        });
        let id_lines = [
            format!("mode {} ({})", r + 1, m.kind.name()),
            format!("identified by frfup {}", env!("CARGO_PKG_VERSION")),
            format!("from {test_name}"),
            format!(
                "f = {:.6} Hz, damping ratio = {:.6}, MPC = {:.4}",
                m.frequency_hz, m.damping_ratio, m.quality.mpc
            ),
            "NONE".into(),
        ];
        let d = normal_mode(id_lines, r + 1, m.frequency_hz, m.damping_ratio, values);
        frfup_parsers::uff::write_nodal_data(&mut out, &d)?;
    }
    Ok(out)
}
