//! A catalogue of hostile inputs (decks, UFF files, options, campaigns,
//! special files), each with the outcome it must have: the exit code, words of
//! the message (naming the file where the input is bad), no panic, no kill by
//! a signal, and a bounded time. Every entry failed before its fix.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// What a run of frfup did.
struct Outcome {
    code: i32,
    stdout: String,
    stderr: String,
}

/// Run frfup with `args`; fail the test on a panic, a signal or a run longer
/// than `limit`.
fn run_within(args: &[&str], limit: Duration) -> Outcome {
    let mut child = Command::new(env!("CARGO_BIN_EXE_frfup"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run frfup");
    let (mut out, mut err) = (child.stdout.take().unwrap(), child.stderr.take().unwrap());
    let reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = out.read_to_end(&mut s);
        s
    });
    let err_reader = std::thread::spawn(move || {
        let mut s = Vec::new();
        let _ = err.read_to_end(&mut s);
        s
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait") {
            break status;
        }
        if start.elapsed() > limit {
            let _ = child.kill();
            let _ = child.wait();
            panic!("frfup {args:?} ran longer than {limit:?}");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let stdout = String::from_utf8_lossy(&reader.join().unwrap()).into_owned();
    let stderr = String::from_utf8_lossy(&err_reader.join().unwrap()).into_owned();
    let Some(code) = status.code() else {
        panic!("frfup {args:?} was killed by a signal: {status:?}\n{stderr}");
    };
    assert!(
        !stderr.contains("panicked"),
        "frfup {args:?} panicked:\n{stderr}"
    );
    Outcome {
        code,
        stdout,
        stderr,
    }
}

fn run(args: &[&str]) -> Outcome {
    run_within(args, Duration::from_secs(60))
}

/// Exit code 2 and a message holding every word of `words`.
fn refused(o: &Outcome, words: &[&str]) {
    assert_eq!(o.code, 2, "exit code; stderr:\n{}", o.stderr);
    for w in words {
        assert!(o.stderr.contains(w), "stderr lacks {w:?}:\n{}", o.stderr);
    }
}

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn fixture(rel: &str) -> String {
    root().join(rel).to_str().unwrap().to_string()
}

fn tmp_dir() -> PathBuf {
    let dir =
        crate::cli_support::scratch_root().join(format!("frfup-hostile-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn write(name: &str, bytes: &[u8]) -> String {
    let path = tmp_dir().join(name);
    std::fs::write(&path, bytes).unwrap();
    path.to_str().unwrap().to_string()
}

fn p(path: &Path) -> &str {
    path.to_str().unwrap()
}

const CANTILEVER: &str = "fixtures/paper/cantilever.deck";
const MEASUREMENT: &str = "fixtures/uff-real/pyuff/measurement.uff";

// ---------------------------------------------------------------- special files

#[test]
fn dev_zero_as_a_deck_or_a_uff_is_refused_at_once() {
    for args in [
        vec!["modes", "/dev/zero"],
        vec!["info", "/dev/zero"],
        vec!["convert", "/dev/zero", "out.csv"],
    ] {
        let o = run_within(&args, Duration::from_secs(10));
        refused(&o, &["/dev/zero", "character device"]);
    }
}

#[test]
fn a_directory_as_an_input_is_refused() {
    let dir = tmp_dir();
    let o = run(&["info", p(&dir)]);
    refused(&o, &[p(&dir), "a directory"]);
}

#[test]
fn an_endless_pipe_is_read_to_a_bound() {
    let fifo = tmp_dir().join("endless.fifo");
    let _ = std::fs::remove_file(&fifo);
    let made = Command::new("mkfifo").arg(&fifo).status();
    if !matches!(made, Ok(s) if s.success()) {
        eprintln!("no mkfifo: skipped");
        return;
    }
    // A writer that never ends until its reader goes away.
    let path = fifo.clone();
    std::thread::spawn(move || {
        use std::io::Write;
        if let Ok(mut f) = std::fs::OpenOptions::new().write(true).open(&path) {
            let block = vec![0u8; 1 << 20];
            while f.write_all(&block).is_ok() {}
        }
    });
    let o = run_within(&["modes", p(&fifo)], Duration::from_secs(60));
    refused(&o, &[p(&fifo), "more than 256 MiB"]);
}

// ---------------------------------------------------------------- options

#[test]
fn nan_thresholds_and_zero_counts_are_refused() {
    for (args, words) in [
        (
            vec![
                "update",
                CANTILEVER,
                MEASUREMENT,
                "--out",
                "o",
                "--fail-below-sfdac",
                "nan",
            ],
            vec!["--fail-below-sfdac", "finite"],
        ),
        (
            vec![
                "batch",
                "c.toml",
                "--out",
                "o",
                "--fail-above-freq-error",
                "inf",
            ],
            vec!["--fail-above-freq-error", "finite"],
        ),
        (
            vec!["batch", "c.toml", "--out", "o", "--jobs", "0"],
            vec!["--jobs", "at least 1"],
        ),
        (
            vec!["modes", CANTILEVER, "--count", "0"],
            vec!["--count", "at least 1"],
        ),
    ] {
        let o = run(&args);
        refused(&o, &words);
    }
}

#[test]
fn repeated_updating_frequencies_are_refused() {
    let o = run(&[
        "update",
        &fixture(CANTILEVER),
        &fixture(MEASUREMENT),
        "--out",
        "o",
        "--freqs",
        "3,3,3",
    ]);
    refused(&o, &["freqs", "3 Hz is given more than once"]);
}

#[test]
fn negative_option_values_reach_frfups_own_checks() {
    let deck = fixture(CANTILEVER);
    let out = tmp_dir().join("neg.uff");
    // Negative numbers are values, not flags: frfup's own check answers.
    let o = run(&[
        "simulate",
        &deck,
        "--input",
        "11:3",
        "--band",
        "-10:200:10",
        "--out",
        p(&out),
    ]);
    refused(&o, &["--band", "F0 is negative"]);
    for flag in ["--offset", "--damping"] {
        let o = run(&[
            "update",
            "missing.deck",
            "missing.uff",
            "--out",
            "o",
            flag,
            "-1",
        ]);
        assert!(
            !o.stderr.contains("unexpected argument"),
            "{flag}: {}",
            o.stderr
        );
        refused(&o, &["missing.deck"]);
    }
}

#[test]
fn huge_bands_are_refused_before_allocating() {
    let deck = fixture(CANTILEVER);
    let out = tmp_dir().join("huge.uff");
    for band in ["0:200:100000000", "0:200:1000000000000"] {
        let o = run_within(
            &[
                "simulate",
                &deck,
                "--input",
                "11:3",
                "--band",
                band,
                "--out",
                p(&out),
            ],
            Duration::from_secs(20),
        );
        refused(&o, &["--band", "more than 1000000"]);
    }
    let o = run_within(
        &[
            "simulate",
            &deck,
            "--input",
            "11:3",
            "--band",
            "0:200:900000",
            "--sensors",
            &vec!["11:3"; 400].join(","),
            "--out",
            p(&out),
        ],
        Duration::from_secs(20),
    );
    refused(&o, &["GiB of FRF values"]);
    assert!(!out.exists());
}

// ---------------------------------------------------------------- UFF files

/// measurement.uff with its second record turned into a coherence (function type 6).
fn frf_and_coherence() -> String {
    let text = std::fs::read_to_string(fixture(MEASUREMENT)).unwrap();
    let mut seen = 0;
    let lines: Vec<String> = text
        .split('\n')
        .map(|l| {
            if l.starts_with("    4         0    0") {
                seen += 1;
                if seen == 2 {
                    return l.replacen("    4", "    6", 1);
                }
            }
            l.to_string()
        })
        .collect();
    assert_eq!(seen, 3);
    write("frf_coherence.uff", lines.join("\n").as_bytes())
}

#[test]
fn convert_to_a_kind_carries_a_coherence_unconverted() {
    let input = frf_and_coherence();
    for kind in ["mobility", "receptance", "accelerance", "displacement-real"] {
        let out = tmp_dir().join(format!("conv-{kind}.uff"));
        let o = run(&["convert", &input, p(&out), "--to", kind]);
        assert_eq!(o.code, 0, "{kind}: {}", o.stderr);
        assert!(
            o.stderr.contains("selected record 2") && o.stderr.contains("coherence"),
            "{}",
            o.stderr
        );
        let info = run(&["info", p(&out)]);
        assert_eq!(info.stdout.matches(" 4 FRF ").count(), 2, "{}", info.stdout);
        assert_eq!(
            info.stdout.matches(" 6 coherence ").count(),
            1,
            "{}",
            info.stdout
        );
    }
}

/// measurement.uff without its first `-1` line: its first channel is lost.
fn missing_first_delimiter() -> String {
    let text = std::fs::read_to_string(fixture(MEASUREMENT)).unwrap();
    let rest = text.split_once('\n').unwrap().1;
    write("no_first_delimiter.uff", rest.as_bytes())
}

#[test]
fn a_lost_channel_is_a_warning_and_strict_refuses_it() {
    let input = missing_first_delimiter();
    let out = tmp_dir().join("lost.csv");
    let o = run(&["convert", &input, p(&out)]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(
        o.stderr.contains(&format!(
            "warning: {input}: line 1: 513 line(s) outside any dataset ignored"
        )),
        "{}",
        o.stderr
    );
    let _ = std::fs::remove_file(&out);
    let o = run(&["--strict", "convert", &input, p(&out)]);
    refused(&o, &[&input, "--strict"]);
    assert!(!out.exists());
    // update and diagnose print the same warning, and refuse under --strict
    // before any computation.
    for cmd in ["update", "diagnose"] {
        let dir = tmp_dir().join(format!("strict-{cmd}"));
        let o = run(&[
            "--strict",
            cmd,
            &fixture(CANTILEVER),
            &input,
            "--out",
            p(&dir),
        ]);
        refused(&o, &[&input, "outside any dataset", "--strict"]);
        assert!(!dir.exists(), "{cmd} left {dir:?}");
    }
}

#[test]
fn an_even_abscissa_that_does_not_increase_is_refused() {
    let text =
        std::fs::read_to_string(fixture("fixtures/uff-real/uffl-jl/dataset58_FRF.unv")).unwrap();
    for (name, step) in [("dx0.unv", " 0.00000E+00"), ("dxneg.unv", "-5.00000E-01")] {
        let bad = text.replacen(" 5.00000E-01", step, 1);
        assert_ne!(bad, text);
        let input = write(name, bad.as_bytes());
        let o = run(&["info", &input]);
        refused(&o, &[&input, "line 9", "increment", "must be > 0"]);
    }
}

#[test]
fn channels_named_by_entities_show_their_names_and_map_to_nodes() {
    let input = fixture("fixtures/uff-real/uffl-jl/dataset58_FRF.unv");
    let o = run(&["info", &input]);
    assert!(
        o.stdout.contains(".1.Z-") && o.stdout.contains(".56.Z"),
        "{}",
        o.stdout
    );
    let o = run(&["info", &input, "--json"]);
    let v: serde_json::Value = serde_json::from_str(&o.stdout).unwrap();
    assert_eq!(v["records"][0]["response"], ".1.Z-");
    assert_eq!(v["records"][0]["reference_entity"], ".56.Z");
    let out = tmp_dir().join("named.csv");
    let o = run(&["convert", &input, p(&out)]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let csv = std::fs::read_to_string(&out).unwrap();
    assert!(
        csv.starts_with("frequency_hz,.1.Z-/.56.Z re[(m/s)/N],.1.Z-/.56.Z im[(m/s)/N]\n"),
        "{}",
        &csv[..80]
    );
    let loaded = frfup::testdata::load_with_notes(Path::new(&input)).unwrap();
    let c = &loaded.frfs.channels[0];
    assert_eq!((c.response_node, c.response_direction), (1, -3));
    assert_eq!((c.reference_node, c.reference_direction), (56, 3));
    assert!(
        loaded
            .notes
            .iter()
            .any(|n| n.contains(".1.Z-/.56.Z as 1-z/56+z")),
        "{:?}",
        loaded.notes
    );
}

#[test]
fn a_58b_record_read_in_the_wrong_byte_order_is_named() {
    use frfup_parsers::uff::{self, Dataset, Ordinate};
    let file = uff::parse(&std::fs::read(fixture(MEASUREMENT)).unwrap()).unwrap();
    let Dataset::Function(f) = &file.datasets[0] else {
        panic!()
    };
    let mut f = (**f).clone();
    // Values whose bytes, read the other way round, are 1e-3..1e-1: as read, ~1e290.
    let swap = |x: f64| f64::from_bits(x.to_bits().swap_bytes());
    let n = f.len();
    f.ordinate = Ordinate::Complex(
        (0..n)
            .map(|i| uff::Complex64::new(swap(1e-3 * (1.0 + i as f64 / n as f64)), swap(2e-3)))
            .collect(),
    );
    f.binary = true;
    let mut bytes = Vec::new();
    uff::write_functions(&mut bytes, &[f]).unwrap();
    let input = write("wrong_byte_order.uff", &bytes);
    let out = tmp_dir().join("wrong_byte_order.csv");
    let o = run(&["convert", &input, p(&out)]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    assert!(
        o.stderr.contains("which no FRF has")
            && o.stderr.contains("other byte order")
            && o.stderr.contains("at most 2e-3"),
        "{}",
        o.stderr
    );
}

#[test]
fn a_time_record_and_a_second_reference_among_frfs_are_warned() {
    let text = std::fs::read_to_string(fixture(MEASUREMENT)).unwrap();
    let mut k = 0;
    let lines: Vec<String> = text
        .split('\n')
        .map(|l| {
            if l.starts_with("    4         0    0") {
                k += 1;
                match k {
                    2 => return l.replacen("    4", "    1", 1),
                    3 => return format!("{}2   1\r", &l[..l.len() - 6]),
                    _ => {}
                }
            }
            l.to_string()
        })
        .collect();
    let input = write("time_and_reference.uff", lines.join("\n").as_bytes());
    let dir = tmp_dir().join("strict-time");
    let o = run(&[
        "--strict",
        "update",
        &fixture(CANTILEVER),
        &input,
        "--out",
        p(&dir),
    ]);
    refused(
        &o,
        &[
            &input,
            "dataset #2",
            "time record",
            "not an FRF: skipped",
            // The second reference makes the two FRFs a row of H.
            "roving hammer: 2 impact point(s)",
        ],
    );
}

// ---------------------------------------------------------------- decks

/// A slender cantilever bolted near its root by six stiff springs between
/// coincident nodes (the standard bolted joint, and what `diagnose` writes).
const JOINT: &str = "\
title slender cantilever bolted near its root by a joint of six stiff springs
analysis space
material steel E=2.1e11 G=8.1e10 rho=7850
section rod A=1e-4 Iy=1e-9 Iz=1e-9 J=2e-9
node 1 0 0 0
node 2 0.01 0 0
node 3 0.01 0 0
node 4 1 0 0
node 5 2 0 0
node 6 3 0 0
beam 1 1 2 steel rod
beam 2 3 4 steel rod
beam 3 4 5 steel rod
beam 4 5 6 steel rod
fix 1 all
spring 1 2 x k=1e10 to=3
spring 2 2 y k=1e10 to=3
spring 3 2 z k=1e10 to=3
spring 4 2 rx k=3000 to=3
spring 5 2 ry k=3000 to=3
spring 6 2 rz k=3000 to=3
";

#[test]
fn a_stiff_joint_is_not_a_mechanism() {
    let deck = write("joint.deck", JOINT.as_bytes());
    let o = run(&["modes", &deck, "--count", "4"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let first: f64 = o
        .stdout
        .lines()
        .nth(1)
        .unwrap()
        .split_whitespace()
        .nth(1)
        .unwrap()
        .parse()
        .unwrap();
    // 0.97295 Hz (about 5 % below the rigidly clamped 1.024 Hz): an eigen
    // solve, exact but for the five decimals `modes` prints.
    assert!((first - 0.97295).abs() <= 1e-5, "{}", o.stdout);
}

#[test]
fn a_real_mechanism_names_its_nodes_and_dofs() {
    // Without the torsion spring the outer part turns freely about x.
    let text: String = JOINT
        .lines()
        .filter(|l| !l.starts_with("spring 4"))
        .map(|l| format!("{l}\n"))
        .collect();
    let deck = write("mechanism.deck", text.as_bytes());
    let o = run(&["modes", &deck]);
    refused(
        &o,
        &[
            &deck,
            "1 mechanism",
            "node 3 rx, node 4 rx, node 5 rx, node 6 rx",
        ],
    );
}

#[test]
fn a_dof_without_mass_is_named_by_node_and_dof() {
    let text = format!("{JOINT}node 7 3 0 0\nspring 7 6 x k=1e6 to=7\n");
    let deck = write("massless.deck", text.as_bytes());
    let o = run(&["modes", &deck]);
    refused(&o, &[&deck, "node 7 DOF x is free but has no mass"]);
    assert!(!o.stderr.contains("equation"), "{}", o.stderr);
}

#[test]
fn misleading_deck_messages_name_the_real_cause() {
    let good = std::fs::read_to_string(fixture(CANTILEVER)).unwrap();
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        (
            "nbsp.deck",
            good.replace("node 5 0.48 0 0", "node 5 0.48 0\u{a0}0"),
            vec![":10:14:", "non-breaking space"],
        ),
        (
            "nul.deck",
            good.replace("node 5 0.48 0 0", "node 5 0.48 0\u{0}0"),
            vec![":10:14:", "NUL byte"],
        ),
        (
            "empty.deck",
            String::new(),
            vec![":1:1:", "the deck is empty"],
        ),
        (
            "comments.deck",
            "# nothing\n\n# here\n".into(),
            vec![":1:1:", "no `node` statement"],
        ),
        (
            "far.deck",
            good.replace("node 16 1.80 0 0", "node 16 1e200 0 0"),
            vec![":21:1:", "node 16", "1e200"],
        ),
        (
            "stiff.deck",
            good.replace("E=2e11", "E=1e308"),
            vec![":4:1:", "E = 1e308"],
        ),
    ];
    for (name, text, words) in cases {
        let deck = write(name, text.as_bytes());
        let o = run(&["modes", &deck, "--count", "2"]);
        let mut all = vec![deck.as_str()];
        all.extend(words);
        refused(&o, &all);
    }
}

#[test]
fn cr_only_line_ends_are_line_ends() {
    let good = std::fs::read_to_string(fixture(CANTILEVER)).unwrap();
    let deck = write("cr.deck", good.replace('\n', "\r").as_bytes());
    let o = run(&["modes", &deck, "--count", "2"]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let reference = run(&["modes", &fixture(CANTILEVER), "--count", "2"]);
    assert_eq!(o.stdout, reference.stdout);
}

#[test]
fn a_huge_title_is_capped_where_it_is_echoed() {
    let good = std::fs::read_to_string(fixture(CANTILEVER)).unwrap();
    let text = format!("title {}\n{good}", "x".repeat(5_000_000));
    let deck = frfup_parsers::deck::parse(&text).unwrap();
    let title = deck.title();
    assert!(
        title.len() < 2000 && title.contains("more characters"),
        "{}",
        title.len()
    );
}

// ---------------------------------------------------------------- output folders

#[test]
fn an_unusable_out_is_refused_before_computing() {
    let file = write("existing_file", b"not a folder");
    let garteur = fixture("fixtures/garteur/garteur_suspended.deck");
    let campaign = fixture("fixtures/garteur/campaign.uff");
    for cmd in ["update", "diagnose"] {
        let o = run_within(
            &[cmd, &garteur, &campaign, "--out", &file],
            Duration::from_secs(5),
        );
        refused(&o, &["--out", &file, "exists and is not a folder"]);
    }
    let o = run_within(&["batch", "c.toml", "--out", &file], Duration::from_secs(5));
    refused(&o, &["exists and is not a folder"]);
    assert_eq!(std::fs::read(&file).unwrap(), b"not a folder");
}

#[test]
fn update_writes_its_folder_whole_and_leaves_no_temporary() {
    let parent = tmp_dir().join("whole");
    let _ = std::fs::remove_dir_all(&parent);
    std::fs::create_dir_all(&parent).unwrap();
    let out = parent.join("result");
    let o = run_within(
        &[
            "update",
            &fixture("fixtures/garteur/garteur_suspended.deck"),
            &fixture("fixtures/garteur/campaign.uff"),
            "--out",
            p(&out),
            "--max-iter",
            "1",
        ],
        Duration::from_secs(300),
    );
    assert!(o.code <= 1, "{}", o.stderr);
    let names: Vec<String> = std::fs::read_dir(&parent)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        vec!["result".to_string()],
        "a temporary folder was left"
    );
    for f in ["report.json", "parameters.csv", "updated.deck", "report.md"] {
        assert!(out.join(f).is_file(), "{f} missing");
    }
}

/// SIGINT while `simulate` writes a large UFF file: exit 130, no temporary
/// file left, no output. The cantilever (24 DOFs) at 200,000 lines solves
/// in about 0.5 s and then writes 130 MB for about 2.5 s (test build), a
/// window the 2 ms polling below cannot miss.
#[test]
fn ctrl_c_while_writing_leaves_no_temporary_file() {
    let dir = tmp_dir().join("sigint");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("big.uff");
    let mut child = Command::new(env!("CARGO_BIN_EXE_frfup"))
        .args([
            "--quiet",
            "simulate",
            &fixture("fixtures/diagnose/added_mass.truth.deck"),
            "--input",
            "9:3",
            "--band",
            "1:200:200000",
            "--out",
            p(&out),
        ])
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let tmp = dir.join(format!(".big.uff.{}.tmp", child.id()));
    let start = Instant::now();
    let mut seen = false;
    while start.elapsed() < Duration::from_secs(240) {
        if tmp.exists() {
            seen = true;
            break;
        }
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(
        seen,
        "the temporary file never appeared (the run ended first?)"
    );
    let _ = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "{status:?}");
    assert!(!tmp.exists(), "{tmp:?} was left behind");
    assert!(!out.exists());
}

#[test]
fn a_missing_first_delimiter_is_named_as_such() {
    let input = missing_first_delimiter();
    let o = run(&["info", &input]);
    let said = format!("{}{}", o.stdout, o.stderr);
    assert!(
        said.contains(
            "line 1 reads like a dataset number: a '    -1' delimiter seems missing before it"
        ),
        "{said}"
    );
}

#[test]
fn a_mechanism_inside_update_names_its_nodes_and_dofs() {
    // The joint's deck with a parameter gives a campaign; without the torsion
    // spring the same deck is a mechanism, found by the update's eigen solve.
    let with_param = format!("{JOINT}param p1 Iy 2-4\n");
    let deck = write("joint_param.deck", with_param.as_bytes());
    let uff = tmp_dir().join("joint.uff");
    let o = run(&[
        "simulate",
        &deck,
        "--input",
        "6:+z",
        "--band",
        "0:100:201",
        "--out",
        p(&uff),
    ]);
    assert_eq!(o.code, 0, "{}", o.stderr);
    let text: String = with_param
        .lines()
        .filter(|l| !l.starts_with("spring 4"))
        .map(|l| format!("{l}\n"))
        .collect();
    let mech = write("mechanism_param.deck", text.as_bytes());
    for cmd in ["update", "diagnose"] {
        let out = tmp_dir().join(format!("mech-{cmd}"));
        let o = run(&[cmd, &mech, p(&uff), "--out", p(&out)]);
        refused(&o, &["mechanism", "node 3 rx"]);
        assert!(!o.stderr.contains("equation"), "{cmd}: {}", o.stderr);
    }
}

/// Start `args`, wait until the path `appears(child's pid)` exists, send
/// SIGINT; returns the exit code.
fn interrupt_when(args: &[&str], appears: impl Fn(u32) -> PathBuf) -> Option<i32> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_frfup"))
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    let appears = appears(child.id());
    let start = Instant::now();
    while start.elapsed() < Duration::from_secs(120) && !appears.exists() {
        if child.try_wait().unwrap().is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(2));
    }
    assert!(appears.exists(), "{appears:?} never appeared");
    let _ = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status();
    child.wait().unwrap().code()
}

#[test]
fn batch_and_demo_write_their_folders_whole() {
    let parent = tmp_dir().join("whole-batch");
    let _ = std::fs::remove_dir_all(&parent);
    std::fs::create_dir_all(&parent).unwrap();
    let campaign = parent.join("c.toml");
    std::fs::write(
        &campaign,
        format!(
            "[[case]]\nname = \"g\"\nmodel = \"{}\"\ntest = \"{}\"\n",
            fixture("fixtures/garteur/garteur_suspended.deck"),
            fixture("fixtures/garteur/campaign.uff")
        ),
    )
    .unwrap();
    // Interrupted once its first case is being written: nothing of it lands.
    let out = parent.join("batch");
    let code = interrupt_when(
        &["--quiet", "batch", p(&campaign), "--out", p(&out)],
        |pid| parent.join(format!(".batch.{pid}.tmp")),
    );
    assert_eq!(code, Some(130));
    assert!(!out.exists(), "an interrupted batch left {out:?}");
    // The demo's inputs are written first: interrupted during the update,
    // they must not be left alone in its folder.
    let demo = parent.join("demo");
    let code = interrupt_when(&["--quiet", "demo", "--out", p(&demo)], |pid| {
        parent
            .join(format!(".demo.{pid}.tmp"))
            .join("input/campaign.uff")
    });
    assert_eq!(code, Some(130));
    assert!(!demo.exists(), "an interrupted demo left {demo:?}");
    let names: Vec<String> = std::fs::read_dir(&parent)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert_eq!(names, vec!["c.toml".to_string()], "temporaries were left");
}
