//! `sensor-mass` (one lumped mass m, kg, at every node that carries a
//! sensor, the same value for all: the response nodes, or the one
//! accelerometer's of a roving-hammer test) and `added-mass` (a lumped mass
//! at a node without sensor).

use super::{Context, Extension, Hypothesis, ParamSpec, Physics};

/// One hypothesis: the same mass at every measured node.
pub fn sensor_mass(ctx: &Context) -> Vec<Hypothesis> {
    if ctx.sensor_nodes.is_empty() {
        return Vec::new();
    }
    let n = ctx.sensor_nodes.len() as f64;
    let m = ctx.total_mass;
    vec![Hypothesis {
        physics: Physics::SensorMass,
        nodes: ctx.sensor_nodes.clone(),
        dofs: vec![],
        param: Some(ParamSpec {
            name: "m",
            lo: 1e-5 * m / n,
            hi: 0.3 * m / n,
            probe: 0.01 * m / n,
            unit: "kg",
        }),
        extension: Extension::Masses {
            nodes: ctx.sensor_nodes.clone(),
        },
        label: match ctx.sensor_nodes.as_slice() {
            [one] => format!("sensor-mass at node {one} (the sensor)"),
            all => format!("sensor-mass at the {} measured nodes", all.len()),
        },
    }]
}

/// One hypothesis per node reached by a beam that carries no sensor.
pub fn added_mass(ctx: &Context) -> Vec<Hypothesis> {
    let m = ctx.total_mass;
    ctx.beam_nodes()
        .into_iter()
        .filter(|n| !ctx.sensor_nodes.contains(n))
        .map(|n| Hypothesis {
            physics: Physics::AddedMass,
            nodes: vec![n],
            dofs: vec![],
            param: Some(ParamSpec {
                name: "m",
                lo: 1e-4 * m,
                hi: 1.0 * m,
                probe: 0.02 * m,
                unit: "kg",
            }),
            extension: Extension::Masses { nodes: vec![n] },
            label: format!("added-mass at node {n}"),
        })
        .collect()
}
