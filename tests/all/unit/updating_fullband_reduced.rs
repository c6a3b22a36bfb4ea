//! Unit tests of `src/updating/fullband/reduced.rs` through its public interface.

use faer::c64;
use frfup::model;
use frfup::model::Damping;
use frfup::model::ParameterValues;
use frfup::testdata::{Channel, FrfKind, MeasuredFrfs};
use frfup::updating::fullband::data::TestData;
use frfup::updating::fullband::fit;
use frfup::updating::fullband::fit::{predict, Mask};
use frfup::updating::fullband::reduced::*;
use frfup_parsers::deck::parse;
use frfup_parsers::deck::Deck;

/// The deck text of a uniform steel beam in the x–z plane, 0.8 m on nodes
/// 1–9 along x, beams 1–8 (nothing else).
pub fn beam_text() -> String {
    beam_text_of(9)
}

/// The deck text of a uniform steel beam in the x–z plane on `nodes` nodes
/// 0.1 m apart along x, numbered from 1, one beam between each pair.
pub fn beam_text_of(nodes: u32) -> String {
    let mut text =
        String::from("analysis plane\nmaterial st E=2.1e11 rho=7850\nsection s A=1e-3 Iy=2e-7\n");
    for i in 1..=nodes {
        text += &format!("node {i} {} 0 0\n", 0.1 * (i - 1) as f64);
    }
    for i in 1..nodes {
        text += &format!("beam {i} {i} {} st s\n", i + 1);
    }
    text
}

/// A free-free beam on soft springs, 4 channels (the Jacobian test's).
pub fn beam() -> (Deck, TestData) {
    let mut text = beam_text();
    text += "mass 1 9 m=0.2\nspring 1 1 z k=500\nspring 2 9 z k=500\n";
    text += "damping modal 0.02\nparam left E 1-4\nparam right Iy 5-8\nparam tip m 1\nparam sup k 1-2\n";
    let deck = parse(&text).unwrap();
    let lines: Vec<f64> = (1..=300).map(|i| i as f64 * 2.0).collect();
    // 1 % off the model so that residuals are not zero.
    let data = accelerances(&deck, lines, 9, &[3, 5, 7, 9], 0.02, c64::new(1.01, 0.005));
    (deck, data)
}

/// A 41-node beam (123 DOFs: more than the band's modes, so a Ritz basis
/// has a static block) on soft springs at its ends, modal damping 0.02,
/// with the deck lines `extra`; accelerances at z of nodes 5, 13, 27, 41
/// for a force at 41 z, 1.5–600 Hz.
pub fn long_beam(extra: &str) -> (Deck, TestData) {
    let mut text = beam_text_of(41);
    text += "spring 1 1 z k=500\nspring 2 41 z k=500\ndamping modal 0.02\n";
    text += extra;
    let deck = parse(&text).unwrap();
    let lines: Vec<f64> = (1..=400).map(|i| i as f64 * 1.5).collect();
    let data = accelerances(&deck, lines, 41, &[5, 13, 27, 41], 0.02, c64::new(1.0, 0.0));
    (deck, data)
}

/// Accelerances of `deck` (direct solution, modal damping `zeta`) at z of
/// `nodes` for a force at z of `input`, times `factor`, as test data.
pub fn accelerances(
    deck: &Deck,
    lines: Vec<f64>,
    input: u32,
    nodes: &[u32],
    zeta: f64,
    factor: c64,
) -> TestData {
    let fe = model::build(deck, &ParameterValues::new()).unwrap();
    let omegas: Vec<f64> = lines
        .iter()
        .map(|f| 2.0 * std::f64::consts::PI * f)
        .collect();
    let outputs: Vec<usize> = nodes
        .iter()
        .map(|&n| fe.measured_dof(n, 3).unwrap().0)
        .collect();
    let h = frfup::solvers::frf::direct_receptance(
        &fe.stiffness,
        &fe.mass,
        Damping::Modal { zeta },
        &omegas,
        fe.measured_dof(input, 3).unwrap().0,
        &outputs,
    );
    let channels = nodes
        .iter()
        .enumerate()
        .map(|(o, &node)| Channel {
            response_node: node as i64,
            response_direction: 3,
            reference_node: input as i64,
            reference_direction: 3,
            values: (0..omegas.len())
                .map(|l| h[(o, l)] * (-omegas[l] * omegas[l]) * factor)
                .collect(),
        })
        .collect();
    let test = MeasuredFrfs {
        frequencies_hz: lines,
        kind: FrfKind::Accelerance,
        channels,
    };
    TestData::new(&test).unwrap()
}

/// At its anchor the reduced model's FRFs are the full modal model's
/// (modes plus R0 + ω²R1) to within a small part of the 1 % floor.
#[test]
fn reduced_frfs_match_the_modal_model_at_the_anchor() {
    let (deck, data) = beam();
    let names = model::parameter_names(&deck);
    let p = [0.1, -0.05, 0.2, 0.0];
    let red = ReducedModel::new(&deck, &names, &p, &data).unwrap();
    let values: ParameterValues = names.iter().cloned().zip(p).collect();
    let full = fit::modal_model(&model::updated_deck(&deck, &values), &data).unwrap();
    let damping = Damping::Modal { zeta: 0.02 };
    let mask = Mask::all(&data);
    let a = predict(&red.solve(&p).unwrap().model, damping, &data, &mask);
    let b = predict(&full, damping, &data, &mask);
    let mut worst = 0.0f64;
    for (ac, bc) in a.iter().zip(&b) {
        for (x, y) in ac.iter().zip(bc) {
            worst = worst.max(((x - y).norm() / y.norm()).min(1.0));
        }
    }
    assert!(worst < 1e-3, "largest relative difference {worst:e}");
}

/// Largest relative difference between two sets of model FRFs (capped at 1).
fn largest_relative_difference(a: &[Vec<c64>], b: &[Vec<c64>]) -> f64 {
    let mut worst = 0.0f64;
    for (ac, bc) in a.iter().zip(b) {
        for (x, y) in ac.iter().zip(bc) {
            worst = worst.max(((x - y).norm() / y.norm()).min(1.0));
        }
    }
    worst
}

/// A reduced model moved to a point 10–20 % from its anchor (one inverse
/// iteration of the full pencil on the old basis's Ritz vectors there) gives
/// the FRFs of a new anchor at that point within 2.5e-4 (a fortieth of the
/// weights' 1 % model floor; measured 6.0e-5 with at least 40 modes in the
/// basis, 1.14e-4 since it holds those up to 4·ω_max, at the band's top
/// modes, which one inverse iteration converges least), and over 100 times closer than
/// the old basis without the move (1.6e-2): the test fails if the inverse
/// iteration is left out or the basis lost.
#[test]
fn a_moved_reduced_model_matches_a_new_anchor() {
    // 41 nodes (123 DOFs): more than the band's modes, so the basis has a
    // static block and `moved` does not fall back to a new solution.
    let (deck, data) = long_beam("param left E 1-20\nparam right Iy 21-40\nparam sup k 1-2\n");
    let names = model::parameter_names(&deck);
    let (p0, p) = ([0.0, 0.0, 0.0], [0.2, -0.1, 0.15]);
    let old = ReducedModel::new(&deck, &names, &p0, &data).unwrap();
    assert!(old.size() < 123, "the basis has every mode: {}", old.size());
    let moved = old
        .moved(&deck, &names, &p, &data, &old.solve(&p).unwrap())
        .unwrap();
    let fresh = ReducedModel::new(&deck, &names, &p, &data).unwrap();
    let damping = Damping::Modal { zeta: 0.02 };
    let mask = Mask::all(&data);
    let frfs = |m: &ReducedModel| predict(&m.solve(&p).unwrap().model, damping, &data, &mask);
    let exact = frfs(&fresh);
    let moved_error = largest_relative_difference(&frfs(&moved), &exact);
    let stale_error = largest_relative_difference(&frfs(&old), &exact);
    assert!(moved_error < 2.5e-4, "moved: {moved_error:e}");
    assert!(
        moved_error < 1e-2 * stale_error,
        "moved {moved_error:e}, old {stale_error:e}"
    );
}

/// The reduced model's parameter derivatives T ᵀ(∂K/∂p̄_j)T and
/// Tᵀ(∂M/∂p̄_j)T, checked through the eigenvalue derivative they give at the
/// anchor, ∂λ_r = ψ_rᵀ(K_j − λ_r M_j)ψ_r (Fox & Kapoor; ψ_r is the full
/// model's mode there), against central differences of the full model's
/// eigenvalues (h = 1e-5: truncation ~h², round-off ~ε/h, both far below
/// the 1e-6 relative tolerance), over the first six modes with λ > 1
/// rad²/s². Each parameter touches part of the model
/// (half the beams' E or Iy, the tip mass, the springs), so the test fails
/// if the projection on a parameter's support rows is wrong.
#[test]
fn parameter_derivatives_give_the_full_models_eigenvalue_derivatives() {
    let (deck, data) = beam();
    let names = model::parameter_names(&deck);
    let p = [0.1, -0.05, 0.2, 0.0];
    let red = ReducedModel::new(&deck, &names, &p, &data).unwrap();
    let modes = red.solve(&p).unwrap();
    let full_at = |q: &[f64]| {
        let values: ParameterValues = names.iter().cloned().zip(q.iter().copied()).collect();
        fit::modal_model(&model::updated_deck(&deck, &values), &data)
            .unwrap()
            .omega2
    };
    let h = 1e-3;
    for j in 0..names.len() {
        let (dk, dm) = red.derivative(j);
        let (mut up, mut down) = (p, p);
        up[j] += h;
        down[j] -= h;
        let (wu, wd) = (full_at(&up), full_at(&down));
        // The modes that are not rigid-body ones (this plane model is free
        // along x: an eigenvalue ~1e-7 there, all round-off).
        let elastic = (0..wu.len()).filter(|&r| modes.model.omega2[r] > 1.0);
        for r in elastic.take(6) {
            let psi = modes.shapes.col(r);
            let quad = |s: faer::MatRef<'_, f64>| {
                let mut v = 0.0;
                for a in 0..psi.nrows() {
                    for b in 0..psi.nrows() {
                        v += psi[a] * s[(a, b)] * psi[b];
                    }
                }
                v
            };
            let lam = modes.model.omega2[r];
            let analytic = quad(dk) - lam * dm.map_or(0.0, quad);
            let numeric = (wu[r] - wd[r]) / (2.0 * h);
            assert!(
                (analytic - numeric).abs() <= 1e-5 * lam,
                "{} mode {r}: {analytic} against {numeric} (λ = {lam})",
                names[j]
            );
        }
    }
}
