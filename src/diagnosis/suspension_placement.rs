//! Suspension springs placed by the test's low band.
//!
//! A free-free structure on soft springs of stiffness k at the nodes S (one
//! direction d) has, to first order in k, the rigid-body modes of the deck
//! on those springs. With Φ_r the deck's mass-normalised rigid-body modes
//! (n_r of them) and u_n = Φ_r(n, d) their row at node n, the suspension
//! modes solve
//!
//!   k·G_S q = ω² q,   G_S = Σ_{n∈S} u_nᵀ u_n   (n_r × n_r),
//!
//! so their eigenvalues are λ_i = k μ_i over the eigenvalues μ_i of G_S and
//! their coefficient at channel c is a_ci = (u_c q_i)(u_e q_i) (u_e: the
//! excitation's row). Below [`SUSPENSION_BAND`] of the deck's first elastic
//! frequency the test is these modes plus the deck's elastic modes:
//!
//!   H_c(ω) = H_c^elastic(ω) + (iω)ⁿ Σ_i a_ci / d(λ_i, ω),
//!
//! with the deck's damping d (the full fit that follows models them so).
//! Every set of one or two nodes, and of three among the nodes of the best
//! pairs, is scored by that prediction's weighted log error on the low
//! band's lines (the cost of the full fit, [`fit::residuals`]), k fitted by
//! a search over ln k. The FRFs themselves are compared, not modes
//! identified from them: suspension modes a few lines above the band's
//! start, or narrower than a line, are rarely found by the identification,
//! but their spring and mass lines and their peaks are in the data. Sets
//! alike in their rigid-body effect (two nodes above one another under
//! vertical springs) score alike to rounding; the full FRF fit of the round,
//! which also sees the springs' small effect on the elastic modes, tells
//! them apart or not at all; then the set hung from hard points wins
//! ([`OFF_HARD_POINT`]).

use std::collections::HashMap;

use faer::c64;
use frfup_parsers::deck::DeckDof;
use nalgebra::{DMatrix, SymmetricEigen};
use rayon::prelude::*;

use super::data::TestData;
use super::fit::{self, Mask, ModalModel};
use super::hypotheses::{prior, Context};
use crate::identification::ColumnMode;
use crate::model::{self, Damping, Dof, ParameterValues};

/// The low band: test lines below this fraction of the deck's first
/// elastic frequency are the suspension's.
pub const SUSPENSION_BAND: f64 = 0.5;
/// Fewer low-band lines than this: no placement (k and the set are fitted
/// to them).
const MIN_LOW_LINES: usize = 4;
/// Each spring beyond the first costs this much (in ln of the low band's
/// cost): a further spring must lower the cost by 2 %.
const PER_SPRING: f64 = 0.02;
/// Each spring off a hard point (a free end, corner or junction, see
/// [`prior::hard_points`]) costs this much: of sets alike in their
/// rigid-body effect (nodes along a leg under vertical springs), the one
/// hung from hard points.
const OFF_HARD_POINT: f64 = 0.01;
/// Nodes of the best pairs among which triples are tried.
const TRIPLE_POOL: usize = 12;
/// Points of the first search over ln k, and golden-section steps after it.
const K_GRID: usize = 12;
const K_REFINE: usize = 12;

/// What a placement is scored against: the test, the current model's modal
/// model at its channels, its damping and the lines and channels in use.
pub struct LowBand<'a> {
    pub data: &'a TestData,
    pub model: &'a ModalModel,
    pub damping: Damping,
    pub mask: &'a Mask,
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

/// One placement: the nodes, the direction, k fitted to the low band (N/m)
/// and its score (ln of the low band's cost, plus [`PER_SPRING`] and
/// [`OFF_HARD_POINT`]).
#[derive(Clone, Debug)]
pub struct Placement {
    pub nodes: Vec<u32>,
    pub dof: DeckDof,
    pub k: f64,
    pub score: f64,
}

/// The rigid-body modes' row u_n at each node (node, u_n).
type NodeRows = Vec<(u32, Vec<f64>)>;

/// The rigid-body rows of the deck: per translational direction of the
/// analysis, u_n for each beam node; u_c at the channels and u_e at the
/// excitation.
struct RigidRows {
    /// (direction, [(node, u_n)]).
    nodes: Vec<(DeckDof, NodeRows)>,
    /// u_c: per channel, the rigid-body modes there (times the channel's
    /// sign and the excitation's, as [`ModalModel::coeff`]).
    channels: Vec<Vec<f64>>,
    /// u_e: the rigid-body modes at the excitation.
    input: Vec<f64>,
}

/// The best `count` placements of same-stiffness springs on the deck of
/// `ctx` (a free-free deck with no spring to ground) for the test's low
/// band, best first; none when the deck has no rigid-body modes or the band
/// fewer than [`MIN_LOW_LINES`] lines.
pub fn placements(ctx: &Context, low: &LowBand, count: usize) -> Vec<Placement> {
    if !ctx.free_free {
        return Vec::new();
    }
    let Some(rows) = rigid_rows(ctx, low.data) else {
        return Vec::new();
    };
    let Some(band) = Band::new(ctx, low, rows.input.len()) else {
        return Vec::new();
    };
    let hard = prior::hard_points(ctx.deck);
    let mut all: Vec<Placement> = Vec::new();
    for (dof, nodes) in &rows.nodes {
        let scale = nodes
            .iter()
            .map(|(_, u)| u.iter().map(|x| x * x).sum::<f64>())
            .fold(0.0f64, f64::max)
            .max(f64::MIN_POSITIVE);
        let scorer = Scorer {
            scale,
            rows: &rows,
            band: &band,
            nodes,
            dof: *dof,
            hard: &hard,
        };
        let mut sets: Vec<Vec<usize>> = Vec::new();
        for a in 0..nodes.len() {
            sets.push(vec![a]);
            for b in a + 1..nodes.len() {
                sets.push(vec![a, b]);
            }
        }
        let mut found = scorer.score_all(&sets);
        let pool = triple_pool(&found, nodes);
        let mut triples: Vec<Vec<usize>> = Vec::new();
        for (i, &a) in pool.iter().enumerate() {
            for (j, &b) in pool.iter().enumerate().skip(i + 1) {
                for &c in pool.iter().skip(j + 1) {
                    triples.push(vec![a, b, c]);
                }
            }
        }
        found.extend(scorer.score_all(&triples));
        all.extend(found);
    }
    all.sort_by(|x, y| x.score.total_cmp(&y.score).then(x.nodes.cmp(&y.nodes)));
    let kept = tied_with_the_best(&all, count);
    all.truncate(kept);
    all
}

/// Placements whose scores differ by less than this are alike (the springs'
/// rows of the rigid-body modes equal to rounding: nodes above one another
/// under vertical springs). Far below [`PER_SPRING`] and [`OFF_HARD_POINT`].
const TIE: f64 = 1e-9;

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
    while kept < sorted.len().min(2 * count) && sorted[kept].score - last <= TIE {
        kept += 1;
    }
    kept
}

/// Indices (into `nodes`) of the nodes of the best pairs of `found` (sorted
/// best first), at most [`TRIPLE_POOL`], ascending.
fn triple_pool(found: &[Placement], nodes: &[(u32, Vec<f64>)]) -> Vec<usize> {
    let mut pool: Vec<usize> = Vec::new();
    for p in found.iter().filter(|p| p.nodes.len() == 2) {
        for n in &p.nodes {
            if let Some(i) = nodes.iter().position(|(m, _)| m == n) {
                if !pool.contains(&i) && pool.len() < TRIPLE_POOL {
                    pool.push(i);
                }
            }
        }
        if pool.len() >= TRIPLE_POOL {
            break;
        }
    }
    pool.sort_unstable();
    pool
}

/// The rigid-body modes of `deck` at its beam nodes, at the channels and at
/// the excitation; `None` if it has none (fixed, or on springs already) or
/// cannot be solved.
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
    let top = modes.omega2.iter().fold(0.0f64, |a, w| a.max(w.abs()));
    let rigid: Vec<usize> = (0..modes.omega2.len())
        .filter(|&r| modes.omega2[r].abs() <= 1e-6 * top)
        .collect();
    if rigid.is_empty() || rigid.len() == modes.omega2.len() {
        return None;
    }
    let row = |eq: usize, sign: f64| -> Vec<f64> {
        rigid
            .iter()
            .map(|&r| sign * modes.shapes[(eq, r)])
            .collect()
    };
    let (input, in_sign) = fe.measured_dof(data.input.0, data.input.1)?;
    let mut channels = Vec::with_capacity(data.channels.len());
    for ch in &data.channels {
        let (eq, sign) = fe.measured_dof(ch.node, ch.direction)?;
        channels.push(row(eq, sign * in_sign));
    }
    let beam_nodes = ctx.beam_nodes();
    let mut nodes = Vec::new();
    for (deck_dof, dof) in [
        (DeckDof::X, Dof::X),
        (DeckDof::Y, Dof::Y),
        (DeckDof::Z, Dof::Z),
    ] {
        if !deck.analysis.has_dof(deck_dof) {
            continue;
        }
        let rows: NodeRows = beam_nodes
            .iter()
            .filter_map(|&n| fe.dofs.index(n, dof).map(|eq| (n, row(eq, 1.0))))
            .filter(|(_, u)| u.iter().any(|x| x.abs() > 0.0))
            .collect();
        if !rows.is_empty() {
            nodes.push((deck_dof, rows));
        }
    }
    Some(RigidRows {
        nodes,
        channels,
        input: row(input, 1.0),
    })
}

/// One measured point of the low band.
struct Point {
    channel: usize,
    weight: f64,
    /// 1 / the measured value.
    inv_measured: c64,
    /// The deck's elastic modes and residual terms there, in the measured kind.
    elastic: c64,
}

/// One line of the low band and its points.
struct Line {
    omega: f64,
    /// (iω)ⁿ of the measured kind.
    factor: c64,
    points: Vec<Point>,
}

/// The low band prepared once per round.
struct Band {
    lines: Vec<Line>,
    /// Points over all lines.
    count: usize,
    damping: Damping,
    /// ω² bounds of the search over k: a quarter of the band's first line
    /// and its top.
    omega2_lo: f64,
    omega2_hi: f64,
}

impl Band {
    /// The low band's points and the model's elastic part there; `None`
    /// when the model's rigid-body modes are not the `n_rigid` of its deck
    /// or the band has fewer than [`MIN_LOW_LINES`] lines.
    fn new(ctx: &Context, low: &LowBand, n_rigid: usize) -> Option<Band> {
        let (data, mm) = (low.data, low.model);
        let cut = SUSPENSION_BAND * ctx.first_elastic_omega;
        let in_band: Vec<bool> = (0..data.omegas.len())
            .map(|l| low.mask.lines[l] && data.omegas[l] > 0.0 && data.omegas[l] < cut)
            .collect();
        let used = informative(data, &in_band, &low.mask.channels);
        if used.len() < MIN_LOW_LINES {
            return None;
        }
        let in_band: Vec<bool> = (0..in_band.len())
            .map(|l| used.binary_search(&l).is_ok())
            .collect();
        let top = mm.omega2.iter().fold(0.0f64, |a, w| a.max(w.abs()));
        let elastic_modes: Vec<usize> = (0..mm.omega2.len())
            .filter(|&r| mm.omega2[r].abs() > 1e-6 * top)
            .collect();
        if mm.omega2.len() - elastic_modes.len() != n_rigid {
            return None;
        }
        let elastic = ModalModel {
            omega2: elastic_modes.iter().map(|&r| mm.omega2[r]).collect(),
            coeff: mm
                .coeff
                .iter()
                .map(|a| elastic_modes.iter().map(|&r| a[r]).collect())
                .collect(),
            frequencies_hz: elastic_modes
                .iter()
                .map(|&r| mm.frequencies_hz[r])
                .collect(),
            ..mm.clone()
        };
        let mask = Mask {
            lines: in_band,
            channels: low.mask.channels.clone(),
        };
        let pred = fit::predict(&elastic, low.damping, data, &mask);
        let lines: Vec<Line> = used
            .iter()
            .map(|&l| Line {
                omega: data.omegas[l],
                factor: crate::testdata::i_omega_power(data.omegas[l], data.kind.order()),
                points: (0..data.channels.len())
                    .filter(|&c| mask.channels[c] && data.weight[c][l] != 0.0)
                    .map(|c| Point {
                        channel: c,
                        weight: data.weight[c][l],
                        inv_measured: data.values[c][l].inv(),
                        elastic: pred[c][l],
                    })
                    .collect(),
            })
            .collect();
        let count = lines.iter().map(|l| l.points.len()).sum::<usize>();
        if count == 0 {
            return None;
        }
        Some(Band {
            lines,
            count,
            damping: low.damping,
            omega2_lo: (0.25 * data.omegas[used[0]]).powi(2),
            omega2_hi: cut * cut,
        })
    }

    /// Mean squared weighted log error of the springs' modes: eigenvalues
    /// `lambda` (rad²/s²), coefficients `coeff[c][i]`. The modes' 1/d(ω)
    /// once per line, for all its channels.
    fn cost(&self, lambda: &[f64], coeff: &[Vec<f64>]) -> f64 {
        let terms: Vec<_> = lambda.iter().map(|&l| self.damping.modal_term(l)).collect();
        let mut g = vec![c64::new(0.0, 0.0); lambda.len()];
        let mut sum = 0.0;
        for line in &self.lines {
            for ((gi, t), &l) in g.iter_mut().zip(&terms).zip(lambda) {
                *gi = t.at(l, line.omega).inv() * line.factor;
            }
            for p in &line.points {
                let mut h = p.elastic;
                for (gi, &ai) in g.iter().zip(&coeff[p.channel]) {
                    h += *gi * ai;
                }
                let (x, y) =
                    fit::log_ratio(h * p.inv_measured).unwrap_or((10.0, std::f64::consts::PI));
                sum += p.weight * p.weight * (x * x + y * y);
            }
        }
        sum / (2 * self.count) as f64
    }
}

/// Lines of a low band with more than this are thinned ([`informative`]).
const MAX_LOW_LINES: usize = 48;
/// Of a thinned band: lines of the even background, peaks kept and the
/// lines kept on each side of a peak.
const BACKGROUND_LINES: usize = 24;
const PEAKS: usize = 4;
const PEAK_SIDE: usize = 3;

/// The lines of `in_band` scored (ascending): all of them, or when more
/// than [`MAX_LOW_LINES`] (a log axis puts hundreds of lines below the
/// first elastic mode), an even background and the neighbourhoods of the
/// band's highest peaks of Σ_c |H_c| / max |H_c| (the suspension's
/// resonances, where the placement is decided).
fn informative(data: &TestData, in_band: &[bool], channels: &[bool]) -> Vec<usize> {
    let band: Vec<usize> = (0..in_band.len()).filter(|&l| in_band[l]).collect();
    if band.len() <= MAX_LOW_LINES {
        return band;
    }
    let mut level = vec![0.0; band.len()];
    for (c, values) in data.values.iter().enumerate() {
        let top = band
            .iter()
            .map(|&l| values[l].norm())
            .fold(0.0f64, f64::max);
        if !channels[c] || !(top > 0.0) {
            continue;
        }
        for (x, &l) in level.iter_mut().zip(&band) {
            *x += values[l].norm() / top;
        }
    }
    let mut peaks: Vec<usize> = (1..band.len() - 1)
        .filter(|&i| level[i] > level[i - 1] && level[i] >= level[i + 1])
        .collect();
    peaks.sort_by(|&a, &b| level[b].total_cmp(&level[a]).then(a.cmp(&b)));
    let mut kept: Vec<usize> = (0..BACKGROUND_LINES)
        .map(|i| i * (band.len() - 1) / (BACKGROUND_LINES - 1))
        .collect();
    for &p in peaks.iter().take(PEAKS) {
        kept.extend(p.saturating_sub(PEAK_SIDE)..(p + PEAK_SIDE + 1).min(band.len()));
    }
    kept.sort_unstable();
    kept.dedup();
    kept.into_iter().map(|i| band[i]).collect()
}

/// Scores sets of nodes of one direction.
struct Scorer<'a> {
    /// The largest |u_n|² of the direction (the scale of [`Self::key`]).
    scale: f64,
    rows: &'a RigidRows,
    band: &'a Band,
    nodes: &'a [(u32, Vec<f64>)],
    dof: DeckDof,
    hard: &'a [u32],
}

impl Scorer<'_> {
    /// Every set of `sets` (indices into `nodes`) scored, best first; sets
    /// alike in their rigid-body effect (the same G_S to rounding) fitted
    /// once.
    fn score_all(&self, sets: &[Vec<usize>]) -> Vec<Placement> {
        let keys: Vec<Vec<i64>> = sets.iter().map(|s| self.key(s)).collect();
        let mut unique: Vec<usize> = (0..sets.len()).collect();
        unique.sort_by(|&a, &b| keys[a].cmp(&keys[b]).then(a.cmp(&b)));
        unique.dedup_by(|a, b| keys[*a] == keys[*b]);
        let fits: Vec<Option<(f64, f64)>> = unique
            .par_iter()
            .map(|&i| self.fit_k(&self.gram(&sets[i])))
            .collect();
        let by_key: HashMap<&Vec<i64>, Option<(f64, f64)>> =
            unique.iter().map(|&i| &keys[i]).zip(fits).collect();
        let mut found: Vec<Placement> = sets
            .iter()
            .zip(&keys)
            .filter_map(|(s, key)| {
                let (k, cost) = by_key.get(key).copied().flatten()?;
                Some(self.placement(s, k, cost))
            })
            .collect();
        found.sort_by(|x, y| x.score.total_cmp(&y.score).then(x.nodes.cmp(&y.nodes)));
        found
    }

    /// G_S = Σ_{n∈S} u_nᵀ u_n.
    fn gram(&self, pick: &[usize]) -> DMatrix<f64> {
        let nr = self.rows.input.len();
        let mut g = DMatrix::<f64>::zeros(nr, nr);
        for &i in pick {
            let u = &self.nodes[i].1;
            for a in 0..nr {
                for b in 0..nr {
                    g[(a, b)] += u[a] * u[b];
                }
            }
        }
        g
    }

    /// G_S's entries to 1e-9 of the largest |u_n|²: equal for sets alike in
    /// their rigid-body effect.
    fn key(&self, pick: &[usize]) -> Vec<i64> {
        let g = self.gram(pick);
        g.iter()
            .map(|v| (v / self.scale * 1e9).round() as i64)
            .collect()
    }

    /// k (N/m) and the low band's cost of springs with Gram matrix `g`: a
    /// search over ln k that puts the highest held mode between a quarter of
    /// the band's first line and its top, then golden-section steps about
    /// the best point. `None` if the springs hold no mode.
    fn fit_k(&self, g: &DMatrix<f64>) -> Option<(f64, f64)> {
        let nr = g.nrows();
        let eig = SymmetricEigen::new(g.clone());
        let mu: Vec<f64> = eig.eigenvalues.iter().map(|m| m.max(0.0)).collect();
        let mu_top = mu.iter().fold(0.0f64, |a, v| a.max(*v));
        if !(mu_top > 0.0) {
            return None;
        }
        let mu: Vec<f64> = mu
            .iter()
            .map(|&m| if m > 1e-9 * mu_top { m } else { 0.0 })
            .collect();
        // a_ci = (u_c q_i)(u_e q_i).
        let dot = |u: &[f64], i: usize| {
            (0..nr)
                .map(|a| u[a] * eig.eigenvectors[(a, i)])
                .sum::<f64>()
        };
        let at_input: Vec<f64> = (0..nr).map(|i| dot(&self.rows.input, i)).collect();
        let coeff: Vec<Vec<f64>> = self
            .rows
            .channels
            .iter()
            .map(|u| (0..nr).map(|i| dot(u, i) * at_input[i]).collect())
            .collect();
        let cost = |ln_k: f64| {
            let k = ln_k.exp();
            let lambda: Vec<f64> = mu.iter().map(|m| k * m).collect();
            self.band.cost(&lambda, &coeff)
        };
        let (lo, hi) = (
            (self.band.omega2_lo / mu_top).ln(),
            (self.band.omega2_hi / mu_top).ln(),
        );
        let step = (hi - lo) / (K_GRID - 1) as f64;
        let grid: Vec<(f64, f64)> = (0..K_GRID)
            .map(|i| {
                let x = lo + step * i as f64;
                (x, cost(x))
            })
            .collect();
        let (x0, c0) = grid.iter().copied().min_by(|a, b| a.1.total_cmp(&b.1))?;
        let (x, c) = golden_minimum(cost, x0 - step, x0 + step, (x0, c0));
        Some((x.exp(), c))
    }

    fn placement(&self, pick: &[usize], k: f64, cost: f64) -> Placement {
        let off = pick
            .iter()
            .filter(|&&i| !self.hard.contains(&self.nodes[i].0))
            .count();
        let mut names: Vec<u32> = pick.iter().map(|&i| self.nodes[i].0).collect();
        names.sort_unstable();
        Placement {
            nodes: names,
            dof: self.dof,
            k,
            score: cost.max(f64::MIN_POSITIVE).ln()
                + PER_SPRING * (pick.len() - 1) as f64
                + OFF_HARD_POINT * off as f64,
        }
    }
}

/// Golden-section steps for the minimum of `f` on [a, b], `best` a point
/// already evaluated; the best point seen.
fn golden_minimum(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64, best: (f64, f64)) -> (f64, f64) {
    let r = 0.5 * (5f64.sqrt() - 1.0);
    let mut best = best;
    let mut x1 = b - r * (b - a);
    let mut x2 = a + r * (b - a);
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..K_REFINE {
        for (x, fx) in [(x1, f1), (x2, f2)] {
            if fx < best.1 {
                best = (x, fx);
            }
        }
        if f1 <= f2 {
            b = x2;
            (x2, f2) = (x1, f1);
            x1 = b - r * (b - a);
            f1 = f(x1);
        } else {
            a = x1;
            (x1, f1) = (x2, f2);
            x2 = a + r * (b - a);
            f2 = f(x2);
        }
    }
    best
}
