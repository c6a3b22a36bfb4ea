//! A randomised benchmark of `frfup update`: random structures, parameter
//! errors, sensor layouts, damping, noise and file formats, each case made
//! deterministically from a seed, with the truth written beside it.
//!
//! - [`generate`]: a seed → a [`Case`]: the nominal deck with `param`s
//!   (`model.deck`), the "measured" campaign simulated from the truth with
//!   [`crate::simulate`] (`test.uff`) and the truth (`truth.json`);
//! - [`score`]: a case's `report.json` (or an in-process update) against the
//!   truth, and the summary table of a run.
//!
//! Extension: what the truth has that the model lacks is an [`Effect`]
//! ([`effect`]), applied to the truth structure (and, for data errors, to the
//! simulated FRFs). Parameter-only cases use [`Effect::None`]. The update
//! benchmark's cases are parameter-only; [`generate_diagnosis`] makes the
//! cases of the `frfup diagnose` benchmark (every class of the diagnosis
//! dictionary and the data errors, alone, in pairs, and controls), scored by
//! [`score_diagnosis`].
//!
//! Units are SI throughout; parameters p are relative changes (updated value =
//! (1 + p) × deck value), as in the deck.

pub mod diagnosis_summary;
pub mod effect;
pub mod generate;
pub mod score;
pub mod score_diagnosis;

pub use diagnosis_summary::{diagnosis_summary_markdown, DiagRecord};
pub use effect::Effect;
pub use generate::{
    case_seed, frf_change, generate, generate_diagnosis, Case, GenError, GenOptions, Structure,
};
pub use score::{
    message_class, score_estimates, score_report, summary_markdown, CaseScore, ReportEstimate,
    RunRecord,
};
pub use score_diagnosis::{score_diagnosis, DiagScore, EffectScore};

/// SplitMix64: a tiny, fast, well-mixed 64-bit generator. The same seed gives
/// the same sequence on every machine (integer arithmetic only).
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
}

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng { state: seed }
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.state = self.state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }

    /// Uniform integer in lo..=hi (lo when hi < lo).
    pub fn int(&mut self, lo: usize, hi: usize) -> usize {
        if hi <= lo {
            return lo;
        }
        lo + (self.next_u64() % (hi - lo + 1) as u64) as usize
    }

    /// True with probability `p`.
    pub fn chance(&mut self, p: f64) -> bool {
        self.uniform() < p
    }

    /// A uniformly chosen element (`None` for an empty slice).
    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> Option<&'a T> {
        if items.is_empty() {
            None
        } else {
            items.get(self.int(0, items.len() - 1))
        }
    }

    /// Fisher–Yates shuffle.
    pub fn shuffle<T>(&mut self, items: &mut [T]) {
        for i in (1..items.len()).rev() {
            let j = self.int(0, i);
            items.swap(i, j);
        }
    }
}

/// Round to `digits` significant digits (so that decks and bands do not
/// depend on the last bits of an eigen solution).
pub fn round_sig(x: f64, digits: i32) -> f64 {
    if x == 0.0 || !x.is_finite() {
        return x;
    }
    let e = x.abs().log10().floor() as i32;
    let scale = 10f64.powi(digits - 1 - e);
    (x * scale).round() / scale
}

/// The kind of structure a case is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum StructureKind {
    /// One straight member (plane or space analysis).
    Beam,
    /// Two members at a right angle (plane).
    LFrame,
    /// A cross-beam with a stem from its middle (plane).
    TFrame,
    /// Two columns and a cross-beam (plane).
    Portal,
    /// A frame in space: a table (four legs, a top ring) or an x–y–z chain.
    SpaceFrame,
}

impl StructureKind {
    pub const ALL: [StructureKind; 5] = [
        StructureKind::Beam,
        StructureKind::LFrame,
        StructureKind::TFrame,
        StructureKind::Portal,
        StructureKind::SpaceFrame,
    ];
    pub fn name(self) -> &'static str {
        match self {
            StructureKind::Beam => "beam",
            StructureKind::LFrame => "L-frame",
            StructureKind::TFrame => "T-frame",
            StructureKind::Portal => "portal",
            StructureKind::SpaceFrame => "space-frame",
        }
    }
}

/// Boundary conditions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Support {
    /// Free-free on soft springs (suspension modes 6–12 times below the
    /// first elastic mode).
    FreeFree,
    /// All DOFs fixed at the base node(s).
    Clamped,
    /// Translations fixed at the support node(s) (plus what a mechanism needs).
    Pinned,
}

impl Support {
    pub fn name(self) -> &'static str {
        match self {
            Support::FreeFree => "free-free",
            Support::Clamped => "clamped",
            Support::Pinned => "pinned",
        }
    }
}

/// Which row or column of the FRF matrix the test measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum LayoutKind {
    /// One exciter, many sensors: a column; reference = the exciter.
    FixedExciter,
    /// One sensor, the hammer moved over the points: a row; each record's
    /// reference is the hit point, its response the fixed sensor.
    RovingHammer,
}

impl LayoutKind {
    pub fn name(self) -> &'static str {
        match self {
            LayoutKind::FixedExciter => "fixed-exciter",
            LayoutKind::RovingHammer => "roving-hammer",
        }
    }
}

/// Damping of truth and model (the same statement in both decks).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DampingSpec {
    /// Viscous ratio ζ of every mode.
    Modal { zeta: f64 },
    /// C = αM + βK (α in 1/s, β in s).
    Rayleigh { alpha: f64, beta: f64 },
    /// Loss factor η: K(1 + iη).
    Hysteretic { eta: f64 },
}

impl DampingSpec {
    pub fn name(self) -> &'static str {
        match self {
            DampingSpec::Modal { .. } => "modal",
            DampingSpec::Rayleigh { .. } => "rayleigh",
            DampingSpec::Hysteretic { .. } => "hysteretic",
        }
    }
    /// The deck statement.
    pub fn statement(self) -> String {
        match self {
            DampingSpec::Modal { zeta } => format!("damping modal {zeta:e}"),
            DampingSpec::Rayleigh { alpha, beta } => {
                format!("damping rayleigh {alpha:e} {beta:e}")
            }
            DampingSpec::Hysteretic { eta } => format!("damping hysteretic {eta:e}"),
        }
    }
    /// Equivalent viscous ratio at `f_hz`: ζ, α/(2ω) + βω/2, or η/2.
    pub fn zeta_at(self, f_hz: f64) -> f64 {
        let w = 2.0 * std::f64::consts::PI * f_hz;
        match self {
            DampingSpec::Modal { zeta } => zeta,
            DampingSpec::Rayleigh { alpha, beta } => alpha / (2.0 * w.max(1e-12)) + beta * w / 2.0,
            DampingSpec::Hysteretic { eta } => eta / 2.0,
        }
    }
}

/// Frequency axis of a case.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AxisKind {
    /// Even lines (an even-abscissa 58 record).
    Even,
    /// Log-spaced lines (uneven abscissa).
    Log,
    /// Even lines each moved by up to ±30 % of a step (uneven abscissa).
    Jittered,
}

impl AxisKind {
    pub fn name(self) -> &'static str {
        match self {
            AxisKind::Even => "even",
            AxisKind::Log => "log",
            AxisKind::Jittered => "jittered",
        }
    }
}

/// One updating parameter of a case and its true value.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamTruth {
    pub name: String,
    /// Deck quantity name (`E`, `rho`, `Iy`, `A`, `k`, `m`).
    pub quantity: &'static str,
    /// The IDs (beam, spring or mass) as the deck lists them, e.g. `3-7`.
    pub ids: String,
    /// True relative change p.
    pub value: f64,
    /// Optional bounds and prior written on the `param` line.
    pub min: Option<f64>,
    pub max: Option<f64>,
    pub sd: Option<f64>,
    /// Largest relative shift of a band mode for p = 0.1 (how visible it is).
    pub visibility: f64,
}
