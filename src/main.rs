//! The `frfup` command line: parses flags, calls the library, and turns
//! errors into messages and exit codes (0 fine, 1 a threshold failed, 2 bad
//! input or usage).

#![forbid(unsafe_code)]

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use frfup::commands::progress::{Progress, StageReporter, StepReporter};
use frfup::commands::{self, convert};
use frfup::tasks::update::Thresholds;
use frfup::tasks::{update, CommandError};
use frfup::testdata::FrfKind;
use frfup::updating::options::finite;
use frfup::updating::{IterationStage, UpdateMethod, UpdateProgress, UpdateSettings};
use std::sync::Mutex;

#[derive(Parser)]
#[command(
    name = "frfup",
    version,
    about = "Make a finite-element model agree with a vibration test (FRF-based model updating)"
)]
struct Cli {
    /// No progress bars or summaries on stderr.
    #[arg(long, global = true)]
    quiet: bool,
    /// Per-stage timings on stderr.
    #[arg(long, global = true)]
    verbose: bool,
    /// Any warning (data skipped or doubtful in an input) is an error: exit 2.
    #[arg(long, global = true)]
    strict: bool,
    /// Show progress even off a terminal or in CI (one line per step on
    /// stderr); without it, bars appear on a terminal only.
    #[arg(long, global = true, conflicts_with = "quiet")]
    progress: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the built-in GARTEUR-like case end to end (read, update, report).
    Demo(DemoArgs),
    /// List the datasets of a UFF file, one line each.
    Info(InfoArgs),
    /// Convert UFF 58 records: to CSV or UFF, between FRF kinds, to the paper's signed real FRF.
    Convert(ConvertArgs),
    /// Natural frequencies and generalised masses of a deck's lowest modes.
    Modes(ModesArgs),
    /// Write a measured-style campaign (dataset 58 FRFs) computed from a deck.
    Simulate(SimulateArgs),
    /// Update the deck's parameters from measured FRFs (the paper's method).
    Update(UpdateArgs),
    /// Which physics the model lacks: update, localise, test hypotheses (diagnosis.json, diagnosed.deck, report.md).
    Diagnose(DiagnoseArgs),
    /// The test's modes by experimental modal analysis (PolyMAX poles, LSFD shapes): modes.csv, modes.uff, report.html.
    Identify(IdentifyArgs),
    /// Run a campaign of updates (CAMPAIGN.toml with [[case]] tables) for CI.
    Batch(BatchArgs),
}

/// The global flags as every command reads them.
struct Global {
    quiet: bool,
    verbose: bool,
    /// `--strict`: any warning about an input is an error.
    strict: bool,
    progress: Progress,
}

// `frfup demo`.
#[derive(clap::Args)]
struct DemoArgs {
    /// Output folder: input/garteur.deck and input/campaign.uff (the case),
    /// then the files of `update`: report.html, report.md, report.json,
    /// estimates.csv, parameters.csv, iterations.csv, frequencies.csv,
    /// resonances.csv, updating-frequencies.csv, sfdac.csv, mac.csv, frf.csv,
    /// shapes.csv and modes.uff (test and FE mode shapes at the measured
    /// DOFs, UFF 15/82/55), updated.deck, convergence.svg, frequencies.svg,
    /// sfdac.svg, mac.svg, mode-shapes.svg (the paired shapes as stills),
    /// frf-overlay.svg and frf/NN-CHANNEL.svg (one chart per channel).
    #[arg(long, default_value = "frfup-demo")]
    out: PathBuf,
}

// `frfup info`.
#[derive(clap::Args)]
struct InfoArgs {
    /// UFF files (dataset 58 FRFs and any other dataset), listed in order.
    #[arg(required = true, num_args = 1..)]
    files: Vec<PathBuf>,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
}

// `frfup convert`.
#[derive(clap::Args)]
struct ConvertArgs {
    /// UFF files to read (dataset 58 records), in order; their records go into one output.
    #[arg(required = true, num_args = 1..)]
    inputs: Vec<PathBuf>,
    /// Output file: .csv, .uff or .unv, or - for CSV on stdout. With several
    /// inputs each CSV column starts with its file's name (FILE:resp/ref).
    output: PathBuf,
    /// Convert FRFs to this kind.
    #[arg(long, value_enum)]
    to: Option<ToKind>,
    /// Records to keep in each input: 1-based positions/ranges (1-4,7) or response DOFs (112:3, 112:+z).
    #[arg(long)]
    channels: Option<String>,
    /// Write 58b binary records (UFF output only).
    #[arg(long)]
    binary: bool,
}

// `frfup modes`.
#[derive(clap::Args)]
struct ModesArgs {
    /// The model: a deck file (docs/deck.md).
    deck: PathBuf,
    /// How many of the lowest modes.
    #[arg(long, default_value_t = 20, value_parser = at_least_one)]
    count: usize,
    /// Also write the table to this CSV file (mode,frequency_hz,generalised_mass_kg).
    #[arg(long)]
    csv: Option<PathBuf>,
    /// Also write the mode shapes to this CSV file: one row per node and
    /// direction (x, y, z), one column per mode (mass-normalised).
    #[arg(long, value_name = "FILE")]
    shapes: Option<PathBuf>,
    /// Also write the modes for a modal viewer to this UFF file: the deck's
    /// nodes (dataset 15), its beams as a trace line (82), and one normal
    /// mode per dataset 55 (three translations per node).
    #[arg(long, value_name = "FILE")]
    uff: Option<PathBuf>,
    /// Parameter values NAME=P (relative change: value = (1 + P) x deck value).
    #[arg(long = "set", value_name = "NAME=VALUE")]
    set: Vec<String>,
    /// Print the table as JSON on stdout (keys as the CSV's columns).
    #[arg(long)]
    json: bool,
}

// `frfup simulate`.
#[derive(clap::Args)]
struct SimulateArgs {
    /// The model whose FRFs are computed: a deck file (docs/deck.md).
    deck: PathBuf,
    /// Excitation DOF NODE:DIR (DIR a UFF code such as 3 or -3, or a name such as +z).
    /// Required unless --response is given.
    #[arg(long, allow_hyphen_values = true)]
    input: Option<String>,
    /// Roving hammer: the fixed sensor NODE:DIR; the hammer hits each --sensors
    /// point, so record i has this response and reference = hit point i (one
    /// row of the FRF matrix, by reciprocity).
    #[arg(long, allow_hyphen_values = true)]
    response: Option<String>,
    /// Frequency lines F0:F1:N (Hz).
    #[arg(long, allow_hyphen_values = true)]
    band: String,
    /// The UFF file written (dataset 58 records, one per sensor).
    #[arg(long)]
    out: PathBuf,
    /// Which FRF is written: displacement (receptance), velocity (mobility)
    /// or acceleration (accelerance) per unit force.
    #[arg(long, value_enum, default_value = "accelerance")]
    kind: KindArg,
    /// Sensors: all (every free translational DOF) or NODE:DIR,NODE:DIR,...
    #[arg(long, default_value = "all", allow_hyphen_values = true)]
    sensors: String,
    /// Complex Gaussian noise, as a fraction of each channel's RMS.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true, value_parser = finite)]
    noise: f64,
    /// Seed of the noise generator.
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Parameter values NAME=P (relative change), e.g. a known defect.
    #[arg(long = "set", value_name = "NAME=VALUE")]
    set: Vec<String>,
    /// Write 58b binary records.
    #[arg(long)]
    binary: bool,
    /// Complex single precision (ordinate type 5) instead of double (6).
    #[arg(long)]
    single: bool,
}

// `frfup update`.
#[derive(clap::Args)]
struct UpdateArgs {
    /// The model: a deck file whose `param` lines are updated (docs/deck.md).
    deck: PathBuf,
    /// The measured FRFs: a UFF file of dataset 58/58b records.
    test: PathBuf,
    /// Output folder (created; replaced as a whole): report.html, report.md,
    /// report.json, estimates.csv (robust only), parameters.csv,
    /// iterations.csv, frequencies.csv, resonances.csv,
    /// updating-frequencies.csv, sfdac.csv, mac.csv, frf.csv, shapes.csv and
    /// modes.uff (test and FE mode shapes at the measured DOFs, UFF
    /// 15/82/55), updated.deck, convergence.svg, frequencies.svg, sfdac.svg,
    /// mac.svg, mode-shapes.svg (the paired shapes as stills), frf-overlay.svg
    /// and frf/NN-CHANNEL.svg (one chart per channel).
    #[arg(long)]
    out: PathBuf,
    /// Print a JSON summary on stdout (the main keys of report.json) instead of text.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    settings: UpdateSettings,
    #[command(flatten)]
    thresholds: Thresholds,
}

// `frfup diagnose`.
#[derive(clap::Args)]
struct DiagnoseArgs {
    /// The model: a deck file (docs/deck.md).
    deck: PathBuf,
    /// The measured FRFs: a UFF file of dataset 58/58b records.
    test: PathBuf,
    /// Output folder (created; replaced as a whole): diagnosis.json,
    /// diagnosed.deck, report.md, report.html, localisation.svg,
    /// mode-shapes.svg (the paired shapes as stills, when modes pair),
    /// frf-overlay.svg and frf/NN-CHANNEL.svg (one chart per channel).
    #[arg(long)]
    out: PathBuf,
    /// Take the deck's parameters as they are (no update first).
    #[arg(long)]
    no_update: bool,
    /// At most this many extensions.
    #[arg(long, default_value_t = 4)]
    max_findings: usize,
    /// Exit 1 if the diagnosed model's FRF error is above X times the noise
    /// level (1 = the model explains the test to the noise), for CI.
    #[arg(long, value_name = "X", value_parser = finite)]
    fail_above_error: Option<f64>,
    /// Print a JSON summary on stdout (diagnosis.json with the verdict) instead of text.
    #[arg(long)]
    json: bool,
    /// Options of the first step, the update of the deck's own parameters
    /// (`frfup update`'s defaults unless given).
    #[command(flatten)]
    settings: UpdateSettings,
}

// `frfup identify`.
#[derive(clap::Args)]
struct IdentifyArgs {
    test: PathBuf,
    /// Output folder.
    #[arg(long)]
    out: PathBuf,
    /// Frequency band F0:F1 (Hz); default: every line.
    #[arg(long, value_name = "F0:F1")]
    band: Option<String>,
    /// Highest model order of the stabilisation diagram (default: from the peaks).
    #[arg(long)]
    max_order: Option<usize>,
    /// Pair the test modes with this deck's modes (MAC and frequency).
    #[arg(long)]
    deck: Option<PathBuf>,
}

// `frfup batch`.
#[derive(clap::Args)]
struct BatchArgs {
    /// The campaign: a TOML file of [[case]] tables (model, test and update
    /// options per case; docs/campaign.md).
    campaign: PathBuf,
    /// Output folder: summary.html, summary.md, summary.csv, summary.json and one folder
    /// per case holding the files of `update` (see `frfup update --help`).
    #[arg(long)]
    out: PathBuf,
    /// Cases run at once.
    #[arg(long, default_value_t = 1, value_parser = at_least_one)]
    jobs: usize,
    /// Run only shard I of N (I/N, 1-based): cases i with i mod N = I - 1.
    #[arg(long, value_name = "I/N")]
    shard: Option<String>,
    /// Print summary.json on stdout instead of the totals line.
    #[arg(long)]
    json: bool,
    #[command(flatten)]
    thresholds: Thresholds,
}

/// A count of at least 1.
fn at_least_one(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(0) => Err("expected at least 1".into()),
        Ok(n) => Ok(n),
        Err(e) => Err(e.to_string()),
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum KindArg {
    Receptance,
    Mobility,
    Accelerance,
}

impl KindArg {
    fn kind(self) -> FrfKind {
        match self {
            KindArg::Receptance => FrfKind::Receptance,
            KindArg::Mobility => FrfKind::Mobility,
            KindArg::Accelerance => FrfKind::Accelerance,
        }
    }
}

#[derive(Clone, Copy, ValueEnum)]
enum ToKind {
    Receptance,
    Mobility,
    Accelerance,
    /// Signed real displacement FRF, the paper's Eq. 50.
    DisplacementReal,
}

impl ToKind {
    fn target(self) -> convert::Target {
        match self {
            ToKind::Receptance => convert::Target::Kind(FrfKind::Receptance),
            ToKind::Mobility => convert::Target::Kind(FrfKind::Mobility),
            ToKind::Accelerance => convert::Target::Kind(FrfKind::Accelerance),
            ToKind::DisplacementReal => convert::Target::DisplacementReal,
        }
    }
}

fn run(cli: Cli) -> Result<(), CommandError> {
    let g = Global {
        quiet: cli.quiet,
        verbose: cli.verbose,
        strict: cli.strict,
        progress: Progress::with_flags(cli.quiet, cli.progress),
    };
    match cli.command {
        Command::Demo(a) => demo(a, &g),
        Command::Info(a) => {
            print!("{}", commands::info::run(&a.files, a.json, g.progress)?);
            Ok(())
        }
        Command::Convert(a) => convert(a, &g),
        Command::Modes(a) => modes(a, &g),
        Command::Simulate(a) => simulate(a, &g),
        Command::Update(a) => update(a, &g),
        Command::Diagnose(a) => diagnose(a, &g),
        Command::Identify(a) => identify(a, &g),
        Command::Batch(a) => batch(a, &g),
    }
}

fn demo(a: DemoArgs, g: &Global) -> Result<(), CommandError> {
    frfup::fsio::check_out_folder(&a.out).map_err(CommandError::input)?;
    let start = std::time::Instant::now();
    let reporter = StepReporter::new(g.progress, 21, "iteration");
    let result = commands::demo::run(&a.out, &mut |event| show_update_progress(&reporter, event));
    reporter.finish();
    let (outcome, report) = result?;
    print_timings(g.verbose, &outcome.timings);
    print_update_summary(&outcome);
    println!(
        "done in {:.1} s. Open {} (and report.html, the .svg charts, updated.deck in {})",
        start.elapsed().as_secs_f64(),
        report.display(),
        a.out.display()
    );
    Ok(())
}

fn convert(a: ConvertArgs, g: &Global) -> Result<(), CommandError> {
    let summary = convert::run(&convert::ConvertOptions {
        inputs: a.inputs,
        output: a.output.clone(),
        to: a.to.map(ToKind::target),
        channels: a.channels,
        binary: a.binary,
        progress: g.progress,
        strict: g.strict,
    })?;
    if !g.quiet {
        for note in &summary.notes {
            eprintln!("note: {note}");
        }
        eprintln!(
            "wrote {} record(s) of {} line(s) to {}",
            summary.records,
            summary.lines,
            if convert::is_stdout(&a.output) {
                "stdout".to_string()
            } else {
                a.output.display().to_string()
            }
        );
    }
    Ok(())
}

fn modes(a: ModesArgs, g: &Global) -> Result<(), CommandError> {
    let values = commands::modes::parse_settings(&a.set)?;
    let opts = commands::modes::ModesOptions {
        deck: a.deck.clone(),
        count: a.count,
        csv: a.csv,
        shapes: a.shapes,
        uff: a.uff,
        values,
    };
    let rows = with_stages(g, |stage| commands::modes::run(&opts, stage))?;
    if a.json {
        print_json(&commands::modes::json(&a.deck, &rows));
    } else {
        print!("{}", commands::modes::table(&rows));
    }
    Ok(())
}

fn simulate(a: SimulateArgs, g: &Global) -> Result<(), CommandError> {
    use commands::simulate as sim;
    let response = a
        .response
        .map(|r| sim::parse_node_direction(&r, "--response"))
        .transpose()?;
    let input = match (a.input, response) {
        (Some(i), _) => sim::parse_node_direction(&i, "--input")?,
        (None, Some(r)) => r,
        (None, None) => {
            return Err(CommandError::input(
                "simulate needs --input NODE:DIR (fixed exciter) or --response NODE:DIR (roving hammer)",
            ))
        }
    };
    let campaign = frfup::simulate::Campaign {
        input,
        band: sim::parse_band(&a.band)?,
        lines_hz: None,
        response,
        output: a.kind.kind(),
        sensors: sim::parse_sensors(&a.sensors)?,
        noise: a.noise,
        seed: a.seed,
    };
    let opts = sim::SimulateOptions {
        deck: a.deck,
        out: a.out.clone(),
        campaign,
        values: commands::modes::parse_settings(&a.set)?,
        binary: a.binary,
        single: a.single,
    };
    let n = with_stages(g, |stage| sim::run(&opts, stage))?;
    if !g.quiet {
        eprintln!("wrote {n} FRF record(s) to {}", a.out.display());
    }
    Ok(())
}

fn update(a: UpdateArgs, g: &Global) -> Result<(), CommandError> {
    let cmd = update::UpdateCommand {
        deck: a.deck,
        test: a.test,
        out: a.out.clone(),
        options: a.settings.resolve(UpdateMethod::Robust),
        strict: g.strict,
    };
    let reporter = StepReporter::new(g.progress, cmd.options.max_iter as u64 + 1, "iteration");
    let result = update::run(&cmd, &mut |event| show_update_progress(&reporter, event));
    reporter.finish();
    let outcome = result?;
    print_timings(g.verbose, &outcome.timings);
    if a.json {
        let mut v = frfup::report::output::summary_json(&outcome.result);
        v["out"] = a.out.display().to_string().into();
        v["threshold_failures"] = update::threshold_failures(&outcome, a.thresholds).into();
        print_json(&v);
        print_warnings(&outcome);
    } else {
        print_update_summary(&outcome);
        println!("wrote {}", a.out.display());
    }
    if !outcome.result.converged {
        return Err(CommandError::threshold(format!(
            "not converged: {}",
            frfup::report::status::not_converged_reason(&outcome.result)
        )));
    }
    check_thresholds(&outcome, a.thresholds)
}

/// Run `work` with a display of its stages (a spinner on a terminal, lines
/// with `--progress` off one), cleared before its result is returned.
fn with_stages<T>(
    g: &Global,
    work: impl FnOnce(&dyn Fn(&str)) -> Result<T, CommandError>,
) -> Result<T, CommandError> {
    let reporter = StageReporter::new(g.progress);
    let out = work(&|s| reporter.stage(s));
    reporter.finish();
    out
}

/// An update's progress on the bar: a step per scored iteration, and the
/// name of the full-band estimate while it runs (it scores nothing until it
/// ends).
fn show_update_progress(reporter: &StepReporter, event: UpdateProgress) {
    match event {
        UpdateProgress::Iteration(rec) => reporter.step(&iteration_line(rec)),
        UpdateProgress::EstimateStarted => {
            reporter.note("full-band estimate: all lines and channels, damping identified along")
        }
    }
}

/// A `--json` summary on stdout, pretty-printed, one value.
fn print_json(v: &serde_json::Value) {
    println!("{}", serde_json::to_string_pretty(v).unwrap_or_default());
}

fn diagnose(a: DiagnoseArgs, g: &Global) -> Result<(), CommandError> {
    let cmd = commands::diagnose::DiagnoseCommand {
        deck: a.deck,
        test: a.test,
        out: a.out.clone(),
        options: frfup::diagnosis::DiagnoseOptions {
            update: a.settings.resolve(UpdateMethod::Robust),
            skip_update: a.no_update,
            max_findings: a.max_findings,
            ..Default::default()
        },
        strict: g.strict,
    };
    let d = with_stages(g, |stage| commands::diagnose::run(&cmd, stage))?;
    if g.verbose {
        for (stage, secs, units) in &d.timings {
            eprintln!("time: {stage:<32} {secs:>8.3} s  ({units} model-solution units)");
        }
        eprintln!(
            "time: {} model solutions asked for again were kept from before",
            d.model_solutions_kept
        );
    }
    if a.json {
        print_json(&commands::diagnose::json(&d, &a.out));
    } else {
        print!("{}", commands::diagnose::summary(&d));
        println!("wrote {}", a.out.display());
    }
    let verdict = frfup::diagnosis::verdict::Verdict::of(&d);
    if !verdict.is_conclusive() {
        return Err(CommandError::threshold(verdict.status()));
    }
    match a.fail_above_error {
        Some(x) if d.diagnosed.frf_error.is_nan() || d.diagnosed.frf_error > x => {
            Err(CommandError::threshold(format!(
                "FRF error {:.2} x the noise level > {x}",
                d.diagnosed.frf_error
            )))
        }
        _ => Ok(()),
    }
}

fn identify(a: IdentifyArgs, g: &Global) -> Result<(), CommandError> {
    let band_hz = a
        .band
        .as_deref()
        .map(commands::identify::parse_band)
        .transpose()?;
    let cmd = commands::identify::IdentifyCommand {
        test: a.test,
        out: a.out.clone(),
        band_hz,
        max_order: a.max_order,
        deck: a.deck,
        strict: g.strict,
    };
    let id = with_stages(g, |stage| commands::identify::run(&cmd, stage))?;
    print_timings(g.verbose, &id.timings);
    if !g.quiet {
        print!("{}", commands::identify::summary(&id));
        println!("wrote {}", a.out.display());
    }
    Ok(())
}

fn batch(a: BatchArgs, g: &Global) -> Result<(), CommandError> {
    frfup::fsio::check_out_folder(&a.out).map_err(CommandError::input)?;
    let shard = a
        .shard
        .map(|s| frfup::batch::Shard::parse(&s))
        .transpose()
        .map_err(CommandError::input)?;
    let reporter = Mutex::new(None::<StepReporter>);
    let result = frfup::batch::run(
        &frfup::batch::BatchOptions {
            campaign: a.campaign,
            out: a.out.clone(),
            jobs: a.jobs,
            shard,
            thresholds: a.thresholds,
            strict: g.strict,
        },
        &|c, n, total| {
            let line = format!("[{n}/{total}] {}", case_line(c));
            if let Ok(mut r) = reporter.lock() {
                r.get_or_insert_with(|| StepReporter::new(g.progress, total as u64, "case"))
                    .step(&line);
            }
        },
    );
    if let Ok(r) = reporter.lock() {
        if let Some(r) = r.as_ref() {
            r.finish();
        }
    }
    let summary = result?;
    if a.json {
        print_json(&frfup::batch::summary_json(&summary));
    } else {
        println!(
            "{}; summary in {}",
            summary.totals(),
            a.out.join("summary.md").display()
        );
    }
    match summary.exit_code() {
        0 => Ok(()),
        1 => {
            let nc = summary.count("not-converged");
            Err(CommandError::threshold(if nc > 0 {
                format!("{nc} case(s) did not converge or a threshold failed (see the summary)")
            } else {
                "a threshold failed (see the summary)".to_string()
            }))
        }
        _ => Err(CommandError::input(
            "a case could not run (see the summary)",
        )),
    }
}

/// One line of a finished batch case: name, status, time and why.
fn case_line(c: &frfup::batch::CaseSummary) -> String {
    use frfup::batch::CaseStatus;
    let why = match &c.status {
        CaseStatus::Passed => String::new(),
        CaseStatus::NotConverged(r) => format!(": {r}"),
        CaseStatus::ThresholdFailed(r) => format!(": {}", r.join("; ")),
        CaseStatus::Error(e) => format!(": {e}"),
    };
    format!(
        "{}: {} ({:.2} s){why}",
        c.name,
        c.status.name(),
        c.wall_time_s
    )
}

fn print_update_summary(outcome: &update::UpdateOutcome) {
    let r = &outcome.result;
    let last = r.final_record();
    println!(
        "{} after {} iteration(s): SFDAC mean {:.4} -> {:.4}, min {:.4} -> {:.4}; mean |df/f| {} -> {}",
        r.stop.name(),
        r.iterations.len() - 1,
        r.iterations[0].sfdac.mean,
        last.sfdac.mean,
        r.iterations[0].sfdac.min,
        last.sfdac.min,
        pct(outcome.freq_error_initial_pct),
        pct(outcome.freq_error_updated_pct),
    );
    println!("layout: {}", r.layout);
    match &r.estimate {
        Some(est) => {
            println!(
                "full-band fit at {:.2}x the noise level; parameters (relative change ± 1 sd):",
                est.misfit
            );
            for p in &est.parameters {
                let note = if p.at_bound {
                    "  at its bound"
                } else if !p.identified {
                    "  NOT IDENTIFIED by these data"
                } else {
                    ""
                };
                println!("  {:<16} {:+.5} ± {:.5}{note}", p.name, p.value, p.sd);
            }
        }
        None => {
            for (name, p) in r.parameter_names.iter().zip(r.parameters()) {
                println!("  {name:<16} {p:+.5}");
            }
        }
    }
    print_warnings(outcome);
}

fn print_warnings(outcome: &update::UpdateOutcome) {
    for w in &outcome.result.warnings {
        eprintln!("warning: {w}");
    }
}

fn iteration_line(rec: &frfup::updating::IterationRecord) -> String {
    let step = rec.step.iter().fold(0.0f64, |a, p| a.max(p.abs()));
    let what = match rec.stage {
        IterationStage::Estimate => "full-band estimate".to_string(),
        _ => format!("iteration {}", rec.index),
    };
    format!(
        "{what}: SFDAC mean {:.4} min {:.4}, max |p| {:.3e}",
        rec.sfdac.mean, rec.sfdac.min, step
    )
}

fn print_timings(verbose: bool, timings: &[(&'static str, f64)]) {
    if verbose {
        for (stage, s) in timings {
            eprintln!("time: {stage:<32} {s:>8.3} s");
        }
    }
}

fn pct(x: Option<f64>) -> String {
    x.map(|v| format!("{v:.3} %"))
        .unwrap_or_else(|| "n/a".into())
}

fn check_thresholds(outcome: &update::UpdateOutcome, t: Thresholds) -> Result<(), CommandError> {
    let reasons = update::threshold_failures(outcome, t);
    if reasons.is_empty() {
        Ok(())
    } else {
        Err(CommandError::threshold(format!(
            "threshold failed: {}",
            reasons.join("; ")
        )))
    }
}

fn main() -> ExitCode {
    // Ctrl-C or a kill leaves no hidden temporary file or folder behind.
    frfup::fsio::remove_temporaries_on_signals();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() { 2 } else { 0 };
            let _ = e.print();
            return ExitCode::from(code);
        }
    };
    let result = run(cli);
    // A signal's thread is removing the temporaries and will exit with
    // 128 + N: the command's own ending (often an error, its files having
    // vanished) must not pre-empt it.
    while frfup::fsio::interrupted() {
        std::thread::park();
    }
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("frfup: {}", e.message);
            ExitCode::from(e.exit_code.clamp(1, 255) as u8)
        }
    }
}
