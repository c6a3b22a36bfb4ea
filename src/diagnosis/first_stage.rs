//! Step 1: the deck's own parameters updated ([`crate::updating::update`]
//! with the diagnosis's update options: by default `frfup update`'s own
//! pipeline without its spread starts, whose full-band estimate fits every line and channel and holds
//! a parameter the data do not determine at the deck's value), polished on
//! all lines and channels when the update did not end in that estimate (the
//! paper's method works on a few updating frequencies), and kept only if
//! the damping-profiled fit does not worsen.

use frfup_parsers::deck::Deck;

use super::fit::{self, DampingState};
use super::search::Search;
use super::select::FitRequest;
use crate::model::{self, ParameterValues};
use crate::updating;

/// The deck after step 1.
pub(super) struct FirstStage {
    /// The deck with its updated parameters (the deck as given when the
    /// update is off, failed or was not kept).
    pub deck: Deck,
    /// The parameters' relative changes p̄ (empty: none kept).
    pub parameters: ParameterValues,
    /// What happened to the update, for the report.
    pub note: Option<String>,
}

/// Update, polish and check the deck's own parameters.
pub(super) fn update_own_parameters(search: &Search) -> FirstStage {
    let mut stage = FirstStage {
        deck: search.deck.clone(),
        parameters: ParameterValues::new(),
        note: None,
    };
    let estimated = search.updates_parameters() && update(search, &mut stage);
    if search.updates_parameters() && !estimated {
        polish(search, &mut stage);
    }
    keep_if_no_worse(search, &mut stage);
    stage
}

/// The update's options without its spread starts: a fit far above the
/// noise level is what the diagnosis then explains by physics, and eight
/// more full-band estimates per update would double a diagnosis's first
/// stage.
fn update_options(search: &Search) -> updating::UpdateOptions {
    let mut opts = search.opts.update.clone();
    opts.spread_starts = 0;
    opts
}

/// The update of the deck's parameters; on failure the deck's values stay
/// and the note says why. True when its result is a full-band estimate.
fn update(search: &Search, stage: &mut FirstStage) -> bool {
    match updating::update(search.deck, search.test, &update_options(search)) {
        Ok(res) => {
            let estimated = ends_in_estimate(&res);
            stage.parameters = res.parameter_values();
            stage.deck = model::updated_deck(search.deck, &stage.parameters);
            stage.note = Some(format!(
                "update {} after {} iteration(s)",
                res.stop.name(),
                res.iterations.len().saturating_sub(1)
            ));
            estimated
        }
        Err(e) => {
            stage.note = Some(format!("update failed ({e}); deck values kept"));
            false
        }
    }
}

/// The update's result is its full-band estimate (not the first stage's
/// values kept after the estimate was rejected).
fn ends_in_estimate(res: &updating::UpdateResult) -> bool {
    res.estimate.is_some() && res.stop != updating::StopReason::Diverged
}

/// The deck's parameters updated on `ext` (the deck with extensions) and,
/// when the update did not end in its full-band estimate, polished from its
/// values with the damping `damp` (`None`: neither gave values); with the
/// estimate's standard deviations (relative, as p̄; none after a polish).
pub(super) fn parameters_on(
    search: &Search,
    ext: &Deck,
    damp: &DampingState,
) -> Option<(ParameterValues, ParameterValues)> {
    let res = updating::update(ext, search.test, &update_options(search)).ok();
    if let Some(res) = res.as_ref().filter(|r| ends_in_estimate(r)) {
        let sd = res.estimate.iter().flat_map(|e| &e.parameters);
        let sd = sd.map(|p| (p.name.clone(), p.sd)).collect();
        return Some((res.parameter_values(), sd));
    }
    let start = res.map(|r| r.parameter_values()).unwrap_or_default();
    polished(search, ext, &start, damp).map(|(v, _)| (v, ParameterValues::new()))
}

/// The deck's parameters fitted on all lines and channels from `start`
/// with the damping `damp` (at most 8 Levenberg–Marquardt iterations):
/// the values and the data's mean squared residual.
fn polished(
    search: &Search,
    deck: &Deck,
    start: &ParameterValues,
    damp: &DampingState,
) -> Option<(ParameterValues, f64)> {
    let engine = search.engine;
    fit::fit_deck_parameters(
        deck,
        start,
        damp,
        engine.data,
        &engine.all,
        8,
        engine.counter(),
    )
    .map(|(v, _, c)| (v, c))
}

/// Polish the deck's parameters on all lines and channels (the paper's
/// update uses a few updating frequencies only): a Levenberg–Marquardt fit
/// of p̄ and the damping from the update's values, kept if its cost is lower.
fn polish(search: &Search, stage: &mut FirstStage) {
    let engine = search.engine;
    let Some(f0) = engine.fit(&FitRequest::damping(
        &stage.deck,
        &search.start_damping,
        &engine.all,
    )) else {
        return;
    };
    if let Some((values, c)) = polished(search, search.deck, &stage.parameters, &f0.damping) {
        if c < f0.cost {
            stage.deck = model::updated_deck(search.deck, &values);
            stage.parameters = values;
        }
    }
}

/// Keep the update only if it does not worsen the damping-profiled fit by
/// more than 2 %.
fn keep_if_no_worse(search: &Search, stage: &mut FirstStage) {
    let engine = search.engine;
    let cost = |deck: &Deck| {
        engine
            .fit(&FitRequest::damping(
                deck,
                &search.start_damping,
                &engine.all,
            ))
            .map_or(f64::INFINITY, |f| f.cost)
    };
    let c_init = cost(search.deck);
    let c_upd = cost(&stage.deck);
    if c_upd > c_init * 1.02 && stage.deck != *search.deck {
        stage.deck = search.deck.clone();
        stage.parameters.clear();
        stage.note = Some(format!(
            "{}; the updated values fitted the FRFs worse and were not kept",
            stage.note.take().unwrap_or_default()
        ));
    }
}
