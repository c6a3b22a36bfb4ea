//! The viewer data of each report: the identified modes paired with a
//! deck's (`identify --deck`, and `diagnose` with the diagnosed deck), and
//! the test resonances paired with the updated model's modes (`update`).

use frfup_parsers::deck::Deck;

use super::{build, fe_shapes, Partner, ViewerData};
use crate::identification::{self, Identification, IdentifyOptions};
use crate::model::{self, Dof};
use crate::report::identification::{pair_with_deck, Pairing};
use crate::solvers::eigen::{lowest_modes, EigenOptions};
use crate::testdata::MeasuredFrfs;
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
    if result.iterations.get(result.final_iteration).is_none() {
        return Err("no returned iteration".into());
    }
    let fe = model::build(deck, &result.parameter_values()).map_err(|e| e.to_string())?;
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
    // As many modes as the report's model view computed, so the pairs'
    // FE mode numbers point at the same modes.
    let count = states
        .updated
        .modes_hz
        .len()
        .max(partners.iter().map(|p| p.fe_mode + 1).max().unwrap_or(1))
        .min(fe.dofs.len());
    let modes = lowest_modes(
        &fe.stiffness,
        &fe.mass,
        &EigenOptions {
            count,
            expect_no_rigid_body_modes: fe.has_fixed_dofs,
            ..EigenOptions::default()
        },
    )
    .map_err(|e| e.to_string())?;
    let test_kind = match result.pairing_shapes.source {
        ShapeSource::Fitted => "test mode (fitted)",
        _ => "test deflection shape at the peak",
    };
    Ok(build(
        deck,
        &fe_shapes(deck, &fe, &modes),
        &meas.points,
        &partners,
        (test_kind, "updated FE mode"),
    ))
}

/// The test's modes identified as `frfup identify` does (whole band,
/// default orders), paired with the modes of `deck`.
pub fn identified(deck: &Deck, test: &MeasuredFrfs) -> Result<ViewerData, String> {
    let id =
        identification::identify(test, &IdentifyOptions::default()).map_err(|e| e.to_string())?;
    let p = pair_with_deck(deck, &id)?;
    Ok(from_identification(deck, &id, &p, "diagnosed FE mode"))
}
