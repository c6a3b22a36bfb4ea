//! The placement prior: which of several candidates that predict held-out
//! data equally well (within the selection margin) is named.
//!
//! The prior of a class is shared among its places, so a candidate that is
//! one of many (an added mass at any of N nodes, a joint at any of the
//! junctions) has less prior weight than the one candidate of its class (the
//! same mass on every sensor, damping, shear deformation). Suspension
//! springs (bungees, air springs) are hung from hard points: a free end, a
//! corner or a junction of members; a spring along a member costs one
//! choice. The penalty counts these choices, and a fitted parameter as one
//! more ([`tie_penalty`]); among tied candidates the smallest penalty wins,
//! then the lowest validation error.

use std::collections::BTreeMap;

use frfup_parsers::deck::Deck;

use super::{beam_direction, Extension, Hypothesis, Physics, STRAIGHT_ON};

/// Free choices of place `h` makes on `deck` (0: none). A support's
/// flexibility sits at a support the deck names, damping and shear
/// deformation everywhere, the sensor masses on every sensor: none.
pub fn placement_penalty(h: &Hypothesis, deck: &Deck) -> usize {
    match h.physics {
        Physics::AddedMass | Physics::JointFlexibility => 1,
        Physics::Suspension => match &h.extension {
            Extension::GroundSprings { nodes, .. } => {
                let hard = hard_points(deck);
                nodes.iter().filter(|n| !hard.contains(n)).count()
            }
            _ => 0,
        },
        _ => 0,
    }
}

/// The penalty that breaks a tie between candidates that predict the
/// held-out lines alike: [`placement_penalty`] plus one for a fitted
/// parameter. Of two explanations that predict alike, the one that fits
/// nothing (shear deformation) has the larger evidence: the Occam factor
/// of a Laplace approximation, the prior's width over the posterior's, is
/// what a fitted parameter costs.
pub fn tie_penalty(h: &Hypothesis, deck: &Deck) -> usize {
    placement_penalty(h, deck) + usize::from(h.param.is_some())
}

/// Nodes where a member ends, turns or meets another (ascending).
pub fn hard_points(deck: &Deck) -> Vec<u32> {
    let mut at: BTreeMap<u32, Vec<&frfup_parsers::deck::Beam>> = BTreeMap::new();
    for b in &deck.beams {
        for n in b.nodes {
            at.entry(n).or_default().push(b);
        }
    }
    at.into_iter()
        .filter(|(n, beams)| match beams.as_slice() {
            [a, b] => {
                match (beam_direction(deck, a, *n), beam_direction(deck, b, *n)) {
                    // Straight through: the two directions opposite.
                    (Some(u), Some(v)) => u[0] * v[0] + u[1] * v[1] + u[2] * v[2] >= -STRAIGHT_ON,
                    _ => true,
                }
            }
            _ => true,
        })
        .map(|(n, _)| n)
        .collect()
}

/// Of `ranked` (placement penalty, validation error; ascending by error),
/// the index of the candidate with the smallest penalty among those within
/// `margin(best error)` of the best, the lowest error breaking ties; `None`
/// when empty.
pub fn tie_pick(ranked: &[(usize, f64)], margin: impl Fn(f64) -> f64) -> Option<usize> {
    let best = ranked.first()?.1;
    let window = best + margin(best);
    ranked
        .iter()
        .enumerate()
        .take_while(|(i, r)| *i == 0 || r.1 < window)
        .min_by_key(|(i, r)| (r.0, *i))
        .map(|(i, _)| i)
}
