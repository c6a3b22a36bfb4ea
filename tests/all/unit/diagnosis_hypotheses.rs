//! The dictionary's extensions as deck parameters
//! (`Hypothesis::apply_as_parameter`): after an acceptance the diagnosis
//! updates an extension's value along with the deck's own parameters, so the
//! deck with the parameter at p̄ must be the model of the value (1 + p̄)·v.

use super::diagnosis_prior::l_frame_context;
use frfup::diagnosis::hypotheses::{joint, masses, shear, springs, Hypothesis};
use frfup::model::{self, ParameterValues};
use frfup_parsers::deck::DeckDof;

const L_FRAME: &str = "analysis plane\n\
    material m E=2.1e11 nu=0.3 rho=7850\n\
    section s A=1e-4 Iy=1e-9 Iz=1e-9 J=2e-9\n\
    node 1 0 0 0\nnode 2 0.5 0 0\nnode 3 1 0 0\nnode 4 1 0 0.5\nnode 5 1 0 1\n\
    beam 1 1 2 m s\nbeam 2 2 3 m s\nbeam 3 3 4 m s\nbeam 4 4 5 m s\n\
    mass 1 5 m=0.2\nparam E_all E 1-4\n";

/// Largest entry of |A − B| over the largest entry of |B|.
fn relative_difference(a: &model::SparseMatrix, b: &model::SparseMatrix) -> f64 {
    let (a, b) = (a.to_dense(), b.to_dense());
    assert_eq!((a.nrows(), a.ncols()), (b.nrows(), b.ncols()));
    let (mut diff, mut scale) = (0.0f64, 0.0f64);
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            diff = diff.max((a[(i, j)] - b[(i, j)]).abs());
            scale = scale.max(b[(i, j)].abs());
        }
    }
    diff / scale
}

/// The deck with `h` as the parameter "x" at p̄ = 0.5 (and the deck's own
/// parameter at −0.1) against `h` applied at 1.5 v: the same K and M to
/// rounding (1e-13 of the largest entry: both are assembled from the same
/// element matrices, the one scaled by 1 + p̄ after, the other before).
fn scaled_parameter_is_scaled_value(h: &Hypothesis, v: f64) {
    let d = frfup_parsers::deck::parse(L_FRAME).expect("test deck parses");
    let with_param = h
        .apply_as_parameter(&d, Some(v), "x")
        .expect("a valued extension");
    assert_eq!(with_param.params.len(), 2, "{}", h.label);
    let values: ParameterValues = [("x".to_string(), 0.5), ("E_all".to_string(), -0.1)].into();
    let a = model::build(&with_param, &values).expect("model builds");
    let own: ParameterValues = [("E_all".to_string(), -0.1)].into();
    let b = model::build(&h.apply(&d, Some(1.5 * v)), &own).expect("model builds");
    assert!(
        relative_difference(&a.stiffness, &b.stiffness) < 1e-13,
        "{}: K",
        h.label
    );
    assert!(
        relative_difference(&a.mass, &b.mass) < 1e-13,
        "{}: M",
        h.label
    );
}

#[test]
fn an_added_mass_as_a_parameter_is_the_mass_scaled() {
    let d = frfup_parsers::deck::parse(L_FRAME).expect("test deck parses");
    let ctx = l_frame_context(&d);
    let added = masses::added_mass(&ctx);
    let at_3 = added
        .iter()
        .find(|h| h.nodes == [3])
        .expect("a mass at node 3");
    scaled_parameter_is_scaled_value(at_3, 0.05);
    let sensor = &masses::sensor_mass(&ctx)[0];
    scaled_parameter_is_scaled_value(sensor, 0.01);
}

#[test]
fn suspension_springs_as_a_parameter_are_the_springs_scaled() {
    let d = frfup_parsers::deck::parse(L_FRAME).expect("test deck parses");
    let hung = springs::suspension(&l_frame_context(&d), vec![1, 5], DeckDof::Z);
    scaled_parameter_is_scaled_value(&hung, 2.0e3);
}

/// A joint's soft spring scales; its stiff springs on the other DOFs do not
/// (the comparison with the joint applied at 1.5 v would fail if they did).
#[test]
fn a_joint_as_a_parameter_scales_its_soft_spring_only() {
    let d = frfup_parsers::deck::parse(L_FRAME).expect("test deck parses");
    let joints = joint::joint_flexibility(&l_frame_context(&d));
    let at_3 = joints
        .iter()
        .find(|h| h.nodes == [3])
        .expect("a joint at node 3");
    scaled_parameter_is_scaled_value(at_3, 1.0e3);
    let with_param = at_3
        .apply_as_parameter(&d, Some(1.0e3), "x")
        .expect("valued");
    let param = with_param
        .params
        .iter()
        .find(|p| p.name == "x")
        .expect("param x");
    assert_eq!(param.ids.len(), 1, "one spring: the soft one");
}

#[test]
fn shear_deformation_and_a_missing_value_are_no_parameter() {
    let d = frfup_parsers::deck::parse(L_FRAME).expect("test deck parses");
    let ctx = l_frame_context(&d);
    let timoshenko = &shear::shear_deformation(&ctx)[0];
    assert!(timoshenko.apply_as_parameter(&d, Some(1.0), "x").is_none());
    let hung = springs::suspension(&ctx, vec![1, 5], DeckDof::Z);
    assert!(hung.apply_as_parameter(&d, None, "x").is_none());
}

/// `Hypothesis::moved` (the places refined after a search): an added mass
/// or one node of a suspension set moved is the hypothesis the dictionary
/// builds at the new place, label and parameter included; a sensor mass, a
/// node it does not have or one it already has give nothing.
#[test]
fn a_moved_mass_or_spring_is_the_dictionary_hypothesis_at_the_new_node() {
    let d = frfup_parsers::deck::parse(L_FRAME).expect("test deck parses");
    let ctx = l_frame_context(&d);
    let added = masses::added_mass(&ctx);
    let at = |n: u32| added.iter().find(|h| h.nodes == [n]).expect("a mass");
    assert_eq!(at(3).moved(3, 5).as_ref(), Some(at(5)));
    assert!(at(3).moved(1, 5).is_none(), "node 1 is not the mass's");
    let hung = springs::suspension(&ctx, vec![1, 5], DeckDof::Z);
    let expected = springs::suspension(&ctx, vec![1, 4], DeckDof::Z);
    assert_eq!(hung.moved(5, 4), Some(expected));
    assert!(hung.moved(5, 1).is_none(), "node 1 is already hung");
    let sensor = &masses::sensor_mass(&ctx)[0];
    assert!(
        sensor.moved(2, 3).is_none(),
        "a sensor mass stays on its sensors"
    );
}
