//! After the extensions, the damping of the extended model. Its form is chosen again (the
//! form chosen before may have compensated for the missing physics), the
//! damping fitted with its uncertainties, and reported as a finding when the
//! deck has none or when the fitted damping predicts held-out data better.

use std::collections::BTreeMap;

use frfup_parsers::deck::Deck;

use super::fit::{DampingForm, DampingState};
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
        indistinguishable_from: vec![],
    })
}
