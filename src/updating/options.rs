//! The options of an update, defined once.
//!
//! * [`UpdateOptions`]: the values the algorithms read, with the two presets
//!   ([`UpdateOptions::default`], the robust pipeline, and
//!   [`UpdateOptions::paper`], the paper's method); serialised as the
//!   `options` of `report.json`.
//! * [`UpdateSettings`]: the options as a user gives them: the flags of
//!   `frfup update` and `frfup diagnose` (clap) and the keys of a campaign
//!   case (serde, kebab-case, the flag's name without `--`). Each one left
//!   unset takes the chosen method's preset ([`UpdateSettings::resolve`]).
//!
//! A new option is a field of each struct (with its preset values) and a
//! line of [`UpdateSettings::resolve`]; the command line, campaign files and
//! `report.json` follow.

use std::str::FromStr;

use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::serep::InverseMethod;

/// Default relative diagonal perturbation of `--inverse perturb`.
pub const DEFAULT_PERTURBATION: f64 = 1e-8;

/// Which pipeline an update runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum UpdateMethod {
    /// Resonances by the multi-channel pole fit, the frequencies-first
    /// stage, damped (Levenberg–Marquardt) FRF steps, then the full-band
    /// estimate with bounds, priors and uncertainties; converged is that
    /// of the final estimate.
    Robust,
    /// The paper's iteration exactly (Eq. 26–29, 49), with the paper's values.
    Paper,
}

impl UpdateMethod {
    pub fn name(self) -> &'static str {
        match self {
            UpdateMethod::Robust => "robust",
            UpdateMethod::Paper => "paper",
        }
    }
}

/// Settings of an update. `Default` is the robust pipeline
/// ([`UpdateMethod::Robust`]); [`UpdateOptions::paper`] the paper's method
/// with the paper's values. Serialised (`report.json`'s `options`) without
/// the method, written beside them, and the estimate's iteration limit.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct UpdateOptions {
    /// The pipeline.
    #[serde(skip)]
    pub method: UpdateMethod,
    /// Levenberg–Marquardt iteration limit of the full-band estimate
    /// ([`UpdateMethod::Robust`] only).
    #[serde(skip)]
    pub estimate_iterations: usize,
    /// Starts spread over the plausible range tried when every other start
    /// of the full-band estimate ends far above the noise level
    /// ([`UpdateMethod::Robust`] only; 0: none).
    #[serde(skip)]
    pub spread_starts: usize,
    /// N_md, modes in the SEREP basis. `None`: min(N_ex, max(2R, R + 4)).
    pub modes: Option<usize>,
    /// R, test resonances used for Eq. 42 (and frequency equations).
    /// `None`: min(resonances found, N_ex, 8).
    pub resonances: Option<usize>,
    /// cξ of Eq. 42: ω = (1 ± cξ) ω̄_r. Paper: 0.05–0.10.
    pub offset: f64,
    /// Explicit updating frequencies (Hz) instead of Eq. 42 (Table 3).
    #[serde(rename = "freqs")]
    pub frequencies_hz: Option<Vec<f64>>,
    /// Add the natural-frequency equations (Eq. 16–22).
    pub with_frequencies: bool,
    /// First bring the paired resonances within 1 % by the natural-frequency
    /// equations alone (steps limited to |p| ≤ 0.3), then update from FRFs.
    /// For initial models whose resonances are far from the test's.
    pub frequencies_first: bool,
    /// Row weighting of the FRF equations (see [`FrfWeighting`]).
    pub weighting: FrfWeighting,
    /// How Z̄ is inverted (§3.3); serialised as `inverse` and `perturbation`.
    #[serde(flatten, serialize_with = "inverse_fields")]
    pub inverse: InverseMethod,
    /// ε of the SVD gap rule σ_{r+1}/σ_r < ε (Eq. 40).
    pub svd_eps: f64,
    /// Tikhonov damping μ/σ₁ of each FRF-stage step (rows μ I added to
    /// Eq. 35; 0: the paper's undamped SVD solution). Bounds the step along
    /// directions the equations barely see, which noise and unmodelled
    /// physics otherwise blow up.
    pub damping: f64,
    /// ε of the stopping rule max_j |p_j| < ε (Eq. 49).
    pub tol: f64,
    /// Maximum number of updating steps.
    pub max_iter: usize,
    /// Modes whose measured partition adds less than this fraction of the
    /// largest measured-partition norm to the basis are left out (SEREP).
    pub basis_tolerance: f64,
    /// How the test's resonances (and their shapes, for pairing) are found.
    pub resonance_method: ResonanceMethod,
    /// Minimum peak-to-valley ratio for a measured resonance.
    pub min_prominence: f64,
    /// Minimum MAC for pairing a test resonance with an FE mode.
    pub mac_min: f64,
    /// |p̄| beyond this counts as a diverging (exploding) parameter.
    pub max_parameter: f64,
}

impl Default for UpdateOptions {
    /// The robust pipeline: the paper's iteration as a first stage with
    /// fitted resonances, the frequencies-first stage, ±5 % offsets and
    /// damped steps (μ = 0.05 σ₁, adapted), then the full-band estimate.
    fn default() -> Self {
        UpdateOptions {
            method: UpdateMethod::Robust,
            resonance_method: ResonanceMethod::ModalFit,
            frequencies_first: true,
            offset: 0.05,
            damping: 0.05,
            spread_starts: 8,
            ..UpdateOptions::paper()
        }
    }
}

impl UpdateOptions {
    /// The paper's method with the paper's values (§4: cξ = 0.08, gap rule
    /// ε = 1e-4, stop at max |p| < 0.01, undamped SVD steps, peak picking).
    pub fn paper() -> Self {
        UpdateOptions {
            method: UpdateMethod::Paper,
            estimate_iterations: 40,
            spread_starts: 0,
            modes: None,
            resonances: None,
            offset: 0.08,
            frequencies_hz: None,
            with_frequencies: false,
            frequencies_first: false,
            weighting: FrfWeighting::None,
            inverse: InverseMethod::Svd,
            svd_eps: 1e-4,
            damping: 0.0,
            tol: 0.01,
            max_iter: 20,
            basis_tolerance: 1e-3,
            resonance_method: ResonanceMethod::PeakPicking,
            min_prominence: 2.0,
            mac_min: 0.6,
            max_parameter: 10.0,
        }
    }

    /// The preset of `method`: [`UpdateOptions::default`] or [`UpdateOptions::paper`].
    pub fn preset(method: UpdateMethod) -> Self {
        match method {
            UpdateMethod::Robust => UpdateOptions::default(),
            UpdateMethod::Paper => UpdateOptions::paper(),
        }
    }
}

/// `inverse` ("svd" or "perturb") and `perturbation` (its relative δ, or null).
fn inverse_fields<S: Serializer>(inverse: &InverseMethod, s: S) -> Result<S::Ok, S::Error> {
    use serde::ser::SerializeMap;
    let (name, perturbation) = match *inverse {
        InverseMethod::Svd => (InverseChoice::Svd, None),
        InverseMethod::Perturb { relative } => (InverseChoice::Perturb, Some(relative)),
    };
    let mut map = s.serialize_map(Some(2))?;
    map.serialize_entry("inverse", &name)?;
    map.serialize_entry("perturbation", &perturbation)?;
    map.end()
}

/// How the test's resonances are found.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, Serialize, Deserialize)]
pub enum ResonanceMethod {
    /// Peak picking on the summed mobility (the paper's way): half-power
    /// damping, operating deflection shapes at the peak lines.
    #[value(name = "peaks")]
    #[serde(rename = "peaks")]
    PeakPicking,
    /// The test's modal identification (`crate::identification`, what
    /// `frfup identify` runs): poles common to all channels, weak modes
    /// found and close ones separated; shapes from the residues.
    #[value(name = "fit")]
    #[serde(rename = "fit")]
    ModalFit,
}

impl ResonanceMethod {
    pub fn name(self) -> &'static str {
        match self {
            ResonanceMethod::PeakPicking => "peaks",
            ResonanceMethod::ModalFit => "fit",
        }
    }
}

/// Row weighting of the stacked FRF equations (Eq. 11).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum FrfWeighting {
    /// As the paper writes Eq. 11: rows in m/N. The FRF magnitude falls like
    /// 1/ω², so the lowest updating frequencies dominate the least squares.
    None,
    /// Block i (A_i, b_i) divided by ‖h̄_i‖: every updating frequency counts
    /// alike. The exact (noise-free) solution is unchanged.
    PerFrequency,
}

impl FrfWeighting {
    pub fn name(self) -> &'static str {
        match self {
            FrfWeighting::None => "none",
            FrfWeighting::PerFrequency => "per-frequency",
        }
    }
}

/// How the reduced dynamic stiffness is inverted, as chosen by a user
/// ([`InverseMethod`] without its value).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum InverseChoice {
    /// Truncated SVD at rank N_md (§3.4).
    Svd,
    /// Small value added to the diagonal (§3.3).
    Perturb,
}

/// Explicit updating frequencies in Hz: finite, positive, each once.
/// Written `F1,F2,...` (command line, campaign) or as a list of numbers
/// (campaign).
#[derive(Clone, Debug, PartialEq)]
pub struct Frequencies(pub Vec<f64>);

impl Frequencies {
    /// `freqs` checked; `written` names them in the message if there are none.
    fn checked(freqs: Vec<f64>, written: &str) -> Result<Frequencies, String> {
        if freqs.is_empty() {
            return Err(format!("{written} holds no frequency"));
        }
        if let Some(f) = freqs.iter().find(|f| !(f.is_finite() && **f > 0.0)) {
            return Err(format!("{f} is not a positive frequency in Hz"));
        }
        // The same frequency twice adds the same equations twice: a typo, not a choice.
        for (i, f) in freqs.iter().enumerate() {
            if freqs[..i].contains(f) {
                return Err(format!("{f} Hz is given more than once"));
            }
        }
        Ok(Frequencies(freqs))
    }
}

impl FromStr for Frequencies {
    type Err = String;

    /// `F1,F2,...` in Hz.
    fn from_str(s: &str) -> Result<Self, String> {
        let freqs = s
            .split(',')
            .map(str::trim)
            .filter(|t| !t.is_empty())
            .map(|t| {
                t.parse::<f64>()
                    .ok()
                    .filter(|f| f.is_finite() && *f > 0.0)
                    .ok_or_else(|| format!("{t:?} is not a positive frequency in Hz"))
            })
            .collect::<Result<Vec<f64>, String>>()?;
        Frequencies::checked(freqs, &format!("{s:?}"))
    }
}

impl<'de> Deserialize<'de> for Frequencies {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl<'de> serde::de::Visitor<'de> for Visitor {
            type Value = Frequencies;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a list of frequencies in Hz or a string \"F1,F2,...\"")
            }
            fn visit_str<E: serde::de::Error>(self, s: &str) -> Result<Frequencies, E> {
                s.parse().map_err(E::custom)
            }
            fn visit_seq<A: serde::de::SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> Result<Frequencies, A::Error> {
                let mut freqs = Vec::new();
                while let Some(f) = seq.next_element::<f64>()? {
                    freqs.push(f);
                }
                Frequencies::checked(freqs, "the list").map_err(serde::de::Error::custom)
            }
        }
        d.deserialize_any(Visitor)
    }
}

/// A finite number (NaN or infinity as an option value is a typo): the
/// command line's parser of such values.
pub fn finite(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        Ok(_) => Err("expected a finite number".into()),
        Err(e) => Err(e.to_string()),
    }
}

/// [`finite`] for an optional key of a file.
pub fn finite_key<'de, D: Deserializer<'de>>(d: D) -> Result<Option<f64>, D::Error> {
    let x = f64::deserialize(d)?;
    if x.is_finite() {
        Ok(Some(x))
    } else {
        Err(serde::de::Error::custom(format!(
            "expected a finite number, found {x}"
        )))
    }
}

/// The options of an update as a user gives them: the flags of
/// `frfup update` and `frfup diagnose`, the keys of a campaign case. Unset
/// options take the values of the chosen `--method` (see
/// [`UpdateOptions::default`] and [`UpdateOptions::paper`]).
#[derive(clap::Args, Clone, Debug, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "kebab-case")]
pub struct UpdateSettings {
    /// Which pipeline runs: `robust` (update's default: resonances fitted,
    /// frequencies brought close first, damped steps, then a full-band
    /// estimate with an uncertainty per parameter) or `paper` (Yan &
    /// Golinval's iteration exactly, with the paper's values [Eq. 26-29, 49]).
    /// Any option below overrides the chosen method's value.
    #[arg(long, value_enum)]
    pub method: Option<UpdateMethod>,
    /// How many FE modes the reduced model is built from (N_md, the SEREP
    /// basis [Eq. 32-34]); more modes describe the FRFs between resonances
    /// better but need more measured DOFs (default: min(measured DOFs,
    /// max(2R, R + 4)), R = --resonances).
    #[arg(long)]
    pub modes: Option<usize>,
    /// How many of the test's resonances (R, lowest first) place updating
    /// frequencies and take part in the fit [Eq. 42] (default: those found,
    /// at most 8).
    #[arg(long)]
    pub resonances: Option<usize>,
    /// Where the FRFs are compared: two frequencies beside each resonance
    /// f_r, at (1 - C)·f_r and (1 + C)·f_r, so 0.08 compares them 8 % below
    /// and above each peak [Eq. 42]; too small sits on the peak where damping
    /// dominates, too large sees little of the mode (default: 0.05 robust,
    /// 0.08 paper).
    #[arg(long, allow_negative_numbers = true, value_parser = finite)]
    #[serde(default, deserialize_with = "finite_key")]
    pub offset: Option<f64>,
    /// Compare the FRFs at these frequencies (Hz, F1,F2,...) instead of
    /// beside each resonance [replaces Eq. 42; the paper's Table 3].
    #[arg(long, value_name = "F1,F2,...", allow_hyphen_values = true)]
    pub freqs: Option<Frequencies>,
    /// Also fit the natural frequencies of the paired modes, not only the
    /// FRFs [Eq. 16-22].
    #[arg(long, num_args = 0..=1, require_equals = true, default_missing_value = "true")]
    pub with_frequencies: Option<bool>,
    /// When the model's resonances are far from the test's: first move them
    /// within 1 % using the natural frequencies alone [Eq. 16-22], then
    /// update from the FRFs (default: on with robust, off with paper).
    #[arg(long, num_args = 0..=1, require_equals = true, default_missing_value = "true")]
    pub frequencies_first: Option<bool>,
    /// How the test's resonances and their shapes are found: `fit` (a pole
    /// fit common to all channels, finds weak and close modes) or `peaks`
    /// (peak picking, the paper's way) (default: fit robust, peaks paper).
    #[arg(long, value_enum)]
    pub resonance_method: Option<ResonanceMethod>,
    /// How the reduced model's dynamic stiffness is inverted when it is
    /// nearly singular: `svd` (truncated at N_md) or `perturb` (a small value
    /// added to its diagonal) [§3.3-3.4] (default: svd).
    #[arg(long, value_enum)]
    pub inverse: Option<InverseChoice>,
    /// With --inverse perturb: the value added to the diagonal, relative to
    /// its largest entry (default: 1e-8).
    #[arg(long, allow_negative_numbers = true, value_parser = finite)]
    #[serde(default, deserialize_with = "finite_key")]
    pub perturbation: Option<f64>,
    /// Which directions each step may move the parameters in: singular
    /// values are kept until one falls below E times the one before it, so
    /// a smaller E keeps more, less well determined, directions [Eq. 40]
    /// (default: 1e-4).
    #[arg(long, allow_negative_numbers = true, value_parser = finite)]
    #[serde(default, deserialize_with = "finite_key")]
    pub svd_eps: Option<f64>,
    /// Damps each step: 0 takes the full least-squares step [Eq. 35-41];
    /// larger values shorten the steps along directions the data barely
    /// see, which noise otherwise blows up (relative to the largest singular
    /// value; default: 0.05 robust, 0 paper).
    #[arg(long, allow_negative_numbers = true, value_parser = finite)]
    #[serde(default, deserialize_with = "finite_key")]
    pub damping: Option<f64>,
    /// Stop when no parameter changes by more than T (relative) in a step,
    /// so 0.01 stops below 1 % [Eq. 49] (default: 0.01).
    #[arg(long, allow_negative_numbers = true, value_parser = finite)]
    #[serde(default, deserialize_with = "finite_key")]
    pub tol: Option<f64>,
    /// At most this many updating steps (the paper's iteration, and the
    /// first stage of robust) (default: 20).
    #[arg(long)]
    pub max_iter: Option<usize>,
}

impl UpdateSettings {
    /// The options: the preset of the chosen method (of `default` when none
    /// is chosen) with every option given applied.
    pub fn resolve(&self, default: UpdateMethod) -> UpdateOptions {
        let preset = UpdateOptions::preset(self.method.unwrap_or(default));
        let inverse = match self.inverse {
            None => preset.inverse,
            Some(InverseChoice::Svd) => InverseMethod::Svd,
            Some(InverseChoice::Perturb) => InverseMethod::Perturb {
                relative: self.perturbation.unwrap_or(DEFAULT_PERTURBATION),
            },
        };
        UpdateOptions {
            modes: self.modes.or(preset.modes),
            resonances: self.resonances.or(preset.resonances),
            offset: self.offset.unwrap_or(preset.offset),
            frequencies_hz: match &self.freqs {
                Some(f) => Some(f.0.clone()),
                None => preset.frequencies_hz.clone(),
            },
            with_frequencies: self.with_frequencies.unwrap_or(preset.with_frequencies),
            frequencies_first: self.frequencies_first.unwrap_or(preset.frequencies_first),
            resonance_method: self.resonance_method.unwrap_or(preset.resonance_method),
            inverse,
            svd_eps: self.svd_eps.unwrap_or(preset.svd_eps),
            damping: self.damping.unwrap_or(preset.damping),
            tol: self.tol.unwrap_or(preset.tol),
            max_iter: self.max_iter.unwrap_or(preset.max_iter),
            ..preset
        }
    }

    /// The names of the options (`method`, `modes`, ..., `max-iter`): the
    /// command line's flags without `--`, a campaign case's keys.
    pub fn names() -> Vec<String> {
        long_names::<UpdateSettings>()
    }
}

/// The long flag names of the arguments `T` defines.
pub fn long_names<T: clap::Args>() -> Vec<String> {
    T::augment_args(clap::Command::new("names"))
        .get_arguments()
        .filter_map(|a| a.get_long().map(str::to_string))
        .collect()
}
