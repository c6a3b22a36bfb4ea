//! Unit tests of `src/report/diagnosis/mod.rs` through its public interface.

use frfup::report::diagnosis::*;
use frfup_parsers::deck::Deck;

fn deck(text: &str) -> Deck {
    frfup_parsers::deck::parse(text).unwrap()
}

#[test]
fn map_plane_is_x_z_for_plane_decks_else_the_largest_extent() {
    let plane = deck(
        "analysis plane\nmaterial s E=2e11 rho=7800\nsection c A=1e-4 Iy=1e-9\nnode 1 0 0 0\nnode 2 1 0 0\nbeam 1 1 2 s c\n",
    );
    assert_eq!(map_axes(&plane), (0, 2));
    // A space frame spread in y and z, thin in x.
    let space = deck(
        "material s E=2e11 rho=7800\nsection c A=1e-4 Iy=1e-9 Iz=1e-9 J=2e-9\nnode 1 0 0 0\nnode 2 0.1 2 0\nnode 3 0 2 1\nbeam 1 1 2 s c\nbeam 2 2 3 s c\n",
    );
    assert_eq!(map_axes(&space), (1, 2));
}
