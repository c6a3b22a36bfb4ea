//! Suspension springs placed by the test's suspension modes.
//!
//! A free-free structure on soft springs of stiffness k at the nodes S (one
//! direction d) has, to first order in k, the rigid-body modes of the deck
//! on those springs. With Φ_r the deck's mass-normalised rigid-body modes
//! (n_r of them) and u_n = Φ_r(n, d) their row at node n, the suspension
//! modes solve
//!
//!   k·G_S q = ω² q,   G_S = Σ_{n∈S} u_nᵀ u_n   (n_r × n_r),
//!
//! so their frequencies are √(k μ_i)/2π over the eigenvalues μ_i of G_S and
//! their shapes at the channels are U q_i (U: the rows of Φ_r there). The
//! frequency ratios and the shapes depend on the placement alone; k only
//! scales. Every set of one, two or three nodes (of three among the nodes
//! of the best pairs on decks of more than 63 nodes) is scored against the
//! suspension modes the
//! identification finds in the test (the modes below [`SUSPENSION_BAND`] of
//! the deck's first elastic frequency), k fitted in closed form
//! (ln k = mean of ln(ω_t²/μ_i) over the paired modes). The best sets go to
//! the full FRF fit of the round, which also sees the springs' small effect
//! on the elastic modes: sets alike in their rigid-body effect (two nodes
//! above one another under vertical springs) are told apart there, or not
//! at all; then the set hung from hard points wins ([`OFF_HARD_POINT`]).

use frfup_parsers::deck::DeckDof;
use nalgebra::{DMatrix, SymmetricEigen};

use super::data::TestData;
use super::hypotheses::{prior, Context};
use crate::identification::ColumnMode;
use crate::model::{self, Dof, ParameterValues};
use crate::updating::correlation::mac;

mod low_band;
pub use low_band::{low_band_placements, mean_misfit, point_misfit};

/// Test modes below this fraction of the deck's first elastic frequency are
/// the suspension's.
pub const SUSPENSION_BAND: f64 = 0.5;
/// A frequency mismatch of this (natural log, ≈ 10 %) costs as much as a
/// shape with no correlation (MAC 0): the deck's mass distribution, not yet
/// updated, moves the frequency ratios by a few per cent.
const LN_FREQUENCY_SCALE: f64 = 0.1;
/// Each spring beyond the first costs this much: of two sets that explain
/// the suspension modes alike, the smaller.
const PER_SPRING: f64 = 1e-3;
/// Each spring off a hard point (a free end, corner or junction, see
/// [`prior::hard_points`]) costs this much: of sets alike in their
/// rigid-body effect (nodes along a leg under vertical springs), the one
/// hung from hard points.
const OFF_HARD_POINT: f64 = 2e-3;
/// Triples of nodes scored per direction by the modal placement: every
/// triple of up to 63 nodes (its score is an n_r × n_r eigen problem and a
/// MAC pairing, microseconds); on larger decks, those among the nodes of the
/// best pairs. A pair holds two rigid-body modes, so when the test shows
/// three, every pair leaves one unmatched and the pairs' ranking says
/// little about which nodes three springs need (seed-1 case 109: springs at
/// nodes 1, 2, 3 of a space frame, none of them among the best pairs'
/// twelve nodes; placed at 14, 15 instead, 9.7× the noise).
const TRIPLE_BUDGET: usize = 40_000;

/// The test's suspension modes: frequency (Hz) and real shape at the
/// channels.
#[derive(Clone, Debug)]
pub struct SuspensionModes {
    pub frequency_hz: Vec<f64>,
    pub shapes: Vec<Vec<f64>>,
}

/// The modes the identification finds in `data` below
/// [`SUSPENSION_BAND`] × `first_elastic_hz` (none if it finds nothing).
pub fn test_suspension_modes(
    data: &TestData,
    modes: &[ColumnMode],
    first_elastic_hz: f64,
) -> SuspensionModes {
    let lo = data.lines_hz.first().copied().unwrap_or(0.0);
    let keep: Vec<&ColumnMode> = modes
        .iter()
        .filter(|m| m.frequency_hz > lo && m.frequency_hz < SUSPENSION_BAND * first_elastic_hz)
        .collect();
    SuspensionModes {
        frequency_hz: keep.iter().map(|m| m.frequency_hz).collect(),
        shapes: keep.iter().map(|m| m.shape.clone()).collect(),
    }
}

/// The test's modes by the identification of the update and `identify`.
/// On the whole record's even axis; `line` indexes `data.lines_hz`. On a
/// long record the band below a third of the lowest mode found is fitted
/// again on its own ([`low_band_modes`]).
pub fn identified_modes(data: &TestData) -> Vec<ColumnMode> {
    let (lines_hz, values) = data.whole_record();
    let mut modes =
        crate::identification::identify_column(lines_hz, data.kind, values).unwrap_or_default();
    if data.record.is_some() {
        let low = low_band_modes(lines_hz, data.kind, values, &modes);
        modes.extend(low);
        modes.sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
        for m in &mut modes {
            m.line = crate::updating::frequencies::nearest_line(&data.lines_hz, m.frequency_hz);
        }
    }
    modes
}

/// Lines a low band needs before it is fitted on its own.
const LOW_BAND_LINES: usize = 32;

/// The modes below a third of the lowest of `found`, fitted on that band
/// alone. One fit over a band of kHz on lines of 0.1 Hz misses suspension
/// modes of a few Hz (the 51,200-line bar of `scripts/bench_long_record.sh`:
/// bounce and pitch at 5.0 and 5.2 Hz, ζ ≈ 1 %, found only on 0–88 Hz).
fn low_band_modes(
    lines_hz: &[f64],
    kind: crate::testdata::FrfKind,
    values: &[Vec<faer::c64>],
    found: &[ColumnMode],
) -> Vec<ColumnMode> {
    let Some(lowest) = found.iter().map(|m| m.frequency_hz).reduce(f64::min) else {
        return Vec::new();
    };
    let n = lines_hz.partition_point(|&f| f <= lowest / 3.0);
    if n < LOW_BAND_LINES {
        return Vec::new();
    }
    let band: Vec<Vec<faer::c64>> = values.iter().map(|v| v[..n].to_vec()).collect();
    crate::identification::identify_column(&lines_hz[..n], kind, &band).unwrap_or_default()
}

/// One placement: the nodes, the direction, k fitted to the frequencies
/// (N/m) and its score (0: the suspension modes matched exactly).
#[derive(Clone, Debug)]
pub struct Placement {
    pub nodes: Vec<u32>,
    pub dof: DeckDof,
    pub k: f64,
    pub score: f64,
    /// Suspension modes the springs make that no test mode was paired with
    /// (the modal placement; 0 for the low band's): the test shows fewer
    /// than the placement needs, unresolved or below its band.
    pub unmatched: usize,
}

/// The rigid-body modes' row u_n at each node (node, u_n).
type NodeRows = Vec<(u32, Vec<f64>)>;

/// The rigid-body rows of the deck: per translational direction of the
/// analysis, u_n for each beam node; and U at the channels.
struct RigidRows {
    /// (direction, [(node, u_n)]).
    nodes: Vec<(DeckDof, NodeRows)>,
    /// U: per channel, the rigid-body modes there (times the channel's sign).
    channels: Vec<Vec<f64>>,
}

/// The best `count` placements of same-stiffness springs on `deck` (a
/// free-free deck with no spring to ground) for the test's suspension
/// modes, best first; none when the test shows none or the deck has no
/// rigid-body modes.
pub fn placements(
    ctx: &Context,
    data: &TestData,
    test: &SuspensionModes,
    count: usize,
) -> Vec<Placement> {
    if test.frequency_hz.is_empty() || !ctx.free_free {
        return Vec::new();
    }
    let Some(rows) = rigid_rows(ctx, data) else {
        return Vec::new();
    };
    let hard = prior::hard_points(ctx.deck);
    best_sets(&rows.nodes, count, TRIPLE_BUDGET, |nodes, pick, dof| {
        score(&rows, test, nodes, pick, dof, &hard)
    })
}

/// The best `count` spring sets by `score` (lower is better; `None`: not a
/// placement), best first, with the ties of the last kept: per direction
/// every set of one or two nodes, then of three among the nodes of the best
/// pairs, as many nodes as keep the triples within `triples`
/// ([`triple_pool`]).
fn best_sets(
    by_direction: &[(DeckDof, NodeRows)],
    count: usize,
    triples: usize,
    score: impl Fn(&[(u32, Vec<f64>)], &[usize], DeckDof) -> Option<Placement>,
) -> Vec<Placement> {
    let mut all: Vec<Placement> = Vec::new();
    for (dof, nodes) in by_direction {
        let mut found: Vec<Placement> = Vec::new();
        for a in 0..nodes.len() {
            found.extend(score(nodes, &[a], *dof));
            for b in a + 1..nodes.len() {
                found.extend(score(nodes, &[a, b], *dof));
            }
        }
        found.sort_by(by_score);
        let pool = triple_pool(&found, nodes, pool_size(triples));
        for (i, &a) in pool.iter().enumerate() {
            for (j, &b) in pool.iter().enumerate().skip(i + 1) {
                for &c in pool.iter().skip(j + 1) {
                    found.extend(score(nodes, &[a, b, c], *dof));
                }
            }
        }
        all.extend(found);
    }
    all.sort_by(by_score);
    let kept = tied_with_the_best(&all, count);
    all.truncate(kept);
    all
}

/// Placements whose scores differ by less than this are alike (the springs'
/// rows of the rigid-body modes equal to rounding: nodes above one another
/// under vertical springs). Far below [`PER_SPRING`] and [`OFF_HARD_POINT`].
const TIE: f64 = 1e-9;

/// Lower score first; scores within [`TIE`] (on a grid of that step, so
/// that the order is total) by their nodes, lowest first: sets alike in
/// their rigid-body effect come in the order of their node numbers, not of
/// their rounding errors.
fn by_score(x: &Placement, y: &Placement) -> std::cmp::Ordering {
    let key = |p: &Placement| (p.score / TIE).round();
    key(x).total_cmp(&key(y)).then(x.nodes.cmp(&y.nodes))
}

/// How many of `sorted` to keep: the best `count`, and every further one
/// tied with the last of them (up to `2·count` in all), so that sets alike
/// in their rigid-body effect all reach the FRF fit and are named as
/// alternatives of each other, instead of rounding choosing among them.
fn tied_with_the_best(sorted: &[Placement], count: usize) -> usize {
    let mut kept = count.min(sorted.len());
    if kept == 0 {
        return 0;
    }
    let last = sorted[kept - 1].score;
    while kept < sorted.len().min(count.saturating_mul(2)) && sorted[kept].score - last <= TIE {
        kept += 1;
    }
    kept
}

/// The largest pool of p nodes whose triples, p(p − 1)(p − 2)/6, number at
/// most `triples`.
fn pool_size(triples: usize) -> usize {
    let mut p = 3;
    while (p + 1) * p * (p - 1) / 6 <= triples {
        p += 1;
    }
    p
}

/// Indices (into `nodes`) of the nodes of the best pairs, at most `size`,
/// ascending.
fn triple_pool(found: &[Placement], nodes: &[(u32, Vec<f64>)], size: usize) -> Vec<usize> {
    let mut pool: Vec<usize> = Vec::new();
    for p in found.iter().filter(|p| p.nodes.len() == 2) {
        for n in &p.nodes {
            if let Some(i) = nodes.iter().position(|(m, _)| m == n) {
                if !pool.contains(&i) && pool.len() < size {
                    pool.push(i);
                }
            }
        }
        if pool.len() >= size {
            break;
        }
    }
    pool.sort_unstable();
    pool
}

/// The rigid-body modes of `deck` at its beam nodes and at the channels;
/// `None` if it has none (fixed, or on springs already) or cannot be solved.
fn rigid_rows(ctx: &Context, data: &TestData) -> Option<RigidRows> {
    let deck = ctx.deck;
    let fe = model::build(deck, &ParameterValues::new()).ok()?;
    if fe.has_fixed_dofs {
        return None;
    }
    let count = 8.min(fe.dofs.len());
    let modes = crate::solvers::eigen::lowest_modes(
        &fe.stiffness,
        &fe.mass,
        &crate::solvers::eigen::EigenOptions {
            count,
            ..Default::default()
        },
    )
    .ok()?;
    let rigid = rigid_columns(&modes.omega2)?;
    let row = |eq: usize, sign: f64| -> Vec<f64> {
        rigid
            .iter()
            .map(|&r| sign * modes.shapes[(eq, r)])
            .collect()
    };
    let mut channels = Vec::with_capacity(data.channels.len());
    for ch in &data.channels {
        let (eq, sign) = fe.measured_dof(ch.node, ch.direction)?;
        channels.push(row(eq, sign));
    }
    let nodes = node_rows(ctx, &fe, |eq| row(eq, 1.0));
    Some(RigidRows { nodes, channels })
}

/// The rigid-body modes among `omega2` (|ω²| ≤ 1e-6 of the largest);
/// `None` if there are none or nothing else.
fn rigid_columns(omega2: &[f64]) -> Option<Vec<usize>> {
    let top = omega2.iter().fold(0.0f64, |a, w| a.max(w.abs()));
    let rigid: Vec<usize> = (0..omega2.len())
        .filter(|&r| omega2[r].abs() <= 1e-6 * top)
        .collect();
    (!rigid.is_empty() && rigid.len() < omega2.len()).then_some(rigid)
}

/// Per translational direction of the analysis, the rigid-body row u_n
/// (`row` of its equation) at each beam node where it is not zero.
fn node_rows(
    ctx: &Context,
    fe: &model::FeModel,
    row: impl Fn(usize) -> Vec<f64>,
) -> Vec<(DeckDof, NodeRows)> {
    let beam_nodes = ctx.beam_nodes();
    let mut nodes = Vec::new();
    for (deck_dof, dof) in [
        (DeckDof::X, Dof::X),
        (DeckDof::Y, Dof::Y),
        (DeckDof::Z, Dof::Z),
    ] {
        if !ctx.deck.analysis.has_dof(deck_dof) {
            continue;
        }
        let rows: NodeRows = beam_nodes
            .iter()
            .filter_map(|&n| fe.dofs.index(n, dof).map(|eq| (n, row(eq))))
            .filter(|(_, u)| u.iter().any(|x| x.abs() > 0.0))
            .collect();
        if !rows.is_empty() {
            nodes.push((deck_dof, rows));
        }
    }
    nodes
}

/// The placement of springs at `pick` (indices into `nodes`), scored.
fn score(
    rows: &RigidRows,
    test: &SuspensionModes,
    nodes: &[(u32, Vec<f64>)],
    pick: &[usize],
    dof: DeckDof,
    hard: &[u32],
) -> Option<Placement> {
    let nr = rows.channels.first()?.len();
    let eig = spring_gram(nodes, pick, nr);
    let mu_top = eig.eigenvalues.iter().fold(0.0f64, |a, v| a.max(*v));
    if !(mu_top > 0.0) {
        return None;
    }
    // The modes the springs hold (μ > 0); their shapes at the channels.
    let held: Vec<(f64, Vec<f64>)> = (0..nr)
        .filter(|&i| eig.eigenvalues[i] > 1e-9 * mu_top)
        .map(|i| {
            let q = eig.eigenvectors.column(i);
            let shape = rows
                .channels
                .iter()
                .map(|u| (0..nr).map(|a| u[a] * q[a]).sum())
                .collect();
            (eig.eigenvalues[i], shape)
        })
        .collect();
    let pairs = pair_by_mac(&test.shapes, &held);
    if pairs.is_empty() {
        return None;
    }
    let omega2 = |t: usize| (2.0 * std::f64::consts::PI * test.frequency_hz[t]).powi(2);
    let ln_k = pairs
        .iter()
        .map(|&(t, i, _)| (omega2(t) / held[i].0).ln())
        .sum::<f64>()
        / pairs.len() as f64;
    let mut s = (test.frequency_hz.len() - pairs.len()) as f64;
    for &(t, i, mac) in &pairs {
        let d = 0.5 * (omega2(t).ln() - ln_k - held[i].0.ln());
        s += (1.0 - mac) + (d / LN_FREQUENCY_SCALE).powi(2);
    }
    s += placement_cost(nodes, pick, hard);
    let mut p = Placement::of(nodes, pick, dof, ln_k.exp(), s);
    p.unmatched = held.len() - pairs.len();
    Some(p)
}

impl Placement {
    /// Springs at `pick` (indices into `nodes`), named by their nodes in
    /// ascending order.
    fn of(nodes: &[(u32, Vec<f64>)], pick: &[usize], dof: DeckDof, k: f64, score: f64) -> Self {
        let mut names: Vec<u32> = pick.iter().map(|&i| nodes[i].0).collect();
        names.sort_unstable();
        Placement {
            nodes: names,
            dof,
            k,
            score,
            unmatched: 0,
        }
    }
}

/// The eigen-decomposition of G_S = Σ_{n∈S} u_nᵀ u_n (n_r × n_r) for the
/// springs at `pick` (indices into `nodes`): μ_i and q_i.
fn spring_gram(
    nodes: &[(u32, Vec<f64>)],
    pick: &[usize],
    nr: usize,
) -> SymmetricEigen<f64, nalgebra::Dyn> {
    SymmetricEigen::new(gram(nodes, pick, nr))
}

/// G_S = Σ_{n∈S} u_nᵀ u_n over the first `n` entries of the rows u_n of
/// the springs at `pick` (indices into `nodes`).
fn gram(nodes: &[(u32, Vec<f64>)], pick: &[usize], n: usize) -> DMatrix<f64> {
    let mut g = DMatrix::<f64>::zeros(n, n);
    for &i in pick {
        let u = &nodes[i].1;
        for a in 0..n {
            for b in 0..n {
                g[(a, b)] += u[a] * u[b];
            }
        }
    }
    g
}

/// The placement penalty of springs at `pick`: [`PER_SPRING`] for each
/// spring beyond the first, [`OFF_HARD_POINT`] for each off a hard point.
fn placement_cost(nodes: &[(u32, Vec<f64>)], pick: &[usize], hard: &[u32]) -> f64 {
    PER_SPRING * (pick.len() - 1) as f64
        + OFF_HARD_POINT
            * pick
                .iter()
                .filter(|&&i| !hard.contains(&nodes[i].0))
                .count() as f64
}

/// Test modes paired with held modes, highest MAC first, each used once:
/// (test index, held index, MAC).
fn pair_by_mac(test: &[Vec<f64>], held: &[(f64, Vec<f64>)]) -> Vec<(usize, usize, f64)> {
    let mut all: Vec<(usize, usize, f64)> = Vec::new();
    for (t, a) in test.iter().enumerate() {
        for (i, (_, b)) in held.iter().enumerate() {
            all.push((t, i, mac(a, b)));
        }
    }
    all.sort_by(|x, y| y.2.total_cmp(&x.2).then((x.0, x.1).cmp(&(y.0, y.1))));
    let mut pairs: Vec<(usize, usize, f64)> = Vec::new();
    for (t, i, m) in all {
        if pairs.iter().all(|&(u, j, _)| u != t && j != i) {
            pairs.push((t, i, m));
        }
    }
    pairs
}
