//! `frfup diagnose MODEL.deck TEST.uff --out DIR`: which physics the model
//! lacks; `diagnosis.json`, `diagnosed.deck`, `report.md`, `report.html` and
//! its charts.

use std::path::PathBuf;

use crate::diagnosis::{self, DiagnoseOptions, Diagnosis};
use crate::report::diagnosis::{write_outputs, DiagnosisReport};
use crate::tasks::{
    check_model_for_modes, load_test_with_notes, name_mechanism_equations, read_deck, CommandError,
};

/// Options of `frfup diagnose`.
#[derive(Clone, Debug)]
pub struct DiagnoseCommand {
    pub deck: PathBuf,
    pub test: PathBuf,
    pub out: PathBuf,
    pub options: DiagnoseOptions,
    /// `--strict`: a warning about an input is an error.
    pub strict: bool,
}

/// Run a diagnosis and write its files into `out`; `stage` hears each
/// stage start (a few words, for a progress display).
pub fn run(cmd: &DiagnoseCommand, stage: &dyn Fn(&str)) -> Result<Diagnosis, CommandError> {
    stage("reading the inputs");
    crate::fsio::check_out_folder(&cmd.out).map_err(CommandError::input)?;
    let deck = read_deck(&cmd.deck)?;
    check_model_for_modes(&cmd.deck, &deck)?;
    let (test, notes) = load_test_with_notes(&cmd.test, cmd.strict)?;
    let notes: Vec<String> = notes
        .iter()
        .map(|n| format!("{}: {n}", cmd.test.display()))
        .collect();
    let d = diagnosis::diagnose_with_progress(&deck, &test, &cmd.options, stage).map_err(|e| {
        let e = name_mechanism_equations(&e.to_string(), &deck);
        CommandError::input(format!(
            "{} with {}: {e}",
            cmd.deck.display(),
            cmd.test.display()
        ))
    })?;
    stage("identifying the test's modes for the mode-shape viewer");
    let test_modes = crate::identification::identify_and_pair(&d.diagnosed_deck, &test);
    stage("writing the report");
    let (deck_name, test_name) = (
        cmd.deck.display().to_string(),
        cmd.test.display().to_string(),
    );
    let report = DiagnosisReport {
        diagnosis: &d,
        deck: &deck,
        test: &test,
        deck_name: &deck_name,
        test_name: &test_name,
        test_modes: &test_modes,
        notes: &notes,
    };
    crate::fsio::write_folder(&cmd.out, |dir| write_outputs(&report, dir))
        .map_err(|e| CommandError::output(&cmd.out, e))?;
    Ok(d)
}

/// The summary of `frfup diagnose --json`: `diagnosis.json`'s content (the
/// same value) with the verdict (`status`, `verdict`) and the output folder.
pub fn json(d: &Diagnosis, out: &std::path::Path) -> serde_json::Value {
    let verdict = diagnosis::verdict::Verdict::of(d);
    let mut v = crate::report::diagnosis::output::diagnosis_json(d);
    v["status"] = verdict.status().into();
    v["verdict"] = verdict.sentence().into();
    v["out"] = out.display().to_string().into();
    v
}

/// One line per finding, for the terminal.
pub fn summary(d: &Diagnosis) -> String {
    let verdict = diagnosis::verdict::Verdict::of(d);
    let mut s = format!("{}: {}\n", verdict.status(), verdict.sentence());
    for f in &d.findings {
        let vals: Vec<String> = f
            .parameters
            .iter()
            .map(|(k, v)| format!("{k}={}", diagnosis::sig(*v)))
            .collect();
        s.push_str(&format!(
            "{}: {} {}\n",
            f.physics.name(),
            f.label,
            vals.join(" ")
        ));
    }
    s.push_str(&format!(
        "FRF error (1 = noise): {:.2} initial, {:.2} updated, {:.2} diagnosed\n",
        d.initial.frf_error, d.updated.frf_error, d.diagnosed.frf_error
    ));
    s
}
