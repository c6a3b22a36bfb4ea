//! Random updating parameters: 2–6 groups on disjoint element segments,
//! suspension springs or lumped masses, each visible in the band.

use frfup_parsers::deck::Deck;

use super::{modes_hz, parse_deck, GenOptions, Structure};
use crate::benchmark::{round_sig, ParamTruth, Rng};
use crate::model::ParameterValues;

/// Least largest relative shift of a band mode for p = 0.1 that a parameter
/// must cause to be drawn (0.3 %: several times what 0.5–3 % noise blurs).
const MIN_VISIBILITY: f64 = 0.003;

/// A candidate group before its true value is drawn.
struct Candidate {
    name: String,
    quantity: &'static str,
    ids: String,
}

/// `a-b` or `a` for a contiguous run of IDs.
fn id_range(ids: &[u32]) -> String {
    match (ids.first(), ids.last()) {
        (Some(a), Some(b)) if a != b => format!("{a}-{b}"),
        (Some(a), _) => a.to_string(),
        _ => String::new(),
    }
}

/// Candidates: each member split into 1–3 segments, each with one quantity
/// (E, Iy, rho or A, weighted 3:3:2:1), plus the suspension springs (k) and
/// each lumped mass (m), shuffled.
fn candidates(st: &Structure, rng: &mut Rng) -> Vec<Candidate> {
    let mut out = Vec::new();
    for (mi, ids) in st.members.iter().enumerate() {
        let segments = rng.int(1, (ids.len() / 2).clamp(1, 3));
        let per = ids.len().div_ceil(segments);
        for (si, chunk) in ids.chunks(per).enumerate() {
            let quantity = *rng
                .pick(&["E", "E", "E", "Iy", "Iy", "Iy", "rho", "rho", "A"])
                .unwrap_or(&"E");
            out.push(Candidate {
                name: format!("{quantity}_m{}s{}", mi + 1, si + 1),
                quantity,
                ids: id_range(chunk),
            });
        }
    }
    if !st.springs.is_empty() {
        out.push(Candidate {
            name: "k_susp".into(),
            quantity: "k",
            ids: format!("1-{}", st.springs.len()),
        });
    }
    for (id, _, _) in &st.masses {
        out.push(Candidate {
            name: format!("m_mass{id}"),
            quantity: "m",
            ids: id.to_string(),
        });
    }
    rng.shuffle(&mut out);
    out
}

/// Largest |Δf/f| of the first `count` modes for p = 0.1 of `p` alone.
fn visibility(st: &Structure, p: &ParamTruth, base: &[f64], count: usize) -> Result<f64, String> {
    // Without bounds: the generator's own decks need no `min`/`max`/`sd`.
    let bare = ParamTruth {
        min: None,
        max: None,
        sd: None,
        ..p.clone()
    };
    let deck: Deck = parse_deck(&st.deck_text("probe", std::slice::from_ref(&bare)))?;
    let values: ParameterValues = [(p.name.clone(), 0.1)].into_iter().collect();
    let modes = modes_hz(&deck, &values, count)?;
    Ok(modes
        .iter()
        .zip(base)
        .filter(|(_, b)| **b > 0.0)
        .map(|(m, b)| ((m - b) / b).abs())
        .fold(0.0, f64::max))
}

/// Draw 2–6 parameters whose 10 % change moves a band mode by ≥ 0.3 %, with
/// true values uniform in ±[0.03, `opts.max_param_change`] (0.4 by
/// default); with `opts.bounds`, half the cases
/// get `min=-0.6 max=0.6` and some parameters `sd=0.5`.
pub fn draw(
    st: &Structure,
    base: &[f64],
    n_rb: usize,
    n_modes: usize,
    rng: &mut Rng,
    opts: &GenOptions,
) -> Result<Vec<ParamTruth>, String> {
    let wanted = rng.int(2, 6);
    let bounded = opts.bounds && rng.chance(0.5);
    let count = n_rb + n_modes;
    let mut out: Vec<ParamTruth> = Vec::new();
    for c in candidates(st, rng) {
        if out.len() == wanted {
            break;
        }
        let magnitude = rng.range(0.03, opts.max_param_change);
        let value = round_sig(
            if rng.chance(0.5) {
                magnitude
            } else {
                -magnitude
            },
            4,
        );
        let mut p = ParamTruth {
            name: c.name,
            quantity: c.quantity,
            ids: c.ids,
            value,
            min: bounded.then_some(-0.6),
            max: bounded.then_some(0.6),
            sd: (bounded && rng.chance(0.5)).then_some(0.5),
            visibility: 0.0,
        };
        p.visibility = round_sig(
            visibility(st, &p, &base[..count.min(base.len())], count)?,
            4,
        );
        if p.visibility >= MIN_VISIBILITY {
            out.push(p);
        }
    }
    if out.len() < 2 {
        return Err(format!("only {} visible parameter(s)", out.len()));
    }
    Ok(out)
}
