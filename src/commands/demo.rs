//! `frfup demo [--out DIR]`: the GARTEUR-like case carried in the binary, end
//! to end — read the UFF campaign, update the deck, write the report.

use std::path::{Path, PathBuf};

use super::update::{run as run_update, UpdateCommand, UpdateOutcome};
use super::CommandError;
use crate::fsio::write_atomic;
use crate::updating::UpdateOptions;

/// The analyst's deck of the GARTEUR-like test bed with its known bungee
/// suspension (fixtures/garteur/garteur_suspended.deck).
pub const GARTEUR_DECK: &str = include_str!("../../fixtures/garteur/garteur_suspended.deck");
/// The measured campaign (fixtures/garteur/campaign.uff): 26 accelerometers,
/// excitation 112 +z, 801 lines to 200 Hz, complex single-precision accelerance.
pub const GARTEUR_CAMPAIGN: &[u8] = include_bytes!("../../fixtures/garteur/campaign.uff");

/// The options the demo updates with: the defaults, as a user would run
/// `frfup update` (the robust pipeline: fitted resonances, frequencies
/// first, damped steps, then the full-band estimate with uncertainties).
pub fn demo_options() -> UpdateOptions {
    UpdateOptions::default()
}

/// Run the demo into `out`: writes `input/garteur.deck`, `input/campaign.uff`
/// and the update's files.
pub fn run(
    out: &Path,
    progress: &mut dyn FnMut(&crate::updating::IterationRecord),
) -> Result<(UpdateOutcome, PathBuf), CommandError> {
    let input = out.join("input");
    std::fs::create_dir_all(&input).map_err(|e| CommandError::output(&input, e))?;
    let deck = input.join("garteur.deck");
    let test = input.join("campaign.uff");
    write_atomic(&deck, GARTEUR_DECK.as_bytes()).map_err(|e| CommandError::output(&deck, e))?;
    write_atomic(&test, GARTEUR_CAMPAIGN).map_err(|e| CommandError::output(&test, e))?;
    let outcome = run_update(
        &UpdateCommand {
            deck,
            test,
            out: out.to_path_buf(),
            options: demo_options(),
        },
        progress,
    )?;
    Ok((outcome, out.join("report.md")))
}
