//! Helpers of the command-line tests: run the binary, name a fixture, a
//! fresh folder per test, a small simulated campaign.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Where the tests write their scratch folders: Cargo's per-target test
/// directory (inside `target/`, removed by `cargo clean`), not the system's
/// temporary directory, which would collect a folder per test per run.
pub fn scratch_root() -> PathBuf {
    PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
}

/// One `frfup demo --verbose` (stderr not a terminal, `CI` set), run once
/// per test process and shared by the tests that only read its folder: the
/// demo takes seconds and six tests read it. Never write into `dir`; copy
/// it first ([`copy_dir`]).
pub struct DemoRun {
    pub dir: PathBuf,
    pub status: std::process::ExitStatus,
    pub stdout: String,
    pub stderr: String,
}

pub fn demo() -> &'static DemoRun {
    static RUN: std::sync::OnceLock<DemoRun> = std::sync::OnceLock::new();
    RUN.get_or_init(|| {
        let dir = scratch_root().join(format!("frfup-demo-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let out = frfup(&["demo", "--verbose", "--out", dir.to_str().unwrap()]);
        DemoRun {
            dir,
            status: out.status,
            stdout: String::from_utf8_lossy(&out.stdout).into_owned(),
            stderr: String::from_utf8_lossy(&out.stderr).into_owned(),
        }
    })
}

/// The shared demo's folder, after checking that the demo succeeded.
pub fn demo_dir() -> &'static Path {
    let run = demo();
    assert!(run.status.success(), "frfup demo failed: {}", run.stderr);
    &run.dir
}

/// Copy the folder `from` (files and subfolders) to `to`, created.
pub fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        let target = to.join(entry.file_name());
        if entry.file_type().unwrap().is_dir() {
            copy_dir(&entry.path(), &target);
        } else {
            std::fs::copy(entry.path(), target).unwrap();
        }
    }
}

/// Run `frfup` with `args`, stderr not a terminal, `CI` set.
pub fn frfup(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_frfup"))
        .args(args)
        .env("CI", "true")
        .output()
        .expect("run frfup")
}

/// Run `frfup` on a pool of `threads` threads (`RAYON_NUM_THREADS`) and
/// insist on exit code 0.
pub fn frfup_ok_on_threads(args: &[&str], threads: &str) -> std::process::Output {
    let out = Command::new(env!("CARGO_BIN_EXE_frfup"))
        .args(args)
        .env("CI", "true")
        .env("RAYON_NUM_THREADS", threads)
        .output()
        .expect("run frfup");
    assert!(
        out.status.success(),
        "frfup {args:?} on {threads} threads: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// Run `frfup` and insist on exit code 0.
pub fn frfup_ok(args: &[&str]) -> std::process::Output {
    let out = frfup(args);
    assert!(
        out.status.success(),
        "frfup {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// A checked-in fixture, as a string argument.
pub fn fixture(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(rel)
        .to_str()
        .unwrap()
        .to_string()
}

/// A fresh, empty folder for one test.
pub fn workdir(name: &str) -> PathBuf {
    let dir = scratch_root().join(format!("frfup-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The paper's cantilever with its p3 doubled, simulated in `dir`: returns
/// (deck, test) paths; updating it converges in a few iterations.
pub fn cantilever_case(dir: &Path) -> (String, String) {
    let deck = dir.join("beam.deck");
    std::fs::copy(fixture("paper/cantilever.deck"), &deck).unwrap();
    let uff = dir.join("beam.uff");
    let sensors: Vec<String> = (2..=16).map(|n| format!("{n}:+z")).collect();
    frfup_ok(&[
        "simulate",
        deck.to_str().unwrap(),
        "--input",
        "16:+z",
        "--band",
        "0:300:1201",
        "--sensors",
        &sensors.join(","),
        "--set",
        "p3=1.0",
        "--out",
        uff.to_str().unwrap(),
    ]);
    (
        deck.to_str().unwrap().to_string(),
        uff.to_str().unwrap().to_string(),
    )
}

/// A path `name` in this process's scratch folder for the tests of `module`
/// (created; files of one module share it, so names must differ).
pub fn scratch(module: &str, name: &str) -> PathBuf {
    let dir = scratch_root().join(format!("frfup-cli-{module}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The rows of a CSV file as fields, header first (no quoted commas).
pub fn csv_rows(path: &Path) -> Vec<Vec<String>> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

/// Whether `python3` with pyuff runs here; prints why a test is skipped if not.
pub fn pyuff_available() -> bool {
    let ok = Command::new("python3")
        .args(["-c", "import pyuff"])
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    if !ok {
        println!("skipped: python3 with pyuff is not available");
    }
    ok
}

/// A JSON file.
pub fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}
