//! The mode-shape viewer of the reports: a test mode and its FE partner
//! animated side by side on the deck's wireframe (an HTML section with one
//! canvas per shape, its data as one JSON blob and a small script, no
//! network), and the same pairs as still images for print
//! (`mode-shapes.svg`).
//!
//! The FE partner is drawn at every node (the mode's translations). The
//! test shape is known at the measured DOFs only: measured nodes move by
//! their measured directions, the other nodes are interpolated along the
//! beams ([`interpolate`]), directions nobody measured stay at rest. Each
//! shape is scaled to largest translation 1 (the page scales it to a
//! fraction of the model's size); the test shape's sign is the one whose
//! dot product with its partner at the measured DOFs is positive.
//!
//! * [`sources`]: the viewer data of `identify`, `update` and `diagnose`;
//! * [`still`]: the still images;
//! * [`page`]: the HTML section and its JSON.

pub mod interpolate;
pub mod page;
pub mod sources;
pub mod still;

use frfup_parsers::deck::{Analysis, Deck};

use crate::model::Dof;
use crate::solvers::eigen::nodal::{self, FeShapes};

pub use page::{section, viewer_json};
pub use still::render as still_svg;

/// File name of the still images.
pub const STILL_FILE: &str = "mode-shapes.svg";

/// One test mode and its FE partner, scaled and aligned for drawing.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewerPair {
    /// 1-based mode numbers, as in the report's tables.
    pub test_mode: usize,
    pub fe_mode: usize,
    pub test_hz: f64,
    pub fe_hz: f64,
    /// MAC of the pair, as the report's tables give it.
    pub mac: f64,
    /// [node] test translations (largest 1, sign aligned with `fe`).
    pub test: Vec<[f64; 3]>,
    /// [node] FE translations (largest 1).
    pub fe: Vec<[f64; 3]>,
}

/// What the viewer draws.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewerData {
    /// e.g. "test mode (identified)" and "FE mode (deck as given)".
    pub test_kind: String,
    pub fe_kind: String,
    /// A plane deck (x–z plane): shown face-on first.
    pub plane: bool,
    /// Node ids (ascending) and coordinates (m).
    pub ids: Vec<u32>,
    pub xyz: Vec<[f64; 3]>,
    /// Beams as node indices.
    pub beams: Vec<[usize; 2]>,
    /// [node] which translations the test measured.
    pub measured: Vec<[bool; 3]>,
    pub pairs: Vec<ViewerPair>,
}

/// A test shape at measured points and the FE mode it pairs with.
#[derive(Clone, Debug, PartialEq)]
pub struct Partner {
    /// 0-based indices.
    pub test_mode: usize,
    pub fe_mode: usize,
    pub test_hz: f64,
    pub mac: f64,
    /// Values at the measured points (FE DOF sense).
    pub test: Vec<f64>,
}

fn largest(v: &[[f64; 3]]) -> f64 {
    v.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()))
}

fn scaled(v: &[[f64; 3]], s: f64) -> Vec<[f64; 3]> {
    v.iter().map(|u| u.map(|x| x * s)).collect()
}

/// The viewer data of `pairs`: `points` are the (FE node, DOF) of the test
/// shapes' entries, `fe` the partner modes at every node of `deck`.
pub fn build(
    deck: &Deck,
    fe: &FeShapes,
    points: &[(u32, Dof)],
    pairs: &[Partner],
    kinds: (&str, &str),
) -> ViewerData {
    let ids = fe.nodal.nodes.clone();
    let index = |id: u32| ids.binary_search(&id).ok();
    let mut xyz = vec![[0.0; 3]; ids.len()];
    for n in &deck.nodes {
        if let Some(i) = index(n.id) {
            xyz[i] = n.xyz;
        }
    }
    let beams: Vec<[usize; 2]> = deck
        .beams
        .iter()
        .filter_map(|b| Some([index(b.nodes[0])?, index(b.nodes[1])?]))
        .collect();
    let freqs: Vec<f64> = pairs.iter().map(|p| p.test_hz).collect();
    let shapes_at: Vec<Vec<f64>> = pairs.iter().map(|p| p.test.clone()).collect();
    let test = nodal::at_points("", "", &freqs, None, points, &shapes_at);
    let mut measured = vec![[false; 3]; ids.len()];
    for (k, n) in test.nodes.iter().enumerate() {
        if let Some(i) = index(*n) {
            measured[i] = test.known[k];
        }
    }
    let graph = interpolate::Graph::new(&xyz, &beams);
    let out = pairs
        .iter()
        .zip(&test.values)
        .filter_map(|(p, at_nodes)| {
            let fe_raw = fe.nodal.values.get(p.fe_mode)?;
            let mut t = vec![[0.0; 3]; ids.len()];
            for (k, n) in test.nodes.iter().enumerate() {
                if let Some(i) = index(*n) {
                    t[i] = at_nodes[k];
                }
            }
            let dot: f64 = (0..ids.len())
                .flat_map(|i| (0..3).map(move |a| (i, a)))
                .filter(|&(i, a)| measured[i][a])
                .map(|(i, a)| t[i][a] * fe_raw[i][a])
                .sum();
            let t = graph.fill(&t, &measured, &fe.free);
            let (ft, ff) = (largest(&t), largest(fe_raw));
            let sign = if dot < 0.0 { -1.0 } else { 1.0 };
            Some(ViewerPair {
                test_mode: p.test_mode + 1,
                fe_mode: p.fe_mode + 1,
                test_hz: p.test_hz,
                fe_hz: fe.nodal.frequencies_hz.get(p.fe_mode).copied()?,
                mac: p.mac,
                test: scaled(&t, if ft > 0.0 { sign / ft } else { 0.0 }),
                fe: scaled(fe_raw, if ff > 0.0 { 1.0 / ff } else { 0.0 }),
            })
        })
        .collect();
    ViewerData {
        test_kind: kinds.0.into(),
        fe_kind: kinds.1.into(),
        plane: deck.analysis == Analysis::Plane,
        ids,
        xyz,
        beams,
        measured,
        pairs: out,
    }
}

/// MAC of a pair's drawn shapes at the measured translations (what a
/// reader of the JSON can recompute; equals the table's MAC when the test
/// shape is real).
pub fn drawn_mac(v: &ViewerData, p: &ViewerPair) -> f64 {
    let (mut tf, mut tt, mut ff) = (0.0, 0.0, 0.0);
    for (i, m) in v.measured.iter().enumerate() {
        for a in (0..3).filter(|&a| m[a]) {
            let (t, f) = (p.test[i][a], p.fe[i][a]);
            tf += t * f;
            tt += t * t;
            ff += f * f;
        }
    }
    if tt > 0.0 && ff > 0.0 {
        tf * tf / (tt * ff)
    } else {
        0.0
    }
}

/// The viewer section of an update's report and `mode-shapes.svg`; a note
/// saying why when there is nothing to draw.
pub fn update_section(
    result: &crate::updating::UpdateResult,
    states: &crate::updating::model_states::ModelStates,
    deck: &Deck,
) -> (String, Option<String>) {
    let intro = "The test resonances and the updated model's modes they pair with (the MAC of the table above), animated.";
    match sources::from_update(result, states, deck) {
        Ok(v) => {
            let still = still_svg(&v);
            (section(&v, intro, &still), Some(still))
        }
        Err(e) => (page::unavailable(&e), None),
    }
}

/// The viewer section of a diagnosis' report and `mode-shapes.svg`: the
/// test's modes identified as `frfup identify` does, paired with the
/// modes of the diagnosed deck (`test_modes`, from
/// [`crate::identification::identify_and_pair`]); a note saying why when
/// there is nothing to draw.
pub fn diagnosis_section(
    diagnosed_deck: &Deck,
    test_modes: &Result<crate::identification::PairedModes, String>,
) -> (String, Option<String>) {
    let intro = format!(
        "The test's modes, identified from the FRFs as <code>frfup identify</code> does, paired by MAC ≥ {} with the diagnosed model's modes (the select lists each pair's MAC), animated.",
        crate::identification::PAIR_MAC
    );
    let intro = intro + " The test shape drawn is the real part of the identified one.";
    let viewer = test_modes.as_ref().map(|m| {
        sources::from_identification(
            diagnosed_deck,
            &m.identification,
            &m.pairing,
            "diagnosed FE mode",
        )
    });
    match viewer {
        Ok(v) => {
            let still = still_svg(&v);
            (section(&v, &intro, &still), Some(still))
        }
        Err(e) => (page::unavailable(e), None),
    }
}
