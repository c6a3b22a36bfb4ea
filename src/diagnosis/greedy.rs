//! The greedy search from one starting deck (steps 2–4): choose the damping
//! form, then round after round fit and validate candidate extensions
//! ([`search_round`]) and accept the one that predicts held-out data
//! best by more than the margin (of candidates tied with it, the one the
//! placement prior names: [`prior`]), or a pair fitted jointly when two effects
//! mask each other; after each acceptance the earlier extensions are
//! re-estimated jointly, the damping form is chosen again and the deck's
//! own parameters are updated again on the extended deck (taken then only
//! at the noise level; at the end of the search when the fit improves).
//! The search stops at the noise level, at `max_findings`, when the
//! evaluation budget is spent or when no candidate passes; then the point
//! extensions may move ([`places`]) and an extension the others have made
//! redundant is dropped ([`prune`]).

use std::cell::Cell;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};

use frfup_parsers::deck::Deck;

use super::data::TestData;
use super::discriminate;
use super::fit::DampingState;
use super::hypotheses::{prior, Hypothesis, Physics};
use super::joint_screen;
use super::places;
use super::prune;
use super::refit;
use super::round::{search_round, Round};
use super::search::{ReUpdate, Search};
use super::select::{self, Engine, FitRequest, HypFit};
use super::with_accepted;
use super::{sig, Alternative, DiagnoseError, Finding, Rejected};
use crate::model::{self, ParameterValues};

/// The state, then the outcome, of one greedy search.
#[derive(Clone)]
pub(super) struct Greedy {
    pub findings: Vec<Finding>,
    /// The accepted extensions in order, with their values (`None`: no
    /// parameter).
    pub accepted: Vec<(Hypothesis, Option<f64>)>,
    /// The deck the accepted extensions are applied to: the start, with the
    /// deck's parameters moved when an extension was fitted along with them
    /// or updated again after an acceptance.
    pub base: Deck,
    /// `base` with the accepted extensions, its damping, its cost on all
    /// data and its validation cost.
    pub current: Deck,
    pub damp: DampingState,
    pub cost: f64,
    pub v: f64,
    pub rejected: Vec<Rejected>,
    /// The node scores of the first round.
    pub localisation: Vec<(u32, f64, String)>,
    /// The relative changes p̄ of the deck's parameters that `base` carries,
    /// relative to the deck as given.
    pub base_values: ParameterValues,
}

/// One state of a greedy search: after some rounds, with the update of the
/// deck's parameters made for it and the work spent to reach it (the
/// engine's model-solution units).
pub(super) struct RoundState {
    g: Greedy,
    pending: Option<ReUpdate>,
    spent: usize,
}

/// The rounds of a greedy search: its state before any round and after each.
pub(super) struct Rounds {
    first: RoundState,
    later: Vec<RoundState>,
}

/// Greedy search from `start` run to its end: [`rounds`], then
/// [`Rounds::finish`] with every round kept. `None` if no damping form gives
/// a usable model. `start_values`: the deck's parameter values `start`
/// carries (relative to the deck as given).
pub(super) fn search(
    search: &Search,
    start: &Deck,
    start_values: &ParameterValues,
) -> Result<Option<Greedy>, DiagnoseError> {
    let no_limit = AtomicUsize::new(usize::MAX);
    Ok(rounds(search, start, start_values, &no_limit)?.map(|r| r.finish(search, usize::MAX).0))
}

/// The rounds of the greedy search from `start`: damping form, then
/// extensions one at a time, each round's state kept. No round starts once
/// the search has `limit` extensions or more (`limit` may be lowered while
/// the search runs: the states reached are the same, only fewer of them).
pub(super) fn rounds(
    search: &Search,
    start: &Deck,
    start_values: &ParameterValues,
    limit: &AtomicUsize,
) -> Result<Option<Rounds>, DiagnoseError> {
    let Some(mut g) = Greedy::start(search, start, start_values) else {
        return Ok(None);
    };
    let (engine, opts) = (search.engine, search.opts);
    // The budget is this search's: a second start gets its own.
    // The updates after an acceptance are not the search's work: the
    // rounds' budget stays what it was without them.
    let spent_before = engine.spent();
    let updates = Cell::new(0);
    let within_budget = || engine.spent() - spent_before - updates.get() <= opts.evaluation_budget;
    // One round can spend the whole budget (its full fits with the deck's
    // parameters free cost thousands of model solutions), and a check made
    // only between rounds would then end every search after its first
    // finding: two effects that mask each other need the second round. The
    // budget therefore bounds the rounds after the second.
    let mut pending = None;
    let mut out = Rounds {
        first: RoundState {
            g: g.clone(),
            pending: None,
            spent: engine.spent(),
        },
        later: Vec::new(),
    };
    for round in 0..opts.max_findings {
        let budget_left = round <= 1 || within_budget();
        if g.findings.len() >= opts.max_findings
            || search.at_noise_level(g.cost)
            || !budget_left
            || g.accepted.len() >= limit.load(Ordering::Relaxed)
        {
            break;
        }
        let used = g.used_labels();
        let step = search_round(search, &g.current, &g.damp, &used)?;
        if round == 0 {
            g.localisation = step.localisation.clone();
        }
        let accepted_before = g.accepted.len();
        if !g.take_round(search, round, step, within_budget()) {
            break;
        }
        if g.accepted.len() > accepted_before {
            let before = engine.spent();
            pending = search.update_after_acceptance(&mut g);
            updates.set(updates.get() + engine.spent() - before);
        }
        out.later.push(RoundState {
            g: g.clone(),
            pending: pending.clone(),
            spent: engine.spent(),
        });
    }
    Ok(Some(out))
}

impl Rounds {
    /// The last state with at most `most` extensions.
    pub(super) fn last_with_at_most(self, most: usize) -> RoundState {
        self.later
            .into_iter()
            .rev()
            .find(|s| s.g.accepted.len() <= most)
            .unwrap_or(self.first)
    }

    /// [`Rounds::last_with_at_most`] `most`, finished ([`RoundState::finish`]).
    pub(super) fn finish(self, search: &Search, most: usize) -> (Greedy, usize) {
        self.last_with_at_most(most).finish(search)
    }
}

impl RoundState {
    /// The labels of the accepted extensions, sorted.
    pub(super) fn labels(&self) -> Vec<String> {
        let mut l = self.g.used_labels();
        l.sort();
        l
    }

    /// The work spent to reach this state.
    pub(super) fn spent(&self) -> usize {
        self.spent
    }

    /// This state finished: the deck's parameters updated again, the point
    /// extensions moved where they fit best ([`places`]) and an extension
    /// the others made redundant dropped ([`prune`]). Also returns the work
    /// spent to reach the state and to finish it.
    pub(super) fn finish(self, search: &Search) -> (Greedy, usize) {
        let RoundState {
            mut g,
            pending,
            spent,
        } = self;
        let before = search.engine.spent();
        search.update_at_end(&mut g, pending);
        if places::refine(search, &mut g) {
            search.update_at_end(&mut g, None);
        }
        if prune::prune(search, &mut g) {
            search.update_at_end(&mut g, None);
        }
        (g, spent + search.engine.spent() - before)
    }
}

impl Greedy {
    /// `start` with the damping form chosen and fitted, nothing accepted.
    fn start(search: &Search, start: &Deck, start_values: &ParameterValues) -> Option<Greedy> {
        let engine = search.engine;
        let (damp, _forms) =
            select::choose_damping(engine, start, search.deck_form.clone(), search.zeta0)?;
        let base_fit = engine.fit(&FitRequest::damping(start, &damp, &engine.all))?;
        Some(Greedy {
            findings: Vec::new(),
            accepted: Vec::new(),
            base: start.clone(),
            current: start.clone(),
            damp: base_fit.damping.clone(),
            cost: base_fit.cost,
            v: engine.validate(None, start, &base_fit),
            rejected: Vec::new(),
            localisation: Vec::new(),
            base_values: start_values.clone(),
        })
    }

    /// Labels of the accepted extensions (not proposed again).
    pub(super) fn used_labels(&self) -> Vec<String> {
        self.accepted.iter().map(|(h, _)| h.label.clone()).collect()
    }

    /// Accept what round `round` (0-based) found, if anything: a pair fitted
    /// jointly when it predicts better than the best single candidate, else
    /// that candidate, or the one tied with it that the placement prior
    /// names. Returns false when nothing was accepted.
    /// `pairs`: the budget allows a pair search.
    fn take_round(&mut self, search: &Search, round: usize, step: Round, pairs: bool) -> bool {
        let (engine, opts, j0) = (search.engine, search.opts, search.j0);
        let m = select::margin(self.v, j0);
        let mut scored = self.judge(round, step.validated, j0, step.parameters_only);
        scored.sort_by(|a, b| a.2.total_cmp(&b.2));
        if self.parameters_alone_suffice(round, &mut scored, search) {
            return true;
        }
        // Two effects can mask each other so that neither fits alone: when
        // the best single extension leaves the fit far from the noise level,
        // pairs of the best-fitting candidates are fitted jointly.
        let single_cost = scored.first().map_or(self.cost, |s| s.1.cost);
        let pair =
            if opts.max_findings - self.findings.len() >= 2 && single_cost > 4.0 * j0 && pairs {
                pair_search(
                    engine,
                    &self.base,
                    &self.accepted,
                    &step.fitted,
                    &self.damp,
                    step.large,
                )
            } else {
                None
            };
        let v_single = scored.first().map_or(self.v, |s| s.2);
        prefer_by_prior(&mut scored, j0, &self.base);
        if let Some(p) = pair.filter(|p| p.v < v_single - select::margin(v_single, j0)) {
            self.accept_pair(round, p, &scored);
            return true;
        }
        let Some(best) = scored.first().cloned() else {
            // Within the budget, as the rounds are: the second always.
            return (round <= 1 || pairs)
                && self.take_with_accepted(
                    search,
                    round,
                    &step.fitted,
                    step.large,
                    step.parameters_only,
                );
        };
        let joint = !best.1.deck_values.is_empty();
        self.accept_single(round, best, &scored, m, engine.data);
        if let (true, Some(vp), Some(last)) =
            (joint, step.parameters_only, self.findings.last_mut())
        {
            // What it was judged against: the deck's parameters refitted alone.
            last.validation_error_before = vp;
        }
        if joint {
            self.validate_as_held(engine);
        }
        self.reestimate_jointly(engine);
        self.choose_damping_form_again(search);
        true
    }

    /// The validated candidates that pass (their fit inside the bounds, the
    /// uncertainty below the value, the validation error below the
    /// reference by more than the margin); the others are recorded as
    /// rejected. The reference of a candidate fitted with the deck's
    /// parameters held is the current validation error; that of a candidate
    /// fitted along with the deck's parameters is those parameters refitted
    /// alone (`parameters_only`, a validation cost), so that the
    /// parameter-only explanation competes on equal terms: both refit the
    /// deck's parameters on each training fold, where the current error
    /// keeps the values the update fitted to all the data, held-out lines
    /// included.
    fn judge(
        &mut self,
        round: usize,
        validated: Vec<(Hypothesis, HypFit, f64)>,
        j0: f64,
        parameters_only: Option<f64>,
    ) -> Vec<(Hypothesis, HypFit, f64)> {
        let v_cur = self.v;
        let mut scored = Vec::new();
        for (h, f, v) in validated {
            let (reference, against) = match parameters_only {
                Some(vp) if !f.deck_values.is_empty() => {
                    (vp, " (the deck's parameters refitted alone)")
                }
                _ => (v_cur, ""),
            };
            let m = select::margin(reference, j0);
            let reason = if f.on_bound {
                Some("fit ends on a bound".to_string())
            } else if f.std.is_some_and(|s| !(s < f.value.unwrap_or(0.0))) {
                Some("uncertainty exceeds the value".to_string())
            } else if !(v < reference - m) {
                Some(format!(
                    "validation error {v:.4} not below {reference:.4}{against} − margin {m:.4}"
                ))
            } else {
                None
            };
            match reason {
                Some(r) => self.rejected.push(Rejected {
                    label: h.label.clone(),
                    round: round + 1,
                    value: f.value,
                    validation_error: v,
                    reason: r,
                }),
                None => scored.push((h, f, v)),
            }
        }
        scored
    }

    /// The best candidate fitted along with the deck's parameters is
    /// dropped when the parameters alone, refitted from the values its joint
    /// fit gave them, fit the data as well (within the margin of its cost):
    /// it only stood in for a parameter-only fit that had stopped short.
    /// Those parameters then become the current model's and every
    /// candidate of the round is set aside (they were fitted on the old
    /// one); returns true then, and the search goes on from there.
    fn parameters_alone_suffice(
        &mut self,
        round: usize,
        scored: &mut Vec<(Hypothesis, HypFit, f64)>,
        search: &Search,
    ) -> bool {
        let engine = search.engine;
        let Some((h, f, v)) = scored.first().cloned() else {
            return false;
        };
        if f.deck_values.is_empty() {
            return false;
        }
        let Some(jf) =
            joint_screen::parameters_only_from(engine, &self.current, &self.damp, &f.deck_values)
        else {
            return false;
        };
        let m = select::margin(f.cost, search.j0);
        if !(jf.cost < f.cost + m && jf.cost < self.cost) {
            return false;
        }
        let base = model::updated_deck(&self.base, &jf.deck_values);
        let base_values = model::composed_values(&self.base_values, &jf.deck_values);
        let current = apply_accepted(&base, &self.accepted);
        let Some(bf) = engine.fit(&FitRequest::damping(&current, &jf.damping, &engine.all)) else {
            return false;
        };
        for (o, fo, vo) in scored.drain(..) {
            let reason = if o.label == h.label {
                format!(
                    "the deck's parameters alone, refitted from the values of its joint fit, cost {:.4} against its {:.4} + margin {m:.4}; taken instead",
                    jf.cost, f.cost
                )
            } else {
                format!(
                    "the deck's parameters alone explain as much as {} did",
                    h.label
                )
            };
            self.rejected.push(Rejected {
                label: o.label.clone(),
                round: round + 1,
                value: fo.value,
                validation_error: if o.label == h.label { v } else { vo },
                reason,
            });
        }
        self.v = engine.validate(None, &current, &bf);
        self.base = base;
        self.base_values = base_values;
        self.current = current;
        self.damp = bf.damping.clone();
        self.cost = bf.cost;
        true
    }

    /// When no candidate of the round passes: the best few fitted again with
    /// the accepted extensions and the deck's parameters free
    /// ([`with_accepted`]); the best is accepted, with the values of that
    /// fit, if it predicts held-out data better by more than the margin
    /// than the best the model without it does (the current model, the
    /// deck's parameters refitted alone `parameters_only`, and the joint
    /// fit without it, computed only when the first two are beaten), else
    /// recorded as rejected.
    fn take_with_accepted(
        &mut self,
        search: &Search,
        round: usize,
        fitted: &[(Hypothesis, HypFit)],
        large: bool,
        parameters_only: Option<f64>,
    ) -> bool {
        let engine = search.engine;
        let Some(w) = with_accepted::best_with_accepted(
            engine,
            &self.base,
            &self.accepted,
            fitted,
            &self.damp,
            large,
        ) else {
            return false;
        };
        let h = w.hypothesis;
        let passes = |reference: f64| w.v < reference - select::margin(reference, search.j0);
        // v − margin(v) grows with v: the smallest reference is the
        // strictest, and the joint fit without it is needed only when the
        // others are beaten.
        let mut reference = parameters_only.map_or(self.v, |vp| vp.min(self.v));
        if passes(reference) {
            let without =
                with_accepted::refitted_without(engine, &self.base, &self.accepted, &self.damp);
            reference = without.map_or(reference, |r| r.min(reference));
        }
        if !passes(reference) {
            let m = select::margin(reference, search.j0);
            self.rejected.push(Rejected {
                label: format!("{} (with the accepted extensions refitted)", h.label),
                round: round + 1,
                value: w.fit.logs.last().map(|l| l.exp()),
                validation_error: w.v,
                reason: format!(
                    "validation error {:.4} not below {reference:.4} (the model without it) − margin {m:.4}",
                    w.v
                ),
            });
            return false;
        }
        let finding = unvalued_finding(&h, (reference, w.v), h.label.clone());
        self.findings.push(finding);
        self.accepted.push((h, None));
        self.base = model::updated_deck(&self.base, &w.fit.deck_values);
        self.base_values = model::composed_values(&self.base_values, &w.fit.deck_values);
        self.take_refit(&w.fit);
        self.v = w.v;
        self.validate_as_held(engine);
        true
    }

    /// The next round's reference after an extension fitted with the deck's
    /// parameters: the new model with its damping refitted on each fold, as
    /// the round's candidates (fitted with the parameters held) will be; the
    /// validation error stays as it is when no model results.
    fn validate_as_held(&mut self, engine: &Engine) {
        if let Some(bf) = engine.fit(&FitRequest::damping(&self.current, &self.damp, &engine.all)) {
            self.v = engine.validate(None, &self.current, &bf);
        }
    }

    /// Accept the pair `p` (both extensions, fitted jointly with the
    /// accepted ones); every single candidate of the round is rejected.
    fn accept_pair(&mut self, round: usize, p: PairFit, scored: &[(Hypothesis, HypFit, f64)]) {
        for (o, fo, vo) in scored {
            self.rejected.push(Rejected {
                label: o.label.clone(),
                round: round + 1,
                value: fo.value,
                validation_error: *vo,
                reason: format!(
                    "a pair fitted jointly predicts better ({} and {})",
                    p.hyps[0].label, p.hyps[1].label
                ),
            });
        }
        let v_before = self.v;
        for h in &p.hyps {
            self.accepted.push((h.clone(), None));
            let label = format!("{} (fitted jointly with the next)", h.label);
            self.findings
                .push(unvalued_finding(h, (v_before, p.v), label));
        }
        if let Some(last) = self.findings.last_mut() {
            last.label = format!("{} (fitted jointly with the previous)", p.hyps[1].label);
        }
        self.take_refit(&p.fit);
        self.v = p.v;
    }

    /// Accept the best single candidate `(h, f, v)`; the others of the round
    /// are rejected, and those within the margin `m` of it are named as
    /// indistinguishable from it.
    fn accept_single(
        &mut self,
        round: usize,
        (h, f, v): (Hypothesis, HypFit, f64),
        scored: &[(Hypothesis, HypFit, f64)],
        m: f64,
        data: &TestData,
    ) {
        let close: Vec<&(Hypothesis, HypFit, f64)> = scored
            .iter()
            .skip(1)
            .filter(|(o, _, vo)| *vo < v + m && o.label != h.label)
            .collect();
        let tell_apart = close.first().and_then(|(o, fo, _)| {
            discriminate::tell_apart(
                (&self.explained(&h, &f), f.damping.damping()),
                (&self.explained(o, fo), fo.damping.damping()),
                &o.label,
                data,
            )
        });
        let alternatives: Vec<Alternative> = close
            .iter()
            .map(|(o, fo, vo)| Alternative {
                physics: o.physics,
                nodes: o.nodes.clone(),
                description: format!(
                    "{} ({}validation error {vo:.4})",
                    o.label,
                    fo.value
                        .zip(o.param.as_ref())
                        .map(|(x, p)| format!("{} = {} {}, ", p.name, sig(x), p.unit))
                        .unwrap_or_default()
                ),
            })
            .collect();
        for (o, fo, vo) in scored.iter().skip(1) {
            self.rejected.push(Rejected {
                label: o.label.clone(),
                round: round + 1,
                value: fo.value,
                validation_error: *vo,
                reason: format!("a better hypothesis was accepted ({})", h.label),
            });
        }
        let mut parameters = BTreeMap::new();
        let mut uncertainty = BTreeMap::new();
        if let (Some(p), Some(x)) = (&h.param, f.value) {
            parameters.insert(p.name.to_string(), x);
            uncertainty.insert(p.name.to_string(), f.std.unwrap_or(f64::INFINITY));
        }
        self.findings.push(Finding {
            physics: h.physics,
            nodes: h.nodes.clone(),
            dofs: h.dofs.clone(),
            parameters,
            uncertainty,
            validation_error_before: self.v,
            validation_error_after: v,
            label: h.label.clone(),
            alternatives,
            tell_apart,
        });
        self.accepted.push((h, f.value));
        if !f.deck_values.is_empty() {
            self.base = model::updated_deck(&self.base, &f.deck_values);
            self.base_values = model::composed_values(&self.base_values, &f.deck_values);
        }
        self.current = apply_accepted(&self.base, &self.accepted);
        self.damp = f.damping.clone();
        self.cost = f.cost;
        self.v = v;
    }

    /// The deck that explains the test by the accepted extensions and `h`
    /// at its fit `f` (with the deck's parameters it fitted along).
    fn explained(&self, h: &Hypothesis, f: &HypFit) -> Deck {
        let base = if f.deck_values.is_empty() {
            self.base.clone()
        } else {
            model::updated_deck(&self.base, &f.deck_values)
        };
        let mut accepted = self.accepted.clone();
        accepted.push((h.clone(), f.value));
        apply_accepted(&base, &accepted)
    }

    /// Re-estimate the earlier extensions' values together with the new
    /// one (each was fitted while the others were missing): kept when the
    /// joint fit costs less, stays inside the bounds and validates no worse.
    fn reestimate_jointly(&mut self, engine: &Engine) {
        if self.accepted.len() <= 1 {
            return;
        }
        let Some(jf) = self.joint_refit(engine) else {
            return;
        };
        let hyps: Vec<&Hypothesis> = self.accepted.iter().map(|a| &a.0).collect();
        let problem = refit::Joint::new(&self.base, hyps);
        if jf.cost < self.cost && !jf.on_bound.iter().any(|b| *b) {
            let vj = refit::validate_joint(engine, &problem, &jf);
            if vj <= self.v {
                self.take_refit(&jf);
                self.v = vj;
                if let Some(last) = self.findings.last_mut() {
                    last.validation_error_after = vj;
                }
            }
        }
    }

    /// The accepted extensions' values and the damping fitted again on all
    /// the data of `engine` from their current values, the deck's
    /// parameters as they are (`None` when no accepted extension has a
    /// value, or no model results).
    pub(super) fn refitted_on(&self, engine: &Engine) -> Option<refit::JointFit> {
        if self.accepted.iter().all(|a| a.1.is_none()) {
            return None;
        }
        self.joint_refit(engine)
    }

    /// The joint fit of [`Self::refitted_on`] (also with no value to fit:
    /// then the damping alone).
    fn joint_refit(&self, engine: &Engine) -> Option<refit::JointFit> {
        self.joint_refit_of(engine, &self.accepted)
    }

    /// [`Self::joint_refit`] of `accepted` in place of the accepted
    /// extensions (on the same base deck, from their values and damping).
    pub(super) fn joint_refit_of(
        &self,
        engine: &Engine,
        accepted: &[(Hypothesis, Option<f64>)],
    ) -> Option<refit::JointFit> {
        let hyps: Vec<&Hypothesis> = accepted.iter().map(|a| &a.0).collect();
        let logs: Vec<f64> = accepted.iter().filter_map(|a| a.1.map(f64::ln)).collect();
        let settings = refit::JointSettings {
            frequency_stage: false,
            iterations: 8,
        };
        let problem = refit::Joint::new(&self.base, hyps);
        let starts = std::slice::from_ref(&logs);
        refit::fit_joint(engine, &problem, starts, &self.damp, &engine.all, settings)
    }

    /// Extension `i` replaced by `moved` (the same class elsewhere) with the
    /// values and damping of `jf`, their joint fit
    /// ([`Self::joint_refit_of`]); its finding renamed, its alternatives
    /// and the measurement to tell them apart dropped (they were the
    /// first place's), and the move listed among the hypotheses tried
    /// (`j0`: the noise level, the unit of the costs it quotes).
    pub(super) fn take_move(
        &mut self,
        i: usize,
        moved: Hypothesis,
        (jf, v): (&refit::JointFit, f64),
        j0: f64,
    ) {
        let (old, value) = self.accepted[i].clone();
        self.rejected.push(Rejected {
            label: old.label.clone(),
            round: self.findings.len(),
            value,
            validation_error: f64::NAN,
            reason: format!(
                "{} after the search ({}): FRF cost {:.2} → {:.2} × the noise level, the deck's parameters held",
                if moved.physics == old.physics {
                    "moved to a neighbouring node"
                } else {
                    "taken as a mass of the other class beside it"
                },
                moved.label,
                self.cost / j0,
                jf.cost / j0
            ),
        });
        if let Some(f) = self.findings.get_mut(i) {
            f.physics = moved.physics;
            f.nodes = moved.nodes.clone();
            f.label = moved.label.clone();
            f.alternatives.clear();
            f.tell_apart = None;
            f.validation_error_after = v;
        }
        self.accepted[i].0 = moved;
        self.take_refit(jf);
        self.v = v;
    }

    /// Extension `i` dropped, the others at the values and damping of
    /// `jf`, their joint fit without it (`v`: its validation cost); the
    /// drop listed among the hypotheses tried (`j0`: the noise level, the
    /// unit of the costs it quotes).
    pub(super) fn take_removal(&mut self, i: usize, (jf, v): (&refit::JointFit, f64), j0: f64) {
        let (old, value) = self.accepted.remove(i);
        self.findings.remove(i);
        let without = if self.accepted.is_empty() {
            "the model without it, its damping refitted,"
        } else {
            "the other extensions, refitted without it,"
        };
        self.rejected.push(Rejected {
            label: old.label.clone(),
            round: self.findings.len() + 1,
            value,
            validation_error: v,
            reason: format!(
                "dropped after the search: {without} cost {:.2} against {:.2} × the noise level with it, within the margin",
                jf.cost / j0,
                self.cost / j0
            ),
        });
        self.take_refit(jf);
        self.v = v;
    }

    /// Take the values and the damping of `jf`, a joint fit over the
    /// accepted extensions on `base` (its validation error is the caller's).
    pub(super) fn take_refit(&mut self, jf: &refit::JointFit) {
        set_values(&mut self.accepted, &mut self.findings, jf);
        self.current = apply_accepted(&self.base, &self.accepted);
        self.damp = jf.damping.clone();
        self.cost = jf.cost;
    }

    /// The damping form may have compensated for what was missing: another
    /// form whose cost is lower replaces the current one.
    fn choose_damping_form_again(&mut self, search: &Search) {
        let engine = search.engine;
        let Some((d2, forms)) = select::choose_damping(
            engine,
            &self.current,
            Some((self.damp.form, self.damp.x.clone())),
            search.zeta0,
        ) else {
            return;
        };
        let c2 = forms
            .iter()
            .find(|x| x.0 == d2.form)
            .map_or(f64::INFINITY, |x| x.1);
        if d2.form != self.damp.form && c2 < self.cost {
            if let Some(bf) = engine.fit(&FitRequest::damping(&self.current, &d2, &engine.all)) {
                self.damp = bf.damping.clone();
                self.cost = bf.cost;
                self.v = engine.validate(None, &self.current, &bf);
            }
        }
    }
}

/// The candidate the placement prior names among those tied with the best
/// (`scored` ascending by validation error; margin of the best's error,
/// [`select::margin`]) is moved to the front ([`prior::tie_pick`] on
/// [`prior::tie_penalty`]: a fitted parameter counts as a choice). Seed-1
/// benchmark case 115 (a stocky pinned portal with shear deformation and an
/// added mass): shear and a flexible support at node 1 validated at 97.4
/// and 97.0 in the first round; the support was taken, a false finding,
/// and the shear never came back.
fn prefer_by_prior(scored: &mut [(Hypothesis, HypFit, f64)], j0: f64, deck: &Deck) {
    let ranked: Vec<(usize, f64)> = scored
        .iter()
        .map(|s| (prior::tie_penalty(&s.0, deck), s.2))
        .collect();
    let Some(pick) = prior::tie_pick(&ranked, |v| select::margin(v, j0)) else {
        return;
    };
    scored[..=pick].rotate_right(1);
}

/// `start` with the accepted extensions at their values.
pub(super) fn apply_accepted(start: &Deck, accepted: &[(Hypothesis, Option<f64>)]) -> Deck {
    accepted
        .iter()
        .fold(start.clone(), |d, (h, v)| h.apply(&d, *v))
}

/// The finding of `h` accepted from a joint fit, its value written later
/// ([`set_values`]): validation errors (before, after), no alternatives.
fn unvalued_finding(h: &Hypothesis, (before, after): (f64, f64), label: String) -> Finding {
    Finding {
        physics: h.physics,
        nodes: h.nodes.clone(),
        dofs: h.dofs.clone(),
        parameters: BTreeMap::new(),
        uncertainty: BTreeMap::new(),
        validation_error_before: before,
        validation_error_after: after,
        label,
        alternatives: vec![],
        tell_apart: None,
    }
}

/// Write the values and uncertainties of a joint fit over all accepted
/// extensions (in order) into the list and the findings.
fn set_values(
    accepted: &mut [(Hypothesis, Option<f64>)],
    findings: &mut [Finding],
    jf: &refit::JointFit,
) {
    let mut k = 0;
    for (i, (h, v)) in accepted.iter_mut().enumerate() {
        let Some(p) = &h.param else {
            continue;
        };
        let x = jf.logs[k].exp();
        *v = Some(x);
        if let Some(f) = findings.get_mut(i) {
            f.parameters.insert(p.name.to_string(), x);
            f.uncertainty.insert(p.name.to_string(), jf.std_log[k] * x);
        }
        k += 1;
    }
}

/// A pair of extensions fitted jointly (with the accepted ones re-estimated).
struct PairFit {
    hyps: [Hypothesis; 2],
    fit: refit::JointFit,
    v: f64,
}

/// Joint fits of pairs among the best-fitting single candidates of a round
/// (after the accepted extensions), each from a grid of starts through the
/// resonance-frequency stage; the pair that predicts held-out data best,
/// if its fit is well determined and inside the bounds.
fn pair_search(
    engine: &Engine,
    start: &Deck,
    accepted: &[(Hypothesis, Option<f64>)],
    fitted: &[(Hypothesis, HypFit)],
    damp: &DampingState,
    large: bool,
) -> Option<PairFit> {
    let pool: Vec<&(Hypothesis, HypFit)> = fitted
        .iter()
        .filter(|(h, _)| h.physics != Physics::Suspension)
        .take(if large { 3 } else { 5 })
        .collect();
    let per_axis = if large { 3 } else { 4 };
    let mut best: Option<PairFit> = None;
    for a in 0..pool.len() {
        for b in a + 1..pool.len() {
            let (ha, fa) = pool[a];
            let (hb, fb) = pool[b];
            if ha.param.is_none() && hb.param.is_none() {
                continue;
            }
            let mut hyps: Vec<&Hypothesis> = accepted.iter().map(|x| &x.0).collect();
            hyps.push(ha);
            hyps.push(hb);
            let mut fixed: Vec<Option<f64>> = accepted
                .iter()
                .filter_map(|x| x.0.param.as_ref().map(|_| x.1.map(f64::ln)))
                .collect();
            let n_acc = fixed.len();
            let singles: Vec<Option<f64>> = [(ha, fa), (hb, fb)]
                .iter()
                .filter(|(h, _)| h.param.is_some())
                .map(|(_, f)| f.log_value)
                .collect();
            let mut from_singles = fixed.iter().map(|x| x.unwrap_or(0.0)).collect::<Vec<_>>();
            from_singles.extend(singles.iter().map(|x| x.unwrap_or(0.0)));
            fixed.extend(singles.iter().map(|_| None));
            let problem = refit::Joint::new(start, hyps);
            let (lo, hi) = problem.bounds();
            let mut starts = refit::grid_starts(&lo, &hi, &fixed, per_axis);
            starts.push(from_singles);
            let settings = refit::JointSettings {
                frequency_stage: true,
                iterations: 12,
            };
            let Some(jf) = refit::fit_joint(engine, &problem, &starts, damp, &engine.all, settings)
            else {
                continue;
            };
            let new = n_acc..jf.logs.len();
            if jf.on_bound[new.clone()].iter().any(|x| *x)
                || jf.std_log[new].iter().any(|s| !(*s < 1.0))
            {
                continue;
            }
            if best.as_ref().is_some_and(|p| p.fit.cost <= jf.cost) {
                continue;
            }
            let v = refit::validate_joint(engine, &problem, &jf);
            if best.as_ref().is_none_or(|p| v < p.v) {
                best = Some(PairFit {
                    hyps: [ha.clone(), hb.clone()],
                    fit: jf,
                    v,
                });
            }
        }
    }
    best
}
