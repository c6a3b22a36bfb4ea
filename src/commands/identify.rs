//! `frfup identify TEST.uff --out DIR [--band F0:F1] [--max-order N]
//! [--deck MODEL.deck]`: the test's modes (frequencies, damping ratios,
//! shapes) identified without picking, written as `modes.csv`, `shapes.csv`,
//! `modes.uff`, charts and `report.html`; with a deck, paired with its modes.

use std::fmt::Write as _;
use std::path::PathBuf;

use crate::identification::{self, pair_with_deck, Identification, IdentifyOptions, ModeKind};
use crate::report::identification::{write_outputs, IdentifyReport};
use crate::report::viewer::sources::from_identification;
use crate::tasks::{load_test_with_notes, read_deck, CommandError};

/// Options of `frfup identify`.
#[derive(Clone, Debug)]
pub struct IdentifyCommand {
    pub test: PathBuf,
    pub out: PathBuf,
    pub band_hz: Option<(f64, f64)>,
    pub max_order: Option<usize>,
    pub deck: Option<PathBuf>,
    /// `--strict`: a warning about an input is an error.
    pub strict: bool,
}

/// `F0:F1` in Hz, 0 ≤ F0 < F1.
pub fn parse_band(s: &str) -> Result<(f64, f64), CommandError> {
    let bad = || {
        CommandError::input(format!(
            "--band {s:?}: expected F0:F1 in Hz with 0 <= F0 < F1"
        ))
    };
    let (a, b) = s.split_once(':').ok_or_else(bad)?;
    let (f0, f1): (f64, f64) = (
        a.trim().parse().map_err(|_| bad())?,
        b.trim().parse().map_err(|_| bad())?,
    );
    if f0 >= 0.0 && f0 < f1 && f1.is_finite() {
        Ok((f0, f1))
    } else {
        Err(bad())
    }
}

/// Identify the modes and write the folder, telling `stage` what it is doing.
pub fn run(cmd: &IdentifyCommand, stage: &dyn Fn(&str)) -> Result<Identification, CommandError> {
    let clock = std::time::Instant::now();
    crate::fsio::check_out_folder(&cmd.out).map_err(CommandError::input)?;
    let deck = cmd.deck.as_ref().map(|p| read_deck(p)).transpose()?;
    let (test, notes) = load_test_with_notes(&cmd.test, cmd.strict)?;
    let read = clock.elapsed().as_secs_f64();
    let opts = IdentifyOptions {
        band_hz: cmd.band_hz,
        max_order: cmd.max_order,
        ..IdentifyOptions::default()
    };
    stage(&format!(
        "identifying modes: {} FRF(s) × {} line(s), poles by model order, then residues",
        test.channels.len(),
        test.frequencies_hz.len()
    ));
    let mut id = identification::identify(&test, &opts)
        .map_err(|e| CommandError::input(format!("{}: {e}", cmd.test.display())))?;
    id.timings.insert(0, ("read the inputs", read));
    let clock = std::time::Instant::now();
    let mut notes: Vec<String> = notes
        .iter()
        .map(|n| format!("{}: {n}", cmd.test.display()))
        .collect();
    if id.data.reciprocal {
        notes.push(format!(
            "roving-hammer test (one response DOF, {} references): fitted by reciprocity \
             (H_ij = H_ji), the hit points as outputs and the response DOF as the reference",
            id.data.n_outputs()
        ));
    }
    if !id.data.left_out.is_empty() {
        notes.push(format!(
            "{} FRF(s) left out: their reference does not have every response (the fit uses {})",
            id.data.left_out.len(),
            id.data.inputs.len()
        ));
    }
    let pairing = match (&deck, &cmd.deck) {
        (Some(deck), Some(path)) => Some(
            pair_with_deck(deck, &id)
                .map_err(|e| CommandError::input(format!("{}: {e}", path.display())))?,
        ),
        _ => None,
    };
    let viewer = deck
        .as_ref()
        .zip(pairing.as_ref())
        .map(|(d, p)| from_identification(d, &id, p, "FE mode"));
    let deck_name = cmd.deck.as_ref().map(|p| p.display().to_string());
    let test_name = cmd.test.display().to_string();
    let report = IdentifyReport {
        id: &id,
        test: &test,
        test_name: &test_name,
        pairing: deck_name.as_deref().zip(pairing.as_ref()),
        notes: &notes,
        viewer: viewer.as_ref(),
    };
    let paired = clock.elapsed().as_secs_f64();
    stage("writing the report");
    let clock = std::time::Instant::now();
    crate::fsio::write_folder(&cmd.out, |dir| {
        write_outputs(&report, dir).map_err(|e| std::io::Error::other(e.to_string()))
    })
    .map_err(|e| CommandError::output(&cmd.out, e))?;
    let written = clock.elapsed().as_secs_f64();
    id.timings.push(("pair with the deck, notes", paired));
    id.timings.push(("write the folder", written));
    Ok(id)
}

/// One line per mode, for the terminal.
pub fn summary(id: &Identification) -> String {
    let mut s = format!(
        "{} mode(s) in {:.3}-{:.3} Hz (orders 1-{}, fit residual {:.2} %)\n",
        id.modes.len(),
        id.data.frequencies_hz[0],
        id.data.frequencies_hz[id.data.n_lines() - 1],
        id.diagram.max_order,
        100.0 * id.relative_residual
    );
    s.push_str(" mode  frequency_hz  damping_%     MPC  kind\n");
    for (k, m) in id.modes.iter().enumerate() {
        let _ = writeln!(
            s,
            "{:>5}  {:>12.4}  {:>9.3}  {:>6.3}  {}",
            k + 1,
            m.frequency_hz,
            100.0 * m.damping_ratio,
            m.quality.mpc,
            if m.kind == ModeKind::RigidBody {
                "rigid-body"
            } else {
                "elastic"
            }
        );
    }
    s
}
