//! Random sensor layouts and the truth record of a case.

use serde_json::json;

use super::{Case, Structure};
use crate::benchmark::{LayoutKind, Rng};
use crate::model::FeModel;
use crate::simulate::NodeDirection;
use crate::solvers::eigen::{lowest_modes, EigenOptions};

/// Draw a layout: 1–3 directions (x, z in plane; x, y, z in space), 6–30
/// channels on randomly chosen nodes (fewer only if the model has fewer free
/// DOFs), a fixed exciter or a roving hammer. The exciter (or the fixed
/// sensor of the hammer test) is one of the points, chosen at random among
/// the third that is farthest from a node line of the first elastic modes, as
/// a test engineer would place it. The driving point is measured unless
/// `omit_driving_point` (and at least six other points remain): a shaker
/// with a force gauge and no accelerometer beside it, or a hammer that never
/// hits the sensor's point.
pub fn draw(
    st: &Structure,
    fe: &FeModel,
    rng: &mut Rng,
    omit_driving_point: bool,
) -> Result<(LayoutKind, NodeDirection, Vec<NodeDirection>), String> {
    let mut dirs: Vec<i32> = if st.plane { vec![1, 3] } else { vec![1, 2, 3] };
    rng.shuffle(&mut dirs);
    let wanted = rng.int(6, 30);
    let mut nd = rng.int(1, dirs.len());
    let free = |node: u32, d: i32| fe.measured_dof(node, d).is_some();
    let count_free = |nd: usize| {
        st.nodes
            .iter()
            .map(|n| dirs[..nd].iter().filter(|&&d| free(n.0, d)).count())
            .sum::<usize>()
    };
    while nd < dirs.len() && count_free(nd) < wanted.min(12) {
        nd += 1;
    }
    let used = &dirs[..nd];
    let mut nodes: Vec<u32> = st.nodes.iter().map(|n| n.0).collect();
    rng.shuffle(&mut nodes);
    let mut points = Vec::new();
    for node in nodes {
        if points.len() >= wanted {
            break;
        }
        for &d in used {
            if free(node, d) && points.len() < wanted {
                points.push(NodeDirection { node, direction: d });
            }
        }
    }
    if points.len() < 3 {
        return Err(format!("only {} free measurable DOFs", points.len()));
    }
    points.sort_by_key(|p| (p.node, p.direction));
    let fixed = choose_fixed(st, fe, &points, rng)?;
    let layout = if rng.chance(0.5) {
        LayoutKind::FixedExciter
    } else {
        LayoutKind::RovingHammer
    };
    if omit_driving_point && points.len() > 6 {
        points.retain(|p| *p != fixed);
    }
    Ok((layout, fixed, points))
}

/// Score each point by min over the first six elastic modes of
/// |φ_r(point)| / max over points |φ_r|; pick at random in the best third.
fn choose_fixed(
    st: &Structure,
    fe: &FeModel,
    points: &[NodeDirection],
    rng: &mut Rng,
) -> Result<NodeDirection, String> {
    let skip = match (st.springs.is_empty(), st.plane) {
        (true, _) => 0,
        (false, true) => 3,
        (false, false) => 6,
    };
    let opts = EigenOptions {
        count: skip + 6,
        expect_no_rigid_body_modes: fe.has_fixed_dofs,
        ..EigenOptions::default()
    };
    let modes = lowest_modes(&fe.stiffness, &fe.mass, &opts).map_err(|e| e.to_string())?;
    let eqs: Vec<usize> = points
        .iter()
        .filter_map(|p| fe.measured_dof(p.node, p.direction).map(|d| d.0))
        .collect();
    let mut score = vec![f64::INFINITY; eqs.len()];
    for r in skip..modes.len() {
        let col: Vec<f64> = eqs.iter().map(|&e| modes.shapes[(e, r)].abs()).collect();
        let max = col.iter().copied().fold(0.0, f64::max).max(1e-300);
        for (s, v) in score.iter_mut().zip(&col) {
            *s = s.min(v / max);
        }
    }
    let mut order: Vec<usize> = (0..eqs.len()).collect();
    order.sort_by(|&a, &b| score[b].total_cmp(&score[a]).then(a.cmp(&b)));
    let best = &order[..order.len().div_ceil(3)];
    let i = *rng.pick(best).ok_or("no point")?;
    Ok(points[i])
}

fn dof(p: &NodeDirection) -> String {
    format!("{}:{}", p.node, p.direction)
}

/// The truth record (`truth.json`) of a case.
pub fn truth_json(c: &Case) -> serde_json::Value {
    let params: Vec<serde_json::Value> = c
        .params
        .iter()
        .map(|p| {
            json!({
                "name": p.name, "quantity": p.quantity, "ids": p.ids, "true": p.value,
                "min": p.min, "max": p.max, "sd": p.sd, "visibility": p.visibility,
            })
        })
        .collect();
    let damping = match c.damping {
        crate::benchmark::DampingSpec::Modal { zeta } => json!({"model": "modal", "zeta": zeta}),
        crate::benchmark::DampingSpec::Rayleigh { alpha, beta } => {
            json!({"model": "rayleigh", "alpha": alpha, "beta": beta})
        }
        crate::benchmark::DampingSpec::Hysteretic { eta } => {
            json!({"model": "hysteretic", "eta": eta})
        }
    };
    let mut dirs: Vec<i32> = c.points.iter().map(|p| p.direction).collect();
    dirs.sort_unstable();
    dirs.dedup();
    let mut out = json!({
        "seed": c.seed,
        "structure": c.structure.name(),
        "analysis": if c.plane { "plane" } else { "space" },
        "support": c.support.name(),
        "dofs": c.dofs,
        "effect": c.effects.first().map_or("none", |e| e.name()),
        "parameters": params,
        "layout": {
            "kind": c.layout.name(),
            "fixed": dof(&c.fixed),
            "points": c.points.iter().map(dof).collect::<Vec<_>>(),
            "directions": dirs,
            "channels": c.points.len(),
            "driving_point_measured": c.driving_point_measured(),
        },
        "noise": c.noise,
        "damping": damping,
        "format": if c.binary { "58b" } else { "ascii" },
        "precision": if c.single { "single" } else { "double" },
        "band": {
            "axis": c.axis.name(),
            "lines": c.lines_hz.len(),
            "start_hz": c.lines_hz.first(),
            "end_hz": c.lines_hz.last(),
        },
        "elastic_modes_hz": c.elastic_modes_hz,
        "suspension_modes_hz": c.suspension_modes_hz,
    });
    if c.diagnosis {
        if let Some(o) = out.as_object_mut() {
            o.insert(
                "effect".into(),
                json!(super::diagnose::plan_name(&c.effects)),
            );
            let effects: Vec<serde_json::Value> = c
                .effects
                .iter()
                .zip(&c.detectability)
                .map(|(e, d)| {
                    let mut v = e.truth_json();
                    if let Some(o) = v.as_object_mut() {
                        o.insert("frf_change".into(), json!(d.frf_change));
                        o.insert("freq_shift".into(), json!(d.freq_shift));
                    }
                    v
                })
                .collect();
            o.insert("effects".into(), json!(effects));
        }
    }
    out
}
