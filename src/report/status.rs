//! What an update came to, in the words both `report.md` and `report.html`
//! use: the status line (converged or why not), the misfit note, and the
//! full-band estimate's parameters with their uncertainty.

use frfup_parsers::deck::Deck;

use crate::updating::fullband::estimate::FullBandEstimate;
use crate::updating::{self, UpdateResult};

/// The estimate's misfit (mean squared residual over its noise-level value)
/// above which the deck's parameters do not explain the test.
pub const MISFIT_LIMIT: f64 = 4.0;

/// The run's status at a glance.
#[derive(Clone, Debug, PartialEq)]
pub struct Status {
    pub converged: bool,
    /// "converged", or "NOT CONVERGED — <why it stopped>".
    pub headline: String,
    /// Set when the estimate's misfit is above [`MISFIT_LIMIT`] times the noise level.
    pub misfit_note: Option<String>,
}

/// The status of `result`; the reason is [`not_converged_reason`]'s.
pub fn status(result: &UpdateResult) -> Status {
    let headline = if result.converged {
        "converged".to_string()
    } else {
        format!("NOT CONVERGED — {}", not_converged_reason(result))
    };
    let misfit_note = result
        .estimate
        .as_ref()
        .filter(|e| e.misfit > MISFIT_LIMIT)
        .map(|e| {
            format!(
                "the misfit is {:.1}× the noise level: the deck's parameters do not explain the test: run `frfup diagnose`",
                e.misfit
            )
        });
    Status {
        converged: result.converged,
        headline,
        misfit_note,
    }
}

/// Why an update that did not converge stopped, in words.
pub fn not_converged_reason(result: &UpdateResult) -> String {
    let why = result
        .warnings
        .iter()
        .find(|w| {
            matches!(
                w,
                updating::UpdateWarning::EstimateNotConverged { .. }
                    | updating::UpdateWarning::EstimateRejected { .. }
                    | updating::UpdateWarning::NotConverged { .. }
                    | updating::UpdateWarning::Diverged { .. }
                    | updating::UpdateWarning::ParameterExploded { .. }
            )
        })
        .map(|w| w.to_string());
    why.unwrap_or_else(|| result.stop.name().to_string())
}

/// One parameter of the full-band estimate, as text.
#[derive(Clone, Debug, PartialEq)]
pub struct EstimateRow {
    pub name: String,
    /// p̄, 4 decimals; "not identified" when the data do not determine it
    /// (its value is then the deck's, not an estimate).
    pub value: String,
    /// "± 0.0123" (one standard deviation), or "–".
    pub sd: String,
    /// "not identified by these data (kept at the deck's value)", "… the
    /// mirror image … fits as well", "at its bound", or empty.
    pub verdict: String,
    /// The deck's bounds and prior (`min=… max=… sd=…`), or empty.
    pub prior: String,
}

fn num(v: f64) -> String {
    if !v.is_finite() {
        "–".into()
    } else if v != 0.0 && v.abs() < 1e-3 {
        format!("{v:.2e}")
    } else {
        format!("{v:.4}")
    }
}

/// The deck's `min= max= sd=` of parameter `name`, as written in the deck.
fn deck_prior(deck: &Deck, name: &str) -> String {
    let Some(p) = deck.params.iter().find(|p| p.name == name) else {
        return String::new();
    };
    let parts: Vec<String> = [("min", p.min), ("max", p.max), ("sd", p.sd)]
        .iter()
        .filter_map(|(k, v)| v.map(|v| format!("{k}={v}")))
        .collect();
    parts.join(" ")
}

/// The rows of the parameter table, in the estimate's (the deck's) order.
pub fn estimate_rows(est: &FullBandEstimate, deck: &Deck) -> Vec<EstimateRow> {
    est.parameters
        .iter()
        .map(|p| EstimateRow {
            name: p.name.clone(),
            value: if p.identified || !p.held {
                num(p.value)
            } else {
                "not identified".into()
            },
            sd: if p.sd.is_finite() {
                format!("± {}", num(p.sd))
            } else {
                "–".into()
            },
            verdict: if !p.identified && p.held {
                "not identified by these data (kept at the deck's value)".into()
            } else if !p.identified {
                "not identified by these data: the mirror image (values swapped along the unseen direction) fits as well".into()
            } else if p.at_bound {
                "at its bound".into()
            } else {
                String::new()
            },
            prior: deck_prior(deck, &p.name),
        })
        .collect()
}

/// The directions in parameter space the data do not determine, one line
/// each: "0.71·a − 1.00·b (sd 0.83)".
pub fn unseen_directions(est: &FullBandEstimate) -> Vec<String> {
    est.missing_directions
        .iter()
        .map(|(dir, sd)| {
            let mut s = String::new();
            for (i, (name, c)) in dir.iter().enumerate() {
                let sign = if *c < 0.0 { "−" } else { "+" };
                if i == 0 {
                    if *c < 0.0 {
                        s.push('−');
                    }
                } else {
                    s.push_str(&format!(" {sign} "));
                }
                s.push_str(&format!("{:.2}·{name}", c.abs()));
            }
            format!("{s} (sd {})", num(*sd))
        })
        .collect()
}

/// "Damping identified along: …".
pub fn damping_sentence(est: &FullBandEstimate) -> String {
    format!(
        "damping identified along: {}",
        crate::model::describe_damping(est.damping)
    )
}
