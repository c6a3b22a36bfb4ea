//! Step 1: the deck's own parameters updated ([`crate::updating::update`],
//! the paper's method on a few updating frequencies), polished on all lines
//! and channels, and kept only if the damping-profiled fit does not worsen.

use frfup_parsers::deck::Deck;

use super::fit;
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
    if search.updates_parameters() {
        paper_update(search, &mut stage);
    }
    if search.updates_parameters() {
        polish(search, &mut stage);
    }
    keep_if_no_worse(search, &mut stage);
    stage
}

/// The paper's update of the deck's parameters; on failure the deck's
/// values stay and the note says why.
fn paper_update(search: &Search, stage: &mut FirstStage) {
    match updating::update(search.deck, search.test, &search.opts.update) {
        Ok(res) => {
            stage.parameters = res.parameter_values();
            stage.deck = model::updated_deck(search.deck, &stage.parameters);
            stage.note = Some(format!(
                "update {} after {} iteration(s)",
                res.stop.name(),
                res.iterations.len().saturating_sub(1)
            ));
        }
        Err(e) => stage.note = Some(format!("update failed ({e}); deck values kept")),
    }
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
    if let Some((values, _, c)) = fit::fit_deck_parameters(
        search.deck,
        &stage.parameters,
        &f0.damping,
        engine.data,
        &engine.all,
        8,
        engine.counter(),
    ) {
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
