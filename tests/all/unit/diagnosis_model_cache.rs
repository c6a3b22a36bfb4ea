//! The diagnosis's cache of modal models: a deck kept is found again (by
//! equality, not by hash), the least recently used is dropped first.

use frfup::diagnosis::fit::ModalModel;
use frfup::diagnosis::model_cache::{ModelCache, CAPACITY};
use frfup::parsers::deck::{Deck, Title};

fn model(w2: f64) -> ModalModel {
    ModalModel {
        omega2: vec![w2],
        coeff: vec![vec![1.0]],
        residual: vec![0.0],
        residual_mass: vec![0.0],
        frequencies_hz: vec![w2.sqrt() / std::f64::consts::TAU],
        dofs: 1,
    }
}

fn deck(title: &str) -> Deck {
    Deck {
        titles: vec![Title {
            text: title.to_string(),
            pos: Default::default(),
        }],
        ..Deck::default()
    }
}

#[test]
fn a_deck_kept_is_found_and_another_is_not() {
    let mut cache = ModelCache::default();
    assert!(cache.get(&deck("a")).is_none());
    cache.keep(&deck("a"), &model(4.0));
    assert_eq!(cache.get(&deck("a")).expect("kept").omega2, vec![4.0]);
    assert!(cache.get(&deck("b")).is_none());
    assert_eq!(cache.hits(), 1);
}

#[test]
fn the_least_recently_used_deck_is_dropped_first() {
    let mut cache = ModelCache::default();
    for i in 0..CAPACITY {
        cache.keep(&deck(&i.to_string()), &model(i as f64));
    }
    assert_eq!(cache.len(), CAPACITY);
    // Deck "0" used again: "1" is now the oldest, and a new deck drops it.
    assert!(cache.get(&deck("0")).is_some());
    cache.keep(&deck("new"), &model(1.0));
    assert_eq!(cache.len(), CAPACITY);
    assert!(cache.get(&deck("0")).is_some(), "deck 0 was kept");
    assert!(cache.get(&deck("1")).is_none(), "deck 1 was dropped");
    assert_eq!(cache.get(&deck("2")).expect("kept").omega2, vec![2.0]);
}

#[test]
fn a_deck_kept_twice_is_kept_once() {
    let mut cache = ModelCache::default();
    assert!(cache.is_empty());
    cache.keep(&deck("a"), &model(1.0));
    cache.keep(&deck("a"), &model(1.0));
    assert_eq!(cache.len(), 1);
}
