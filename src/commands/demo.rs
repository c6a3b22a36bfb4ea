//! `frfup demo [--out DIR]`: the GARTEUR-like case carried in the binary, end
//! to end — read the UFF campaign, update the deck, write the report.

use std::path::{Path, PathBuf};

use crate::fsio::{write_atomic, write_folder};
use crate::tasks::update::{run_into, Shown, UpdateCommand, UpdateOutcome};
use crate::tasks::CommandError;
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
/// and the update's files, as a whole (`fsio::write_folder`): the inputs and
/// the results land together or not at all. The reports name the inputs by
/// their final paths in `out`.
pub fn run(
    out: &Path,
    progress: &mut dyn FnMut(crate::updating::UpdateProgress),
) -> Result<(UpdateOutcome, PathBuf), CommandError> {
    crate::fsio::check_out_folder(out).map_err(CommandError::input)?;
    let shown = Shown {
        deck: out.join("input").join("garteur.deck").display().to_string(),
        test: out.join("input").join("campaign.uff").display().to_string(),
    };
    let mut outcome = write_folder(out, |dir| {
        let input = dir.join("input");
        std::fs::create_dir_all(&input).map_err(|e| CommandError::output(&input, e))?;
        let deck = input.join("garteur.deck");
        let test = input.join("campaign.uff");
        write_atomic(&deck, GARTEUR_DECK.as_bytes()).map_err(|e| CommandError::output(&deck, e))?;
        write_atomic(&test, GARTEUR_CAMPAIGN).map_err(|e| CommandError::output(&test, e))?;
        let cmd = UpdateCommand {
            deck,
            test,
            out: out.to_path_buf(),
            options: demo_options(),
            strict: false,
        };
        run_into(&cmd, dir, &shown, progress)
    })?;
    outcome.files = list_files(out);
    Ok((outcome, out.join("report.md")))
}

/// The files directly in `dir`, sorted.
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
