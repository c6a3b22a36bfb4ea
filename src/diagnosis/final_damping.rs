//! After the extensions, the damping of the extended model. Its form is chosen again (the
//! form chosen before may have compensated for the missing physics), the
//! damping fitted with its uncertainties, and reported as a finding when the
//! deck has none, or when the fitted damping predicts held-out data better
//! and the deck's damping disagrees with the test's own damping ratios.
//!
//! The second condition keeps a damping form from standing in for missing
//! physics: refitted damping widens or narrows peaks to cover a frequency
//! or amplitude mismatch of any cause, so a better FRF fit alone is weak
//! evidence. The test's modes identified by experimental modal analysis
//! ([`crate::identification`], poles common to all channels) give damping
//! ratios that no model enters; if the deck's damping predicts them within
//! a factor [`DAMPING_AGREEMENT`] (median over the elastic modes), the deck's
//! damping is not what is wrong, and the refitted damping stays in the
//! diagnosed deck without a finding.

use std::collections::BTreeMap;

use frfup_parsers::deck::Deck;

use super::fit::{DampingForm, DampingState};
use crate::identification::{self, IdentifyOptions, ModeKind};
use crate::model::Damping;
use crate::testdata::MeasuredFrfs;

/// The deck's damping agrees with the test's when it predicts the
/// identified damping ratios within this factor (median over the elastic
/// modes): ratios identified from FRFs at 1–3 % noise scatter by 10–20 %.
pub const DAMPING_AGREEMENT: f64 = 1.2;
use super::hypotheses::Physics;
use super::search::Search;
use super::select::{self, FitRequest, HypFit};
use super::{DiagnoseError, Finding};

/// The damping form chosen again on the extended deck `current`: another
/// form replaces `damp` if it fits no worse, the deck's own form (modal
/// without one) if it costs less than 3 % more.
pub(super) fn choose_form_again(
    search: &Search,
    current: &Deck,
    damp: DampingState,
) -> DampingState {
    let engine = search.engine;
    let deck_form = &search.deck_form;
    let Some((d2, _)) = select::choose_damping(engine, current, deck_form.clone(), search.zeta0)
    else {
        return damp;
    };
    let c_now = engine
        .fit(&FitRequest::damping(current, &damp, &engine.all))
        .map_or(f64::INFINITY, |f| f.cost);
    let c_new = engine
        .fit(&FitRequest::damping(current, &d2, &engine.all))
        .map_or(f64::INFINITY, |f| f.cost);
    if c_new <= c_now
        || d2.form == deck_form.as_ref().map_or(DampingForm::Modal, |d| d.0) && c_new < c_now * 1.03
    {
        d2
    } else {
        damp
    }
}

/// The damping of `current` fitted on all data from `damp`, with the
/// standard deviations of its log parameters.
pub(super) fn fit_final_damping(
    search: &Search,
    current: &Deck,
    damp: &DampingState,
) -> Result<HypFit, DiagnoseError> {
    let engine = search.engine;
    engine
        .fit(&FitRequest {
            with_std: true,
            ..FitRequest::damping(current, damp, &engine.all)
        })
        .ok_or_else(|| DiagnoseError::Eigen("the diagnosed model gives no usable FRF".into()))
}

/// The damping finding: when the deck has no damping, or when the fitted
/// damping (`final_fit`, validation cost `v_fitted`) predicts held-out data
/// better than the deck's own by more than the margin.
pub(super) fn damping_finding(
    search: &Search,
    current: &Deck,
    final_fit: &HypFit,
    v_fitted: f64,
) -> Option<Finding> {
    // A damped deck (also one the log-parameter forms cannot hold, such as
    // Rayleigh with β = 0) whose damping the test's own ratios confirm.
    let deck_damping = Damping::of_deck(search.deck);
    if deck_damping != Damping::None
        && identified_disagreement(search.test, deck_damping)
            .is_some_and(|d| d < DAMPING_AGREEMENT.ln())
    {
        return None;
    }
    let before = match &search.deck_form {
        None => f64::INFINITY,
        Some((form, x)) => {
            let deck_state = DampingState {
                form: *form,
                x: x.clone(),
            };
            let v_deck = search.engine.validate_fixed_damping(current, &deck_state);
            if !(v_fitted < v_deck - select::margin(v_deck, search.j0)) {
                return None;
            }
            v_deck
        }
    };
    let damp = &final_fit.damping;
    let mut parameters = BTreeMap::new();
    let mut uncertainty = BTreeMap::new();
    for (i, name) in damp.form.parameter_names().iter().enumerate() {
        let x = damp.x[i].exp();
        parameters.insert(name.to_string(), x);
        let s = final_fit
            .damping_std_log
            .get(i)
            .copied()
            .unwrap_or(f64::INFINITY);
        uncertainty.insert(name.to_string(), s * x);
    }
    Some(Finding {
        physics: Physics::Damping,
        nodes: vec![],
        dofs: vec![],
        parameters,
        uncertainty,
        validation_error_before: before,
        validation_error_after: v_fitted,
        label: format!("{} damping", damp.form.name()),
        alternatives: vec![],
        tell_apart: None,
    })
}

/// Median |ln(ζ_test/ζ_deck)| over the test's elastic modes identified by
/// experimental modal analysis; `None` when fewer than two are identified
/// (or the identification fails): no independent evidence then.
pub fn identified_disagreement(test: &MeasuredFrfs, deck: Damping) -> Option<f64> {
    let id = identification::identify(test, &IdentifyOptions::default()).ok()?;
    let mut d: Vec<f64> = id
        .modes
        .iter()
        .filter(|m| m.kind == ModeKind::Elastic && m.damping_ratio > 0.0)
        .map(|m| (m.damping_ratio / deck.ratio_at(m.frequency_hz)).ln().abs())
        .filter(|x| x.is_finite())
        .collect();
    if d.len() < 2 {
        return None;
    }
    d.sort_by(f64::total_cmp);
    Some(d[d.len() / 2])
}
