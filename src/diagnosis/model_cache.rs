//! The modal models of the decks a diagnosis solved last, kept so that a
//! deck asked for again is not solved again.
//!
//! A diagnosis asks for the same deck many times over: a fit's best point is
//! solved again to profile its damping, each cross-validation fold starts
//! from the full-data optimum, a refit starts where the previous fit ended.
//! On the GARTEUR-size campaign 24 % of the model solutions asked for were
//! of a deck already solved, 93 % of those among the last 64 decks. A deck
//! is the same when it compares equal (every statement, value and source
//! position); the solution is deterministic, so a hit returns the very
//! model a new solution would give, and the diagnosis's course and output
//! do not depend on the cache.

use std::collections::VecDeque;

use frfup_parsers::deck::Deck;

use super::fit::ModalModel;

/// Decks kept (least recently used dropped first).
pub const CAPACITY: usize = 64;

/// The last [`CAPACITY`] decks solved and their modal models, most recently
/// used first.
///
/// Threads share one cache behind a lock held only to look up or keep, not
/// while solving: two threads may solve the same deck at once, and both
/// get the same model.
#[derive(Default)]
pub struct ModelCache {
    entries: VecDeque<(Deck, ModalModel)>,
    pub(super) hits: usize,
}

impl ModelCache {
    /// The kept modal model of `deck`, if any (then the most recently used).
    pub fn get(&mut self, deck: &Deck) -> Option<ModalModel> {
        let i = self.entries.iter().position(|(d, _)| d == deck)?;
        let entry = self.entries.remove(i)?;
        let mm = entry.1.clone();
        self.entries.push_front(entry);
        self.hits += 1;
        Some(mm)
    }

    /// Keep `mm` as the modal model of `deck` (dropping the least recently
    /// used when full).
    pub fn keep(&mut self, deck: &Deck, mm: &ModalModel) {
        if self.entries.iter().any(|(d, _)| d == deck) {
            return;
        }
        if self.entries.len() == CAPACITY {
            self.entries.pop_back();
        }
        self.entries.push_front((deck.clone(), mm.clone()));
    }

    /// Decks kept.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// No deck kept.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// Decks found kept so far.
    pub fn hits(&self) -> usize {
        self.hits
    }
}
