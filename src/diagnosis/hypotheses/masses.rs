//! `sensor-mass` (one lumped mass m, kg, at every node that carries a
//! sensor, the same value for all: the response nodes, or the one
//! accelerometer's of a roving-hammer test) and `added-mass` (a lumped mass
//! at a node without sensor).

use super::{Context, Extension, Hypothesis, ParamSpec, Physics};

/// One hypothesis: the same mass at every measured node.
pub fn sensor_mass(ctx: &Context) -> Vec<Hypothesis> {
    sensor_mass_at(&ctx.sensor_nodes, ctx.total_mass)
        .into_iter()
        .collect()
}

/// The sensor-mass hypothesis of a model of `total_mass` (kg) whose
/// measured nodes are `sensor_nodes`; `None` without sensors.
pub fn sensor_mass_at(sensor_nodes: &[u32], total_mass: f64) -> Option<Hypothesis> {
    if sensor_nodes.is_empty() {
        return None;
    }
    let n = sensor_nodes.len() as f64;
    let m = total_mass;
    Some(Hypothesis {
        physics: Physics::SensorMass,
        nodes: sensor_nodes.to_vec(),
        dofs: vec![],
        param: Some(ParamSpec {
            name: "m",
            lo: 1e-5 * m / n,
            hi: 0.3 * m / n,
            probe: 0.01 * m / n,
            unit: "kg",
        }),
        extension: Extension::Masses {
            nodes: sensor_nodes.to_vec(),
        },
        label: match sensor_nodes {
            [one] => format!("sensor-mass at node {one} (the sensor)"),
            all => format!("sensor-mass at the {} measured nodes", all.len()),
        },
    })
}

/// One hypothesis per node reached by a beam that carries no sensor.
pub fn added_mass(ctx: &Context) -> Vec<Hypothesis> {
    ctx.beam_nodes()
        .into_iter()
        .filter(|n| !ctx.sensor_nodes.contains(n))
        .map(|n| added_mass_at(n, ctx.total_mass))
        .collect()
}

/// The added-mass hypothesis at `node` of a model of `total_mass` (kg).
pub fn added_mass_at(node: u32, total_mass: f64) -> Hypothesis {
    let m = total_mass;
    Hypothesis {
        physics: Physics::AddedMass,
        nodes: vec![node],
        dofs: vec![],
        param: Some(ParamSpec {
            name: "m",
            lo: 1e-4 * m,
            hi: 1.0 * m,
            probe: 0.02 * m,
            unit: "kg",
        }),
        extension: Extension::Masses { nodes: vec![node] },
        label: format!("added-mass at node {node}"),
    }
}
