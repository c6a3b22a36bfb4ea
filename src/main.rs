//! The `frfup` command line: parses flags, calls the library, and turns
//! errors into messages and exit codes (0 fine, 1 a threshold failed, 2 bad
//! input or usage).

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand, ValueEnum};
use frfup::commands::{self, convert, progress::Progress, CommandError};
use frfup::testdata::FrfKind;

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
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
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
    match cli.command {
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
    }
    Ok(())
}

fn main() -> ExitCode {
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
