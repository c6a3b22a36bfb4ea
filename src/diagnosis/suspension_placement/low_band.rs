//! Suspension springs placed by the test's low band, without its modes.
//!
//! Below the first elastic mode a free-free deck on springs k at the nodes
//! S (one direction) responds as the deck with its lowest modes (the
//! rigid-body modes and the elastic ones below [`COUPLED_BAND`] × the
//! first) coupled by the springs: with φ_n the row of those modes at node
//! n, G_S = Σ_{n∈S} φ_n φ_nᵀ and the basis mass-normalised, the modes on
//! springs solve (diag(ω_r²) + k·G_S) q_i = Ω_i² q_i, and with Φ_c the
//! row at channel c (times its sign) and φ_e at the excitation,
//!
//!   H_c(ω) = H_c^rest(ω) + (iω)ⁿ Σ_i (Φ_c q_i)(φ_e q_i) / d(Ω_i², ω)
//!
//! (d the damping's modal denominator; H^rest the deck's other modes and
//! static residual; directions the springs do not hold stay rigid). To
//! first order in k the elastic modes drop out and the suspension modes
//! are the rigid-body modes on springs of the parent module; kept, they
//! move a suspension mode near the first elastic one by several per cent,
//! which a lightly damped peak cannot afford. Every set of one or two
//! nodes, and of three among the nodes of the best pairs, is scored by the
//! weighted misfit of that prediction on the lines below [`LOW_BAND`] × the
//! deck's first elastic frequency, k by a search on ln k; the best sets are
//! improved one node at a time ([`exchange`]). No identified suspension
//! mode is needed: lines a few hertz apart with both suspension modes
//! between them are enough (seed-1 diagnosis benchmark cases 054 and 224,
//! where the pole fit finds neither mode and the modal placement has
//! nothing to work on).
//!
//! The misfit of a point is w²|z − 1|²/|z|, z = H_model/H_test: the squared
//! log ratio of the FRF fit ([`fit::residuals`], same weights w) to second
//! order at z = 1, symmetric under z → 1/z like it (a model peak where the
//! test has none costs what a missing one does), without a logarithm per
//! point and per trial k.

use faer::c64;
use nalgebra::{DMatrix, Dyn, SymmetricEigen};

use frfup_parsers::deck::DeckDof;
use rayon::prelude::*;

use super::{
    best_sets, by_score, gram, node_rows, placement_cost, rigid_columns, spring_gram,
    tied_with_the_best, Placement, SUSPENSION_BAND,
};
use crate::diagnosis::data::TestData;
use crate::diagnosis::fit::{self, Mask};
use crate::diagnosis::hypotheses::{prior, Context};
use crate::model::{self, Damping, ParameterValues};
use crate::updating::serep::dot;

/// Lines below this fraction of the deck's first elastic frequency carry the
/// suspension's signature.
const LOW_BAND: f64 = SUSPENSION_BAND;
/// Fewer low lines than this: no placement from the low band.
const MIN_LINES: usize = 3;
/// Points of the first grid on ln k, then golden-section steps.
const K_GRID: usize = 48;
const K_GOLDEN: usize = 24;
/// Triples scored per direction: those of the best pairs' twelve nodes (a
/// score here is a search on ln k over the band's lines, about 2 ms).
const TRIPLES: usize = 220;

/// The deck's low band: the lines, the elastic part of its prediction and
/// the rigid-body rows at the channels and the excitation.
struct LowBand<'a> {
    data: &'a TestData,
    damping: Damping,
    /// Low lines (indices into `data.lines_hz`) and their ω (rad/s).
    lines: Vec<usize>,
    /// H^rest[k][j]: the k-th active channel (of the mask) at line
    /// `lines[j]`, the modes of the basis left out.
    rest: Vec<Vec<c64>>,
    /// w² and 1/H_test at the same points (w the fit's weight; w = 0: the
    /// point is left out); w² flat, channel by channel.
    weight2: Vec<f64>,
    inv_test: Vec<Vec<c64>>,
    /// ω² of the basis: the rigid-body modes (0) first, then the coupled
    /// elastic modes.
    omega2: Vec<f64>,
    /// Rigid-body modes in the basis (its first entries).
    rigid: usize,
    /// U_c: the basis row at each channel (times its sign), and u_e.
    u: Vec<Vec<f64>>,
    u_e: Vec<f64>,
}

/// The best `count` placements of same-stiffness springs on the free-free
/// deck of `ctx` for the test's low band (masked by `mask`), best first
/// (ties with the last kept, as [`super::placements`]); none when the deck
/// has no rigid-body modes, the band has too few lines or no placement fits
/// it better than the deck without springs.
pub fn low_band_placements(
    ctx: &Context,
    data: &TestData,
    damping: Damping,
    mask: &Mask,
    count: usize,
) -> Vec<Placement> {
    if !ctx.free_free {
        return Vec::new();
    }
    // The band's two models, each searched on its own (see the module's
    // doc): coupled to the deck's elastic modes, and on its rigid-body
    // modes alone, the safer when those elastic modes are themselves off
    // (the deck's parameters not yet right, another effect missing). Seed-1
    // case 279: the coupled model's misfit for the true springs 1, 3 has
    // no valley near the true k and springs at 1, 96 come first; the
    // rigid-body one places 1, 3. The GARTEUR-like fixture: the reverse.
    // The best of each go to the round's FRF fits, which decide.
    let mut placed = Vec::new();
    for coupled in [COUPLED_MODES, 0] {
        for p in search(ctx, data, damping, mask, count, coupled) {
            if !placed
                .iter()
                .any(|q: &Placement| q.dof == p.dof && q.nodes == p.nodes)
            {
                placed.push(p);
            }
        }
    }
    placed
}

/// The best `count` placements (with ties) of the low band's model with
/// up to `coupled` elastic modes coupled to the springs.
fn search(
    ctx: &Context,
    data: &TestData,
    damping: Damping,
    mask: &Mask,
    count: usize,
    coupled: usize,
) -> Vec<Placement> {
    let Some((band, nodes)) = LowBand::of(ctx, data, damping, mask, coupled) else {
        return Vec::new();
    };
    let free = band.cost_free();
    let hard = prior::hard_points(ctx.deck);
    // The search on at most SEARCH_LINES of the band's lines, the best
    // sets scored again on all of them.
    let coarse = band.thinned(SEARCH_LINES);
    let score =
        |nodes: &[(u32, Vec<f64>)], pick: &[usize], dof| coarse.score(nodes, pick, dof, &hard);
    let mut all = best_sets(&nodes, usize::MAX, TRIPLES, score);
    exchange(&mut all, &nodes, score);
    all.truncate(RESCORED * count);
    let mut all: Vec<Placement> = all
        .iter()
        .filter_map(|p| {
            let (rows, pick) = pick_of(&p.nodes, p.dof, &nodes)?;
            band.score(rows, &pick, p.dof, &hard)
        })
        // Only what fits the band better than the deck without springs.
        .filter(|p| p.score < free)
        .collect();
    all.sort_by(by_score);
    let kept = tied_with_the_best(&all, count);
    all.truncate(kept);
    all
}

/// Lines of the band the sets are searched on at most (evenly among its
/// lines): a score is a search on ln k, about 80 evaluations of the band's
/// prediction, for every set of one or two nodes; a log axis puts hundreds
/// of lines below the first elastic mode (seed-1 case 095: 421 lines, 97
/// nodes, 80 s for the sets on every line).
const SEARCH_LINES: usize = 64;
/// The best `RESCORED × count` sets of the search are scored again on
/// every line of the band.
const RESCORED: usize = 4;

/// The nodes of direction `dof` and the springs at `ids` as indices into
/// them.
fn pick_of<'n>(
    ids: &[u32],
    dof: DeckDof,
    by_direction: &'n [(DeckDof, super::NodeRows)],
) -> Option<(&'n super::NodeRows, Vec<usize>)> {
    let (_, nodes) = by_direction.iter().find(|(d, _)| *d == dof)?;
    let pick = ids
        .iter()
        .map(|n| nodes.iter().position(|(m, _)| m == n))
        .collect::<Option<Vec<usize>>>()?;
    Some((nodes, pick))
}

/// The best sets from which [`exchange`] starts.
const EXCHANGE_SEEDS: usize = 4;
/// Exchanges made from one seed at most.
const EXCHANGE_MOVES: usize = 6;

/// Sets of up to three springs improved one node at a time: from each of
/// the [`EXCHANGE_SEEDS`] best of `all` (sorted), the best of every set
/// that exchanges one of its nodes for another node of its direction, or
/// (below three) adds one, taken while it lowers the score; the sets found
/// join `all`, which is sorted again. The triples of the best pairs' nodes
/// miss a set whose pairs each fit poorly: the GARTEUR-like fixture
/// (`fixtures/garteur`) hangs from cords at nodes 104, 204 (the wings) and
/// 10 (the fuselage); no pair among them is among the best, and the
/// triple, better than every set of the pool, was never scored.
fn exchange(
    all: &mut Vec<Placement>,
    by_direction: &[(DeckDof, super::NodeRows)],
    score: impl Fn(&[(u32, Vec<f64>)], &[usize], DeckDof) -> Option<Placement> + Sync,
) {
    let seeds: Vec<Placement> = all.iter().take(EXCHANGE_SEEDS).cloned().collect();
    for seed in seeds {
        let Some((nodes, mut pick)) = pick_of(&seed.nodes, seed.dof, by_direction) else {
            continue;
        };
        let mut best = seed;
        for _ in 0..EXCHANGE_MOVES {
            let moves = neighbours(&pick, nodes.len());
            let found = moves
                .par_iter()
                .filter_map(|m| score(nodes, m, best.dof).map(|p| (p, m)))
                .min_by(|a, b| by_score(&a.0, &b.0));
            match found {
                Some((p, m)) if by_score(&p, &best).is_lt() => {
                    pick = m.clone();
                    if !all.iter().any(|q| q.dof == p.dof && q.nodes == p.nodes) {
                        all.push(p.clone());
                    }
                    best = p;
                }
                _ => break,
            }
        }
    }
    all.sort_by(by_score);
}

/// The sets one exchange (or, below three nodes, one addition) away from
/// `pick` among `n` nodes, each ascending.
fn neighbours(pick: &[usize], n: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    for other in (0..n).filter(|o| !pick.contains(o)) {
        for k in 0..pick.len() {
            let mut m = pick.to_vec();
            m[k] = other;
            m.sort_unstable();
            out.push(m);
        }
        if pick.len() < 3 {
            let mut m = pick.to_vec();
            m.push(other);
            m.sort_unstable();
            out.push(m);
        }
    }
    out
}

/// Elastic modes coupled to the springs in the basis: those below
/// [`COUPLED_BAND`] × the first elastic frequency, at most
/// [`COUPLED_MODES`]. Suspension modes within a factor of three of the
/// first elastic mode are moved by it by several per cent (the GARTEUR-like
/// fixture: 2.5 Hz against 6.2 Hz), and lines near a mode damped at 1 %
/// move by tens of per cent when its frequency moves by one.
const COUPLED_BAND: f64 = 3.0;
const COUPLED_MODES: usize = 6;

/// The modes on springs in the basis: ω²_i and per active channel the
/// coefficients (U_c q_i)(u_e q_i).
struct SpringModes {
    mu: Vec<f64>,
    coeff: Vec<Vec<f64>>,
}

type DirectionRows = Vec<(frfup_parsers::deck::DeckDof, super::NodeRows)>;

impl<'a> LowBand<'a> {
    /// The deck of `ctx` solved at the channels of `data`, with up to
    /// `coupled_modes` elastic modes in the basis; its rows per direction at
    /// the beam nodes.
    fn of(
        ctx: &Context,
        data: &'a TestData,
        damping: Damping,
        mask: &Mask,
        coupled_modes: usize,
    ) -> Option<(Self, DirectionRows)> {
        // Springs to ground already: the low modes are not rigid (soft
        // springs would pass the ω² test below, as in a sprung deck).
        if ctx.deck.springs.iter().any(|s| s.to.is_none()) {
            return None;
        }
        let fe = model::build(ctx.deck, &ParameterValues::new()).ok()?;
        if fe.has_fixed_dofs {
            return None;
        }
        let sol = fit::modal_solution(&fe, data).ok()?;
        let rigid = rigid_columns(&sol.model.omega2)?;
        let coupled_top = (COUPLED_BAND * ctx.first_elastic_omega).powi(2);
        let coupled = (0..sol.model.omega2.len())
            .filter(|r| !rigid.contains(r) && sol.model.omega2[*r] <= coupled_top)
            .take(coupled_modes);
        let basis: Vec<usize> = rigid.iter().copied().chain(coupled).collect();
        let top_hz = LOW_BAND * ctx.first_elastic_omega / (2.0 * std::f64::consts::PI);
        let lines: Vec<usize> = (0..data.lines_hz.len())
            .filter(|&l| mask.lines[l] && data.lines_hz[l] < top_hz)
            .collect();
        if lines.len() < MIN_LINES {
            return None;
        }
        let low = Mask {
            lines: (0..data.lines_hz.len())
                .map(|l| lines.binary_search(&l).is_ok())
                .collect(),
            channels: mask.channels.clone(),
        };
        let mut rest_model = sol.model.clone();
        for c in &mut rest_model.coeff {
            for &r in &basis {
                c[r] = 0.0;
            }
        }
        let pred = fit::predict(&rest_model, damping, data, &low);
        let channels: Vec<usize> = (0..data.channels.len())
            .filter(|&c| mask.channels[c])
            .collect();
        let rest = at_points(&channels, &lines, |c, l| pred[c][l]);
        let inv_test = at_points(&channels, &lines, |c, l| data.values[c][l].inv());
        let weight2 = at_points(&channels, &lines, |c, l| data.weight[c][l].powi(2)).concat();
        let shapes = &sol.modes.shapes;
        let row = |eq: usize| -> Vec<f64> { basis.iter().map(|&r| shapes[(eq, r)]).collect() };
        let omega2 = basis
            .iter()
            .map(|&r| {
                if rigid.contains(&r) {
                    0.0
                } else {
                    sol.model.omega2[r]
                }
            })
            .collect();
        let u = channels
            .iter()
            .map(|&c| {
                row(sol.outputs[c])
                    .iter()
                    .map(|x| x * sol.signs[c])
                    .collect()
            })
            .collect();
        let nodes = node_rows(ctx, &fe, row);
        let band = LowBand {
            data,
            damping,
            lines,
            rest,
            weight2,
            inv_test,
            omega2,
            rigid: rigid.len(),
            u,
            u_e: row(sol.input),
        };
        Some((band, nodes))
    }

    /// The band on every `⌈n / max⌉`-th of its n lines (all when n ≤ max).
    fn thinned(&self, max: usize) -> LowBand<'a> {
        let step = self.lines.len().div_ceil(max.max(1)).max(1);
        fn keep<T: Copy>(rows: &[Vec<T>], step: usize) -> Vec<Vec<T>> {
            rows.iter()
                .map(|v| v.iter().step_by(step).copied().collect())
                .collect()
        }
        LowBand {
            data: self.data,
            damping: self.damping,
            lines: self.lines.iter().step_by(step).copied().collect(),
            rest: keep(&self.rest, step),
            weight2: self
                .weight2
                .chunks(self.lines.len().max(1))
                .flat_map(|w| w.iter().step_by(step).copied())
                .collect(),
            inv_test: keep(&self.inv_test, step),
            omega2: self.omega2.clone(),
            rigid: self.rigid,
            u: self.u.clone(),
            u_e: self.u_e.clone(),
        }
    }

    /// The misfit of the deck as it is (its rigid-body modes free).
    fn cost_free(&self) -> f64 {
        let m = self.omega2.len();
        self.cost(&self.on_springs(&DMatrix::zeros(m, m), 0.0))
    }

    /// The basis's modes on springs k·G (G = Σ_{n∈S} φ_n φ_nᵀ over the
    /// basis rows φ_n of the spring nodes): the eigen solution of
    /// diag(ω²) + k·G (the basis is mass-normalised).
    fn on_springs(&self, g: &DMatrix<f64>, k: f64) -> SpringModes {
        let mut a = g * k;
        for (i, w2) in self.omega2.iter().enumerate() {
            a[(i, i)] += w2;
        }
        let eig = SymmetricEigen::new(a);
        let modes: Vec<(f64, Vec<f64>)> = (0..self.omega2.len())
            .map(|i| {
                let w2 = eig.eigenvalues[i].max(0.0);
                (w2, eig.eigenvectors.column(i).iter().copied().collect())
            })
            .collect();
        self.spring_modes(&modes)
    }

    /// The rigid-body modes on springs, (μ_i, q_i), as μ_i and the
    /// coefficients (U_c q_i)(u_e q_i) of each active channel.
    fn spring_modes(&self, modes: &[(f64, Vec<f64>)]) -> SpringModes {
        let at_excitation: Vec<f64> = modes.iter().map(|(_, q)| dot(&self.u_e, q)).collect();
        SpringModes {
            mu: modes.iter().map(|m| m.0).collect(),
            coeff: self
                .u
                .iter()
                .map(|u| {
                    modes
                        .iter()
                        .zip(&at_excitation)
                        .map(|((_, q), e)| dot(u, q) * e)
                        .collect()
                })
                .collect(),
        }
    }

    /// The placement of springs at `pick` (indices into `nodes`), k by a
    /// search on ln k, scored by its misfit (times 1 + the placement
    /// penalty of the parent module).
    fn score(
        &self,
        nodes: &[(u32, Vec<f64>)],
        pick: &[usize],
        dof: frfup_parsers::deck::DeckDof,
        hard: &[u32],
    ) -> Option<Placement> {
        let nr = self.rigid;
        let eig: SymmetricEigen<f64, Dyn> = spring_gram(nodes, pick, nr);
        let mu_top = eig.eigenvalues.iter().fold(0.0f64, |a, v| a.max(*v));
        if !(mu_top > 0.0) {
            return None;
        }
        // The range of k: the suspension modes (to first order √(kμ_i))
        // from a quarter of the band's first line to twice its last.
        let mu_low = eig
            .eigenvalues
            .iter()
            .copied()
            .filter(|&m| m > 1e-9 * mu_top)
            .fold(mu_top, f64::min);
        let w_lo = self.data.omegas[self.lines[0]] / 4.0;
        let w_hi = self.data.omegas[*self.lines.last()?] * 2.0;
        let (lo, hi) = ((w_lo * w_lo / mu_top).ln(), (w_hi * w_hi / mu_low).ln());
        let g = gram(nodes, pick, self.omega2.len());
        let (ln_k, misfit) = minimise(|x| self.cost(&self.on_springs(&g, x.exp())), lo, hi);
        let score = misfit * (1.0 + placement_cost(nodes, pick, hard));
        Some(Placement::of(nodes, pick, dof, ln_k.exp(), score))
    }

    /// Mean squared weighted misfit with the basis's part given by `modes`.
    ///
    /// Every point's operations are those of one point at a time, in the
    /// same order (the same bits), but laid out for the processor: the sums
    /// over the modes of [`LANES`] lines at once (independent chains of
    /// additions), then the misfits of all points ([`mean_misfit`]), whose
    /// square roots and divisions were most of the band's time.
    fn cost(&self, modes: &SpringModes) -> f64 {
        let data = self.data;
        let (nm, nl) = (modes.mu.len(), self.lines.len());
        // (iω)ⁿ / d(Ω_i², ω) of mode i at line j: entry i·nl + j.
        let mut inv_re = vec![0.0; nm * nl];
        let mut inv_im = vec![0.0; nm * nl];
        for (j, &l) in self.lines.iter().enumerate() {
            let w = data.omegas[l];
            let kind = crate::testdata::i_omega_power(w, data.kind.order());
            for (i, w2) in modes.mu.iter().enumerate() {
                let g = kind * self.damping.modal_denominator(*w2, w).inv();
                (inv_re[i * nl + j], inv_im[i * nl + j]) = (g.re, g.im);
            }
        }
        // z = H_model/H_test at every point, channel by channel.
        let points = modes.coeff.len() * nl;
        let (mut z_re, mut z_im) = (vec![0.0; points], vec![0.0; points]);
        let full = nl / LANES * LANES;
        for (kc, a) in modes.coeff.iter().enumerate() {
            let (rest, inv_test) = (&self.rest[kc], &self.inv_test[kc]);
            let (z_re, z_im) = (&mut z_re[kc * nl..], &mut z_im[kc * nl..]);
            for j0 in (0..full).step_by(LANES) {
                let mut h_re: [f64; LANES] = std::array::from_fn(|t| rest[j0 + t].re);
                let mut h_im: [f64; LANES] = std::array::from_fn(|t| rest[j0 + t].im);
                for (i, &ai) in a.iter().enumerate() {
                    let (g_re, g_im) = (lanes(&inv_re, i * nl + j0), lanes(&inv_im, i * nl + j0));
                    for t in 0..LANES {
                        h_re[t] += g_re[t] * ai;
                        h_im[t] += g_im[t] * ai;
                    }
                }
                for t in 0..LANES {
                    let z = c64::new(h_re[t], h_im[t]) * inv_test[j0 + t];
                    (z_re[j0 + t], z_im[j0 + t]) = (z.re, z.im);
                }
            }
            for j in full..nl {
                let mut h = rest[j];
                for (i, &ai) in a.iter().enumerate() {
                    h += c64::new(inv_re[i * nl + j], inv_im[i * nl + j]) * ai;
                }
                let z = h * inv_test[j];
                (z_re[j], z_im[j]) = (z.re, z.im);
            }
        }
        mean_misfit(&z_re, &z_im, &self.weight2)
    }
}

/// Lines, or points, whose operations [`LowBand::cost`] lays side by side.
const LANES: usize = 8;

/// `LANES` entries of `v` from `start`.
fn lanes(v: &[f64], start: usize) -> &[f64; LANES] {
    v[start..]
        .first_chunk()
        .expect("a block of lanes lies within its row")
}

/// The mean of [`point_misfit`] over the points z = `z_re` + i`z_im` with
/// weights² `w2` (those of w² = 0 left out; +∞ when none is left), summed in
/// their order; `LANES` points at a time ([`point_misfits`]).
pub fn mean_misfit(z_re: &[f64], z_im: &[f64], w2: &[f64]) -> f64 {
    let (mut sum, mut n) = (0.0, 0usize);
    let full = w2.len() / LANES * LANES;
    for p0 in (0..full).step_by(LANES) {
        let w = lanes(w2, p0);
        let m = point_misfits(lanes(z_re, p0), lanes(z_im, p0), w);
        for t in (0..LANES).filter(|&t| w[t] != 0.0) {
            sum += m[t];
            n += 1;
        }
    }
    for p in (full..w2.len()).filter(|&p| w2[p] != 0.0) {
        sum += point_misfit(c64::new(z_re[p], z_im[p]), w2[p]);
        n += 1;
    }
    if n == 0 {
        f64::INFINITY
    } else {
        sum / n as f64
    }
}

/// [`point_misfit`] of `LANES` points: each operation the same as one
/// point's, so the same bits, in loops the compiler turns into vector
/// instructions (several square roots or divisions in one).
#[inline(always)]
fn point_misfits(z_re: &[f64; LANES], z_im: &[f64; LANES], w2: &[f64; LANES]) -> [f64; LANES] {
    let n2: [f64; LANES] = std::array::from_fn(|t| z_re[t] * z_re[t] + z_im[t] * z_im[t]);
    let mut size: [f64; LANES] = std::array::from_fn(|t| n2[t].sqrt());
    for t in (0..LANES).filter(|&t| !n2[t].is_finite()) {
        size[t] = c64::new(z_re[t], z_im[t]).norm();
    }
    std::array::from_fn(|t| {
        let (dr, di) = (z_re[t] - 1.0, z_im[t] - 0.0);
        w2[t] * (dr * dr + di * di) / size[t].max(1e-300)
    })
}

/// The misfit w²|z − 1|²/|z| of one point, z = H_model/H_test and `w2`
/// = w² (see the module's doc): 0 at z = 1, the same for z and 1/z. |z| is
/// √|z|² (glibc's hypot was a quarter of the band's time), hypot only where
/// |z|² overflows, so that such a point costs +∞, never ∞/∞ = NaN (x86's
/// NaN is negative, and `total_cmp` sorts it below every cost).
pub fn point_misfit(z: c64, w2: f64) -> f64 {
    let n2 = z.norm_sqr();
    let size = if n2.is_finite() { n2.sqrt() } else { z.norm() };
    w2 * (z - c64::new(1.0, 0.0)).norm_sqr() / size.max(1e-300)
}

/// `f(c, l)` at every channel of `channels` (rows) and line of `lines`.
fn at_points<T>(channels: &[usize], lines: &[usize], f: impl Fn(usize, usize) -> T) -> Vec<Vec<T>> {
    channels
        .iter()
        .map(|&c| lines.iter().map(|&l| f(c, l)).collect())
        .collect()
}

/// The minimum of `f` over [lo, hi]: a grid of [`K_GRID`] points, then
/// [`K_GOLDEN`] golden-section steps around the best (the bracket, two grid
/// steps, shrinks to 1e-5 of itself: a line near a lightly damped
/// suspension mode moves by tens of per cent when k moves by one); (x, f(x)).
fn minimise(f: impl Fn(f64) -> f64, lo: f64, hi: f64) -> (f64, f64) {
    let step = (hi - lo) / (K_GRID - 1) as f64;
    let grid: Vec<(f64, f64)> = (0..K_GRID)
        .map(|i| {
            let x = lo + step * i as f64;
            (x, f(x))
        })
        .collect();
    let best = (0..K_GRID)
        .min_by(|&a, &b| grid[a].1.total_cmp(&grid[b].1))
        .unwrap_or(0);
    let (mut a, mut b) = (grid[best].0 - step, grid[best].0 + step);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..K_GOLDEN {
        if fc < fd {
            (b, d, fd) = (d, c, fc);
            c = b - g * (b - a);
            fc = f(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + g * (b - a);
            fd = f(d);
        }
    }
    [grid[best], (c, fc), (d, fd)]
        .into_iter()
        .min_by(|x, y| x.1.total_cmp(&y.1))
        .unwrap_or(grid[best])
}
