//! Progress display: an indicatif bar on a terminal for large inputs; nothing
//! when output is not a terminal, in CI (`CI=true`), or with `--quiet`.

use std::io::{IsTerminal, Read};

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
/// terminal, plain one-line messages in CI or off a terminal, nothing with `--quiet`.
pub enum StepReporter {
    Bar(ProgressBar),
    Lines,
    Silent,
}

impl StepReporter {
    /// A reporter for `total` steps.
    pub fn new(quiet: bool, total: u64, what: &str) -> Self {
        if quiet {
            return StepReporter::Silent;
        }
        if Progress::detect(false).enabled {
            let bar = ProgressBar::new(total);
            bar.set_style(
                ProgressStyle::with_template(&format!("{what} {{pos}}/{{len}} {{bar:30}} {{msg}}"))
                    .unwrap_or_else(|_| ProgressStyle::default_bar()),
            );
            StepReporter::Bar(bar)
        } else {
            StepReporter::Lines
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

    /// Clear the bar.
    pub fn finish(&self) {
        if let StepReporter::Bar(bar) = self {
            bar.finish_and_clear();
        }
    }
}
