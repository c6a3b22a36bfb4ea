//! One greedy round: generate the candidate extensions of the current model
//! ([`hypotheses`]), screen them by linear probes ([`localise`]), choose the
//! best-scored of each class (and suspension springs by forward selection
//! and by the test's suspension modes, [`suspension_placement`]),
//! fit those in full, and cross-validate the most promising ([`select`]).

use std::collections::BTreeMap;

use rayon::prelude::*;

use frfup_parsers::deck::Deck;

use super::data::TestData;
use super::fit::{self, DampingState};
use super::hypotheses::{self, Context, Hypothesis, Physics};
use super::joint_screen::{self, frequency_seeded_with};
use super::search::Search;
use super::select::{Engine, FitRequest, HypFit, LogSearch};
use super::{localise, refit, suspension_placement, DiagnoseError};

/// Suspension spring sets placed by the test's suspension modes, fitted in
/// full each round (see [`suspension_placement`]).
const PLACED_SETS: usize = 3;
use crate::model::{self, ParameterValues};

/// What a round found.
pub(super) struct Round {
    /// The candidates cross-validated: hypothesis, fit, validation cost.
    pub validated: Vec<(Hypothesis, HypFit, f64)>,
    /// Every candidate fitted in full this round, best cost first.
    pub fitted: Vec<(Hypothesis, HypFit)>,
    /// Node scores: the best candidate's score at each node, descending (at most 10).
    pub localisation: Vec<(u32, f64, String)>,
    /// The model has more than 200 DOFs (smaller searches).
    pub large: bool,
    /// The validation cost of the current model with the deck's parameters
    /// refitted alone (computed when a candidate was fitted along with them).
    pub parameters_only: Option<f64>,
}

/// The current model as a round sees it.
struct Current<'a> {
    deck: &'a Deck,
    damp: &'a DampingState,
    /// Labels of the extensions already accepted (not proposed again).
    used: &'a [String],
    /// The weighted residual r₀ of the current model on all data.
    r0: Vec<f64>,
    /// What the hypothesis generators need to know of the model.
    ctx: Context<'a>,
    /// More than 200 DOFs: smaller searches.
    large: bool,
    /// The deck's own parameters are free (updated): candidates are scored
    /// by what those cannot explain.
    free_parameters: bool,
}

/// The round's candidates and their linear probes (index-aligned).
struct Screened {
    candidates: Vec<Hypothesis>,
    probes: Vec<localise::Probe>,
    /// Candidates before this index are the main classes; the suspension
    /// single springs follow.
    n_main: usize,
    /// The current residual off the deck parameters' directions (what the
    /// probes are scored against).
    r0: Vec<f64>,
}

/// One greedy round on `current` (damping `damp`): generate, screen, fit,
/// validate. `used`: labels of the extensions already accepted.
pub(super) fn search_round(
    search: &Search,
    current: &Deck,
    damp: &DampingState,
    used: &[String],
) -> Result<Round, DiagnoseError> {
    let engine = search.engine;
    let mut cur = Current::new(engine, current, damp, used)?;
    cur.free_parameters = search.updates_parameters();
    let screened = screen(engine, &cur);
    let localisation = node_localisation(&screened);
    let mut chosen = choose_by_score(&screened, search.opts.fitted_per_round);
    let mut placed = Vec::new();
    if cur.ctx.free_free {
        choose_suspension_springs(engine, &cur, &screened, &mut chosen);
        placed = placed_suspension(engine, &cur, &mut chosen);
    }
    // Shear deformation has no parameter: always fitted.
    chosen.extend(
        hypotheses::shear::shear_deformation(&cur.ctx)
            .into_iter()
            .filter(|h| !used.contains(&h.label)),
    );
    // Full fits, then cross-validation of the most promising.
    let mut fitted = fit_in_full(engine, &cur, chosen);
    let base_cost = fit::mean_sq(&cur.r0).min(
        engine
            .fit(&FitRequest::damping(current, damp, &engine.all))
            .map_or(f64::INFINITY, |f| f.cost),
    );
    refit_with_deck_parameters(engine, &cur, &mut fitted, &placed);
    let beside = beside_best_point_mass(&screened, &fitted, cur.deck);
    if !beside.is_empty() {
        let mut more = fit_in_full(engine, &cur, beside);
        refit_with_deck_parameters(engine, &cur, &mut more, &[]);
        merge_fits(&mut fitted, more);
    }
    if !cur.large {
        let main = &screened.candidates[..screened.n_main];
        let joint = joint_screen::best_joint_fits(engine, cur.deck, cur.damp, main, 3);
        merge_fits(&mut fitted, joint);
    }
    let validated = validate_best(engine, &cur, &fitted, base_cost);
    let parameters_only = if validated.iter().any(|(_, f, _)| !f.deck_values.is_empty()) {
        joint_screen::parameters_only_validation(engine, current, damp)
    } else {
        None
    };
    Ok(Round {
        validated,
        fitted,
        localisation,
        large: cur.large,
        parameters_only,
    })
}

impl<'a> Current<'a> {
    /// Solve the current model: its residual, its first elastic frequency
    /// and the sensor nodes for the hypothesis generators.
    fn new(
        engine: &Engine,
        deck: &'a Deck,
        damp: &'a DampingState,
        used: &'a [String],
    ) -> Result<Self, DiagnoseError> {
        let data = engine.data;
        let mm = engine.model(deck)?;
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
        let fe = model::build(deck, &ParameterValues::new()).map_err(DiagnoseError::Model)?;
        let large = fe.dofs.len() > 200;
        let ctx = Context {
            deck,
            sensor_nodes: sensor_nodes(data, &fe),
            total_mass: hypotheses::total_mass(deck),
            free_free: !fe.has_fixed_dofs,
            first_elastic_omega: first_elastic,
        };
        Ok(Current {
            deck,
            damp,
            used,
            r0,
            ctx,
            large,
            free_parameters: false,
        })
    }
}

/// The FE nodes that carry a sensor of `data` in `fe` (ascending, unique;
/// a `sensor` statement of the deck maps a channel's node to its FE node).
pub(super) fn sensor_nodes(data: &TestData, fe: &model::FeModel) -> Vec<u32> {
    let mut nodes: Vec<u32> = data
        .sensor_nodes()
        .into_iter()
        .map(|n| fe.sensors.get(&n).copied().unwrap_or(n))
        .collect();
    nodes.sort_unstable();
    nodes.dedup();
    nodes
}

/// Every candidate of the dictionary not yet accepted, each probed once.
fn screen(engine: &Engine, cur: &Current) -> Screened {
    let ctx = &cur.ctx;
    let mut candidates: Vec<Hypothesis> = Vec::new();
    candidates.extend(hypotheses::masses::sensor_mass(ctx));
    candidates.extend(hypotheses::springs::support_flexibility(ctx));
    candidates.extend(hypotheses::joint::joint_flexibility(ctx));
    candidates.extend(hypotheses::masses::added_mass(ctx));
    let suspension_singles = hypotheses::springs::suspension_single(ctx);
    let n_main = candidates.len();
    candidates.extend(suspension_singles);
    candidates.retain(|h| !cur.used.contains(&h.label));
    let basis = if cur.free_parameters {
        localise::parameter_directions(cur.deck, &cur.r0, cur.damp, engine.data)
    } else {
        Vec::new()
    };
    let probes = localise::probe(
        cur.deck,
        &cur.r0,
        &basis,
        cur.damp,
        engine.data,
        &candidates,
    );
    Screened {
        n_main: n_main.min(candidates.len()),
        candidates,
        probes,
        r0: localise::project_out(&cur.r0, &basis),
    }
}

/// Node map: the best score at each node (single-node candidates), the ten
/// highest, descending.
fn node_localisation(screened: &Screened) -> Vec<(u32, f64, String)> {
    let mut node_scores: BTreeMap<u32, (f64, String)> = BTreeMap::new();
    for p in &screened.probes {
        let h = &screened.candidates[p.index];
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
    localisation
}

/// Selection among the main classes: the best-scored candidates overall
/// (half of `fitted_per_round`), plus the best two of each class.
fn choose_by_score(screened: &Screened, fitted_per_round: usize) -> Vec<Hypothesis> {
    let (candidates, probes, n_main) = (&screened.candidates, &screened.probes, screened.n_main);
    let mut order: Vec<usize> = (0..candidates.len()).collect();
    order.sort_by(|&a, &b| probes[b].score.total_cmp(&probes[a].score).then(a.cmp(&b)));
    let mut chosen: Vec<Hypothesis> = Vec::new();
    let main_order: Vec<usize> = order
        .iter()
        .copied()
        .filter(|&i| i < n_main && candidates[i].physics != Physics::Suspension)
        .collect();
    for &i in main_order.iter().take(fitted_per_round / 2) {
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
    chosen
}

/// Suspension of a free-free model: per direction (by their best
/// single-spring score), same-stiffness spring sets by forward selection,
/// and pairs of springs screened by a coarse fit.
fn choose_suspension_springs(
    engine: &Engine,
    cur: &Current,
    screened: &Screened,
    chosen: &mut Vec<Hypothesis>,
) {
    let (candidates, probes, n_main) = (&screened.candidates, &screened.probes, screened.n_main);
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
        let picked = localise::forward_select(&screened.r0, &set, 4);
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
            let h = hypotheses::springs::suspension(&cur.ctx, set, dof);
            if !cur.used.contains(&h.label) {
                chosen.push(h);
            }
        }
        // Pairs of springs among the best-scored nodes (all nodes on
        // small models), screened by a coarse fit: one spring leaves a
        // rigid-body mode at 0 Hz, so linear probes rank pairs poorly.
        let mut ranked: Vec<usize> = (0..set.len()).collect();
        ranked.sort_by(|&a, &b| set[b].score.total_cmp(&set[a].score).then(a.cmp(&b)));
        let top = if cur.large && di > 0 {
            0
        } else if cur.large {
            ranked.len().min(5)
        } else {
            ranked.len().min(16)
        };
        let pool: Vec<u32> = ranked[..top]
            .iter()
            .map(|&k| candidates[set[k].index].nodes[0])
            .collect();
        let pairs = spring_pairs(engine, cur, &pool, dof, chosen);
        chosen.extend(pairs);
    }
}

/// The suspension spring sets whose rigid-body modes on springs match the
/// test's suspension modes in frequency ratio and shape and, when the pole
/// fit finds none or fewer than the best of those sets makes, those that
/// fit the test's band below the first elastic mode best, added to `chosen`;
/// their labels (they are refitted with the deck's parameters: the
/// placement is evidence of its own, and a deck distorted by an update
/// that lacked the springs fits them badly).
fn placed_suspension(engine: &Engine, cur: &Current, chosen: &mut Vec<Hypothesis>) -> Vec<String> {
    let first_hz = cur.ctx.first_elastic_omega / (2.0 * std::f64::consts::PI);
    let test =
        suspension_placement::test_suspension_modes(engine.data, engine.test_modes(), first_hz);
    let mut placed = suspension_placement::placements(&cur.ctx, engine.data, &test, PLACED_SETS);
    // No suspension mode in the test, or fewer than the best modal
    // placement makes (two modes closer than the line spacing seen as one,
    // one below the band): the modes alone do not place the springs, the
    // low band's lines are asked too.
    if placed.first().is_none_or(|p| p.unmatched > 0) {
        placed.extend(suspension_placement::low_band_placements(
            &cur.ctx,
            engine.data,
            cur.damp.damping(),
            &engine.all,
            PLACED_SETS,
        ));
    }
    let mut labels = Vec::new();
    for p in placed {
        let h = hypotheses::springs::suspension(&cur.ctx, p.nodes, p.dof);
        if cur.used.contains(&h.label) || labels.contains(&h.label) {
            continue;
        }
        labels.push(h.label.clone());
        if !chosen.iter().any(|c| c.label == h.label) {
            chosen.push(h);
        }
    }
    labels
}

/// Damping iterations of each trial stiffness in the pairs' coarse fit:
/// none, the current model's damping held. The pairs are only ranked
/// here (the best two are fitted in full, their damping along); with
/// three iterations the screen was 43 % of a free-free diagnosis (seed-2
/// case 087, perf), the damping's Jacobians 70 % of it.
const PAIR_DAMPING_ITERATIONS: usize = 0;

/// The two pairs of same-stiffness springs in direction `dof` among the
/// nodes of `pool` that fit best (coarse grid, the current damping held:
/// [`PAIR_DAMPING_ITERATIONS`]); pairs already accepted or chosen are left
/// out.
fn spring_pairs(
    engine: &Engine,
    cur: &Current,
    pool: &[u32],
    dof: frfup_parsers::deck::DeckDof,
    chosen: &[Hypothesis],
) -> Vec<Hypothesis> {
    let mut untried: Vec<Hypothesis> = Vec::new();
    for a in 0..pool.len() {
        for b in a + 1..pool.len() {
            let mut ns = vec![pool[a], pool[b]];
            ns.sort_unstable();
            let h = hypotheses::springs::suspension(&cur.ctx, ns, dof);
            if cur.used.contains(&h.label) || chosen.iter().any(|c| c.label == h.label) {
                continue;
            }
            untried.push(h);
        }
    }
    let costs: Vec<Option<f64>> = untried
        .par_iter()
        .map(|h| {
            let f = engine.fit(&FitRequest {
                hypothesis: Some(h),
                search: LogSearch::over_bounds(5, 3),
                with_std: false,
                damping_iterations: PAIR_DAMPING_ITERATIONS,
                ..FitRequest::damping(cur.deck, cur.damp, &engine.all)
            })?;
            Some(f.cost)
        })
        .collect();
    let mut pairs: Vec<(f64, Hypothesis)> = costs
        .into_iter()
        .zip(untried)
        .filter_map(|(c, h)| Some((c?, h)))
        .collect();
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    pairs.into_iter().take(2).map(|(_, h)| h).collect()
}

/// Full fits of the chosen candidates (log grid and golden section; on
/// small models also from the resonance-frequency stage, which finds the
/// basin a coarse grid on the FRF misfit can miss), best cost first.
fn fit_in_full(
    engine: &Engine,
    cur: &Current,
    chosen: Vec<Hypothesis>,
) -> Vec<(Hypothesis, HypFit)> {
    let fits: Vec<Option<(Hypothesis, HypFit)>> = chosen
        .into_par_iter()
        .map(|h| {
            let grid = engine.fit(&FitRequest {
                hypothesis: Some(&h),
                search: LogSearch::over_bounds(9, 10),
                with_std: true,
                ..FitRequest::damping(cur.deck, cur.damp, &engine.all)
            });
            let seeded = if cur.large || h.param.is_none() {
                None
            } else {
                frequency_seeded(engine, cur.deck, &h, cur.damp, grid.as_ref())
            };
            match (grid, seeded) {
                (Some(g), Some(f)) if f.cost < g.cost => Some((h, f)),
                (None, Some(f)) => Some((h, f)),
                (g, _) => g.map(|g| (h, g)),
            }
        })
        .collect();
    let mut fitted: Vec<(Hypothesis, HypFit)> = fits.into_iter().flatten().collect();
    fitted.sort_by(|a, b| a.1.cost.total_cmp(&b.1.cost));
    fitted
}

/// The deck's own parameters may have absorbed part of the missing effect
/// in the update: on decks with one to six parameters, the three best
/// candidates with a parameter (two on models over 200 DOFs), the best of
/// each class besides, every candidate without a parameter (shear
/// deformation) and those named in `always` are fitted again with them
/// free; on decks with more, only the [`PLACED_SETS`] best-fitting of those
/// named in `always` (each refit is a fit of every parameter). Kept where
/// the cost falls. The GARTEUR-like fixture's free-free deck (20
/// parameters, cords at nodes 10, 104, 204): on the updated deck the cords'
/// set fits at 195× the noise and a pair of springs on one wing at 192×;
/// refitted with the parameters, 64× against 101× for the next set, and
/// the diagnosis ends at the noise level with the cords found.
fn refit_with_deck_parameters(
    engine: &Engine,
    cur: &Current,
    fitted: &mut [(Hypothesis, HypFit)],
    always: &[String],
) {
    let np = cur.deck.params.len();
    let many = np > 6;
    let always: Vec<&String> = if many {
        // `fitted` is sorted by cost.
        fitted
            .iter()
            .map(|(h, _)| &h.label)
            .filter(|l| always.contains(l))
            .take(PLACED_SETS)
            .collect()
    } else {
        always.iter().collect()
    };
    if np == 0 || (many && always.is_empty()) {
        return;
    }
    // Which are refitted (decided in order), then the refits in parallel.
    let mut with_param = 0;
    let mut classes: Vec<Physics> = Vec::new();
    let mut refitted: Vec<bool> = Vec::with_capacity(fitted.len());
    for (h, _) in fitted.iter() {
        let forced = always.contains(&&h.label);
        // The best of each class is refitted too: a class whose fit on the
        // distorted deck is poor would otherwise never compete.
        let first_of_class = !classes.contains(&h.physics);
        if first_of_class {
            classes.push(h.physics);
        }
        let refit = forced
            || !many
                && (h.param.is_none()
                    || first_of_class
                    || with_param < if cur.large { 2 } else { 3 });
        if refit && h.param.is_some() {
            with_param += usize::from(!forced);
        }
        refitted.push(refit);
    }
    let refits: Vec<Option<HypFit>> = fitted
        .par_iter()
        .zip(&refitted)
        .map(|((h, f), &refit)| {
            if !refit {
                None
            } else if h.param.is_none() {
                joint_screen::parameterless_with_deck(engine, cur.deck, h, cur.damp)
            } else {
                let problem = refit::Joint::with_deck_parameters(cur.deck, vec![h]);
                frequency_seeded_with(engine, &problem, cur.damp, Some(f))
            }
        })
        .collect();
    for ((_, f), g) in fitted.iter_mut().zip(refits) {
        if let Some(g) = g.filter(|g| g.cost < f.cost) {
            *f = g;
        }
    }
    fitted.sort_by(|a, b| a.1.cost.total_cmp(&b.1.cost));
}

/// The added-mass candidates at the nodes that share a beam with the
/// best-fitted added mass, and with the sensor mass of a test with one
/// sensor, when they are among the five best fits (those cross-validated)
/// and the screen did not choose them. Linear probes place a point mass
/// only to within a node or two along a member (seed-1 benchmark case 017:
/// a 0.12 kg mass at node 70 screened at 72, whose fit validates at 18.3
/// where node 71's does at 4.2); the fits decide. A mass beside a
/// roving-hammer test's one sensor is screened as the sensor mass (case
/// 174: 3.42 kg at node 87 reported as the sensor's at 86, the added mass
/// at 87 never fitted).
fn beside_best_point_mass(
    screened: &Screened,
    fitted: &[(Hypothesis, HypFit)],
    deck: &Deck,
) -> Vec<Hypothesis> {
    let best_of = |point_mass: &dyn Fn(&Hypothesis) -> bool| {
        fitted
            .iter()
            .take(5)
            .find(|(h, _)| point_mass(h))
            .map(|(h, _)| h.nodes[0])
    };
    let centres: Vec<u32> = [
        best_of(&|h| h.physics == Physics::AddedMass),
        best_of(&|h| h.physics == Physics::SensorMass && h.nodes.len() == 1),
    ]
    .into_iter()
    .flatten()
    .collect();
    let beside: Vec<u32> = deck
        .beams
        .iter()
        .filter(|b| centres.iter().any(|c| b.nodes.contains(c)))
        .flat_map(|b| b.nodes.iter().copied())
        .filter(|n| !centres.contains(n))
        .collect();
    screened.candidates[..screened.n_main]
        .iter()
        .filter(|h| h.physics == Physics::AddedMass && beside.contains(&h.nodes[0]))
        .filter(|h| !fitted.iter().any(|(g, _)| g.label == h.label))
        .cloned()
        .collect()
}

/// `extra` fits merged into `fitted`: a candidate already there keeps the
/// lower-cost fit; best cost first.
fn merge_fits(fitted: &mut Vec<(Hypothesis, HypFit)>, extra: Vec<(Hypothesis, HypFit)>) {
    for (h, f) in extra {
        match fitted.iter_mut().find(|(g, _)| g.label == h.label) {
            Some(old) if f.cost < old.1.cost => old.1 = f,
            Some(_) => {}
            None => fitted.push((h, f)),
        }
    }
    fitted.sort_by(|a, b| a.1.cost.total_cmp(&b.1.cost));
}

/// Cross-validation of the five best fits that lower the cost below 97 % of
/// `base_cost`: (hypothesis, fit, validation cost).
fn validate_best(
    engine: &Engine,
    cur: &Current,
    fitted: &[(Hypothesis, HypFit)],
    base_cost: f64,
) -> Vec<(Hypothesis, HypFit, f64)> {
    let promising: Vec<&(Hypothesis, HypFit)> = fitted
        .iter()
        .take(5)
        .filter(|(_, f)| f.cost < base_cost * 0.97)
        .collect();
    let costs: Vec<f64> = promising
        .par_iter()
        .map(|(h, f)| validation_cost(engine, cur, h, f))
        .collect();
    promising
        .into_iter()
        .zip(costs)
        .map(|((h, f), v)| (h.clone(), f.clone(), v))
        .collect()
}

/// The validation cost of candidate `h` fitted as `f` (with the deck's
/// parameters, when it was fitted along with them).
fn validation_cost(engine: &Engine, cur: &Current, h: &Hypothesis, f: &HypFit) -> f64 {
    if f.deck_values.is_empty() {
        engine.validate(Some(h), cur.deck, f)
    } else {
        let problem = refit::Joint::with_deck_parameters(cur.deck, vec![h]);
        let logs: Vec<f64> = f.log_value.into_iter().collect();
        let mut x = logs.clone();
        x.extend(problem.deck_params.iter().map(|n| f.deck_values[n]));
        let jf = refit::JointFit {
            logs,
            deck_values: f.deck_values.clone(),
            x,
            damping: f.damping.clone(),
            cost: f.cost,
            std_log: vec![],
            on_bound: vec![],
        };
        refit::validate_joint(engine, &problem, &jf)
    }
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
