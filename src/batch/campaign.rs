//! Campaign files of `frfup batch`: TOML with one `[[case]]` table per case
//! (the format is described in `docs/campaign.md`).
//!
//! ```toml
//! fail-below-sfdac = 0.9          # optional campaign-wide thresholds
//! fail-above-freq-error = 2.0     # mean |Δf/f| in %
//!
//! [[case]]
//! name = "cantilever"
//! model = "beam.deck"             # paths relative to the campaign file
//! test = "beam-test.uff"
//! modes = 12                      # any `frfup update` option under its long name
//! offset = 0.08
//! freqs = [6.0, 24.0]             # or "6,24"
//! with-frequencies = true
//! fail-below-sfdac = 0.95         # per-case thresholds override the campaign's
//! ```
//!
//! Keys are the command line's flags without `--`: the options of a case
//! are [`UpdateSettings`] and the thresholds [`Thresholds`], read by their
//! serde derives. `_` may stand for `-` in a key (`fail_below_sfdac`, as
//! campaign files were first written).

use std::path::{Path, PathBuf};

use serde::de::DeserializeOwned;

use crate::tasks::update::Thresholds;
use crate::updating::options::long_names;
use crate::updating::{UpdateMethod, UpdateOptions, UpdateSettings};

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
    let mut table = kebab_keys(table, "campaign").map_err(err)?;
    let threshold_keys = long_names::<Thresholds>();
    if let Some(key) = table
        .keys()
        .find(|k| *k != "case" && !threshold_keys.contains(k))
    {
        return Err(err(format!(
            "unknown top-level key `{key}`: expected [[case]] tables and optional {}",
            threshold_keys.join(", ")
        )));
    }
    let cases_value = table.remove("case").ok_or_else(|| {
        err("no [[case]] table: a campaign lists its cases as [[case]] tables".into())
    })?;
    let thresholds: Thresholds = from_table(table, "campaign").map_err(err)?;
    let toml::Value::Array(cases_array) = cases_value else {
        return Err(err("`case` must be an array of tables ([[case]])".into()));
    };
    let mut cases = Vec::with_capacity(cases_array.len());
    for (index, v) in cases_array.into_iter().enumerate() {
        let toml::Value::Table(t) = v else {
            return Err(err(format!("case #{} is not a table", index + 1)));
        };
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

/// `t` with `_` in its keys read as `-` (one spelling of each key).
fn kebab_keys(t: toml::Table, what: &str) -> Result<toml::Table, String> {
    let mut out = toml::Table::new();
    for (key, value) in t {
        let kebab = key.replace('_', "-");
        if out.contains_key(&kebab) {
            return Err(format!(
                "{what}: `{kebab}` is given twice (`_` and `-` spell the same key)"
            ));
        }
        out.insert(kebab, value);
    }
    Ok(out)
}

/// `t` read as `T` (its serde derive); errors name `what` and the key.
fn from_table<T: DeserializeOwned>(t: toml::Table, what: &str) -> Result<T, String> {
    toml::Value::Table(t)
        .try_into()
        .map_err(|e: toml::de::Error| {
            let e = e.to_string();
            format!("{what}: {}", e.trim().replace('\n', " "))
        })
}

/// Remove the string `key` of `t`: present and not blank.
fn take_string(t: &mut toml::Table, key: &str, what: &str) -> Result<String, String> {
    match t.remove(key) {
        Some(toml::Value::String(s)) if !s.trim().is_empty() => Ok(s),
        Some(v) => Err(format!(
            "{what}: `{key}` must be a non-empty string, found {v}"
        )),
        None => Err(format!("{what}: missing `{key}`")),
    }
}

fn case(index: usize, t: toml::Table, base: &Path) -> Result<Case, String> {
    let mut what = format!("case #{}", index + 1);
    if let Some(toml::Value::String(name)) = t.get("name") {
        what = format!("{what} ({name})");
    }
    let mut t = kebab_keys(t, &what)?;
    let name = take_string(&mut t, "name", &what)?;
    if name.contains(['/', '\\']) || name == "." || name == ".." {
        return Err(format!(
            "{what}: name {name:?} must not contain path separators (it names the case's folder)"
        ));
    }
    let model = base.join(take_string(&mut t, "model", &what)?);
    let test = base.join(take_string(&mut t, "test", &what)?);
    let (option_keys, threshold_keys) = (UpdateSettings::names(), long_names::<Thresholds>());
    if let Some(key) = t
        .keys()
        .find(|k| !option_keys.contains(k) && !threshold_keys.contains(k))
    {
        return Err(format!(
            "{what}: unknown key `{key}`; expected name, model, test, an update option ({}) or a threshold ({})",
            option_keys.join(", "),
            threshold_keys.join(", ")
        ));
    }
    let (thresholds, options): (toml::Table, toml::Table) =
        t.into_iter().partition(|(k, _)| threshold_keys.contains(k));
    let settings: UpdateSettings = from_table(options, &what)?;
    Ok(Case {
        index,
        name,
        model,
        test,
        options: settings.resolve(UpdateMethod::Robust),
        thresholds: from_table(thresholds, &what)?,
    })
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
