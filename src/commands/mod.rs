//! The command line's own tasks as library calls (`info`, `convert`,
//! `modes`, `simulate`, `diagnose`, `identify`, `demo`): each takes typed options, writes
//! its files atomically and returns a [`CommandError`] that `main` turns into
//! a message and an exit code (0 fine, 1 a threshold failed, 2 bad input or
//! usage). `update` and `batch` are library tasks below this layer
//! ([`crate::tasks::update`], [`crate::batch`]).

pub mod convert;
pub mod demo;
pub mod diagnose;
pub mod identify;
pub mod info;
pub mod modes;
pub mod progress;
pub mod simulate;

use crate::tasks::CommandError;

/// Read and parse a UFF file as every command does
/// ([`crate::testdata::parse_uff`]), with a byte bar on a terminal for large
/// files; errors name the file.
pub fn read_uff(
    path: &std::path::Path,
    progress: progress::Progress,
) -> Result<frfup_parsers::uff::UffFile, CommandError> {
    let input = |e: crate::testdata::TestDataError| CommandError::input(e.to_string());
    let (file, len) = crate::testdata::open_uff(path).map_err(input)?;
    // The parser streams: the bar advances as bytes are parsed, not just read.
    let mut reader =
        progress::ProgressReader::new(file, len, &path.display().to_string(), progress);
    let parsed = crate::testdata::parse_uff(path, &mut reader);
    reader.finish();
    parsed.map_err(input)
}
