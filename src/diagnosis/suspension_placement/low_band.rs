//! Suspension springs placed by the test's low band, without its modes.
//!
//! Below the first elastic mode a free-free deck on springs k at the nodes
//! S (one direction) responds, to first order in k, as the deck with its
//! rigid-body part replaced by the rigid-body modes on springs (see the
//! parent module): with G_S = Σ_{n∈S} u_nᵀ u_n = Σ_i μ_i q_i q_iᵀ, U_c the
//! rigid-body row at channel c (times its sign) and u_e at the excitation,
//!
//!   H_c(ω) = H_c^elastic(ω) + (iω)ⁿ Σ_i (U_c q_i)(u_e q_i) / d(kμ_i, ω)
//!
//! (d the damping's modal denominator; directions the springs do not hold,
//! μ_i = 0, stay rigid). Every set of one or two nodes, and of three among
//! the nodes of the best pairs, is scored by the weighted misfit of that
//! prediction on the lines below [`LOW_BAND`] × the deck's first elastic
//! frequency, k by a search on ln k. No identified suspension mode is
//! needed: lines a few hertz apart with both suspension modes between them
//! are enough (seed-1 diagnosis benchmark cases 054 and 224, where the pole
//! fit finds neither mode and the modal placement has nothing to work on).
//!
//! The misfit of a point is w²|z − 1|²/|z|, z = H_model/H_test: the squared
//! log ratio of the FRF fit ([`fit::residuals`], same weights w) to second
//! order at z = 1, symmetric under z → 1/z like it (a model peak where the
//! test has none costs what a missing one does), without a logarithm per
//! point and per trial k.

use faer::c64;
use nalgebra::{Dyn, SymmetricEigen};

use super::{
    best_sets, node_rows, placement_cost, rigid_columns, spring_gram, tied_with_the_best,
    Placement, SUSPENSION_BAND,
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
    /// Active channels (indices into `data.channels`).
    channels: Vec<usize>,
    /// H^elastic[k][j]: channel `channels[k]` at line `lines[j]`.
    elastic: Vec<Vec<c64>>,
    /// U_c: rigid-body row at each channel (times its sign), and u_e.
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
    let Some((band, nodes)) = LowBand::of(ctx, data, damping, mask) else {
        return Vec::new();
    };
    let free = band.cost_free();
    let hard = prior::hard_points(ctx.deck);
    let mut all = best_sets(&nodes, usize::MAX, TRIPLES, |nodes, pick, dof| {
        band.score(nodes, pick, dof, &hard)
    });
    // Only what fits the band better than the deck without springs.
    all.retain(|p| p.score < free);
    let kept = tied_with_the_best(&all, count);
    all.truncate(kept);
    all
}

/// Rigid-body modes on springs of unit stiffness: μ_i, and per active
/// channel the coefficients (U_c q_i)(u_e q_i).
struct SpringModes {
    mu: Vec<f64>,
    coeff: Vec<Vec<f64>>,
}

type DirectionRows = Vec<(frfup_parsers::deck::DeckDof, super::NodeRows)>;

impl<'a> LowBand<'a> {
    /// The deck of `ctx` solved at the channels of `data`; its rigid-body
    /// rows per direction at the beam nodes.
    fn of(
        ctx: &Context,
        data: &'a TestData,
        damping: Damping,
        mask: &Mask,
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
        let mut elastic_model = sol.model.clone();
        for c in &mut elastic_model.coeff {
            for &r in &rigid {
                c[r] = 0.0;
            }
        }
        let pred = fit::predict(&elastic_model, damping, data, &low);
        let channels: Vec<usize> = (0..data.channels.len())
            .filter(|&c| mask.channels[c])
            .collect();
        let elastic = channels
            .iter()
            .map(|&c| lines.iter().map(|&l| pred[c][l]).collect())
            .collect();
        let shapes = &sol.modes.shapes;
        let row = |eq: usize| -> Vec<f64> { rigid.iter().map(|&r| shapes[(eq, r)]).collect() };
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
            channels,
            elastic,
            u,
            u_e: row(sol.input),
        };
        Some((band, nodes))
    }

    /// The misfit of the deck as it is (its rigid-body modes free).
    fn cost_free(&self) -> f64 {
        let nr = self.u_e.len();
        let modes: Vec<(f64, Vec<f64>)> = (0..nr)
            .map(|i| (0.0, (0..nr).map(|a| f64::from(a == i)).collect()))
            .collect();
        self.cost(&self.spring_modes(&modes), 1.0)
    }

    /// The rigid-body modes on springs, (μ_i, q_i), as μ_i and the
    /// coefficients (U_c q_i)(u_e q_i) of each active channel.
    fn spring_modes(&self, modes: &[(f64, Vec<f64>)]) -> SpringModes {
        SpringModes {
            mu: modes.iter().map(|m| m.0).collect(),
            coeff: self
                .u
                .iter()
                .map(|u| {
                    modes
                        .iter()
                        .map(|(_, q)| dot(u, q) * dot(&self.u_e, q))
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
        let nr = self.u_e.len();
        let eig: SymmetricEigen<f64, Dyn> = spring_gram(nodes, pick, nr);
        let mu_top = eig.eigenvalues.iter().fold(0.0f64, |a, v| a.max(*v));
        if !(mu_top > 0.0) {
            return None;
        }
        let modes: Vec<(f64, Vec<f64>)> = (0..nr)
            .map(|i| {
                let mu = eig.eigenvalues[i];
                let mu = if mu > 1e-9 * mu_top { mu } else { 0.0 };
                (mu, eig.eigenvectors.column(i).iter().copied().collect())
            })
            .collect();
        let mu_low = modes
            .iter()
            .map(|m| m.0)
            .filter(|&m| m > 0.0)
            .fold(mu_top, f64::min);
        let w_lo = self.data.omegas[self.lines[0]] / 4.0;
        let w_hi = self.data.omegas[*self.lines.last()?] * 2.0;
        let (lo, hi) = ((w_lo * w_lo / mu_top).ln(), (w_hi * w_hi / mu_low).ln());
        let modes = self.spring_modes(&modes);
        let (ln_k, misfit) = minimise(|x| self.cost(&modes, x.exp()), lo, hi);
        let score = misfit * (1.0 + placement_cost(nodes, pick, hard));
        Some(Placement::of(nodes, pick, dof, ln_k.exp(), score))
    }

    /// Mean squared weighted misfit with the rigid-body part given by
    /// `modes` on springs of stiffness `k`.
    fn cost(&self, modes: &SpringModes, k: f64) -> f64 {
        let data = self.data;
        let inv: Vec<Vec<c64>> = self
            .lines
            .iter()
            .map(|&l| {
                let w = data.omegas[l];
                let kind = crate::testdata::i_omega_power(w, data.kind.order());
                modes
                    .mu
                    .iter()
                    .map(|mu| kind * self.damping.modal_denominator(k * mu, w).inv())
                    .collect()
            })
            .collect();
        let (mut sum, mut n) = (0.0, 0usize);
        for (kc, &c) in self.channels.iter().enumerate() {
            let a = &modes.coeff[kc];
            for (j, &l) in self.lines.iter().enumerate() {
                let w = data.weight[c][l];
                if w == 0.0 {
                    continue;
                }
                let mut h = self.elastic[kc][j];
                for (ai, g) in a.iter().zip(&inv[j]) {
                    h += *g * *ai;
                }
                let ratio = h / data.values[c][l];
                let d = ratio - c64::new(1.0, 0.0);
                sum += w * w * d.norm_sqr() / ratio.norm().max(1e-300);
                n += 1;
            }
        }
        if n == 0 {
            f64::INFINITY
        } else {
            sum / n as f64
        }
    }
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
