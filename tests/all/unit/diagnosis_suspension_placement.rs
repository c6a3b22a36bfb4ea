//! Unit tests of `src/diagnosis/suspension_placement/` through its public
//! interface.

use crate::unit::updating_fullband_reduced::{accelerances, beam_text};
use faer::c64;
use frfup::diagnosis::hypotheses::{total_mass, Context};
use frfup::diagnosis::suspension_placement::*;
use frfup::updating::fullband::data::TestData;
use frfup_parsers::deck::{parse, Deck, DeckDof};

const K: f64 = 500.0;

/// A uniform free-free steel beam in the x–z plane, 0.8 m on 9 nodes; with
/// `springs`, on vertical springs K at its two ends.
fn deck(springs: bool) -> Deck {
    let mut text = beam_text();
    if springs {
        text += &format!("spring 1 1 z k={K}\nspring 2 9 z k={K}\n");
    }
    parse(&text).unwrap()
}

/// Accelerances of `deck` at z of nodes 2, 4, 6, 8, 9 for a force at 9 z,
/// 0.05–60 Hz (its suspension modes; the first elastic one is near 400 Hz).
fn test_data(deck: &Deck) -> TestData {
    let lines: Vec<f64> = (1..=1200).map(|i| i as f64 * 0.05).collect();
    accelerances(deck, lines, 9, &[2, 4, 6, 8, 9], 0.01, c64::new(1.0, 0.0))
}

fn context(deck: &Deck) -> Context<'_> {
    Context {
        deck,
        sensor_nodes: vec![2, 4, 6, 8, 9],
        total_mass: total_mass(deck),
        free_free: true,
        first_elastic_omega: 2.0 * std::f64::consts::PI * 400.0,
    }
}

/// A rigid uniform beam of mass m and length L on two springs k at its
/// ends bounces at ω² = 2k/m and pitches at ω² = 2k(L/2)²/(mL²/12) = 6k/m,
/// with shapes 1 and x − L/2. Given those, the placement is the two ends
/// and k comes back to rounding (the consistent mass matrix holds the rigid
/// body's mass and inertia exactly).
#[test]
fn the_ends_and_k_from_the_closed_form_rigid_body_modes() {
    let free = deck(false);
    let data = test_data(&free);
    let m = 7850.0 * 1e-3 * 0.8;
    let hz = |w2: f64| w2.sqrt() / (2.0 * std::f64::consts::PI);
    let x = [0.1, 0.3, 0.5, 0.7, 0.8];
    let test = SuspensionModes {
        frequency_hz: vec![hz(2.0 * K / m), hz(6.0 * K / m)],
        shapes: vec![vec![1.0; 5], x.iter().map(|x| x - 0.4).collect()],
    };
    let placed = placements(&context(&free), &data, &test, 3);
    let best = &placed[0];
    assert_eq!((best.nodes.clone(), best.dof), (vec![1, 9], DeckDof::Z));
    assert!((best.k / K - 1.0).abs() < 1e-9, "k = {}", best.k);
    // Nothing but the cost of the second spring (1e-3).
    assert!((best.score - 1e-3).abs() < 1e-9, "score {}", best.score);
    // Every other set misses the frequency ratio √3 or the pitch's node.
    assert!(placed[1].score > 0.05, "runner-up {:?}", placed[1]);
}

/// End to end: the suspension modes identified from FRFs simulated on the
/// springs (the elastic modes' coupling shifts them by ~(2 Hz / 400 Hz)²),
/// then placed on the deck without them.
#[test]
fn springs_at_the_ends_are_placed_from_simulated_frfs() {
    let data = test_data(&deck(true));
    let free = deck(false);
    let test = test_suspension_modes(&data, &identified_modes(&data), 400.0);
    assert_eq!(test.frequency_hz.len(), 2, "{:?}", test.frequency_hz);
    let placed = placements(&context(&free), &data, &test, 3);
    assert_eq!(placed[0].nodes, vec![1, 9]);
    // The identification's frequencies (0.01 % here) set k to twice that.
    assert!((placed[0].k / K - 1.0).abs() < 2e-3, "k = {}", placed[0].k);
}

/// Lines 1.5 Hz apart from 1.5 Hz (the suspension modes, bounce 2.0 Hz and
/// pitch 3.5 Hz, fall between the first three lines: no pole fit resolves
/// them): the low band alone places the springs at the two ends. k comes
/// from a grid and 24 golden-section steps on ln k (resolution 1e-5 of two
/// grid steps); the data are exact but for the elastic modes' coupling, of
/// order (3.5 Hz / 400 Hz)² ≈ 1e-4 in ω²: within 1e-3.
#[test]
fn springs_at_the_ends_are_placed_from_the_low_band_alone() {
    let lines: Vec<f64> = (1..=130).map(|i| i as f64 * 1.5).collect();
    let data = accelerances(
        &deck(true),
        lines,
        9,
        &[2, 4, 6, 8, 9],
        0.01,
        c64::new(1.0, 0.0),
    );
    let free = deck(false);
    let damping = frfup::model::Damping::Modal { zeta: 0.01 };
    let mask = frfup::updating::fullband::fit::Mask::all(&data);
    let placed = low_band_placements(&context(&free), &data, damping, &mask, 3);
    assert_eq!(
        (placed[0].nodes.clone(), placed[0].dof),
        (vec![1, 9], DeckDof::Z),
        "{placed:?}"
    );
    assert!((placed[0].k / K - 1.0).abs() < 1e-3, "k = {}", placed[0].k);
    // Springs one node in from the ends hold the same two modes at other
    // frequency ratios: their misfit is far larger.
    let inner = placed.iter().find(|p| p.nodes != vec![1, 9]).unwrap();
    assert!(
        inner.score > 10.0 * placed[0].score.max(1e-12),
        "{placed:?}"
    );
}

/// A deck with springs already (no rigid-body mode) gets no placement.
#[test]
fn no_low_band_placement_on_a_deck_with_springs() {
    let lines: Vec<f64> = (1..=130).map(|i| i as f64 * 1.5).collect();
    let sprung = deck(true);
    let data = accelerances(
        &sprung,
        lines,
        9,
        &[2, 4, 6, 8, 9],
        0.01,
        c64::new(1.0, 0.0),
    );
    let damping = frfup::model::Damping::Modal { zeta: 0.01 };
    let mask = frfup::updating::fullband::fit::Mask::all(&data);
    assert!(low_band_placements(&context(&sprung), &data, damping, &mask, 3).is_empty());
}
