//! `frfup diagnose`: find the physics a model lacks.
//!
//! 1. Correlate the deck with the test and update its own parameters
//!    ([`crate::updating::update`]).
//! 2. Localise what remains ([`localise`]: sensitivity screening of every
//!    candidate extension, mapped onto nodes).
//! 3. Fit hypotheses from a dictionary ([`hypotheses`]), each a small model
//!    extension with at most one parameter on a log scale within bounds,
//!    with the damping fitted along ([`fit`]).
//! 4. Keep those that predict held-out frequency bands and channels better
//!    by more than the noise explains, greedily ([`select`]).
//!
//! The files of a diagnosis are written by `report::diagnosis` (the report
//! layer, above this one).

pub mod hypotheses;
pub mod localise;
pub mod refit;
pub mod select;

mod final_damping;
mod first_stage;
mod greedy;
mod search;

use std::collections::BTreeMap;

use frfup_parsers::deck::Deck;

use crate::model::{self, ParameterValues};
use crate::testdata::MeasuredFrfs;
use crate::updating::{self, UpdateOptions};
use data::TestData;
use fit::{DampingState, Mask};
use hypotheses::{damping as hdamp, Context, Hypothesis, Physics};
use search::Search;
use select::{Engine, FitRequest, HypFit, LogSearch};

pub use crate::updating::fullband::{data, fit};

/// Settings of a diagnosis.
#[derive(Clone, Debug)]
pub struct DiagnoseOptions {
    /// Options of the first step, the update of the deck's own parameters.
    pub update: UpdateOptions,
    /// Skip the update (the deck's parameters are taken as they are).
    pub skip_update: bool,
    /// At most this many extensions are accepted.
    pub max_findings: usize,
    /// Candidates (after screening) fitted in full per round.
    pub fitted_per_round: usize,
    /// No new search round starts after this many model solutions
    /// (a deterministic bound on run time).
    pub evaluation_budget: usize,
}

impl Default for DiagnoseOptions {
    fn default() -> Self {
        DiagnoseOptions {
            update: UpdateOptions::paper(),
            skip_update: false,
            max_findings: 4,
            fitted_per_round: 8,
            evaluation_budget: 2000,
        }
    }
}

/// Why a diagnosis could not run (the full-band fit's errors).
pub use crate::updating::fullband::FitError as DiagnoseError;

/// How well a model matches the test.
#[derive(Clone, Debug, PartialEq)]
pub struct FitQuality {
    /// SFDAC (Eq. 45) of the signed FRF vectors at the measured resonances.
    pub sfdac_mean: f64,
    pub sfdac_min: f64,
    /// Mean |f_model − f_test|/f_test (%) over the resonances, model peaks paired by nearness.
    pub freq_error_mean_pct: f64,
    /// Mean squared weighted log-FRF error over all lines and channels above
    /// the noise floor, divided by its noise-only value (1 = noise level).
    pub frf_error: f64,
    /// RMS of |ln(H_model/H_test)| over the same points.
    pub frf_log_rms: f64,
    /// The damping the numbers were computed with.
    pub damping: String,
}

/// One accepted extension.
#[derive(Clone, Debug)]
pub struct Finding {
    pub physics: Physics,
    pub nodes: Vec<u32>,
    pub dofs: Vec<String>,
    /// Fitted values (SI): `zeta`, `alpha`/`beta`, `eta`, `m` (kg) or `k`.
    pub parameters: BTreeMap<String, f64>,
    /// One standard deviation of each parameter (same units).
    pub uncertainty: BTreeMap<String, f64>,
    pub validation_error_before: f64,
    pub validation_error_after: f64,
    pub label: String,
    /// Other hypotheses the data cannot tell apart from this one.
    pub indistinguishable_from: Vec<String>,
}

/// A hypothesis that was fitted and validated but not accepted.
#[derive(Clone, Debug)]
pub struct Rejected {
    pub label: String,
    pub round: usize,
    pub value: Option<f64>,
    pub validation_error: f64,
    pub reason: String,
}

/// The outcome of a diagnosis.
#[derive(Clone, Debug)]
pub struct Diagnosis {
    pub findings: Vec<Finding>,
    pub initial: FitQuality,
    pub updated: FitQuality,
    pub diagnosed: FitQuality,
    pub diagnosed_deck: Deck,
    /// The deck after the first stage, its own parameters updated (what
    /// `updated` scores).
    pub updated_deck: Deck,
    /// Parameter values of the update (relative changes), empty if none.
    pub updated_parameters: ParameterValues,
    pub update_note: Option<String>,
    /// Validation cost noise level J0.
    pub noise_level: f64,
    /// Node scores of the first localisation round (best candidate at each node), descending.
    pub localisation: Vec<(u32, f64, String)>,
    pub rejected: Vec<Rejected>,
    /// The test data as fitted: channels the model places, noise levels,
    /// weights and resonances (what the report's charts are drawn from).
    pub data: TestData,
    /// Channels used and ignored.
    pub channels: Vec<String>,
    pub ignored_channels: Vec<String>,
    pub model_evaluations: usize,
    /// True when the final model explains the data to the noise level.
    pub at_noise_level: bool,
    /// Wall time of each stage (name, seconds, model solutions), for `--verbose`
    /// (not written to any file: outputs stay byte-identical run to run).
    pub timings: Vec<(&'static str, f64, usize)>,
}

/// Run the diagnosis of `deck` against `test`: the test data the model
/// places, the deck's own parameters updated (step 1), extensions searched
/// greedily from each start (steps 2–4), then the damping of the
/// extended model.
pub fn diagnose(
    deck: &Deck,
    test: &MeasuredFrfs,
    opts: &DiagnoseOptions,
) -> Result<Diagnosis, DiagnoseError> {
    let mut timings: Vec<(&'static str, f64, usize)> = Vec::new();
    let mut clock = std::time::Instant::now();
    let mut solved = 0usize;
    let mut lap = |name: &'static str, evaluations: usize| {
        timings.push((name, clock.elapsed().as_secs_f64(), evaluations - solved));
        clock = std::time::Instant::now();
        solved = evaluations;
    };
    // Channels the model cannot place are ignored.
    let (data, ignored_channels) = search::placed_test_data(deck, test)?;
    let engine = Engine::new(&data);
    let search = Search::new(&engine, deck, test, opts);
    lap("prepare test data", 0);

    // 1. The deck as given, then with its own parameters updated.
    let initial = quality(&engine, deck, &search.start_damping)?;
    let first = first_stage::update_own_parameters(&search);
    let updated = quality(&engine, &first.deck, &search.start_damping)?;
    lap("update the deck's parameters", engine.evaluations.get());

    // 2.–4. Greedy extensions from each start.
    let best = search.extensions_from_starts(&first.deck)?;
    lap("search extensions (all starts)", engine.evaluations.get());
    let Some(g) = best else {
        return Err(DiagnoseError::Eigen(
            "the updated model gives no usable FRF".into(),
        ));
    };

    // The damping of the extended model.
    let current = g.current;
    let damp = final_damping::choose_form_again(&search, &current, g.damp);
    let final_fit = final_damping::fit_final_damping(&search, &current, &damp)?;
    let damp = final_fit.damping.clone();
    let v_fitted = engine.validate(None, &current, &final_fit);
    let mut findings = g.findings;
    if let Some(f) = final_damping::damping_finding(&search, &current, &final_fit, v_fitted) {
        findings.insert(0, f);
    }
    let mut diagnosed_deck = hdamp::with_damping(&current, damp.damping());
    // Round trip through the writer so the deck is exactly what a file gives.
    let text = frfup_parsers::deck::write(&diagnosed_deck);
    diagnosed_deck = frfup_parsers::deck::parse(&text).map_err(|e| {
        DiagnoseError::Data(format!("internal: the diagnosed deck does not parse: {e}"))
    })?;
    let diagnosed = quality(&engine, &diagnosed_deck, &damp)?;
    let at_noise_level = final_fit.cost <= 1.25 * search.j0;
    lap("damping and final scores", engine.evaluations.get());
    Ok(Diagnosis {
        findings,
        initial,
        updated,
        diagnosed,
        diagnosed_deck,
        updated_deck: first.deck,
        updated_parameters: g.parameters.unwrap_or(first.parameters),
        update_note: first.note,
        noise_level: search.j0,
        localisation: g.localisation,
        rejected: g.rejected,
        channels: data.channels.iter().map(|c| c.label.clone()).collect(),
        ignored_channels,
        model_evaluations: engine.evaluations.get(),
        data: data.clone(),
        at_noise_level,
        timings,
    })
}

/// Number with 4 significant digits.
pub use crate::model::sig;

struct Round {
    validated: Vec<(Hypothesis, HypFit, f64)>,
    /// Every candidate fitted in full this round, best cost first.
    fitted: Vec<(Hypothesis, HypFit)>,
    localisation: Vec<(u32, f64, String)>,
    /// The model has more than 200 DOFs (smaller searches).
    large: bool,
}

/// One greedy round: generate, screen, fit, validate.
fn search_round(
    engine: &Engine,
    current: &Deck,
    damp: &DampingState,
    data: &TestData,
    opts: &DiagnoseOptions,
    used: &[String],
) -> Result<Round, DiagnoseError> {
    let mm = engine.model(current)?;
    let r0 = fit::residuals(
        &fit::predict(&mm, damp.damping(), data, &engine.all),
        data,
        &engine.all,
    );
    let first_elastic = mm
        .omega2
        .iter()
        .copied()
        .find(|&w2| w2 > 1e-6 * mm.omega2.last().copied().unwrap_or(1.0).max(1e-300))
        .unwrap_or(1.0)
        .max(1e-12)
        .sqrt();
    let fe = model::build(current, &ParameterValues::new()).map_err(DiagnoseError::Model)?;
    let large = fe.dofs.len() > 200;
    let mut sensor_nodes: Vec<u32> = data
        .channels
        .iter()
        .map(|c| fe.sensors.get(&c.node).copied().unwrap_or(c.node))
        .collect();
    sensor_nodes.sort_unstable();
    sensor_nodes.dedup();
    let ctx = Context {
        deck: current,
        sensor_nodes,
        total_mass: hypotheses::total_mass(current),
        free_free: !fe.has_fixed_dofs,
        first_elastic_omega: first_elastic,
    };
    let mut candidates: Vec<Hypothesis> = Vec::new();
    candidates.extend(hypotheses::masses::sensor_mass(&ctx));
    candidates.extend(hypotheses::springs::support_flexibility(&ctx));
    candidates.extend(hypotheses::joint::joint_flexibility(&ctx));
    candidates.extend(hypotheses::masses::added_mass(&ctx));
    let suspension_singles = hypotheses::springs::suspension_single(&ctx);
    let n_main = candidates.len();
    candidates.extend(suspension_singles);
    candidates.retain(|h| !used.contains(&h.label));
    let probes = localise::probe(current, &r0, damp, data, &candidates);
    // Node map: the best score at each node.
    let mut node_scores: BTreeMap<u32, (f64, String)> = BTreeMap::new();
    for p in &probes {
        let h = &candidates[p.index];
        if h.nodes.len() != 1 {
            continue;
        }
        let e = node_scores
            .entry(h.nodes[0])
            .or_insert((0.0, String::new()));
        if p.score > e.0 {
            *e = (p.score, h.label.clone());
        }
    }
    let mut localisation: Vec<(u32, f64, String)> = node_scores
        .into_iter()
        .filter(|(_, (s, _))| *s > 0.0)
        .map(|(n, (s, l))| (n, s, l))
        .collect();
    localisation.sort_by(|a, b| b.1.total_cmp(&a.1).then(a.0.cmp(&b.0)));
    localisation.truncate(10);

    // Selection: the best-scored candidates overall, plus the best of each class.
    let n_main = n_main.min(candidates.len());
    let mut order: Vec<usize> = (0..candidates.len()).collect();
    order.sort_by(|&a, &b| probes[b].score.total_cmp(&probes[a].score).then(a.cmp(&b)));
    let mut chosen: Vec<Hypothesis> = Vec::new();
    let main_order: Vec<usize> = order
        .iter()
        .copied()
        .filter(|&i| i < n_main && candidates[i].physics != Physics::Suspension)
        .collect();
    for &i in main_order.iter().take(opts.fitted_per_round / 2) {
        if probes[i].score > 0.0 {
            chosen.push(candidates[i].clone());
        }
    }
    for class in [
        Physics::SensorMass,
        Physics::SupportFlexibility,
        Physics::JointFlexibility,
        Physics::AddedMass,
    ] {
        // A model far from the test can make every linear probe useless
        // (score ≤ 0): the few support DOFs and the one sensor-mass
        // hypothesis are then fitted anyway.
        let in_class = main_order
            .iter()
            .filter(|&&i| candidates[i].physics == class)
            .count();
        let always = matches!(class, Physics::SensorMass | Physics::SupportFlexibility);
        let take = if always && in_class <= 6 { in_class } else { 2 };
        for &i in main_order
            .iter()
            .filter(|&&i| candidates[i].physics == class && (always || probes[i].score > 0.0))
            .take(take)
        {
            if !chosen.iter().any(|c| c.label == candidates[i].label) {
                chosen.push(candidates[i].clone());
            }
        }
    }
    // Suspension: forward selection of same-stiffness springs per direction.
    if ctx.free_free {
        let mut dirs: Vec<String> = Vec::new();
        for c in &candidates[n_main..] {
            let d = c.dofs[0].clone();
            if !dirs.contains(&d) {
                dirs.push(d);
            }
        }
        // Directions by their best single-spring score; on larger models
        // only the best direction gets the pair search.
        let best_single = |d: &String| {
            (n_main..candidates.len())
                .filter(|&i| candidates[i].dofs[0] == *d)
                .map(|i| probes[i].score)
                .fold(0.0f64, f64::max)
        };
        dirs.sort_by(|a, b| best_single(b).total_cmp(&best_single(a)).then(a.cmp(b)));
        for (di, d) in dirs.into_iter().enumerate() {
            let set: Vec<&localise::Probe> = (n_main..candidates.len())
                .filter(|&i| candidates[i].dofs[0] == d)
                .map(|i| &probes[i])
                .collect();
            let picked = localise::forward_select(&r0, &set, 4);
            if picked.is_empty() {
                continue;
            }
            let nodes: Vec<u32> = picked
                .iter()
                .map(|&k| candidates[set[k].index].nodes[0])
                .collect();
            let dof = match &candidates[set[0].index].extension {
                hypotheses::Extension::GroundSprings { dof, .. } => *dof,
                _ => continue,
            };
            for k in 1..=nodes.len() {
                let mut set = nodes[..k].to_vec();
                set.sort_unstable();
                let h = hypotheses::springs::suspension(&ctx, set, dof);
                if !used.contains(&h.label) {
                    chosen.push(h);
                }
            }
            // Pairs of springs among the best-scored nodes (all nodes on
            // small models), screened by a coarse fit: one spring leaves a
            // rigid-body mode at 0 Hz, so linear probes rank pairs poorly.
            let mut ranked: Vec<usize> = (0..set.len()).collect();
            ranked.sort_by(|&a, &b| set[b].score.total_cmp(&set[a].score).then(a.cmp(&b)));
            let top = if large && di > 0 {
                0
            } else if large {
                ranked.len().min(5)
            } else {
                ranked.len().min(16)
            };
            let pool: Vec<u32> = ranked[..top]
                .iter()
                .map(|&k| candidates[set[k].index].nodes[0])
                .collect();
            let mut pairs: Vec<(f64, Hypothesis)> = Vec::new();
            for a in 0..pool.len() {
                for b in a + 1..pool.len() {
                    let mut ns = vec![pool[a], pool[b]];
                    ns.sort_unstable();
                    let h = hypotheses::springs::suspension(&ctx, ns, dof);
                    if used.contains(&h.label) || chosen.iter().any(|c| c.label == h.label) {
                        continue;
                    }
                    engine.damping_iterations.set(3);
                    let f = engine.fit(&FitRequest {
                        hypothesis: Some(&h),
                        search: LogSearch::over_bounds(5, 3),
                        with_std: false,
                        ..FitRequest::damping(current, damp, &engine.all)
                    });
                    engine.damping_iterations.set(10);
                    if let Some(f) = f {
                        pairs.push((f.cost, h));
                    }
                }
            }
            pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
            chosen.extend(pairs.into_iter().take(2).map(|(_, h)| h));
        }
    }
    // Shear deformation has no parameter: always fitted.
    chosen.extend(
        hypotheses::shear::shear_deformation(&ctx)
            .into_iter()
            .filter(|h| !used.contains(&h.label)),
    );
    // Full fits, then cross-validation of the most promising.
    let mut fitted: Vec<(Hypothesis, HypFit)> = chosen
        .into_iter()
        .filter_map(|h| {
            let grid = engine.fit(&FitRequest {
                hypothesis: Some(&h),
                search: LogSearch::over_bounds(9, 10),
                with_std: true,
                ..FitRequest::damping(current, damp, &engine.all)
            });
            // Small models: also from the resonance-frequency stage, which
            // finds the basin a coarse grid on the FRF misfit can miss.
            let seeded = if large || h.param.is_none() {
                None
            } else {
                frequency_seeded(engine, current, &h, damp, grid.as_ref())
            };
            match (grid, seeded) {
                (Some(g), Some(f)) if f.cost < g.cost => Some((h, f)),
                (None, Some(f)) => Some((h, f)),
                (g, _) => g.map(|g| (h, g)),
            }
        })
        .collect();
    fitted.sort_by(|a, b| a.1.cost.total_cmp(&b.1.cost));
    let base_cost = fit::mean_sq(&r0).min(
        engine
            .fit(&FitRequest::damping(current, damp, &engine.all))
            .map_or(f64::INFINITY, |f| f.cost),
    );
    // The deck's own parameters may have absorbed part of the missing
    // effect in the update: the best candidates are fitted again with them
    // free (small models with a few parameters).
    let np = current.params.len();
    if !large && (1..=6).contains(&np) {
        for (h, f) in fitted.iter_mut().take(3) {
            if h.param.is_none() {
                continue;
            }
            let problem = refit::Joint::with_deck_parameters(current, vec![&*h]);
            if let Some(g) = frequency_seeded_with(engine, &problem, damp, Some(f)) {
                if g.cost < f.cost {
                    *f = g;
                }
            }
        }
        fitted.sort_by(|a, b| a.1.cost.total_cmp(&b.1.cost));
    }
    let mut validated = Vec::new();
    for (h, f) in fitted.iter().take(5) {
        if !(f.cost < base_cost * 0.97) {
            continue;
        }
        let v = if f.deck_values.is_empty() {
            engine.validate(Some(h), current, f)
        } else {
            let problem = refit::Joint::with_deck_parameters(current, vec![h]);
            let mut x = vec![f.log_value.unwrap_or(0.0)];
            x.extend(problem.deck_params.iter().map(|n| f.deck_values[n]));
            let jf = refit::JointFit {
                logs: vec![x[0]],
                deck_values: f.deck_values.clone(),
                x,
                damping: f.damping.clone(),
                cost: f.cost,
                std_log: vec![],
                on_bound: vec![],
            };
            refit::validate_joint(engine, &problem, &jf)
        };
        validated.push((h.clone(), f.clone(), v));
    }
    Ok(Round {
        validated,
        fitted,
        localisation,
        large,
    })
}

/// A one-parameter fit of `h` through [`refit::fit_joint`]: 7 starts across
/// its bounds (and the grid fit's optimum), resonance-frequency stage, then
/// the FRFs.
fn frequency_seeded(
    engine: &Engine,
    current: &Deck,
    h: &Hypothesis,
    damp: &DampingState,
    grid: Option<&HypFit>,
) -> Option<HypFit> {
    frequency_seeded_with(engine, &refit::Joint::new(current, vec![h]), damp, grid)
}

/// As [`frequency_seeded`] for a one-extension problem that may fit the
/// deck's parameters along (they start at 0).
fn frequency_seeded_with(
    engine: &Engine,
    problem: &refit::Joint,
    damp: &DampingState,
    grid: Option<&HypFit>,
) -> Option<HypFit> {
    let (lo, hi) = problem.bounds();
    let np = problem.deck_params.len();
    let mut fixed = vec![None];
    fixed.extend(std::iter::repeat_n(Some(0.0), np));
    let mut starts = refit::grid_starts(&lo, &hi, &fixed, 7);
    if let Some(s) = grid.and_then(|g| g.log_value) {
        let mut x = vec![s];
        x.extend(std::iter::repeat_n(0.0, np));
        starts.push(x);
    }
    let settings = refit::JointSettings {
        frequency_stage: true,
        iterations: 10,
    };
    let jf = refit::fit_joint(engine, problem, &starts, damp, &engine.all, settings)?;
    let value = jf.logs[0].exp();
    Some(HypFit {
        value: Some(value),
        log_value: Some(jf.logs[0]),
        damping: jf.damping.clone(),
        cost: jf.cost,
        std: Some(jf.std_log[0] * value),
        damping_std_log: vec![],
        on_bound: jf.on_bound[0],
        deck_values: jf.deck_values.clone(),
    })
}

/// Fit quality of `deck` with damping `damp` (damping refitted first).
fn quality(engine: &Engine, deck: &Deck, damp: &DampingState) -> Result<FitQuality, DiagnoseError> {
    let data = engine.data;
    let mm = engine.model(deck)?;
    let all = Mask::all(data);
    let (d, r) = fit::fit_damping(&mm, damp, data, &all, 10);
    let pred = fit::predict(&mm, d.damping(), data, &all);
    let j = fit::mean_sq(&r);
    let j0 = fit::noise_level(data, &all);
    // Log RMS of the magnitude part.
    let mut s = 0.0;
    let mut n = 0usize;
    for (c, p) in pred.iter().enumerate() {
        for (l, h) in p.iter().enumerate() {
            if data.weight[c][l] > 0.0 {
                let v = (h.norm() / data.values[c][l].norm()).ln();
                if v.is_finite() {
                    s += v * v;
                    n += 1;
                }
            }
        }
    }
    let mut sf = Vec::new();
    for res in &data.resonances {
        let l = res.line.min(data.lines_hz.len().saturating_sub(1));
        let fe: Vec<f64> = pred
            .iter()
            .map(|p| crate::testdata::signed_real(p[l]))
            .collect();
        let te: Vec<f64> = data
            .values
            .iter()
            .map(|v| crate::testdata::signed_real(v[l]))
            .collect();
        sf.push(updating::sfdac(&fe, &te));
    }
    let model_peaks = updating::frequencies::pick_peaks(
        &data.lines_hz,
        &updating::frequencies::indicator(&pred),
        &updating::frequencies::PeakOptions {
            min_prominence: 2.0,
        },
    );
    let mut fe_err = Vec::new();
    for res in &data.resonances {
        if let Some(mp) = model_peaks.iter().min_by(|a, b| {
            (a.frequency_hz - res.frequency_hz)
                .abs()
                .total_cmp(&(b.frequency_hz - res.frequency_hz).abs())
        }) {
            fe_err.push(100.0 * (mp.frequency_hz - res.frequency_hz).abs() / res.frequency_hz);
        }
    }
    let mean = |v: &[f64]| {
        if v.is_empty() {
            f64::NAN
        } else {
            v.iter().sum::<f64>() / v.len() as f64
        }
    };
    Ok(FitQuality {
        sfdac_mean: mean(&sf),
        sfdac_min: sf.iter().copied().fold(f64::NAN, f64::min),
        freq_error_mean_pct: mean(&fe_err),
        frf_error: if j0 > 0.0 { j / j0 } else { j },
        frf_log_rms: if n > 0 {
            (s / n as f64).sqrt()
        } else {
            f64::NAN
        },
        damping: describe_damping(d.damping()),
    })
}

pub use crate::model::describe_damping;
