//! Unit tests of `src/diagnosis/localise.rs` through its public interface.

use crate::unit::updating_fullband_reduced::{accelerances, beam_text_of};
use faer::c64;
use frfup::diagnosis::hypotheses::{Extension, Hypothesis, ParamSpec, Physics};
use frfup::diagnosis::localise::{probe, reduction};
use frfup::model::Damping;
use frfup::updating::fullband::fit::{self, Mask};
use frfup_parsers::deck::parse;

/// An added mass at node `n` probed at 0.05 kg (the beam is 1.2 kg).
fn added_mass(n: u32) -> Hypothesis {
    Hypothesis {
        physics: Physics::AddedMass,
        nodes: vec![n],
        dofs: Vec::new(),
        param: Some(ParamSpec {
            name: "m",
            lo: 1e-3,
            hi: 1.0,
            probe: 0.05,
            unit: "kg",
        }),
        extension: Extension::Masses { nodes: vec![n] },
        label: format!("added-mass at node {n}"),
    }
}

/// The probes of candidates that keep the deck's DOFs are taken on one
/// Ritz basis of the deck; their scores match those of full solutions
/// (each candidate's deck solved and its Δr taken against the full r₀) to
/// 1e-4 of |r₀|² (measured 1.4e-5, the best score being 0.9986: the Ritz
/// model's error at a mass of 4 % of the beam's), and
/// both rank the truth's node first. A 41-node free-free beam on soft
/// springs (123 DOFs: the basis has a static block), a 0.1 kg mass at node
/// 17 missing from the deck, five channels.
#[test]
fn probes_on_the_ritz_basis_score_as_full_solutions() {
    let mut text = beam_text_of(41);
    text += "spring 1 1 z k=500\nspring 2 41 z k=500\n";
    let base = parse(&text).unwrap();
    let truth = parse(&(text.clone() + "mass 1 17 m=0.1\n")).unwrap();
    let lines: Vec<f64> = (1..=400).map(|i| i as f64 * 1.5).collect();
    let data = accelerances(
        &truth,
        lines,
        41,
        &[5, 13, 21, 29, 41],
        0.02,
        c64::new(1.0, 0.0),
    );
    let damping = fit::start_damping(Damping::Modal { zeta: 0.02 }, &data);
    let mask = Mask::all(&data);
    let residual = |deck: &frfup_parsers::deck::Deck| {
        let mm = fit::modal_model(deck, &data).unwrap();
        fit::residuals(
            &fit::predict(&mm, damping.damping(), &data, &mask),
            &data,
            &mask,
        )
    };
    let r0 = residual(&base);
    let n0: f64 = r0.iter().map(|v| v * v).sum();
    let candidates: Vec<Hypothesis> = (2..=40).map(added_mass).collect();
    let probes = probe(&base, &r0, &[], &damping, &data, &candidates);
    let full: Vec<f64> = candidates
        .iter()
        .map(|h| {
            let r = residual(&h.apply(&base, Some(0.05)));
            let delta: Vec<f64> = r.iter().zip(&r0).map(|(a, b)| a - b).collect();
            reduction(&r0, &delta) / n0
        })
        .collect();
    let mut worst = 0.0f64;
    for (p, f) in probes.iter().zip(&full) {
        worst = worst.max((p.score - f).abs());
    }
    assert!(worst < 1e-4, "largest score difference {worst:e}");
    let best = |s: &[f64]| (0..s.len()).max_by(|&a, &b| s[a].total_cmp(&s[b])).unwrap();
    let ritz: Vec<f64> = probes.iter().map(|p| p.score).collect();
    assert_eq!(candidates[best(&ritz)].nodes, vec![17]);
    assert_eq!(candidates[best(&full)].nodes, vec![17]);
}
