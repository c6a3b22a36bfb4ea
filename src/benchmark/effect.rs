//! What the truth of a case has that the model deck leaves out: one
//! [`Effect`] per physics class of the diagnosis dictionary, and the data
//! errors of a test. Structural effects edit the truth [`Structure`] before
//! simulation; data errors edit the simulated FRFs.

use serde_json::{json, Value};

use super::generate::Structure;
use super::{DampingSpec, Rng};
use crate::testdata::MeasuredFrfs;

/// One effect, with where it is and how strong (SI units).
#[derive(Clone, Debug, PartialEq)]
pub enum Effect {
    /// Parameter-only case: the truth is the model deck at the true p.
    None,
    /// The truth's damping has another form (and values) than the deck's.
    Damping { truth: DampingSpec },
    /// A mass m (kg) at every node that carries a sensor (response node).
    SensorMass { nodes: Vec<u32>, mass: f64 },
    /// A fixed DOF of a support node replaced by a grounded spring k.
    SupportFlexibility {
        node: u32,
        dof: &'static str,
        k: f64,
    },
    /// The beams `moved` leave `node` for a copy of it (`new_node`), joined
    /// by a spring k (N·m/rad) on `dof` and stiff springs on the other DOFs.
    JointFlexibility {
        node: u32,
        new_node: u32,
        dof: &'static str,
        k: f64,
        moved: Vec<u32>,
        rigid: Vec<(&'static str, f64)>,
    },
    /// Grounded springs k (N/m) on `dof` at `nodes` (free-free deck).
    Suspension {
        nodes: Vec<u32>,
        dof: &'static str,
        k: f64,
    },
    /// Timoshenko theory for every beam of the truth.
    ShearDeformation,
    /// One lumped mass m (kg) at a node without a sensor.
    AddedMass { node: u32, mass: f64 },
    /// Channel `channel` (index in the file) multiplied by −1; `node` is its
    /// point (sensor, or hit point of a roving hammer).
    ReversedChannel { channel: usize, node: u32 },
    /// The values of two channels exchanged (headers kept).
    SwappedChannels {
        channels: [usize; 2],
        nodes: [u32; 2],
    },
    /// One channel multiplied by a units factor (9.81, 1000, 1/25.4, …).
    ChannelScale {
        channel: usize,
        node: u32,
        factor: f64,
    },
    /// One channel replaced by complex Gaussian noise of the case's level
    /// (RMS |n| = `noise` × RMS |H| of the channel).
    DeadChannel {
        channel: usize,
        node: u32,
        noise: f64,
    },
}

/// The classes of [`Effect`] other than `None`, as `diagnosis.json` names them.
pub const CLASSES: [&str; 11] = [
    "damping",
    "sensor-mass",
    "support-flexibility",
    "joint-flexibility",
    "suspension",
    "shear-deformation",
    "added-mass",
    "reversed-channel",
    "swapped-channels",
    "channel-scale",
    "dead-channel",
];

/// True for the classes that are data errors (the FRFs change, not the structure).
pub fn is_data_error(class: &str) -> bool {
    matches!(
        class,
        "reversed-channel" | "swapped-channels" | "channel-scale" | "dead-channel"
    )
}

impl Effect {
    /// The class name (`none` for parameter-only cases).
    pub fn name(&self) -> &'static str {
        match self {
            Effect::None => "none",
            Effect::Damping { .. } => "damping",
            Effect::SensorMass { .. } => "sensor-mass",
            Effect::SupportFlexibility { .. } => "support-flexibility",
            Effect::JointFlexibility { .. } => "joint-flexibility",
            Effect::Suspension { .. } => "suspension",
            Effect::ShearDeformation => "shear-deformation",
            Effect::AddedMass { .. } => "added-mass",
            Effect::ReversedChannel { .. } => "reversed-channel",
            Effect::SwappedChannels { .. } => "swapped-channels",
            Effect::ChannelScale { .. } => "channel-scale",
            Effect::DeadChannel { .. } => "dead-channel",
        }
    }

    /// The nodes where it is (empty for damping and shear deformation, which
    /// are everywhere).
    pub fn nodes(&self) -> Vec<u32> {
        match self {
            Effect::None | Effect::Damping { .. } | Effect::ShearDeformation => Vec::new(),
            Effect::SensorMass { nodes, .. } | Effect::Suspension { nodes, .. } => nodes.clone(),
            Effect::SupportFlexibility { node, .. }
            | Effect::JointFlexibility { node, .. }
            | Effect::AddedMass { node, .. }
            | Effect::ReversedChannel { node, .. }
            | Effect::ChannelScale { node, .. }
            | Effect::DeadChannel { node, .. } => vec![*node],
            Effect::SwappedChannels { nodes, .. } => nodes.to_vec(),
        }
    }

    /// Change the truth structure (no-op for `None` and data errors).
    pub fn apply_to_structure(&self, truth: &mut Structure, _rng: &mut Rng) {
        match self {
            Effect::Damping { truth: d } => truth.damping = Some(*d),
            Effect::SensorMass { nodes, mass } => {
                for &n in nodes {
                    let id = truth.masses.iter().map(|m| m.0).max().unwrap_or(0) + 1;
                    truth.masses.push((id, n, *mass));
                }
            }
            Effect::AddedMass { node, mass } => {
                let id = truth.masses.iter().map(|m| m.0).max().unwrap_or(0) + 1;
                truth.masses.push((id, *node, *mass));
            }
            Effect::SupportFlexibility { node, dof, k } => {
                unfix(truth, *node, dof);
                let id = next_spring_id(truth);
                truth.springs.push((id, *node, dof, *k));
            }
            Effect::Suspension { nodes, dof, k } => {
                for &n in nodes {
                    let id = next_spring_id(truth);
                    truth.springs.push((id, n, dof, *k));
                }
            }
            Effect::ShearDeformation => truth.timoshenko = true,
            Effect::JointFlexibility {
                node,
                new_node,
                dof,
                k,
                moved,
                rigid,
            } => {
                let xyz = truth
                    .nodes
                    .iter()
                    .find(|n| n.0 == *node)
                    .map_or([0.0; 3], |n| n.1);
                truth.nodes.push((*new_node, xyz));
                for b in truth.beams.iter_mut().filter(|b| moved.contains(&b.id)) {
                    for n in [&mut b.n1, &mut b.n2] {
                        if *n == *node {
                            *n = *new_node;
                        }
                    }
                }
                for &(d, kd) in std::iter::once(&(*dof, *k)).chain(rigid.iter()) {
                    let id = next_spring_id(truth);
                    truth.links.push((id, *node, d, kd, *new_node));
                }
            }
            Effect::None
            | Effect::ReversedChannel { .. }
            | Effect::SwappedChannels { .. }
            | Effect::ChannelScale { .. }
            | Effect::DeadChannel { .. } => {}
        }
    }

    /// Change the simulated FRFs (no-op for structural effects). A dead
    /// channel draws its noise from `rng`.
    pub fn apply_to_data(&self, frfs: &mut MeasuredFrfs, rng: &mut Rng) {
        let n = frfs.channels.len();
        match self {
            Effect::ReversedChannel { channel, .. } if *channel < n => {
                for v in &mut frfs.channels[*channel].values {
                    *v = -*v;
                }
            }
            Effect::ChannelScale {
                channel, factor, ..
            } if *channel < n => {
                for v in &mut frfs.channels[*channel].values {
                    *v *= *factor;
                }
            }
            Effect::SwappedChannels {
                channels: [a, b], ..
            } if *a < n && *b < n => {
                let va = std::mem::take(&mut frfs.channels[*a].values);
                let vb = std::mem::replace(&mut frfs.channels[*b].values, va);
                frfs.channels[*a].values = vb;
            }
            Effect::DeadChannel { channel, noise, .. } if *channel < n => {
                let values = &mut frfs.channels[*channel].values;
                let rms = (values.iter().map(|v| v.norm_sqr()).sum::<f64>()
                    / values.len().max(1) as f64)
                    .sqrt();
                let sigma = noise * rms / std::f64::consts::SQRT_2;
                for v in values.iter_mut() {
                    *v = faer::c64::new(sigma * gauss(rng), sigma * gauss(rng));
                }
            }
            _ => {}
        }
    }

    /// The record of this effect in `truth.json`: class, nodes, DOFs, true
    /// values (kg, N/m, N·m/rad, damping parameters) and channels.
    pub fn truth_json(&self) -> Value {
        let mut v = json!({"class": self.name(), "nodes": self.nodes()});
        let o = v.as_object_mut().expect("object");
        match self {
            Effect::Damping { truth } => {
                o.insert("damping".into(), damping_json(*truth));
            }
            Effect::SensorMass { mass, .. } | Effect::AddedMass { mass, .. } => {
                o.insert("m".into(), json!(mass));
            }
            Effect::SupportFlexibility { dof, k, .. } | Effect::Suspension { dof, k, .. } => {
                o.insert("dofs".into(), json!([dof]));
                o.insert("k".into(), json!(k));
            }
            Effect::JointFlexibility { dof, k, moved, .. } => {
                o.insert("dofs".into(), json!([dof]));
                o.insert("k".into(), json!(k));
                o.insert("moved_beams".into(), json!(moved));
            }
            Effect::ReversedChannel { channel, .. } | Effect::DeadChannel { channel, .. } => {
                o.insert("channels".into(), json!([channel]));
            }
            Effect::ChannelScale {
                channel, factor, ..
            } => {
                o.insert("channels".into(), json!([channel]));
                o.insert("factor".into(), json!(factor));
            }
            Effect::SwappedChannels { channels, .. } => {
                o.insert("channels".into(), json!(channels));
            }
            Effect::None | Effect::ShearDeformation => {}
        }
        v
    }
}

/// A damping statement as JSON (`model` and its parameters).
pub fn damping_json(d: DampingSpec) -> Value {
    match d {
        DampingSpec::Modal { zeta } => json!({"model": "modal", "zeta": zeta}),
        DampingSpec::Rayleigh { alpha, beta } => {
            json!({"model": "rayleigh", "alpha": alpha, "beta": beta})
        }
        DampingSpec::Hysteretic { eta } => json!({"model": "hysteretic", "eta": eta}),
    }
}

/// Standard normal draw (Box–Muller on two uniforms).
fn gauss(rng: &mut Rng) -> f64 {
    let u = rng.uniform().max(1e-300);
    let v = rng.uniform();
    (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
}

fn next_spring_id(st: &Structure) -> u32 {
    st.springs
        .iter()
        .map(|s| s.0)
        .chain(st.links.iter().map(|l| l.0))
        .max()
        .unwrap_or(0)
        + 1
}

/// The DOFs of a `fix` list (`all` expanded for the analysis).
pub fn fix_dofs(st: &Structure, list: &str) -> Vec<&'static str> {
    let all: &[&'static str] = if st.plane {
        &["x", "z", "ry"]
    } else {
        &["x", "y", "z", "rx", "ry", "rz"]
    };
    if list == "all" {
        return all.to_vec();
    }
    all.iter()
        .copied()
        .filter(|d| list.split(',').any(|x| x == *d))
        .collect()
}

/// Remove `dof` from the fixes of `node` (an emptied fix is dropped).
fn unfix(st: &mut Structure, node: u32, dof: &str) {
    let lists: Vec<(u32, String)> = st.fixes.clone();
    st.fixes = lists
        .into_iter()
        .filter_map(|(n, list)| {
            if n != node {
                return Some((n, list));
            }
            let left: Vec<&str> = fix_dofs(st, &list)
                .into_iter()
                .filter(|d| *d != dof)
                .collect();
            (!left.is_empty()).then(|| (n, left.join(",")))
        })
        .collect();
}
