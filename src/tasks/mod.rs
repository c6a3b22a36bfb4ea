//! Tasks as library calls, below `batch` and the command line: read the
//! inputs (errors and warnings naming the files), run one algorithm, write
//! its result folder as a whole. Each returns a [`CommandError`] that the
//! caller turns into a message and an exit code (0 fine, 1 a threshold
//! failed, 2 bad input or usage): `batch` as a case's status, `main` as the
//! process's exit.

mod inputs;
pub mod update;

pub use inputs::{
    check_model_for_modes, eigen_error, load_test, load_test_with_notes, model_error,
    name_mechanism_equations, read_deck, warn_notes,
};

/// A failed task (a command, a case of a batch): what to print and which
/// exit code to use.
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

/// A failure to write or move a result file (exit code 2).
impl From<std::io::Error> for CommandError {
    fn from(e: std::io::Error) -> Self {
        CommandError::input(format!("cannot write the results: {e}"))
    }
}
