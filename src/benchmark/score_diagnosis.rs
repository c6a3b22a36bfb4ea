//! Scoring a `frfup diagnose` run (`diagnosis.json`) against the truth of a
//! diagnosis benchmark case (`truth.json`), and the summary of a run.
//!
//! Per true effect: the *physics* is right when a finding has its class; the
//! *place* is right when, besides, a node of that finding is a true node or
//! one element away from one (for data errors the true node is the channel's
//! point: its sensor, or its hit point in a roving-hammer test; damping and
//! shear deformation are everywhere, any place is right). The fitted *value*
//! of a right finding is within tolerance when a mass is within 20 %, a
//! spring within a factor 2, a damping within 30 % (its equivalent viscous
//! ratio at every elastic band mode of the truth). A *false finding* is one
//! whose class is not in the truth.
//!
//! A true effect not placed by any finding is *tied* when a finding names
//! it among the alternatives the data cannot tell apart (`alternatives` of
//! `diagnosis.json`: the issue's outcome (b), "X and Y explain the data
//! equally well"). Ties are counted apart from the strict score, never in it.

use std::collections::{BTreeMap, BTreeSet};

use frfup_parsers::deck::Deck;
use serde_json::Value;

use super::DampingSpec;

/// How one true effect was found.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct EffectScore {
    pub class: String,
    pub nodes: Vec<u32>,
    /// FRF change in noise units (truth.json `frf_change`).
    pub frf_change: f64,
    pub physics: bool,
    pub place: bool,
    /// Not placed, but named among a finding's indistinguishable alternatives.
    pub tied: bool,
    /// Fitted value within tolerance (None: no value to compare, or not found).
    pub value_ok: Option<bool>,
    /// Fitted / true value (masses, springs) or the worst ζ ratio (damping).
    pub value_ratio: Option<f64>,
}

/// How one case scored.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DiagScore {
    pub effects: Vec<EffectScore>,
    /// Classes and nodes of every finding, as reported.
    pub reported: Vec<(String, Vec<u32>)>,
    /// Classes of the findings that are not in the truth.
    pub false_findings: Vec<String>,
    /// `diagnosis.json` was read.
    pub has_report: bool,
}

impl DiagScore {
    /// A control (no effect in the truth).
    pub fn is_control(&self) -> bool {
        self.effects.is_empty()
    }
    /// Every true effect found at its place (a control: nothing reported).
    pub fn right(&self) -> bool {
        if self.is_control() {
            self.has_report && self.reported.is_empty()
        } else {
            self.effects.iter().all(|e| e.place)
        }
    }
    /// [`DiagScore::right`], or every effect not placed tied (named among
    /// the alternatives the data cannot tell apart).
    pub fn right_or_tied(&self) -> bool {
        self.right() || (!self.is_control() && self.effects.iter().all(|e| e.place || e.tied))
    }
}

/// Nodes one element apart: node → its neighbours through a beam or a spring.
fn neighbours(deck: &Deck) -> BTreeMap<u32, BTreeSet<u32>> {
    let mut m: BTreeMap<u32, BTreeSet<u32>> = BTreeMap::new();
    let mut link = |a: u32, b: u32| {
        m.entry(a).or_default().insert(b);
        m.entry(b).or_default().insert(a);
    };
    for b in &deck.beams {
        link(b.nodes[0], b.nodes[1]);
    }
    for s in &deck.springs {
        if let Some(to) = s.to {
            link(s.node, to);
        }
    }
    m
}

fn nodes_of(v: &Value) -> Vec<u32> {
    v.get("nodes")
        .and_then(Value::as_array)
        .map(|a| {
            a.iter()
                .filter_map(|n| n.as_u64().map(|n| n as u32))
                .collect()
        })
        .unwrap_or_default()
}

/// A damping statement from its JSON (`model` and parameters).
pub fn damping_of(v: &Value) -> Option<DampingSpec> {
    let f = |k: &str| v.get(k).and_then(Value::as_f64);
    match v.get("model").and_then(Value::as_str)? {
        "modal" => Some(DampingSpec::Modal { zeta: f("zeta")? }),
        "hysteretic" => Some(DampingSpec::Hysteretic { eta: f("eta")? }),
        "rayleigh" => Some(DampingSpec::Rayleigh {
            alpha: f("alpha").unwrap_or(0.0),
            beta: f("beta").unwrap_or(0.0),
        }),
        _ => None,
    }
}

/// A fitted damping from a finding's `parameters`.
fn fitted_damping(p: &Value) -> Option<DampingSpec> {
    let f = |k: &str| p.get(k).and_then(Value::as_f64);
    if let Some(zeta) = f("zeta") {
        Some(DampingSpec::Modal { zeta })
    } else if let Some(eta) = f("eta") {
        Some(DampingSpec::Hysteretic { eta })
    } else if f("alpha").is_some() || f("beta").is_some() {
        Some(DampingSpec::Rayleigh {
            alpha: f("alpha").unwrap_or(0.0),
            beta: f("beta").unwrap_or(0.0),
        })
    } else {
        None
    }
}

/// The fitted value of `finding` against the true effect `e`: (within
/// tolerance, ratio), None when the class has no value.
fn value_check(e: &Value, finding: &Value, modes_hz: &[f64]) -> Option<(bool, f64)> {
    let params = finding.get("parameters")?;
    let get = |k: &str| params.get(k).and_then(Value::as_f64);
    if let Some(m) = e.get("m").and_then(Value::as_f64) {
        let r = get("m").unwrap_or(f64::NAN) / m;
        return Some(((r - 1.0).abs() <= 0.2, r));
    }
    if let Some(k) = e.get("k").and_then(Value::as_f64) {
        let r = get("k").unwrap_or(f64::NAN) / k;
        return Some(((0.5..=2.0).contains(&r), r));
    }
    let truth = damping_of(e.get("damping")?)?;
    let Some(fit) = fitted_damping(params) else {
        return Some((false, f64::NAN));
    };
    // The worst ratio of equivalent viscous damping over the band modes.
    let mut worst = 1.0f64;
    for &f in modes_hz {
        let r = fit.zeta_at(f) / truth.zeta_at(f);
        if !r.is_finite() || (r.ln()).abs() > worst.ln().abs() {
            worst = r;
        }
    }
    Some(((worst - 1.0).abs() <= 0.3, worst))
}

/// Score `diagnosis` (`diagnosis.json`, None when the run wrote none)
/// against `truth` (`truth.json` of a diagnosis case), with `deck` the
/// case's model deck (for "one element away").
pub fn score_diagnosis(truth: &Value, deck: &Deck, diagnosis: Option<&Value>) -> DiagScore {
    let near = neighbours(deck);
    let close = |a: u32, b: u32| a == b || near.get(&a).is_some_and(|s| s.contains(&b));
    let modes: Vec<f64> = truth
        .get("elastic_modes_hz")
        .and_then(Value::as_array)
        .map(|a| a.iter().filter_map(Value::as_f64).collect())
        .unwrap_or_default();
    let findings: Vec<Value> = diagnosis
        .and_then(|d| d.get("findings"))
        .and_then(Value::as_array)
        .cloned()
        .unwrap_or_default();
    let class_of = |f: &Value| {
        f.get("physics")
            .and_then(Value::as_str)
            .unwrap_or("?")
            .to_string()
    };
    let effects: Vec<Value> = truth
        .get("effects")
        .and_then(Value::as_array)
        .cloned()
        .unwrap_or_default();
    let true_classes: BTreeSet<String> = effects.iter().map(class_of_effect).collect();
    let mut out = DiagScore {
        has_report: diagnosis.is_some(),
        reported: findings
            .iter()
            .map(|f| (class_of(f), nodes_of(f)))
            .collect(),
        false_findings: findings
            .iter()
            .map(class_of)
            .filter(|c| !true_classes.contains(c))
            .collect(),
        ..DiagScore::default()
    };
    for e in &effects {
        let class = class_of_effect(e);
        let nodes = nodes_of(e);
        let same: Vec<&Value> = findings.iter().filter(|f| class_of(f) == class).collect();
        let placed = same.iter().find(|f| {
            nodes.is_empty()
                || nodes_of(f)
                    .iter()
                    .any(|&a| nodes.iter().any(|&b| close(a, b)))
        });
        let check = placed.and_then(|f| value_check(e, f, &modes));
        let matches = |a: &Value| {
            a.get("physics").and_then(Value::as_str) == Some(class.as_str())
                && (nodes.is_empty()
                    || nodes_of(a)
                        .iter()
                        .any(|&x| nodes.iter().any(|&b| close(x, b))))
        };
        let tied = placed.is_none()
            && findings.iter().any(|f| {
                f.get("alternatives")
                    .and_then(Value::as_array)
                    .is_some_and(|alts| alts.iter().any(matches))
            });
        out.effects.push(EffectScore {
            frf_change: e.get("frf_change").and_then(Value::as_f64).unwrap_or(0.0),
            physics: !same.is_empty(),
            place: placed.is_some(),
            tied,
            value_ok: check.map(|c| c.0),
            value_ratio: check.map(|c| c.1),
            class,
            nodes,
        });
    }
    out
}

fn class_of_effect(e: &Value) -> String {
    e.get("class")
        .and_then(Value::as_str)
        .unwrap_or("?")
        .to_string()
}
