//! `frfup demo [--out DIR]`: the GARTEUR-like case carried in the binary, end
//! to end — read the UFF campaign, update the deck, write the report.

use std::path::{Path, PathBuf};

use super::update::{run_into, Shown, UpdateCommand, UpdateOutcome};
use super::CommandError;
use crate::fsio::{write_atomic, write_folder};
use crate::updating::{ResonanceMethod, UpdateOptions};

/// The analyst's deck of the GARTEUR-like test bed with its known bungee
/// suspension (fixtures/garteur/garteur_suspended.deck).
pub const GARTEUR_DECK: &str = include_str!("../../fixtures/garteur/garteur_suspended.deck");
/// The measured campaign (fixtures/garteur/campaign.uff): 26 accelerometers,
/// excitation 112 +z, 801 lines to 200 Hz, complex single-precision accelerance.
pub const GARTEUR_CAMPAIGN: &[u8] = include_bytes!("../../fixtures/garteur/campaign.uff");

/// The options the demo updates with (see the README's GARTEUR section for why).
pub fn demo_options() -> UpdateOptions {
    // The initial GARTEUR-like model is 5–11 % off the test's resonances,
    // two wing-torsion modes sit 0.65 Hz apart and 26 sensors alias high FE
    // modes onto low ones. So: resonances and shapes by a multi-channel modal
    // fit (peak picking merges the torsion pair and misses weak modes); a
    // first stage on natural frequencies and mode shapes of the clearly paired
    // modes (MAC ≥ 0.8, ±30 % in frequency); then the paper's FRF equations
    // around the suspension mode and the first 10 elastic resonances (R = 11),
    // ±5 % offsets, every step damped (Levenberg–Marquardt, μ = 0.05 σ₁ and
    // adapted) so that noise cannot blow up the parameters the data barely
    // see. README, "The GARTEUR-like test bed", has the figures.
    UpdateOptions {
        resonances: Some(11),
        resonance_method: ResonanceMethod::ModalFit,
        frequencies_first: true,
        offset: 0.05,
        damping: 0.05,
        tol: 0.001,
        max_iter: 30,
        ..UpdateOptions::paper()
    }
}

/// Run the demo into `out`: writes `input/garteur.deck`, `input/campaign.uff`
/// and the update's files, as a whole (`fsio::write_folder`): the inputs and
/// the results land together or not at all. The reports name the inputs by
/// their final paths in `out`.
pub fn run(
    out: &Path,
    progress: &mut dyn FnMut(&crate::updating::IterationRecord),
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
