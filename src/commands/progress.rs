//! Progress display: an indicatif bar or spinner on a terminal (stderr) for
//! every step that can take more than a second; nothing when stderr is not a
//! terminal, in CI (`CI=true`), or with `--quiet`. `--progress` asks for it
//! anyway: bars on a terminal, one plain line per step elsewhere (logs).

use std::io::{IsTerminal, Read};

use indicatif::{ProgressBar, ProgressStyle};

/// Files smaller than this read without a bar.
const LARGE_FILE_BYTES: u64 = 8 << 20;

/// Whether and how to show progress.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// Bars and spinners (stderr is a terminal).
    pub enabled: bool,
    /// One plain line per step on stderr (`--progress` off a terminal).
    pub lines: bool,
}

impl Progress {
    /// Bars only on an interactive terminal, outside CI, without `--quiet`.
    pub fn detect(quiet: bool) -> Self {
        Self::with_flags(quiet, false)
    }

    /// As [`Progress::detect`]; `forced` (`--progress`) shows progress in CI
    /// too, as plain lines where stderr is not a terminal. `quiet` wins.
    pub fn with_flags(quiet: bool, forced: bool) -> Self {
        let ci = std::env::var("CI")
            .map(|v| !v.is_empty() && v != "false" && v != "0")
            .unwrap_or(false);
        let tty = std::io::stderr().is_terminal();
        Progress {
            enabled: !quiet && tty && (forced || !ci),
            lines: !quiet && forced && !tty,
        }
    }

    pub fn hidden() -> Self {
        Progress {
            enabled: false,
            lines: false,
        }
    }
}

/// A reader that advances a byte bar (on a terminal, for large inputs) as it is read.
pub struct ProgressReader<R> {
    inner: R,
    bar: Option<ProgressBar>,
}

impl<R: Read> ProgressReader<R> {
    /// Wrap `inner`, whose total size is `len` bytes, labelled `label`.
    pub fn new(inner: R, len: u64, label: &str, progress: Progress) -> Self {
        let bar = (progress.enabled && len >= LARGE_FILE_BYTES).then(|| {
            let bar = ProgressBar::new(len);
            bar.set_style(
                ProgressStyle::with_template(
                    "reading {msg} {bar:40} {bytes}/{total_bytes} {bytes_per_sec}",
                )
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            bar.set_message(label.to_string());
            bar
        });
        ProgressReader { inner, bar }
    }

    /// Clear the bar.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

impl<R: Read> Read for ProgressReader<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        if let Some(bar) = &self.bar {
            bar.inc(n as u64);
        }
        Ok(n)
    }
}

/// Progress of a counted task (iterations, batch cases): an indicatif bar on a
/// terminal, plain one-line messages with `--progress` off a terminal,
/// otherwise nothing.
pub enum StepReporter {
    Bar(ProgressBar),
    Lines,
    Silent,
}

impl StepReporter {
    /// A reporter for `total` steps.
    pub fn new(progress: Progress, total: u64, what: &str) -> Self {
        if progress.enabled {
            let bar = ProgressBar::new(total);
            bar.set_style(
                ProgressStyle::with_template(&format!(
                    "{what} {{pos}}/{{len}} {{bar:30}} [{{elapsed}}] {{msg}}"
                ))
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            // The clock runs on between steps (a long last stage).
            bar.enable_steady_tick(std::time::Duration::from_millis(250));
            StepReporter::Bar(bar)
        } else if progress.lines {
            StepReporter::Lines
        } else {
            StepReporter::Silent
        }
    }

    /// One step done, with a one-line message.
    pub fn step(&self, message: &str) {
        match self {
            StepReporter::Bar(bar) => {
                bar.inc(1);
                bar.set_message(message.to_string());
            }
            StepReporter::Lines => eprintln!("{message}"),
            StepReporter::Silent => {}
        }
    }

    /// A stage starts that is not a step (its message replaces the last
    /// step's until the next step).
    pub fn note(&self, message: &str) {
        match self {
            StepReporter::Bar(bar) => bar.set_message(message.to_string()),
            StepReporter::Lines => eprintln!("{message}"),
            StepReporter::Silent => {}
        }
    }

    /// Clear the bar.
    pub fn finish(&self) {
        if let StepReporter::Bar(bar) = self {
            bar.finish_and_clear();
        }
    }
}

/// Progress of a task in stages of unknown length (a diagnosis): a spinner
/// with the stage and the elapsed time on a terminal, one line per stage
/// with `--progress` off a terminal, otherwise nothing.
pub struct StageReporter {
    bar: Option<ProgressBar>,
    lines: bool,
}

impl StageReporter {
    pub fn new(progress: Progress) -> Self {
        let bar = progress.enabled.then(|| {
            let bar = ProgressBar::new_spinner();
            bar.set_style(
                ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
                    .unwrap_or_else(|_| ProgressStyle::default_spinner()),
            );
            bar.enable_steady_tick(std::time::Duration::from_millis(120));
            bar
        });
        StageReporter {
            bar,
            lines: progress.lines,
        }
    }

    /// A new stage starts.
    pub fn stage(&self, message: &str) {
        if let Some(bar) = &self.bar {
            bar.set_message(message.to_string());
        } else if self.lines {
            eprintln!("{message}");
        }
    }

    /// Clear the spinner.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
