//! After a search that ends above the noise level: the accepted added
//! masses and suspension springs moved to neighbouring nodes.
//!
//! A round places a point extension by the linear probes of its screen and
//! the full fits of the few best-scored nodes; a large effect's probes can
//! point an element or two off (seed-1 diagnosis benchmark case 205: an
//! added mass of 0.09 kg at node 37 of a clamped beam fitted at node 39,
//! 0.067 kg, 2.7× the noise level left; case 104: a mass at node 14 fitted
//! at 13 beside a joint, 11×). Each move of one node of an accepted added
//! mass or suspension set to a node that shares a beam with it (an added
//! mass not onto a sensor, which is the sensor mass's place) is fitted with
//! the other extensions, their values and the damping refitted jointly
//! ([`Greedy::joint_refit_of`], the deck's parameters held). An added mass
//! beside a sensor may also become the sensor mass (the same mass at every
//! sensor), and with one sensor the sensor mass may move to a node beside
//! it as an added mass: the two classes are told apart by where the mass
//! sits, and a round's probes place a mass beside a sensor as easily as on
//! it (seed-2 case 028: a roving-hammer test whose one accelerometer, at
//! node 1, weighs 0.252 kg, fitted as an added mass of 0.42 kg at node 9
//! beside a joint, 4.8× the noise level left). The move that
//! lowers the cost most is taken when it lowers it by more than the margin
//! ([`select::margin`]) (its validation error is computed for the report
//! only), and the moves go on from there, at most [`MAX_MOVES`], until none pays or the
//! fit is at the noise level. A move adds no parameter: the cost compares
//! places on equal terms.

use rayon::prelude::*;

use super::greedy::Greedy;
use super::hypotheses::{self, masses, Hypothesis, Physics};
use super::refit::{self, JointFit};
use super::round::sensor_nodes;
use super::search::Search;
use super::select;
use crate::model::{self, ParameterValues};

/// Moves taken at most after one search (each one node by one element).
const MAX_MOVES: usize = 4;

/// Move `g`'s accepted point extensions while that pays (see the module's
/// documentation). True when one moved.
pub(super) fn refine(search: &Search, g: &mut Greedy) -> bool {
    let Ok(fe) = model::build(search.deck, &ParameterValues::new()) else {
        return false;
    };
    let sensors = sensor_nodes(search.engine.data, &fe);
    let mut moved = false;
    for _ in 0..MAX_MOVES {
        if search.at_noise_level(g.cost) {
            break;
        }
        let Some((i, h, jf, v)) = best_move(search, g, &sensors) else {
            break;
        };
        g.take_move(i, h, (&jf, v), search.j0);
        moved = true;
    }
    moved
}

/// The move of one accepted extension that fits best, with its joint fit
/// and validation cost (for the report), if it pays.
fn best_move(
    search: &Search,
    g: &Greedy,
    sensors: &[u32],
) -> Option<(usize, Hypothesis, JointFit, f64)> {
    let engine = search.engine;
    let moves: Vec<(usize, Hypothesis)> = g
        .accepted
        .iter()
        .enumerate()
        .flat_map(|(i, (h, _))| {
            moves_of(search, h, sensors)
                .into_iter()
                .map(move |m| (i, m))
        })
        .collect();
    let fits: Vec<Option<JointFit>> = moves
        .par_iter()
        .map(|(i, m)| {
            let mut accepted = g.accepted.clone();
            accepted[*i].0 = m.clone();
            g.joint_refit_of(engine, &accepted)
                .filter(|jf| !jf.on_bound.iter().any(|b| *b))
        })
        .collect();
    let (k, jf) = fits
        .into_iter()
        .enumerate()
        .filter_map(|(k, f)| Some((k, f?)))
        .min_by(|a, b| a.1.cost.total_cmp(&b.1.cost))?;
    if !(jf.cost < g.cost - select::margin(g.cost, search.j0)) {
        return None;
    }
    let (i, h) = moves[k].clone();
    let mut accepted = g.accepted.clone();
    accepted[i].0 = h.clone();
    let hyps: Vec<&Hypothesis> = accepted.iter().map(|a| &a.0).collect();
    let v = refit::validate_joint(engine, &refit::Joint::new(&g.base, hyps), &jf);
    Some((i, h, jf, v))
}

/// `h` with one of its nodes moved to a node that shares a beam of the
/// deck with it (an added mass onto a sensor: the sensor mass), and a sensor
/// mass at one sensor moved off it as an added mass; nothing for the classes
/// that do not move ([`Hypothesis::moved`]).
fn moves_of(search: &Search, h: &Hypothesis, sensors: &[u32]) -> Vec<Hypothesis> {
    let deck = search.deck;
    let total = hypotheses::total_mass(deck);
    let mut out: Vec<Hypothesis> = Vec::new();
    for &from in &h.nodes {
        for to in beside(deck, from) {
            let moved = match h.physics {
                Physics::AddedMass if sensors.contains(&to) => {
                    masses::sensor_mass_at(sensors, total)
                }
                Physics::SensorMass if sensors.len() == 1 && !sensors.contains(&to) => {
                    Some(masses::added_mass_at(to, total))
                }
                _ => h.moved(from, to),
            };
            if let Some(m) = moved.filter(|m| out.iter().all(|o| o.label != m.label)) {
                out.push(m);
            }
        }
    }
    out
}

/// The nodes that share a beam of `deck` with `node` (ascending).
fn beside(deck: &frfup_parsers::deck::Deck, node: u32) -> Vec<u32> {
    let mut nodes: Vec<u32> = deck
        .beams
        .iter()
        .filter(|b| b.nodes.contains(&node))
        .flat_map(|b| b.nodes)
        .filter(|&n| n != node)
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}
