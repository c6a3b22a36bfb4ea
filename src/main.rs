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
    /// Natural frequencies and generalised masses of a deck's lowest modes.
    Modes {
        deck: PathBuf,
        /// How many of the lowest modes.
        #[arg(long, default_value_t = 20)]
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
        #[arg(long)]
        input: String,
        /// Frequency lines F0:F1:N (Hz).
        #[arg(long)]
        band: String,
        /// Output UFF file.
        #[arg(long)]
        out: PathBuf,
        /// FRF kind written.
        #[arg(long, value_enum, default_value = "accelerance")]
        output: OutputKind,
        /// Sensors: all (every free translational DOF) or NODE:DIR,NODE:DIR,...
        #[arg(long, default_value = "all")]
        sensors: String,
        /// Complex Gaussian noise, as a fraction of each channel's RMS.
        #[arg(long, default_value_t = 0.0)]
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
            let campaign = frfup::simulate::Campaign {
                input: sim::parse_node_direction(&input, "--input")?,
                band: sim::parse_band(&band)?,
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
