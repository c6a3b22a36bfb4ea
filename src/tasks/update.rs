//! An update as a task (`frfup update`, `frfup demo`, each case of `frfup
//! batch`): read the deck and the test data, update, write the tables, the
//! updated deck and the report into one folder; check the thresholds.

use std::path::{Path, PathBuf};

use super::{read_deck, CommandError};
use crate::updating::options::{finite, finite_key};
use crate::updating::{self, UpdateOptions, UpdateResult};

/// Pass/fail thresholds of an update: the flags of `frfup update` and
/// `frfup batch`, the keys of a campaign file and of its cases.
#[derive(clap::Args, Clone, Copy, Debug, Default, PartialEq, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Thresholds {
    /// Fail if the updated mean SFDAC is below X (update: exit code 1; batch:
    /// the case fails, whatever the campaign file says unless the case sets it).
    #[arg(long = "fail-below-sfdac", value_name = "X", allow_negative_numbers = true, value_parser = finite)]
    #[serde(rename = "fail-below-sfdac", default, deserialize_with = "finite_key")]
    pub min_sfdac: Option<f64>,
    /// Fail if the updated mean |df/f| (%) is above PCT (update: exit code 1;
    /// batch: the case fails, whatever the campaign file says unless the case
    /// sets it).
    #[arg(long = "fail-above-freq-error", value_name = "PCT", allow_negative_numbers = true, value_parser = finite)]
    #[serde(
        rename = "fail-above-freq-error",
        default,
        deserialize_with = "finite_key"
    )]
    pub max_freq_error_pct: Option<f64>,
}

impl Thresholds {
    /// `self` where set, else `fallback`.
    pub fn or(self, fallback: Thresholds) -> Thresholds {
        Thresholds {
            min_sfdac: self.min_sfdac.or(fallback.min_sfdac),
            max_freq_error_pct: self.max_freq_error_pct.or(fallback.max_freq_error_pct),
        }
    }
}

/// Options of `frfup update`.
#[derive(Clone, Debug)]
pub struct UpdateCommand {
    pub deck: PathBuf,
    pub test: PathBuf,
    pub out: PathBuf,
    pub options: UpdateOptions,
    /// `--strict`: a warning about an input is an error.
    pub strict: bool,
}

/// What an update produced, for summaries and thresholds.
#[derive(Clone, Debug)]
pub struct UpdateOutcome {
    pub result: UpdateResult,
    /// Mean |Δf/f| (%) over the paired test resonances, initial and updated model.
    pub freq_error_initial_pct: Option<f64>,
    pub freq_error_updated_pct: Option<f64>,
    pub files: Vec<PathBuf>,
    /// Wall time of each stage (name, seconds), for `--verbose`.
    pub timings: Vec<(&'static str, f64)>,
    /// What the readers noticed in the inputs ("FILE: note"), as in the reports.
    pub input_notes: Vec<String>,
}

/// Mean |f_FE − f_test| / f_test in % over the test resonances paired with an FE mode
/// in iteration `record`.
pub fn mean_frequency_error_pct(result: &UpdateResult, record: usize) -> Option<f64> {
    let rec = result.iterations.get(record)?;
    let mut sum = 0.0;
    let mut n = 0usize;
    for (res, pair) in result.resonances.iter().zip(&rec.pairs) {
        if let Some(p) = pair {
            sum += ((p.fe_hz - res.frequency_hz) / res.frequency_hz).abs();
            n += 1;
        }
    }
    (n > 0).then(|| 100.0 * sum / n as f64)
}

/// Run an update and write its files into `out`, as a whole
/// (`fsio::write_folder`): `out` is checked first, the files land together
/// or not at all.
pub fn run(
    cmd: &UpdateCommand,
    progress: &mut dyn FnMut(updating::UpdateProgress),
) -> Result<UpdateOutcome, CommandError> {
    crate::fsio::check_out_folder(&cmd.out).map_err(CommandError::input)?;
    let shown = Shown::of(cmd);
    let mut outcome =
        crate::fsio::write_folder(&cmd.out, |dir| run_into(cmd, dir, &shown, progress))?;
    outcome.files = list_files(&cmd.out);
    Ok(outcome)
}

/// How the inputs are named in messages and reports (the paths the user
/// knows, which may differ from where they are read, as in `demo`).
#[derive(Clone, Debug)]
pub struct Shown {
    pub deck: String,
    pub test: String,
}

impl Shown {
    /// The command's own paths.
    pub fn of(cmd: &UpdateCommand) -> Shown {
        Shown {
            deck: cmd.deck.display().to_string(),
            test: cmd.test.display().to_string(),
        }
    }
}

/// Run an update and write its files straight into `dir` (no check of
/// `cmd.out`, no whole-folder write: the caller's `fsio::write_folder` does
/// that). `outcome.files` is left empty.
pub fn run_into(
    cmd: &UpdateCommand,
    dir: &Path,
    shown: &Shown,
    progress: &mut dyn FnMut(updating::UpdateProgress),
) -> Result<UpdateOutcome, CommandError> {
    let mut timings = Vec::new();
    let mut clock = std::time::Instant::now();
    let mut lap = |name: &'static str, timings: &mut Vec<(&'static str, f64)>| {
        timings.push((name, clock.elapsed().as_secs_f64()));
        clock = std::time::Instant::now();
    };
    let deck = read_deck(&cmd.deck)?;
    super::check_model_for_modes(&cmd.deck, &deck)?;
    lap("read deck", &mut timings);
    let (test, notes) = super::load_test_with_notes(&cmd.test, cmd.strict)?;
    lap("read test data", &mut timings);
    let result =
        updating::update_with_progress(&deck, &test, &cmd.options, progress).map_err(|e| {
            let e = super::name_mechanism_equations(&e.to_string(), &deck);
            CommandError::input(format!("{} with {}: {e}", shown.deck, shown.test))
        })?;
    lap("update", &mut timings);
    let notes: Vec<String> = notes
        .iter()
        .map(|n| format!("{}: {n}", shown.test))
        .collect();
    crate::report::output::write_outputs_with_notes(&result, &deck, dir, &notes)
        .map_err(|e| CommandError::output(&cmd.out, e))?;
    lap("write tables and updated deck", &mut timings);
    let states = crate::updating::model_states::model_states(&result, &deck, &test);
    lap("evaluate the initial and updated models", &mut timings);
    let inputs = crate::report::ReportInputs {
        deck_path: shown.deck.clone(),
        test_path: shown.test.clone(),
        title: None,
        command: None,
        input_notes: notes.clone(),
    };
    crate::report::write_report(dir, &result, &states, &deck, &test, &inputs).map_err(|e| {
        CommandError::input(format!(
            "writing the report into {}: {e}",
            cmd.out.display()
        ))
    })?;
    lap("write charts and report", &mut timings);
    Ok(UpdateOutcome {
        freq_error_initial_pct: mean_frequency_error_pct(&result, 0),
        freq_error_updated_pct: mean_frequency_error_pct(&result, result.final_iteration),
        result,
        files: Vec::new(),
        timings,
        input_notes: notes,
    })
}

fn list_files(dir: &Path) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.filter_map(|e| e.ok())
                .map(|e| e.path())
                .filter(|p| p.is_file())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// The thresholds an update fails, in words (empty: all passed).
pub fn threshold_failures(outcome: &UpdateOutcome, t: Thresholds) -> Vec<String> {
    let last = outcome.result.final_record();
    let mut reasons = Vec::new();
    if let Some(min) = t.min_sfdac {
        if !(last.sfdac.mean >= min) {
            reasons.push(format!("mean SFDAC {:.4} < {min}", last.sfdac.mean));
        }
    }
    if let Some(max) = t.max_freq_error_pct {
        match outcome.freq_error_updated_pct {
            Some(e) if e <= max => {}
            Some(e) => reasons.push(format!("mean |df/f| {e:.3} % > {max} %")),
            None => reasons
                .push("no test resonance paired with an FE mode: frequency error unknown".into()),
        }
    }
    reasons
}
