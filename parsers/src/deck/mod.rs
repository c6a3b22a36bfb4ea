//! The model deck (`.deck`, version 1): see docs/deck.md.
