//! Unit tests of `src/updating/options.rs` through its public interface.

use clap::Parser;
use frfup::updating::options::*;
use frfup::updating::serep::InverseMethod;

/// `frfup update`'s way of taking the settings: flattened among positionals.
#[derive(Parser)]
struct Cli {
    #[command(flatten)]
    settings: UpdateSettings,
    files: Vec<String>,
}

fn cli(args: &[&str]) -> Cli {
    Cli::try_parse_from(std::iter::once("frfup").chain(args.iter().copied())).unwrap()
}

#[test]
fn unset_options_take_the_chosen_methods_preset() {
    let none = UpdateSettings::default();
    assert_eq!(none.resolve(UpdateMethod::Robust), UpdateOptions::default());
    assert_eq!(none.resolve(UpdateMethod::Paper), UpdateOptions::paper());
    let c = cli(&["--method", "paper", "--offset", "0.1", "deck", "test"]);
    assert_eq!(c.files, ["deck", "test"]);
    let o = c.settings.resolve(UpdateMethod::Robust);
    assert_eq!(
        o,
        UpdateOptions {
            offset: 0.1,
            ..UpdateOptions::paper()
        }
    );
}

#[test]
fn switches_take_no_value_unless_written_with_equals() {
    let c = cli(&[
        "--with-frequencies",
        "deck",
        "--frequencies-first=false",
        "test",
    ]);
    assert_eq!(c.files, ["deck", "test"]);
    let o = c.settings.resolve(UpdateMethod::Robust);
    assert!(o.with_frequencies && !o.frequencies_first);
}

#[test]
fn the_inverse_takes_its_perturbation() {
    let c = cli(&["--inverse", "perturb", "--perturbation", "1e-6"]);
    let o = c.settings.resolve(UpdateMethod::Paper);
    assert_eq!(o.inverse, InverseMethod::Perturb { relative: 1e-6 });
    let c = cli(&["--inverse", "perturb"]);
    let o = c.settings.resolve(UpdateMethod::Paper);
    assert_eq!(
        o.inverse,
        InverseMethod::Perturb {
            relative: DEFAULT_PERTURBATION
        }
    );
}

#[test]
fn frequencies_are_positive_and_given_once() {
    let f: Frequencies = "6, 24".parse().unwrap();
    assert_eq!(f.0, [6.0, 24.0]);
    assert_eq!(
        "3,3".parse::<Frequencies>().unwrap_err(),
        "3 Hz is given more than once"
    );
    assert!("-1".parse::<Frequencies>().is_err());
    assert!(","
        .parse::<Frequencies>()
        .unwrap_err()
        .contains("no frequency"));
}

/// The keys and values of `report.json`'s `options`.
#[test]
fn the_options_serialise_as_report_json_writes_them() {
    let v = serde_json::to_value(UpdateOptions::paper()).unwrap();
    let keys: Vec<&String> = v.as_object().unwrap().keys().collect();
    assert_eq!(
        keys,
        [
            "basis_tolerance",
            "damping",
            "freqs",
            "frequencies_first",
            "inverse",
            "mac_min",
            "max_iter",
            "max_parameter",
            "min_prominence",
            "modes",
            "offset",
            "perturbation",
            "resonance_method",
            "resonances",
            "svd_eps",
            "tol",
            "weighting",
            "with_frequencies",
        ]
    );
    assert_eq!(v["inverse"], "svd");
    assert!(v["perturbation"].is_null());
    assert_eq!(v["resonance_method"], "peaks");
    assert_eq!(v["weighting"], "none");
    let o = UpdateOptions {
        inverse: InverseMethod::Perturb { relative: 1e-6 },
        weighting: FrfWeighting::PerFrequency,
        ..UpdateOptions::default()
    };
    let v = serde_json::to_value(o).unwrap();
    assert_eq!(v["inverse"], "perturb");
    assert_eq!(v["perturbation"], 1e-6);
    assert_eq!(v["resonance_method"], "fit");
    assert_eq!(v["weighting"], "per-frequency");
}
