//! `--help`: every positional argument described, option help citing the
//! paper's equations, `--out` listing the files a run really writes, global
//! flags accepted after the command's own.

use std::collections::BTreeSet;
use std::path::Path;

use crate::cli_support::{cantilever_case, fixture, frfup, frfup_ok, workdir};

const COMMANDS: [&str; 8] = [
    "demo", "info", "convert", "modes", "simulate", "update", "diagnose", "batch",
];

fn help(command: &str) -> String {
    String::from_utf8(frfup_ok(&[command, "--help"]).stdout).unwrap()
}

/// The help of the option `flag` (`--out`): the rest of its line (short
/// help, every option on one line) or the paragraph below it (long help).
fn option_help(help: &str, flag: &str) -> String {
    let mut lines = help
        .lines()
        .skip_while(|l| !l.trim_start().starts_with(flag));
    let first = lines
        .next()
        .unwrap_or_else(|| panic!("{flag} not in:\n{help}"));
    let rest = first
        .trim()
        .split_once("  ")
        .map(|x| x.1.trim())
        .unwrap_or("");
    if !rest.is_empty() {
        return rest.to_string();
    }
    lines
        .take_while(|l| !l.trim().is_empty())
        .map(str::trim)
        .collect::<Vec<_>>()
        .join(" ")
}

#[test]
fn every_positional_argument_is_described() {
    for command in COMMANDS {
        let text = help(command);
        let mut lines = text.lines().skip_while(|l| *l != "Arguments:").skip(1);
        let mut seen = 0;
        while let Some(line) = lines.next() {
            if line.trim().is_empty() {
                continue;
            }
            if !line.starts_with("  <") {
                break;
            }
            seen += 1;
            // `<NAME>  text` (short help) or `<NAME>` then the text below.
            let after = line.trim().split_once(char::is_whitespace).map(|x| x.1);
            let description = match after.map(str::trim) {
                Some(text) if !text.is_empty() => text,
                _ => lines.next().unwrap_or_default().trim(),
            };
            assert!(
                !description.is_empty(),
                "{command}: {} has no description:\n{text}",
                line.trim()
            );
        }
        assert!(
            seen > 0 || command == "demo",
            "{command}: no positional?\n{text}"
        );
    }
}

#[test]
fn option_help_cites_the_paper_s_equations() {
    let text = help("update");
    for (flag, eq) in [
        ("--offset", "[Eq. 42]"),
        ("--svd-eps", "[Eq. 40]"),
        ("--tol", "[Eq. 49]"),
        ("--with-frequencies", "[Eq. 16-22]"),
        ("--modes", "[Eq. 32-34]"),
    ] {
        assert!(
            option_help(&text, flag).contains(eq),
            "{flag}: {eq}\n{text}"
        );
    }
    assert!(help("simulate").contains("--kind <KIND>"));
    assert!(!help("simulate").contains("--output"));
}

/// The files under `dir`, per-channel charts as `frf/NN-CHANNEL.svg`.
fn written(dir: &Path) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if e.path().is_dir() {
            names.insert(if name == "frf" {
                "frf/NN-CHANNEL.svg".to_string()
            } else {
                format!("{name}/")
            });
        } else {
            names.insert(name);
        }
    }
    names
}

/// The file names (`x.ext`) a help paragraph mentions.
fn mentioned(paragraph: &str) -> BTreeSet<String> {
    paragraph
        .split(|c: char| c.is_whitespace() || c == ',' || c == '(' || c == ')')
        .map(|w| w.trim_end_matches(['.', ';', ':']))
        .filter(|w| {
            let ext = w.rsplit('.').next().unwrap_or_default();
            w.contains('.')
                && ["csv", "json", "md", "html", "svg", "deck", "uff"].contains(&ext)
                && !w.starts_with("docs/")
        })
        .map(String::from)
        .collect()
}

fn assert_out_help_lists(command: &str, dir: &Path) {
    let said = mentioned(&option_help(&help(command), "--out"));
    let files = written(dir);
    assert_eq!(said, files, "{command} --out help vs the files written");
}

#[test]
fn out_help_lists_the_files_each_command_writes() {
    let dir = workdir("help-out");
    let (deck, uff) = cantilever_case(&dir);
    let update = dir.join("update");
    let out = frfup(&["update", &deck, &uff, "--out", update.to_str().unwrap()]);
    assert!(matches!(out.status.code(), Some(0 | 1)));
    assert_out_help_lists("update", &update);

    let diagnose = dir.join("diagnose");
    frfup_ok(&[
        "diagnose",
        &fixture("diagnose/damping.deck"),
        &fixture("diagnose/damping.uff"),
        "--out",
        diagnose.to_str().unwrap(),
    ]);
    assert_out_help_lists("diagnose", &diagnose);

    let campaign = dir.join("campaign.toml");
    std::fs::write(
        &campaign,
        "[[case]]\nname = \"beam\"\nmodel = \"beam.deck\"\ntest = \"beam.uff\"\n",
    )
    .unwrap();
    let batch = dir.join("batch");
    let out = frfup(&[
        "batch",
        campaign.to_str().unwrap(),
        "--out",
        batch.to_str().unwrap(),
    ]);
    assert!(matches!(out.status.code(), Some(0 | 1)));
    let said = mentioned(&option_help(&help("batch"), "--out"));
    let mut files = written(&batch);
    assert!(files.remove("beam/"), "{files:?}");
    assert_eq!(said, files);
    assert_eq!(written(&batch.join("beam")), written(&update));
}

#[test]
fn demo_out_help_lists_the_files_it_writes() {
    let dir = crate::cli_support::demo_dir();
    let said = mentioned(&option_help(&help("demo"), "--out"));
    let mut files = written(dir);
    assert!(files.remove("input/"), "{files:?}");
    for f in written(&dir.join("input")) {
        files.insert(format!("input/{f}"));
    }
    assert_eq!(said, files);
}

#[test]
fn global_flags_are_accepted_after_the_command_s_own() {
    let deck = fixture("paper/cantilever.deck");
    for flags in [vec!["--quiet"], vec!["--verbose", "--strict", "--progress"]] {
        let mut args = vec!["modes", deck.as_str(), "--count", "2"];
        args.extend(flags.iter().copied());
        frfup_ok(&args);
    }
}
