//! The viewer data of each report, arranged from what the algorithms
//! computed: the identified modes paired with a deck's (`identify --deck`,
//! and `diagnose` with the diagnosed deck), and the test resonances paired
//! with the updated model's modes (`update`).

use frfup_parsers::deck::Deck;

use super::{build, Partner, ViewerData};
use crate::identification::{Identification, Pairing};
use crate::model::Dof;
use crate::updating::correlation::ShapeSource;
use crate::updating::model_states::ModelStates;
use crate::updating::UpdateResult;

/// The identified modes of `id` and their partners in `p` (paired on
/// `deck`): the real part of each shape (the shapes are rotated to be most
/// nearly real), in the FE DOFs' sense.
pub fn from_identification(
    deck: &Deck,
    id: &Identification,
    p: &Pairing,
    fe_kind: &str,
) -> ViewerData {
    let points: Vec<(u32, Dof)> = p.measured.iter().map(|m| m.1).collect();
    let partners: Vec<Partner> = p
        .pairs
        .iter()
        .map(|&(t, f)| Partner {
            test_mode: t,
            fe_mode: f,
            test_hz: id.modes[t].frequency_hz,
            mac: p.mac[t][f],
            test: p
                .measured
                .iter()
                .map(|&(o, _, sign)| id.modes[t].shape[o].re * sign)
                .collect(),
        })
        .collect();
    build(
        deck,
        &p.fe_shapes,
        &points,
        &partners,
        ("test mode", fe_kind),
    )
}

/// The test resonances of an update and the updated model's modes they
/// paired with at the returned iteration (the MAC of the report's
/// frequency table).
pub fn from_update(
    result: &UpdateResult,
    states: &ModelStates,
    deck: &Deck,
) -> Result<ViewerData, String> {
    let meas = states
        .measured
        .as_ref()
        .ok_or("the test does not map onto the model")?;
    let fe = match (&states.updated.nodal, &states.updated.error) {
        (Some(fe), _) => fe,
        (None, Some(e)) => return Err(e.clone()),
        (None, None) => return Err("the updated model's modes were not computed".into()),
    };
    let partners: Vec<Partner> = states
        .last_pairs
        .iter()
        .flatten()
        .filter_map(|p| {
            Some(Partner {
                test_mode: p.test,
                fe_mode: p.fe,
                test_hz: result.resonances.get(p.test)?.frequency_hz,
                mac: p.mac,
                test: result.pairing_shapes.shapes.get(p.test)?.clone(),
            })
        })
        .collect();
    let test_kind = match result.pairing_shapes.source {
        ShapeSource::Fitted => "test mode (fitted)",
        _ => "test deflection shape at the peak",
    };
    Ok(build(
        deck,
        fe,
        &meas.points,
        &partners,
        (test_kind, "updated FE mode"),
    ))
}
