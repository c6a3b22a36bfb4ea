//! `benchmark::score_diagnosis`: the place of a finding, and ties (a true
//! effect named only among the alternatives the data cannot tell apart)
//! counted apart from the strict score.

use frfup::benchmark::score_diagnosis;
use frfup::parsers::deck;
use serde_json::json;

/// A portal in the x-z plane meshed with two elements per member: feet 1
/// and 4, corners 2 and 3, mid-points 5 (1–2), 6 (2–3), 7 (3–4).
fn portal() -> deck::Deck {
    deck::parse(
        "analysis plane\nmaterial s E=2e11 rho=7800\nsection b A=1e-4 Iy=1e-8\n\
         node 1 0 0 0\nnode 2 0 0 1\nnode 3 1 0 1\nnode 4 1 0 0\n\
         node 5 0 0 0.5\nnode 6 0.5 0 1\nnode 7 1 0 0.5\n\
         beam 1 1 5 s b\nbeam 2 5 2 s b\nbeam 3 2 6 s b\nbeam 4 6 3 s b\n\
         beam 5 3 7 s b\nbeam 6 7 4 s b\n",
    )
    .unwrap()
}

fn truth() -> serde_json::Value {
    json!({"effects": [{"class": "suspension", "nodes": [1, 4], "k": 2190.0}]})
}

fn finding(nodes: &[u32], alternatives: serde_json::Value) -> serde_json::Value {
    json!({"findings": [{
        "physics": "suspension", "nodes": nodes, "parameters": {"k": 2198.0},
        "alternatives": alternatives,
    }]})
}

#[test]
fn springs_at_the_true_feet_are_right() {
    let s = score_diagnosis(&truth(), &portal(), Some(&finding(&[1, 4], json!([]))));
    assert!(s.right() && s.right_or_tied());
    assert!(s.effects[0].place && !s.effects[0].tied);
    assert_eq!(s.effects[0].value_ok, Some(true));
}

#[test]
fn a_tie_that_names_the_truth_counts_only_as_a_tie() {
    // The corners above the feet: the same lever arms for the rigid-body
    // modes, so the data may not tell them from the feet (case 038).
    let alts = json!([{"physics": "suspension", "nodes": [1, 4]}]);
    let s = score_diagnosis(&truth(), &portal(), Some(&finding(&[2, 3], alts)));
    assert!(!s.right(), "strictly, the place is wrong");
    assert!(s.effects[0].tied && s.right_or_tied());
    assert!(s.false_findings.is_empty());
}

#[test]
fn a_tie_with_other_places_or_another_class_is_not_counted() {
    let elsewhere = json!([{"physics": "suspension", "nodes": [3, 6]}]);
    let s = score_diagnosis(&truth(), &portal(), Some(&finding(&[2, 3], elsewhere)));
    assert!(!s.effects[0].tied && !s.right_or_tied());
    let other_class = json!([{"physics": "added-mass", "nodes": [1, 4]}]);
    let s = score_diagnosis(&truth(), &portal(), Some(&finding(&[2, 3], other_class)));
    assert!(!s.effects[0].tied && !s.right_or_tied());
    // One element away from a true node is right (node 5 is beside 1).
    let s = score_diagnosis(&truth(), &portal(), Some(&finding(&[5, 7], json!([]))));
    assert!(s.right());
}
