//! The `frfup` command line: parses flags, calls the library, and turns
//! errors into messages and exit codes (0 fine, 1 a threshold failed, 2 bad
//! input or usage).

#![forbid(unsafe_code)]

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use frfup::commands::progress::{Progress, StepReporter};
use frfup::commands::{self, convert};
use frfup::tasks::update::Thresholds;
use frfup::tasks::{self, update, CommandError};
use frfup::testdata::FrfKind;
use frfup::updating::options::finite;
use frfup::updating::{UpdateMethod, UpdateSettings};
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
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the built-in GARTEUR-like case end to end (read, update, report).
    Demo {
        /// Output folder.
        #[arg(long, default_value = "frfup-demo")]
        out: PathBuf,
    },
    /// List the datasets of a UFF file, one line each.
    Info {
        file: PathBuf,
        /// Print JSON instead of a table.
        #[arg(long)]
        json: bool,
    },
    /// Convert UFF 58 records: to CSV or UFF, between FRF kinds, to the paper's signed real FRF.
    Convert {
        input: PathBuf,
        /// Output file: .csv, .uff or .unv.
        output: PathBuf,
        /// Convert FRFs to this kind.
        #[arg(long, value_enum)]
        to: Option<ToKind>,
        /// Records to keep: 1-based positions/ranges (1-4,7) or response DOFs (112:3, 112:+z).
        #[arg(long)]
        channels: Option<String>,
        /// Write 58b binary records (UFF output only).
        #[arg(long)]
        binary: bool,
    },
    /// Natural frequencies and generalised masses of a deck's lowest modes.
    Modes {
        deck: PathBuf,
        /// How many of the lowest modes.
        #[arg(long, default_value_t = 20, value_parser = at_least_one)]
        count: usize,
        /// Also write the table as CSV (mode,frequency_hz,generalised_mass_kg).
        #[arg(long)]
        csv: Option<PathBuf>,
        /// Parameter values NAME=P (relative change: value = (1 + P) x deck value).
        #[arg(long = "set", value_name = "NAME=VALUE")]
        set: Vec<String>,
    },
    /// Write a measured-style campaign (dataset 58 FRFs) computed from a deck.
    Simulate {
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
        /// Output UFF file.
        #[arg(long)]
        out: PathBuf,
        /// FRF kind written.
        #[arg(long, value_enum, default_value = "accelerance")]
        output: OutputKind,
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
    },
    /// Update the deck's parameters from measured FRFs (the paper's method).
    Update {
        deck: PathBuf,
        test: PathBuf,
        /// Output folder: report.json, CSV tables, updated.deck, report.md.
        #[arg(long)]
        out: PathBuf,
        #[command(flatten)]
        args: UpdateSettings,
        #[command(flatten)]
        thresholds: Thresholds,
    },
    /// Which physics the model lacks: update, localise, test hypotheses (diagnosis.json, diagnosed.deck, report.md).
    Diagnose {
        deck: PathBuf,
        test: PathBuf,
        /// Output folder.
        #[arg(long)]
        out: PathBuf,
        /// Take the deck's parameters as they are (no update first).
        #[arg(long)]
        no_update: bool,
        /// At most this many extensions.
        #[arg(long, default_value_t = 4)]
        max_findings: usize,
        /// Options of the first step, the update of the deck's own parameters
        /// (`--method paper` unless given).
        #[command(flatten)]
        args: UpdateSettings,
    },
    /// Run a campaign of updates (CAMPAIGN.toml with [[case]] tables) for CI.
    Batch {
        campaign: PathBuf,
        /// Output folder: one folder per case, summary.md/.csv/.json.
        #[arg(long)]
        out: PathBuf,
        /// Cases run at once.
        #[arg(long, default_value_t = 1, value_parser = at_least_one)]
        jobs: usize,
        /// Run only shard I of N (I/N, 1-based): cases i with i mod N = I - 1.
        #[arg(long, value_name = "I/N")]
        shard: Option<String>,
        #[command(flatten)]
        thresholds: Thresholds,
    },
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
enum OutputKind {
    Receptance,
    Mobility,
    Accelerance,
}

#[derive(Clone, Copy, ValueEnum)]
enum ToKind {
    Receptance,
    Mobility,
    Accelerance,
    /// Signed real displacement FRF, the paper's Eq. 50.
    DisplacementReal,
}

fn run(cli: Cli) -> Result<(), CommandError> {
    let progress = Progress::detect(cli.quiet);
    tasks::set_strict(cli.strict);
    match cli.command {
        Command::Demo { out } => {
            frfup::fsio::check_out_folder(&out).map_err(CommandError::input)?;
            let start = std::time::Instant::now();
            let reporter = StepReporter::new(cli.quiet, 21, "iteration");
            let result = commands::demo::run(&out, &mut |rec| {
                reporter.step(&iteration_line(rec));
            });
            reporter.finish();
            let (outcome, report) = result?;
            print_timings(cli.verbose, &outcome);
            print_update_summary(&outcome);
            println!(
                "done in {:.1} s. Open {} (and report.html, the .svg charts, updated.deck in {})",
                start.elapsed().as_secs_f64(),
                report.display(),
                out.display()
            );
        }
        Command::Info { file, json } => {
            print!("{}", commands::info::run(&file, json, progress)?);
        }
        Command::Convert {
            input,
            output,
            to,
            channels,
            binary,
        } => {
            let to = to.map(|t| match t {
                ToKind::Receptance => convert::Target::Kind(FrfKind::Receptance),
                ToKind::Mobility => convert::Target::Kind(FrfKind::Mobility),
                ToKind::Accelerance => convert::Target::Kind(FrfKind::Accelerance),
                ToKind::DisplacementReal => convert::Target::DisplacementReal,
            });
            let summary = convert::run(&convert::ConvertOptions {
                input,
                output: output.clone(),
                to,
                channels,
                binary,
                progress,
            })?;
            if !cli.quiet {
                for note in &summary.notes {
                    eprintln!("note: {note}");
                }
                eprintln!(
                    "wrote {} record(s) of {} line(s) to {}",
                    summary.records,
                    summary.lines,
                    output.display()
                );
            }
        }
        Command::Modes {
            deck,
            count,
            csv,
            set,
        } => {
            let values = commands::modes::parse_settings(&set)?;
            print!(
                "{}",
                commands::modes::run(&commands::modes::ModesOptions {
                    deck,
                    count,
                    csv,
                    values,
                })?
            );
        }
        Command::Simulate {
            deck,
            input,
            response,
            band,
            out,
            output,
            sensors,
            noise,
            seed,
            set,
            binary,
            single,
        } => {
            use commands::simulate as sim;
            let response = response
                .map(|r| sim::parse_node_direction(&r, "--response"))
                .transpose()?;
            let input = match (input, response) {
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
                band: sim::parse_band(&band)?,
                lines_hz: None,
                response,
                output: match output {
                    OutputKind::Receptance => FrfKind::Receptance,
                    OutputKind::Mobility => FrfKind::Mobility,
                    OutputKind::Accelerance => FrfKind::Accelerance,
                },
                sensors: sim::parse_sensors(&sensors)?,
                noise,
                seed,
            };
            let values = commands::modes::parse_settings(&set)?;
            let n = sim::run(&sim::SimulateOptions {
                deck,
                out: out.clone(),
                campaign,
                values,
                binary,
                single,
            })?;
            if !cli.quiet {
                eprintln!("wrote {n} FRF record(s) to {}", out.display());
            }
        }
        Command::Update {
            deck,
            test,
            out,
            args,
            thresholds,
        } => {
            let cmd = update::UpdateCommand {
                deck,
                test,
                out: out.clone(),
                options: args.resolve(UpdateMethod::Robust),
            };
            let reporter =
                StepReporter::new(cli.quiet, cmd.options.max_iter as u64 + 1, "iteration");
            let result = update::run(&cmd, &mut |rec| {
                reporter.step(&iteration_line(rec));
            });
            reporter.finish();
            let outcome = result?;
            print_timings(cli.verbose, &outcome);
            print_update_summary(&outcome);
            println!("wrote {}", out.display());
            if !outcome.result.converged {
                return Err(CommandError::threshold(format!(
                    "not converged: {}",
                    frfup::report::status::not_converged_reason(&outcome.result)
                )));
            }
            check_thresholds(&outcome, thresholds)?;
        }
        Command::Diagnose {
            deck,
            test,
            out,
            no_update,
            max_findings,
            args,
        } => {
            let cmd = commands::diagnose::DiagnoseCommand {
                deck,
                test,
                out: out.clone(),
                options: frfup::diagnosis::DiagnoseOptions {
                    update: args.resolve(UpdateMethod::Paper),
                    skip_update: no_update,
                    max_findings,
                    ..Default::default()
                },
            };
            let d = commands::diagnose::run(&cmd)?;
            if cli.verbose {
                for (stage, secs, units) in &d.timings {
                    eprintln!("time: {stage:<32} {secs:>8.3} s  ({units} model-solution units)");
                }
            }
            print!("{}", commands::diagnose::summary(&d));
            println!("wrote {}", out.display());
        }
        Command::Batch {
            campaign,
            out,
            jobs,
            shard,
            thresholds,
        } => {
            frfup::fsio::check_out_folder(&out).map_err(CommandError::input)?;
            let shard = shard
                .map(|s| frfup::batch::Shard::parse(&s))
                .transpose()
                .map_err(CommandError::input)?;
            let reporter = Mutex::new(None::<StepReporter>);
            let quiet = cli.quiet;
            let result = frfup::batch::run(
                &frfup::batch::BatchOptions {
                    campaign,
                    out: out.clone(),
                    jobs,
                    shard,
                    thresholds,
                },
                &|c, n, total| {
                    let line = format!(
                        "[{n}/{total}] {}: {} ({:.2} s){}",
                        c.name,
                        c.status.name(),
                        c.wall_time_s,
                        match &c.status {
                            frfup::batch::CaseStatus::Passed => String::new(),
                            frfup::batch::CaseStatus::NotConverged(r) => format!(": {r}"),
                            frfup::batch::CaseStatus::ThresholdFailed(r) =>
                                format!(": {}", r.join("; ")),
                            frfup::batch::CaseStatus::Error(e) => format!(": {e}"),
                        }
                    );
                    if let Ok(mut r) = reporter.lock() {
                        r.get_or_insert_with(|| StepReporter::new(quiet, total as u64, "case"))
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
            println!(
                "{}; summary in {}",
                summary.totals(),
                out.join("summary.md").display()
            );
            match summary.exit_code() {
                0 => {}
                1 => {
                    let nc = summary.count("not-converged");
                    return Err(CommandError::threshold(if nc > 0 {
                        format!(
                            "{nc} case(s) did not converge or a threshold failed (see the summary)"
                        )
                    } else {
                        "a threshold failed (see the summary)".to_string()
                    }));
                }
                _ => {
                    return Err(CommandError::input(
                        "a case could not run (see the summary)",
                    ))
                }
            }
        }
    }
    Ok(())
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
    for w in &r.warnings {
        eprintln!("warning: {w}");
    }
}

fn iteration_line(rec: &frfup::updating::IterationRecord) -> String {
    let step = rec.step.iter().fold(0.0f64, |a, p| a.max(p.abs()));
    format!(
        "iteration {}: SFDAC mean {:.4} min {:.4}, max |p| {:.3e}",
        rec.index, rec.sfdac.mean, rec.sfdac.min, step
    )
}

fn print_timings(verbose: bool, outcome: &update::UpdateOutcome) {
    if verbose {
        for (stage, s) in &outcome.timings {
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
    match run(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("frfup: {}", e.message);
            ExitCode::from(e.exit_code.clamp(1, 255) as u8)
        }
    }
}
