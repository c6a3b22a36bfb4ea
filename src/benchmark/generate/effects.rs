//! The effects of the diagnosis benchmark: for a class, a random place and
//! strength, kept only when the effect is detectable in the case's test
//! (its [`Detectability::frf_change`] ≥ [`MIN_FRF_CHANGE`]).
//!
//! Strengths are drawn on a log scale from a strength u ∈ [0, 1] (0 weakest):
//! masses a fraction of the structure's mass, springs a multiple of the
//! stiffness of the beams at the node (Σ 12EI/L³ for translations, Σ
//! max(4EI/L, GJ/L) for rotations, as the diagnosis dictionary scales them).
//! A draw below the threshold is redrawn (another place, a stronger range).

use super::{parse_deck, rescale_rayleigh, Detectability, Structure};
use crate::benchmark::effect::fix_dofs;
use crate::benchmark::{round_sig, DampingSpec, Effect, LayoutKind, ParamTruth, Rng};
use crate::model::ParameterValues;
use crate::simulate::{self, Campaign, NodeDirection};
use crate::testdata::MeasuredFrfs;

/// Least FRF change, in units of the noise, of an effect that is drawn:
/// three times what the noise alone gives.
pub const MIN_FRF_CHANGE: f64 = 3.0;

/// Draws of place and strength before a class gives up on a case.
const ATTEMPTS: usize = 6;

/// What the effects of one case are drawn against.
pub(super) struct Setting<'a> {
    /// The model structure (with the case's damping).
    pub st: &'a Structure,
    pub params: &'a [ParamTruth],
    pub values: &'a ParameterValues,
    /// The noise-free campaign and its FRFs from the truth without effects.
    pub campaign: Campaign,
    pub reference: MeasuredFrfs,
    /// Natural frequencies (Hz) of the truth without effects.
    pub ref_modes: Vec<f64>,
    pub n_rb: usize,
    pub n_modes: usize,
    pub noise: f64,
    pub layout: LayoutKind,
    pub fixed: NodeDirection,
    pub points: &'a [NodeDirection],
    /// The sections were made stocky (shear deformation can be drawn).
    pub stocky: bool,
}

/// Draw an effect of `class`; channels in `used` are not touched again.
pub(super) fn draw(
    class: &str,
    set: &Setting,
    used: &mut Vec<usize>,
    rng: &mut Rng,
) -> Result<(Effect, Detectability), String> {
    for attempt in 0..ATTEMPTS {
        let u = rng.range(attempt as f64 / ATTEMPTS as f64, 1.0);
        let e = draw_one(class, set, u, used, rng)?;
        let d = detectability(set, &e)?;
        if d.frf_change >= MIN_FRF_CHANGE {
            if let Effect::SwappedChannels { channels, .. } = &e {
                used.extend(channels);
            }
            match &e {
                Effect::ReversedChannel { channel, .. }
                | Effect::ChannelScale { channel, .. }
                | Effect::DeadChannel { channel, .. } => used.push(*channel),
                _ => {}
            }
            return Ok((e, d));
        }
    }
    Err(format!("{class}: no detectable draw"))
}

/// The response nodes (what carries a sensor): the points of a fixed
/// exciter test, the fixed sensor of a roving hammer test.
pub(super) fn sensor_nodes(set: &Setting) -> Vec<u32> {
    let mut v: Vec<u32> = match set.layout {
        LayoutKind::FixedExciter => set.points.iter().map(|p| p.node).collect(),
        LayoutKind::RovingHammer => vec![set.fixed.node],
    };
    v.sort_unstable();
    v.dedup();
    v
}

/// One draw of `class` at strength `u`.
fn draw_one(
    class: &str,
    set: &Setting,
    u: f64,
    used: &[usize],
    rng: &mut Rng,
) -> Result<Effect, String> {
    let st = set.st;
    let total = st.total_mass();
    let free_channels: Vec<usize> = (0..set.points.len())
        .filter(|c| !used.contains(c))
        .collect();
    let channel = |rng: &mut Rng| {
        rng.pick(&free_channels)
            .copied()
            .ok_or("no channel left".to_string())
    };
    let node_of = |c: usize| set.points[c].node;
    Ok(match class {
        "damping" => Effect::Damping {
            truth: other_damping(set, u, rng),
        },
        "sensor-mass" => {
            let nodes = sensor_nodes(set);
            let f = 0.005 * 40f64.powf(u);
            Effect::SensorMass {
                mass: round_sig(total * f / nodes.len().max(1) as f64, 3),
                nodes,
            }
        }
        "added-mass" => {
            let sensors = sensor_nodes(set);
            let clamped: Vec<u32> = st
                .fixes
                .iter()
                .filter(|f| f.1 == "all")
                .map(|f| f.0)
                .collect();
            let nodes: Vec<u32> = st
                .nodes
                .iter()
                .map(|n| n.0)
                .filter(|n| !sensors.contains(n) && !clamped.contains(n))
                .collect();
            Effect::AddedMass {
                node: *rng.pick(&nodes).ok_or("no node without a sensor")?,
                mass: round_sig(total * 0.01 * 50f64.powf(u), 3),
            }
        }
        "support-flexibility" => {
            let fixed: Vec<(u32, &'static str)> = st
                .fixes
                .iter()
                .flat_map(|(n, l)| fix_dofs(st, l).into_iter().map(move |d| (*n, d)))
                .collect();
            let &(node, dof) = rng.pick(&fixed).ok_or("no support")?;
            let k = stiffness_scale(st, node, dof) * 30.0 * 1e-3f64.powf(u);
            Effect::SupportFlexibility {
                node,
                dof,
                k: round_sig(k, 3),
            }
        }
        "joint-flexibility" => joint(st, u, rng)?,
        "suspension" => {
            if !st.springs.is_empty() || !st.fixes.is_empty() {
                return Err("suspension needs a free-free deck".into());
            }
            let f1 = set.ref_modes[set.n_rb];
            let ws = 2.0 * std::f64::consts::PI * f1 / (20.0 * 0.2f64.powf(u));
            let nodes = st.key_nodes.clone();
            let k = round_sig(total * ws * ws / nodes.len() as f64, 3);
            Effect::Suspension { nodes, dof: "z", k }
        }
        "shear-deformation" if set.stocky => Effect::ShearDeformation,
        "shear-deformation" => return Err("shear deformation needs stocky sections".into()),
        "reversed-channel" => {
            let c = channel(rng)?;
            Effect::ReversedChannel {
                channel: c,
                node: node_of(c),
            }
        }
        "channel-scale" => {
            let c = channel(rng)?;
            let factors = [9.81, 1.0 / 9.81, 1000.0, 1e-3, 25.4, 1.0 / 25.4];
            Effect::ChannelScale {
                channel: c,
                node: node_of(c),
                factor: *rng.pick(&factors).unwrap_or(&9.81),
            }
        }
        "swapped-channels" => {
            let a = channel(rng)?;
            let b = channel(rng)?;
            if a == b {
                return Err("swapped-channels needs two channels".into());
            }
            let (a, b) = (a.min(b), a.max(b));
            Effect::SwappedChannels {
                channels: [a, b],
                nodes: [node_of(a), node_of(b)],
            }
        }
        "dead-channel" => {
            let c = channel(rng)?;
            Effect::DeadChannel {
                channel: c,
                node: node_of(c),
                noise: set.noise,
            }
        }
        other => return Err(format!("unknown effect class {other}")),
    })
}

/// A damping of another form than the deck's: its equivalent ratio at the
/// first and last band modes is the deck's times e^(±m), m = 0.15 + 0.95u
/// (a factor 1.16 to 3), within 0.2–5 %.
fn other_damping(set: &Setting, u: f64, rng: &mut Rng) -> DampingSpec {
    let deck = set.st.damping.unwrap_or(DampingSpec::Modal { zeta: 0.01 });
    let (fa, fb) = (
        set.ref_modes[set.n_rb],
        set.ref_modes[set.n_rb + set.n_modes - 1],
    );
    let m = 0.15 + 0.95 * u;
    let mut factor = || if rng.chance(0.5) { m.exp() } else { (-m).exp() };
    let za = (deck.zeta_at(fa) * factor()).clamp(0.002, 0.05);
    let zb = (deck.zeta_at(fb) * factor()).clamp(0.002, 0.05);
    let forms: Vec<usize> = (0..3)
        .filter(|&i| {
            i != ["modal", "hysteretic", "rayleigh"]
                .iter()
                .position(|n| *n == deck.name())
                .unwrap_or(0)
        })
        .collect();
    match rng.pick(&forms).copied().unwrap_or(2) {
        0 => DampingSpec::Modal {
            zeta: round_sig(za, 3),
        },
        1 => DampingSpec::Hysteretic {
            eta: round_sig(2.0 * za, 3),
        },
        _ => rescale_rayleigh(
            DampingSpec::Rayleigh {
                alpha: za,
                beta: zb,
            },
            fa,
            fb,
        ),
    }
}

/// Nodes where members meet at an angle, with the beams the dictionary
/// moves there: all but the first beam at the node (in deck order) and any
/// beam running straight on from it. Fixed nodes are left out.
pub(super) fn joint_nodes(st: &Structure) -> Vec<(u32, Vec<u32>)> {
    let pos = |id: u32| {
        st.nodes
            .iter()
            .find(|n| n.0 == id)
            .map_or([0.0; 3], |n| n.1)
    };
    let mut out = Vec::new();
    for &(n, p) in &st.nodes {
        if st.fixes.iter().any(|f| f.0 == n) {
            continue;
        }
        let beams: Vec<_> = st.beams.iter().filter(|b| b.n1 == n || b.n2 == n).collect();
        let mut members: Vec<usize> = beams.iter().map(|b| b.member).collect();
        members.sort_unstable();
        members.dedup();
        if beams.len() < 2 || members.len() < 2 {
            continue;
        }
        let dir = |b: &super::BeamElement| {
            let q = pos(if b.n1 == n { b.n2 } else { b.n1 });
            let v = [q[0] - p[0], q[1] - p[1], q[2] - p[2]];
            let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt().max(1e-300);
            [v[0] / l, v[1] / l, v[2] / l]
        };
        let d0 = dir(beams[0]);
        let moved: Vec<u32> = beams[1..]
            .iter()
            .filter(|b| {
                let d = dir(b);
                d[0] * d0[0] + d[1] * d0[1] + d[2] * d0[2] >= -0.95
            })
            .map(|b| b.id)
            .collect();
        if !moved.is_empty() {
            out.push((n, moved));
        }
    }
    out
}

/// A flexible joint: k = (0.01 to 3) × the rotational stiffness scale on one
/// rotation, 10³ × the scale on every other DOF.
fn joint(st: &Structure, u: f64, rng: &mut Rng) -> Result<Effect, String> {
    let nodes = joint_nodes(st);
    let (node, moved) = rng.pick(&nodes).cloned().ok_or("no joint")?;
    let dofs: &[&'static str] = if st.plane {
        &["x", "z", "ry"]
    } else {
        &["x", "y", "z", "rx", "ry", "rz"]
    };
    let dof = if st.plane {
        "ry"
    } else {
        *rng.pick(&["rx", "ry", "rz"]).unwrap_or(&"ry")
    };
    let k = stiffness_scale(st, node, dof) * 3.0 * (1.0f64 / 300.0).powf(u);
    let rigid = dofs
        .iter()
        .filter(|d| **d != dof)
        .map(|d| (*d, round_sig(1e3 * stiffness_scale(st, node, d), 3)))
        .collect();
    Ok(Effect::JointFlexibility {
        node,
        new_node: st.nodes.iter().map(|n| n.0).max().unwrap_or(0) + 1,
        dof,
        k: round_sig(k, 3),
        moved,
        rigid,
    })
}

/// Stiffness scale of the beams at `node` for `dof`: Σ 12EI/L³
/// (translations) or Σ max(4EI/L, GJ/L) (rotations), I the larger second
/// moment (Iy in plane), G = E/2.6 (ν = 0.3).
pub(super) fn stiffness_scale(st: &Structure, node: u32, dof: &str) -> f64 {
    let rot = dof.starts_with('r');
    let mut k = 0.0;
    for b in st.beams.iter().filter(|b| b.n1 == node || b.n2 == node) {
        let (m, s) = (&st.materials[b.material], &st.sections[b.section]);
        let l = st.length(b);
        if l <= 0.0 {
            continue;
        }
        let i = if st.plane { s.iy } else { s.iy.max(s.iz) };
        k += if rot {
            (4.0 * m.e * i / l).max(m.e / 2.6 * s.j / l)
        } else {
            12.0 * m.e * i / l.powi(3)
        };
    }
    if k > 0.0 {
        k
    } else {
        1.0
    }
}

/// The effect's [`Detectability`] against the reference of `set`.
pub(super) fn detectability(set: &Setting, e: &Effect) -> Result<Detectability, String> {
    let (frfs, shift) = if crate::benchmark::effect::is_data_error(e.name()) {
        let mut f = set.reference.clone();
        e.apply_to_data(&mut f, &mut Rng::new(0x00DE_7EC7));
        (f, 0.0)
    } else {
        let mut truth = set.st.clone();
        e.apply_to_structure(&mut truth, &mut Rng::new(0));
        let deck = parse_deck(&truth.deck_text("probe", &bare(set.params)))?;
        let f = simulate::simulate(&deck, set.values, &set.campaign).map_err(|e| e.to_string())?;
        let count = set.n_rb + set.n_modes;
        let modes = super::modes_hz(&deck, set.values, count)?;
        let shift = (set.n_rb..count.min(modes.len()))
            .map(|i| ((modes[i] - set.ref_modes[i]) / set.ref_modes[i]).abs())
            .fold(0.0, f64::max);
        (f, shift)
    };
    Ok(Detectability {
        frf_change: round_sig(frf_change(&set.reference, &frfs, set.noise), 4),
        freq_shift: round_sig(shift, 4),
    })
}

/// RMS over channels and lines of |H − H_ref| / (noise × RMS |H_ref,c|).
/// A channel the reference leaves at rounding level (an axial sensor of a
/// straight beam excited across it: its response is zero by symmetry)
/// takes the noise of a channel at [`SILENT`] × the strongest channel's
/// RMS: rounding differences there are not a change anyone can see.
pub fn frf_change(reference: &MeasuredFrfs, other: &MeasuredFrfs, noise: f64) -> f64 {
    let rms2 = |values: &[faer::c64]| {
        values.iter().map(|v| v.norm_sqr()).sum::<f64>() / values.len().max(1) as f64
    };
    let strongest = reference
        .channels
        .iter()
        .map(|c| rms2(&c.values))
        .fold(0.0, f64::max);
    let floor = SILENT * SILENT * strongest;
    let mut sum = 0.0;
    let mut n = 0usize;
    for (a, b) in reference.channels.iter().zip(&other.channels) {
        let sigma2 = (noise * noise * rms2(&a.values).max(floor)).max(1e-300);
        for (x, y) in a.values.iter().zip(&b.values) {
            sum += (x - y).norm_sqr() / sigma2;
            n += 1;
        }
    }
    (sum / n.max(1) as f64).sqrt()
}

/// RMS, relative to the campaign's strongest channel, below which a
/// reference channel counts as silent in [`frf_change`] (rounding of a
/// response that is zero by symmetry sits near 1e-15).
const SILENT: f64 = 1e-8;

/// Parameters without bounds (the truth deck's `param` lines).
pub(super) fn bare(params: &[ParamTruth]) -> Vec<ParamTruth> {
    params
        .iter()
        .map(|p| ParamTruth {
            min: None,
            max: None,
            sd: None,
            ..p.clone()
        })
        .collect()
}
