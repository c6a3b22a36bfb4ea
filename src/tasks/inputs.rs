//! Reading the inputs of a task: decks and test data, with errors that name
//! the file (and line), and warnings on what was skipped or doubtful.

use super::CommandError;

/// Print what was noticed in the input `path` (data skipped or doubtful) on
/// stderr as `warning: FILE: NOTE` lines, whatever `--quiet` says. With
/// `strict` (`--strict`) any such note is an error naming the file (exit 2).
pub fn warn_notes(
    path: &std::path::Path,
    notes: &[String],
    strict: bool,
) -> Result<(), CommandError> {
    if notes.is_empty() {
        return Ok(());
    }
    let mut err = std::io::stderr().lock();
    for note in notes {
        use std::io::Write;
        let _ = writeln!(err, "warning: {}: {note}", path.display());
    }
    if strict {
        return Err(CommandError::input(format!(
            "{}: {} warning(s) and --strict: refused (first: {})",
            path.display(),
            notes.len(),
            notes[0]
        )));
    }
    Ok(())
}

/// Load test data (FRF records of a UFF file) and report on stderr what was
/// skipped or doubtful while reading them (see [`warn_notes`]).
pub fn load_test(
    path: &std::path::Path,
    strict: bool,
) -> Result<crate::testdata::MeasuredFrfs, CommandError> {
    load_test_with_notes(path, strict).map(|(frfs, _)| frfs)
}

/// [`load_test`], also returning the notes (for the reports).
pub fn load_test_with_notes(
    path: &std::path::Path,
    strict: bool,
) -> Result<(crate::testdata::MeasuredFrfs, Vec<String>), CommandError> {
    let loaded =
        crate::testdata::load_with_notes(path).map_err(|e| CommandError::input(e.to_string()))?;
    warn_notes(path, &loaded.notes, strict)?;
    Ok((loaded.frfs, loaded.notes))
}

/// Read and parse a deck; errors read `FILE:LINE:COLUMN: what was expected`.
pub fn read_deck(path: &std::path::Path) -> Result<frfup_parsers::deck::Deck, CommandError> {
    let bytes = crate::fsio::read_input(path).map_err(CommandError::input)?;
    let text = String::from_utf8(bytes).map_err(|e| {
        let offset = e.utf8_error().valid_up_to();
        let line = e.as_bytes()[..offset]
            .iter()
            .filter(|&&b| b == b'\n')
            .count()
            + 1;
        CommandError::input(format!(
            "{}:{line}: the deck is not UTF-8 text (invalid byte at offset {offset})",
            path.display()
        ))
    })?;
    let deck = frfup_parsers::deck::parse(&text)
        .map_err(|e| CommandError::input(format!("{}:{e}", path.display())))?;
    if deck.nodes.is_empty() {
        // Said here rather than as "no free degree of freedom" by the model.
        let lines = text.lines().count();
        return Err(CommandError::input(if text.trim().is_empty() {
            format!(
                "{}:1:1: the deck is empty: expected `material`, `section`, `node` and `beam` statements (see docs/deck.md)",
                path.display()
            )
        } else {
            format!(
                "{}:1:1: the deck's {lines} line(s) hold no `node` statement (only comments, titles or settings): expected a model (see docs/deck.md)",
                path.display()
            )
        }));
    }
    Ok(deck)
}

/// A model-building error, prefixed with the deck's file name
/// (`FILE:LINE:COLUMN: ...` where a statement is at fault).
pub fn model_error(path: &std::path::Path, e: crate::model::ModelError) -> CommandError {
    match e.pos() {
        Some(_) => CommandError::input(format!("{}:{e}", path.display())),
        None => CommandError::input(format!("{}: {e}", path.display())),
    }
}

/// Check before a long computation that the deck's model (at the deck's own
/// values) can have modes: every free DOF has mass. Errors name the node and DOF.
pub fn check_model_for_modes(
    path: &std::path::Path,
    deck: &frfup_parsers::deck::Deck,
) -> Result<(), CommandError> {
    let fe = crate::model::build(deck, &Default::default()).map_err(|e| model_error(path, e))?;
    crate::model::check_mass(&fe).map_err(|e| model_error(path, e))
}

/// An eigen-solver error in the words of the model: equations named as node and DOF.
pub fn eigen_error(
    path: &std::path::Path,
    fe: &crate::model::FeModel,
    e: crate::solvers::eigen::EigenError,
) -> CommandError {
    use crate::solvers::eigen::EigenError;
    match e {
        EigenError::Mechanisms { count, equations } => {
            let names = fe.dofs.labels(&equations);
            CommandError::input(format!(
                "{}: the model has fixed DOFs but {count} mechanism(s) (zero-energy modes) moving {}: check fix, springs and element connectivity there",
                path.display(),
                names.join(", ")
            ))
        }
        e => CommandError::input(format!("{}: {e}", path.display())),
    }
}

/// The words of an eigen solver's mechanism error ("... moving equation(s)
/// 3, 4: ...") with the equations named as node and DOF of `deck`'s model
/// (equation numbers do not depend on parameter values). Any other message,
/// or a deck that does not build, is returned as it is.
pub fn name_mechanism_equations(message: &str, deck: &frfup_parsers::deck::Deck) -> String {
    const KEY: &str = "moving equation(s) ";
    let Some(at) = message.find(KEY) else {
        return message.to_string();
    };
    let start = at + KEY.len();
    let end = message[start..]
        .find(|c: char| !(c.is_ascii_digit() || c == ',' || c == ' '))
        .map_or(message.len(), |e| start + e);
    let equations: Vec<usize> = message[start..end]
        .split(',')
        .filter_map(|t| t.trim().parse().ok())
        .collect();
    let Ok(fe) = crate::model::build(deck, &Default::default()) else {
        return message.to_string();
    };
    let names = fe.dofs.labels(&equations);
    if names.len() != equations.len() || names.is_empty() {
        return message.to_string();
    }
    format!(
        "{}moving {}{}",
        &message[..at],
        names.join(", "),
        &message[end..]
    )
}
