//! Campaign files of `frfup batch`: TOML with one `[[case]]` table per case.
//!
//! ```toml
//! fail_below_sfdac = 0.9          # optional campaign-wide thresholds
//! fail_above_freq_error = 2.0     # mean |Δf/f| in %
//!
//! [[case]]
//! name = "cantilever"
//! model = "beam.deck"             # paths relative to the campaign file
//! test = "beam-test.uff"
//! modes = 12                      # any `frfup update` option under its long name
//! offset = 0.08
//! freqs = [6.0, 24.0]             # or "6,24"
//! with-frequencies = true
//! fail_below_sfdac = 0.95         # per-case thresholds override the campaign's
//! ```

use std::path::{Path, PathBuf};

use crate::tasks::update::Thresholds;
use crate::updating::{InverseMethod, ResonanceMethod, UpdateOptions};

/// One case of a campaign.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    /// 0-based position in the campaign file.
    pub index: usize,
    pub name: String,
    pub model: PathBuf,
    pub test: PathBuf,
    pub options: UpdateOptions,
    pub thresholds: Thresholds,
}

/// A parsed campaign.
#[derive(Clone, Debug, PartialEq)]
pub struct Campaign {
    pub cases: Vec<Case>,
    pub thresholds: Thresholds,
}

/// Why a campaign file could not be read.
#[derive(Debug, Clone, PartialEq)]
pub struct CampaignError {
    pub message: String,
}

impl std::fmt::Display for CampaignError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for CampaignError {}

const THRESHOLD_KEYS: [&str; 2] = ["fail_below_sfdac", "fail_above_freq_error"];

/// Parse a campaign; `path` names the file in errors and anchors relative paths.
pub fn parse(text: &str, path: &Path) -> Result<Campaign, CampaignError> {
    let err = |m: String| CampaignError {
        message: format!("{}: {m}", path.display()),
    };
    let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
        let msg = e.to_string();
        let line = e
            .span()
            .map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
        match line {
            Some(l) => err(format!("line {l}: {}", msg.trim())),
            None => err(msg.trim().to_string()),
        }
    })?;
    let base = path.parent().unwrap_or(Path::new("."));
    for key in table.keys() {
        if key != "case" && !THRESHOLD_KEYS.contains(&key.as_str()) {
            return Err(err(format!(
                "unknown top-level key `{key}`: expected [[case]] tables and optional fail_below_sfdac, fail_above_freq_error"
            )));
        }
    }
    let thresholds = thresholds(&table, "campaign").map_err(err)?;
    let cases_value = table.get("case").ok_or_else(|| {
        err("no [[case]] table: a campaign lists its cases as [[case]] tables".into())
    })?;
    let cases_array = cases_value
        .as_array()
        .ok_or_else(|| err("`case` must be an array of tables ([[case]])".into()))?;
    let mut cases = Vec::with_capacity(cases_array.len());
    for (index, v) in cases_array.iter().enumerate() {
        let t = v
            .as_table()
            .ok_or_else(|| err(format!("case #{} is not a table", index + 1)))?;
        cases.push(case(index, t, base).map_err(err)?);
    }
    let mut names: Vec<&str> = cases.iter().map(|c| c.name.as_str()).collect();
    names.sort_unstable();
    if let Some(w) = names.windows(2).find(|w| w[0] == w[1]) {
        return Err(err(format!(
            "two cases are named {:?}: names give the output folders and must differ",
            w[0]
        )));
    }
    Ok(Campaign { cases, thresholds })
}

fn thresholds(t: &toml::Table, what: &str) -> Result<Thresholds, String> {
    Ok(Thresholds {
        min_sfdac: opt_f64(t, "fail_below_sfdac", what)?,
        max_freq_error_pct: opt_f64(t, "fail_above_freq_error", what)?,
    })
}

fn opt_f64(t: &toml::Table, key: &str, what: &str) -> Result<Option<f64>, String> {
    match t.get(key) {
        None => Ok(None),
        Some(toml::Value::Float(x)) if x.is_finite() => Ok(Some(*x)),
        Some(toml::Value::Integer(i)) => Ok(Some(*i as f64)),
        Some(v) => Err(format!("{what}: `{key}` must be a number, found {v}")),
    }
}

fn opt_usize(t: &toml::Table, key: &str, what: &str) -> Result<Option<usize>, String> {
    match t.get(key) {
        None => Ok(None),
        Some(toml::Value::Integer(i)) if *i >= 0 => Ok(Some(*i as usize)),
        Some(v) => Err(format!(
            "{what}: `{key}` must be a non-negative integer, found {v}"
        )),
    }
}

fn case(index: usize, t: &toml::Table, base: &Path) -> Result<Case, String> {
    let what = format!("case #{}", index + 1);
    let string = |key: &str| -> Result<String, String> {
        match t.get(key) {
            Some(toml::Value::String(s)) if !s.trim().is_empty() => Ok(s.clone()),
            Some(v) => Err(format!(
                "{what}: `{key}` must be a non-empty string, found {v}"
            )),
            None => Err(format!("{what}: missing `{key}`")),
        }
    };
    let name = string("name")?;
    if name.contains(['/', '\\']) || name == "." || name == ".." {
        return Err(format!(
            "{what}: name {name:?} must not contain path separators (it names the case's folder)"
        ));
    }
    let what = format!("case #{} ({name})", index + 1);
    let model = base.join(string("model")?);
    let test = base.join(string("test")?);
    const KNOWN: [&str; 21] = [
        "name",
        "model",
        "test",
        "modes",
        "resonances",
        "offset",
        "freqs",
        "with-frequencies",
        "frequencies-first",
        "inverse",
        "perturbation",
        "svd-eps",
        "damping",
        "resonance-method",
        "tol",
        "max-iter",
        "method",
        "fail_below_sfdac",
        "fail_above_freq_error",
        "fail-below-sfdac",
        "fail-above-freq-error",
    ];
    for key in t.keys() {
        if !KNOWN.contains(&key.as_str()) {
            return Err(format!(
                "{what}: unknown key `{key}`; expected name, model, test, an update option (method, modes, resonances, offset, freqs, with-frequencies, frequencies-first, resonance-method, inverse, perturbation, svd-eps, damping, tol, max-iter) or a threshold"
            ));
        }
    }
    let defaults = match t.get("method") {
        None => UpdateOptions::default(),
        Some(v) => match v.as_str() {
            Some("robust") => UpdateOptions::default(),
            Some("paper") => UpdateOptions::paper(),
            _ => {
                return Err(format!(
                    "{what}: `method` must be \"robust\" or \"paper\", found {v}"
                ))
            }
        },
    };
    let frequencies_hz = match t.get("freqs") {
        None => None,
        Some(toml::Value::Array(a)) => Some(
            a.iter()
                .map(|x| match x {
                    toml::Value::Float(f) => Ok(*f),
                    toml::Value::Integer(i) => Ok(*i as f64),
                    other => Err(format!("{what}: `freqs` must hold numbers, found {other}")),
                })
                .collect::<Result<Vec<f64>, String>>()?,
        ),
        Some(toml::Value::String(s)) => Some(parse_freqs(s).map_err(|e| format!("{what}: {e}"))?),
        Some(other) => {
            return Err(format!(
                "{what}: `freqs` must be a list of numbers, found {other}"
            ))
        }
    };
    let with_frequencies = match t.get("with-frequencies") {
        None => defaults.with_frequencies,
        Some(v) => v
            .as_bool()
            .ok_or_else(|| format!("{what}: `with-frequencies` must be true or false"))?,
    };
    let frequencies_first = match t.get("frequencies-first") {
        None => defaults.frequencies_first,
        Some(v) => v
            .as_bool()
            .ok_or_else(|| format!("{what}: `frequencies-first` must be true or false"))?,
    };
    let resonance_method = match t.get("resonance-method") {
        None => defaults.resonance_method,
        Some(v) => match v.as_str() {
            Some("peaks") => ResonanceMethod::PeakPicking,
            Some("fit") => ResonanceMethod::ModalFit,
            _ => {
                return Err(format!(
                    "{what}: `resonance-method` must be \"peaks\" or \"fit\", found {v}"
                ))
            }
        },
    };
    let perturbation = opt_f64(t, "perturbation", &what)?;
    let inverse = match t.get("inverse") {
        None => defaults.inverse,
        Some(v) => match v.as_str() {
            Some("svd") => InverseMethod::Svd,
            Some("perturb") => InverseMethod::Perturb {
                relative: perturbation.unwrap_or(crate::updating::DEFAULT_PERTURBATION),
            },
            _ => {
                return Err(format!(
                    "{what}: `inverse` must be \"svd\" or \"perturb\", found {v}"
                ))
            }
        },
    };
    let o = UpdateOptions {
        modes: opt_usize(t, "modes", &what)?,
        resonances: opt_usize(t, "resonances", &what)?,
        offset: opt_f64(t, "offset", &what)?.unwrap_or(defaults.offset),
        frequencies_hz,
        with_frequencies,
        frequencies_first,
        inverse,
        svd_eps: opt_f64(t, "svd-eps", &what)?.unwrap_or(defaults.svd_eps),
        damping: opt_f64(t, "damping", &what)?.unwrap_or(defaults.damping),
        resonance_method,
        tol: opt_f64(t, "tol", &what)?.unwrap_or(defaults.tol),
        max_iter: opt_usize(t, "max-iter", &what)?.unwrap_or(defaults.max_iter),
        ..defaults
    };
    let mut th = thresholds(t, &what)?;
    th.min_sfdac = th.min_sfdac.or(opt_f64(t, "fail-below-sfdac", &what)?);
    th.max_freq_error_pct = th
        .max_freq_error_pct
        .or(opt_f64(t, "fail-above-freq-error", &what)?);
    Ok(Case {
        index,
        name,
        model,
        test,
        options: o,
        thresholds: th,
    })
}

/// `F1,F2,...` in Hz.
pub fn parse_freqs(s: &str) -> Result<Vec<f64>, String> {
    let freqs = s
        .split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .map(|t| {
            t.parse::<f64>()
                .ok()
                .filter(|f| f.is_finite() && *f > 0.0)
                .ok_or_else(|| format!("freqs: {t:?} is not a positive frequency in Hz"))
        })
        .collect::<Result<Vec<f64>, String>>()?;
    if freqs.is_empty() {
        return Err(format!("freqs: {s:?} holds no frequency"));
    }
    // The same frequency twice adds the same equations twice: a typo, not a choice.
    for (i, f) in freqs.iter().enumerate() {
        if freqs[..i].contains(f) {
            return Err(format!("freqs: {f} Hz is given more than once"));
        }
    }
    Ok(freqs)
}

/// `I/N` (1-based I): this machine runs the cases whose 0-based index i has i mod N = I − 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    pub index: usize,
    pub count: usize,
}

impl Shard {
    pub fn parse(s: &str) -> Result<Shard, String> {
        let bad = || format!("--shard {s:?}: expected I/N with 1 <= I <= N, e.g. 2/4");
        let (i, n) = s.split_once('/').ok_or_else(bad)?;
        let index: usize = i.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// Whether the case at 0-based position `case_index` belongs to this shard.
    pub fn contains(&self, case_index: usize) -> bool {
        case_index % self.count == self.index - 1
    }
}
