//! Progress display: an indicatif bar on a terminal for large inputs; nothing
//! when output is not a terminal, in CI (`CI=true`), or with `--quiet`.

use std::io::{IsTerminal, Read};
use std::path::Path;

use indicatif::{ProgressBar, ProgressStyle};

/// Files smaller than this read without a bar.
const LARGE_FILE_BYTES: u64 = 8 << 20;

/// Whether and how to show progress.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    pub enabled: bool,
}

impl Progress {
    /// Bars only on an interactive terminal, outside CI, without `--quiet`.
    pub fn detect(quiet: bool) -> Self {
        let ci = std::env::var("CI")
            .map(|v| !v.is_empty() && v != "false" && v != "0")
            .unwrap_or(false);
        Progress {
            enabled: !quiet && !ci && std::io::stderr().is_terminal(),
        }
    }

    pub fn hidden() -> Self {
        Progress { enabled: false }
    }

    /// A spinner for a phase of unknown length, shown only for large inputs.
    pub fn spinner(&self, message: String, input_bytes: usize) -> Spinner {
        if !self.enabled || (input_bytes as u64) < LARGE_FILE_BYTES {
            return Spinner(None);
        }
        let bar = ProgressBar::new_spinner();
        bar.set_message(message);
        bar.enable_steady_tick(std::time::Duration::from_millis(120));
        Spinner(Some(bar))
    }
}

/// A running spinner; `finish` clears it.
pub struct Spinner(Option<ProgressBar>);

impl Spinner {
    pub fn finish(self) {
        if let Some(bar) = self.0 {
            bar.finish_and_clear();
        }
    }
}

/// Read a file whole, with a byte bar for large files on a terminal.
pub fn read_with_progress(path: &Path, progress: Progress) -> std::io::Result<Vec<u8>> {
    let mut file = std::fs::File::open(path)?;
    let len = file.metadata().map(|m| m.len()).unwrap_or(0);
    if !progress.enabled || len < LARGE_FILE_BYTES {
        let mut bytes = Vec::with_capacity(len as usize);
        file.read_to_end(&mut bytes)?;
        return Ok(bytes);
    }
    let bar = ProgressBar::new(len);
    bar.set_style(
        ProgressStyle::with_template(
            "reading {msg} {bar:40} {bytes}/{total_bytes} {bytes_per_sec}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_message(path.display().to_string());
    let mut bytes = Vec::with_capacity(len as usize);
    let mut chunk = vec![0u8; 4 << 20];
    loop {
        let n = file.read(&mut chunk)?;
        if n == 0 {
            break;
        }
        bytes.extend_from_slice(&chunk[..n]);
        bar.inc(n as u64);
    }
    bar.finish_and_clear();
    Ok(bytes)
}
