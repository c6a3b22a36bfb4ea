//! The command-line tasks as library calls: each takes typed options, writes
//! its files atomically and returns a typed error that `main` turns into a
//! message and an exit code (0 fine, 1 a threshold failed, 2 bad input or usage).

pub mod convert;
pub mod demo;
pub mod diagnose;
pub mod info;
pub mod modes;
pub mod progress;
pub mod simulate;
pub mod update;

/// A failed command: what to print and which exit code to use.
#[derive(Debug)]
pub struct CommandError {
    /// 1: a threshold failed; 2: bad input, usage or an output that could not be written.
    pub exit_code: i32,
    pub message: String,
}

impl CommandError {
    /// Bad input or usage (exit code 2).
    pub fn input(message: impl Into<String>) -> Self {
        CommandError {
            exit_code: 2,
            message: message.into(),
        }
    }
    /// A quality threshold failed (exit code 1).
    pub fn threshold(message: impl Into<String>) -> Self {
        CommandError {
            exit_code: 1,
            message: message.into(),
        }
    }
    /// An output file could not be written (exit code 2).
    pub fn output(path: &std::path::Path, e: std::io::Error) -> Self {
        CommandError::input(format!("{}: cannot write: {e}", path.display()))
    }
}

impl std::fmt::Display for CommandError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for CommandError {}

/// Read and parse a UFF file, streaming (bounded memory, parsing on all
/// cores while reading; a byte bar on a terminal for large files); errors
/// name the file.
pub fn read_uff(
    path: &std::path::Path,
    progress: progress::Progress,
) -> Result<frfup_parsers::uff::UffFile, CommandError> {
    let cannot_read =
        |e: std::io::Error| CommandError::input(format!("{}: cannot read: {e}", path.display()));
    let file = std::fs::File::open(path).map_err(cannot_read)?;
    let len = file.metadata().map_or(0, |m| m.len());
    let reader = progress::ProgressReader::new(file, len, &path.display().to_string(), progress);
    // The parser streams: the bar advances as bytes are parsed, not just read.
    let mut reader = reader;
    // Decoded data in huge pages when the binary's allocator is installed, as
    // far as the file's size: values are kept no wider than 58b stores them,
    // and ASCII text is longer than its values.
    let expected = usize::try_from(len).unwrap_or(usize::MAX);
    let parsed = crate::alloc::huge_pages_for_reading(expected, || {
        frfup_parsers::uff::parse_reader(&mut reader)
    });
    reader.finish();
    parsed.map_err(|e| CommandError::input(format!("{}: {e}", path.display())))
}

/// Read and parse a deck; errors read `FILE:LINE:COLUMN: what was expected`.
pub fn read_deck(path: &std::path::Path) -> Result<frfup_parsers::deck::Deck, CommandError> {
    let bytes = std::fs::read(path)
        .map_err(|e| CommandError::input(format!("{}: cannot read: {e}", path.display())))?;
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
    frfup_parsers::deck::parse(&text)
        .map_err(|e| CommandError::input(format!("{}:{e}", path.display())))
}

/// A model-building error, prefixed with the deck's file name
/// (`FILE:LINE:COLUMN: ...` where a statement is at fault).
pub fn model_error(path: &std::path::Path, e: crate::model::ModelError) -> CommandError {
    match e.pos() {
        Some(_) => CommandError::input(format!("{}:{e}", path.display())),
        None => CommandError::input(format!("{}: {e}", path.display())),
    }
}
