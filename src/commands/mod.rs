//! The command line's own tasks as library calls (`info`, `convert`,
//! `modes`, `simulate`, `diagnose`, `demo`): each takes typed options, writes
//! its files atomically and returns a [`CommandError`] that `main` turns into
//! a message and an exit code (0 fine, 1 a threshold failed, 2 bad input or
//! usage). `update` and `batch` are library tasks below this layer
//! ([`crate::tasks::update`], [`crate::batch`]).

pub mod convert;
pub mod demo;
pub mod diagnose;
pub mod info;
pub mod modes;
pub mod progress;
pub mod simulate;

use crate::tasks::CommandError;

/// Read and parse a UFF file, streaming (bounded memory, parsing on all
/// cores while reading; a byte bar on a terminal for large files); errors
/// name the file.
pub fn read_uff(
    path: &std::path::Path,
    progress: progress::Progress,
) -> Result<frfup_parsers::uff::UffFile, CommandError> {
    // Directories and devices refused, a pipe read to a bound (`fsio::open_input`).
    let (file, len) = crate::fsio::open_input(path).map_err(CommandError::input)?;
    let reader = progress::ProgressReader::new(file, len, &path.display().to_string(), progress);
    // The parser streams: the bar advances as bytes are parsed, not just read.
    let mut reader = reader;
    let parsed = frfup_parsers::uff::parse_reader(&mut reader);
    reader.finish();
    parsed.map_err(|e| CommandError::input(format!("{}: {e}", path.display())))
}
