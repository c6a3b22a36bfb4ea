//! The sentences `report.md` and `report.html` share, written once: each is a
//! list of [`Run`]s that both formats render (bold as `**…**` or `<b>…</b>`,
//! code as backticks or `<code>`), so the two reports cannot drift apart.

use super::html::esc;
use super::output::{frequency_rows, mean_abs_dev};
use crate::updating::fullband::estimate::FullBandEstimate;
use crate::updating::{ShapeSource, UpdateResult};

/// A piece of a sentence.
#[derive(Clone, Debug, PartialEq)]
pub enum Run {
    Text(String),
    Strong(String),
    Code(String),
}

/// A sentence (or a few) made of runs.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Prose(pub Vec<Run>);

impl Prose {
    /// Plain text.
    pub fn text(mut self, s: impl Into<String>) -> Self {
        self.0.push(Run::Text(s.into()));
        self
    }

    /// Emphasised text (bold).
    pub fn strong(mut self, s: impl Into<String>) -> Self {
        self.0.push(Run::Strong(s.into()));
        self
    }

    /// A name the user types (code style).
    pub fn code(mut self, s: impl Into<String>) -> Self {
        self.0.push(Run::Code(s.into()));
        self
    }

    /// Markdown text.
    pub fn markdown(&self) -> String {
        self.0
            .iter()
            .map(|r| match r {
                Run::Text(t) => t.clone(),
                Run::Strong(t) => format!("**{t}**"),
                Run::Code(t) => format!("`{t}`"),
            })
            .collect()
    }

    /// HTML text (escaped).
    pub fn html(&self) -> String {
        self.0
            .iter()
            .map(|r| match r {
                Run::Text(t) => esc(t),
                Run::Strong(t) => format!("<b>{}</b>", esc(t)),
                Run::Code(t) => format!("<code>{}</code>", esc(t)),
            })
            .collect()
    }

    /// Plain text.
    pub fn plain(&self) -> String {
        self.0
            .iter()
            .map(|r| match r {
                Run::Text(t) | Run::Strong(t) | Run::Code(t) => t.as_str(),
            })
            .collect()
    }
}

fn f(v: f64, d: usize) -> String {
    super::charts::fmt_fixed(v, d)
}

/// "Converged after 21 iteration(s) (converged); returned iteration 21.
/// SFDAC mean 0.2990 → **0.9992**, minimum … ; mean |Δf| of the paired
/// resonances 5.43 % → **0.06 %**."
pub fn update_summary(result: &UpdateResult) -> Prose {
    let (Some(first), Some(last)) = (
        result.iterations.first(),
        result.iterations.get(result.final_iteration),
    ) else {
        return Prose::default().text("The run holds no iteration.");
    };
    let rows = frequency_rows(result);
    let dev = |u: bool| {
        mean_abs_dev(&rows, u)
            .map(|v| format!("{} %", f(v, 2)))
            .unwrap_or_else(|| "–".into())
    };
    Prose::default()
        .strong(if result.converged {
            "Converged"
        } else {
            "Not converged"
        })
        .text(format!(
            " after {} iteration(s) ({}); returned iteration {}. SFDAC mean {} → ",
            result.iterations.len().saturating_sub(1),
            result.stop.name(),
            result.final_iteration,
            f(first.sfdac.mean, 4)
        ))
        .strong(f(last.sfdac.mean, 4))
        .text(format!(", minimum {} → ", f(first.sfdac.min, 4)))
        .strong(f(last.sfdac.min, 4))
        .text(format!(
            "; mean |Δf| of the paired resonances {} → ",
            dev(false)
        ))
        .strong(dev(true))
        .text(".")
}

/// "Misfit 0.86× the noise level; damping identified along: …."
pub fn estimate_sentence(est: &FullBandEstimate) -> Prose {
    Prose::default().text(format!(
        "Misfit {}× the noise level; {}.",
        f(est.misfit, 2),
        super::status::damping_sentence(est)
    ))
}

/// The sentence under the estimate table when the deck gives no prior.
pub fn no_priors() -> Prose {
    Prose::default()
        .text("The deck gives no bounds or priors (")
        .code("param … min= max= sd=")
        .text("): defaults apply.")
}

/// The test shapes that paired test resonances with FE modes: the MAC of
/// the frequency table and of the MAC chart.
pub fn pairing_shapes(result: &UpdateResult) -> &'static str {
    result.pairing_shapes.source.name()
}

/// What the MAC of the frequency table and of the MAC chart are computed
/// from: one source, the shapes that paired the resonances.
pub fn mac_sources(result: &UpdateResult) -> Prose {
    let p = Prose::default()
        .text("MAC (frequency table and MAC chart): ")
        .strong(format!("MAC of the {}", pairing_shapes(result)));
    let p = match result.pairing_shapes.source {
        ShapeSource::Fitted => p.text(
            " (from the pole fit common to all channels; the peaks' deflection shapes where no pole fits)",
        ),
        ShapeSource::OperatingDeflection => p.text(" (the measured FRFs at each resonance line)"),
    };
    p.text(
        " against the FE modes; these shapes paired each test resonance with an FE mode, and the chart's outlined cells are the table's pairs.",
    )
}

/// The column name of the pairing MAC: "MAC (fitted shapes)" or "MAC (ODS)".
pub fn pairing_mac_header(result: &UpdateResult) -> &'static str {
    match result.pairing_shapes.source {
        ShapeSource::Fitted => "MAC (fitted shapes)",
        ShapeSource::OperatingDeflection => "MAC (ODS)",
    }
}
