//! The cases of the `frfup diagnose` benchmark: the update benchmark's
//! random structures, parameters, layouts and damping, with 0–2 effects of
//! different classes (every class of the diagnosis dictionary and the data
//! errors) at random places and strengths, each detectable, and 1–3 % noise.
//!
//! Mix: 15 % parameter-only controls, 55 % one effect, 30 % two; classes
//! uniform among [`CLASSES`]. The plan is drawn first from the seed, the
//! structure fitted to it (suspension: a free-free deck without springs;
//! support flexibility: clamped or pinned; joint flexibility: a frame;
//! shear deformation: sections 2.5–6 × stockier).

use super::effects::{self, bare, Setting};
use super::{
    draw_axis, draw_damping_and_parameters, layout, modes_hz, parse_deck, structure, Case, Drawn,
    GenError, GenOptions,
};
use crate::benchmark::effect::CLASSES;
use crate::benchmark::{round_sig, Effect, LayoutKind, Rng, StructureKind, Support};
use crate::model::{self, ParameterValues};
use crate::simulate::{self, Band, Campaign, NodeDirection, Sensors};
use crate::testdata::FrfKind;

/// The classes of a case: none (control), one, or two different ones.
pub fn draw_plan(rng: &mut Rng) -> Vec<&'static str> {
    let u = rng.uniform();
    let pick = |rng: &mut Rng| *rng.pick(&CLASSES).unwrap_or(&"damping");
    if u < 0.15 {
        return Vec::new();
    }
    let a = pick(rng);
    if u < 0.70 {
        return vec![a];
    }
    loop {
        let b = pick(rng);
        let clash = |x: &str, y: &str| {
            (x == "suspension" && y == "support-flexibility")
                || (y == "suspension" && x == "support-flexibility")
        };
        if b != a && !clash(a, b) {
            return vec![a, b];
        }
    }
}

/// Make the diagnosis case of `seed`: the plan, then up to 20 draws of a
/// structure and test on which every planned effect is detectable.
pub fn generate_diagnosis(seed: u64, opts: &GenOptions) -> Result<Case, GenError> {
    let mut rng = Rng::new(seed);
    let plan = draw_plan(&mut rng);
    let mut last = String::new();
    for _ in 0..20 {
        match try_case(seed, &plan, &mut rng, opts) {
            Ok(case) => return Ok(case),
            Err(e) => last = e,
        }
    }
    Err(GenError(format!("seed {seed} ({plan:?}): {last}")))
}

/// A structure that admits the plan.
fn draw_structure(
    plan: &[&str],
    rng: &mut Rng,
    opts: &GenOptions,
) -> Result<(super::Structure, bool), String> {
    let has = |c: &str| plan.contains(&c);
    let kinds: Vec<StructureKind> = StructureKind::ALL
        .into_iter()
        .filter(|k| !has("joint-flexibility") || *k != StructureKind::Beam)
        .collect();
    let kind = *rng.pick(&kinds).ok_or("no kind")?;
    let supports: &[Support] = if has("suspension") {
        &[Support::FreeFree]
    } else if has("support-flexibility") {
        &[Support::Clamped, Support::Pinned]
    } else {
        &[Support::FreeFree, Support::Clamped, Support::Pinned]
    };
    let support = *rng.pick(supports).ok_or("no support")?;
    let stocky = has("shear-deformation");
    let mut o = opts.clone();
    if stocky {
        o.section_scale = rng.range(2.5, 6.0);
    }
    let mut st = structure::build(kind, support, rng, &o)?;
    if support == Support::FreeFree && !has("suspension") {
        structure::suspend(&mut st, rng)?;
    }
    Ok((st, stocky))
}

/// One attempt of [`generate_diagnosis`].
fn try_case(seed: u64, plan: &[&str], rng: &mut Rng, opts: &GenOptions) -> Result<Case, String> {
    let (mut st, stocky) = draw_structure(plan, rng, opts)?;
    let n_modes = rng.int(4, 8);
    let Drawn {
        nominal,
        n_rb,
        damping,
        params,
        values,
        ..
    } = draw_damping_and_parameters(&mut st, n_modes, rng, opts)?;
    let fe = model::build(&nominal, &ParameterValues::new()).map_err(|e| e.to_string())?;
    let (layout, fixed, points) = layout::draw(&st, &fe, rng, false)?;
    let ref_deck = parse_deck(&st.deck_text("reference", &bare(&params)))?;
    let ref_modes = modes_hz(&ref_deck, &values, n_rb + n_modes + 1)?;
    if ref_modes.len() < n_rb + n_modes + 1 {
        return Err("reference has too few modes".into());
    }
    let elastic = &ref_modes[n_rb..n_rb + n_modes];
    let f_end = round_sig(
        elastic[n_modes - 1] + 0.5 * (ref_modes[n_rb + n_modes] - elastic[n_modes - 1]),
        4,
    );
    // A suspension to be found must be inside the band: it is drawn at
    // least 1/20 of the first elastic mode.
    let low = if plan.contains(&"suspension") {
        vec![ref_modes[n_rb] / 25.0]
    } else {
        ref_modes[..n_rb].to_vec()
    };
    let (axis, lines) = draw_axis(rng, &low, elastic, f_end, damping, opts);
    let noise = round_sig(rng.range(0.01, 0.03), 3);
    let binary = rng.chance(0.5);
    let single = binary && rng.chance(0.5);
    let campaign = noise_free_campaign(layout, fixed, &points, &lines, seed);
    let reference = simulate::simulate(&ref_deck, &values, &campaign).map_err(|e| e.to_string())?;
    let set = Setting {
        st: &st,
        params: &params,
        values: &values,
        campaign,
        reference,
        ref_modes: ref_modes.clone(),
        n_rb,
        n_modes,
        noise,
        layout,
        fixed,
        points: &points,
        stocky,
    };
    let mut used = Vec::new();
    let mut drawn = Vec::new();
    for class in plan {
        drawn.push(effects::draw(class, &set, &mut used, rng)?);
    }
    let mut truth_st = st.clone();
    for (e, _) in &drawn {
        e.apply_to_structure(&mut truth_st, rng);
    }
    let truth_text = truth_st.deck_text("truth", &bare(&params));
    let truth_modes = modes_hz(&parse_deck(&truth_text)?, &values, n_rb + n_modes + 4)?;
    let truth_elastic: Vec<f64> = truth_modes
        .iter()
        .skip(n_rb)
        .copied()
        .filter(|f| *f < f_end)
        .collect();
    if truth_elastic.len() < n_modes {
        return Err("truth has too few modes in the band".into());
    }
    let title = format!(
        "frfup random diagnosis benchmark case {seed:016x}: {}",
        st.kind.name()
    );
    Ok(Case {
        seed,
        structure: st.kind,
        plane: st.plane,
        support: st.support,
        dofs: fe.dofs.len(),
        model_deck: st.deck_text(&title, &params),
        params,
        layout,
        fixed,
        points,
        damping,
        noise,
        binary,
        single,
        axis,
        lines_hz: lines,
        elastic_modes_hz: truth_elastic,
        suspension_modes_hz: truth_modes[..n_rb].to_vec(),
        effects: drawn.iter().map(|d| d.0.clone()).collect(),
        detectability: drawn.iter().map(|d| d.1).collect(),
        truth_deck: truth_text,
        diagnosis: true,
    })
}

/// The case's campaign without noise.
fn noise_free_campaign(
    layout: LayoutKind,
    fixed: NodeDirection,
    points: &[NodeDirection],
    lines: &[f64],
    seed: u64,
) -> Campaign {
    Campaign {
        input: fixed,
        band: Band {
            start_hz: lines.first().copied().unwrap_or(0.0),
            end_hz: lines.last().copied().unwrap_or(0.0),
            count: lines.len(),
        },
        lines_hz: Some(lines.to_vec()),
        response: (layout == LayoutKind::RovingHammer).then_some(fixed),
        output: FrfKind::Accelerance,
        sensors: Sensors::List(points.to_vec()),
        noise: 0.0,
        seed,
    }
}

/// The effects of a case, for the record (`none` when there are none).
pub fn plan_name(effects: &[Effect]) -> String {
    if effects.is_empty() {
        return "none".into();
    }
    effects
        .iter()
        .map(|e| e.name())
        .collect::<Vec<_>>()
        .join("+")
}
