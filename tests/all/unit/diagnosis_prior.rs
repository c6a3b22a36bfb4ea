//! The placement prior of the diagnosis (`diagnosis::hypotheses::prior`):
//! hard points from the deck's geometry, and the free choices of place a
//! candidate makes.

use frfup::diagnosis::hypotheses::prior::{hard_points, placement_penalty, tie_penalty, tie_pick};
use frfup::diagnosis::hypotheses::{masses, shear, springs, Context};
use frfup_parsers::deck::Deck;

fn deck(text: &str) -> Deck {
    frfup_parsers::deck::parse(text).expect("test deck parses")
}

const L_FRAME: &str = "analysis plane\n\
    material m E=2.1e11 nu=0.3 rho=7850\n\
    section s A=1e-4 Iy=1e-9 Iz=1e-9 J=2e-9\n\
    node 1 0 0 0\nnode 2 0.5 0 0\nnode 3 1 0 0\nnode 4 1 0 0.5\nnode 5 1 0 1\n\
    beam 1 1 2 m s\nbeam 2 2 3 m s\nbeam 3 3 4 m s\nbeam 4 4 5 m s\n";

/// The L-frame free-free, with sensors at nodes 2 and 4 (also the
/// context of `diagnosis_hypotheses`).
pub(super) fn l_frame_context(d: &Deck) -> Context<'_> {
    Context {
        deck: d,
        sensor_nodes: vec![2, 4],
        total_mass: 1.0,
        free_free: true,
        first_elastic_omega: 100.0,
    }
}

#[test]
fn ends_and_corners_are_hard_points_and_straight_runs_are_not() {
    assert_eq!(hard_points(&deck(L_FRAME)), vec![1, 3, 5]);
}

#[test]
fn springs_along_a_member_and_a_mass_at_any_node_cost_a_choice() {
    let d = deck(L_FRAME);
    let ctx = l_frame_context(&d);
    let hung = |nodes: Vec<u32>| springs::suspension(&ctx, nodes, frfup_parsers::deck::DeckDof::Z);
    assert_eq!(placement_penalty(&hung(vec![1, 5]), &d), 0);
    assert_eq!(placement_penalty(&hung(vec![1, 4]), &d), 1);
    assert_eq!(placement_penalty(&hung(vec![2, 4]), &d), 2);
    let sensor = &masses::sensor_mass(&ctx)[0];
    assert_eq!(placement_penalty(sensor, &d), 0);
    let added = masses::added_mass(&ctx);
    assert!(!added.is_empty() && added.iter().all(|h| placement_penalty(h, &d) == 1));
}

#[test]
fn a_junction_of_three_members_is_a_hard_point() {
    // A T: node 2 joins a straight run 1-2-3 and a branch 2-4; 5 is midway
    // along the branch.
    let t = deck(
        "analysis plane\n\
        material m E=2.1e11 nu=0.3 rho=7850\n\
        section s A=1e-4 Iy=1e-9 Iz=1e-9 J=2e-9\n\
        node 1 0 0 0\nnode 2 1 0 0\nnode 3 2 0 0\nnode 5 1 0 0.5\nnode 4 1 0 1\n\
        beam 1 1 2 m s\nbeam 2 2 3 m s\nbeam 3 2 5 m s\nbeam 4 5 4 m s\n",
    );
    assert_eq!(hard_points(&t), vec![1, 2, 3, 4]);
}

#[test]
fn the_tie_goes_to_the_fewest_choices_within_the_best_margin() {
    let margin = |v: f64| 0.1 * v;
    // (penalty, validation error), ascending by error.
    assert_eq!(tie_pick(&[], margin), None);
    assert_eq!(tie_pick(&[(1, 2.0)], margin), Some(0));
    // 2.15 is within 2.0 + 0.2; 2.25 is not, although its penalty is 0.
    assert_eq!(tie_pick(&[(1, 2.0), (0, 2.15), (0, 2.25)], margin), Some(1));
    assert_eq!(tie_pick(&[(1, 2.0), (1, 2.1), (0, 2.25)], margin), Some(0));
    // Equal penalties: the lowest error.
    assert_eq!(tie_pick(&[(0, 2.0), (0, 2.1)], margin), Some(0));
    // A non-finite best keeps the order.
    assert_eq!(tie_pick(&[(1, f64::NAN), (0, 2.0)], margin), Some(0));
}

#[test]
fn a_fitted_parameter_counts_as_one_more_choice_in_a_tie() {
    let d = deck(L_FRAME);
    let ctx = l_frame_context(&d);
    // Shear deformation fits nothing and has no place to choose: 0.
    let shear = shear::shear_deformation(&ctx);
    assert!(!shear.is_empty());
    for h in &shear {
        assert!(h.param.is_none());
        assert_eq!(tie_penalty(h, &d), 0);
    }
    // The sensor masses: one value, no place (1); suspension springs at
    // hard points: one stiffness (1), one off them: 2; an added mass: a
    // node and a value (2).
    assert_eq!(tie_penalty(&masses::sensor_mass(&ctx)[0], &d), 1);
    let hung = |nodes: Vec<u32>| springs::suspension(&ctx, nodes, frfup_parsers::deck::DeckDof::Z);
    assert_eq!(tie_penalty(&hung(vec![1, 5]), &d), 1);
    assert_eq!(tie_penalty(&hung(vec![1, 4]), &d), 2);
    assert!(masses::added_mass(&ctx)
        .iter()
        .all(|h| tie_penalty(h, &d) == 2));
    // So shear within the margin of a sensor mass that validates a little
    // better is the one taken.
    let ranked = [
        (tie_penalty(&masses::sensor_mass(&ctx)[0], &d), 97.0),
        (tie_penalty(&shear[0], &d), 97.4),
    ];
    assert_eq!(tie_pick(&ranked, |v| 0.03 * v), Some(1));
}
