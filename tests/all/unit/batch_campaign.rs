//! Unit tests of `src/batch/campaign.rs` through its public interface.

use frfup::batch::campaign::*;
use frfup::tasks::update::Thresholds;
use frfup::updating::options::long_names;
use frfup::updating::UpdateMethod;
use frfup::updating::UpdateOptions;
use frfup::updating::UpdateSettings;
use std::path::Path;

const CASE: &str = "[[case]]\nname = \"a\"\nmodel = \"m.deck\"\ntest = \"t.uff\"\n";

fn parsed(text: &str) -> Result<Campaign, String> {
    parse(text, Path::new("dir/c.toml")).map_err(|e| e.message)
}

#[test]
fn every_key_is_documented() {
    let doc = include_str!("../../../docs/campaign.md");
    for key in UpdateSettings::names()
        .into_iter()
        .chain(long_names::<Thresholds>())
    {
        assert!(
            doc.contains(&format!("| `{key}` |")),
            "docs/campaign.md does not describe `{key}`"
        );
    }
}

#[test]
fn options_resolve_from_the_cases_method() {
    let c = parsed(&format!(
        "fail_below_sfdac = 0.5\n{CASE}method = \"paper\"\noffset = 0.1\nfreqs = [6, 24.5]\nmax_iter = 3\nfail-above-freq-error = 2\n"
    ))
    .unwrap();
    let case = &c.cases[0];
    assert_eq!(case.model, Path::new("dir/m.deck"));
    assert_eq!(
        case.options,
        UpdateOptions {
            offset: 0.1,
            frequencies_hz: Some(vec![6.0, 24.5]),
            max_iter: 3,
            ..UpdateOptions::paper()
        }
    );
    assert_eq!(c.thresholds.min_sfdac, Some(0.5));
    assert_eq!(case.thresholds.max_freq_error_pct, Some(2.0));
    let text = parsed(&format!("{CASE}freqs = \"6,24.5\"\n")).unwrap();
    assert_eq!(text.cases[0].options.frequencies_hz, Some(vec![6.0, 24.5]));
    assert_eq!(text.cases[0].options.method, UpdateMethod::Robust);
}

#[test]
fn errors_name_the_file_the_case_and_the_key() {
    for (extra, words) in [
        ("modez = 3\n", vec!["unknown key `modez`", "max-iter"]),
        ("modes = -1\n", vec!["`modes`", "-1"]),
        ("offset = nan\n", vec!["`offset`", "finite"]),
        (
            "freqs = [3, 3]\n",
            vec!["`freqs`", "3 Hz is given more than once"],
        ),
        ("method = \"fast\"\n", vec!["`method`", "paper"]),
        (
            "fail_below_sfdac = 1\nfail-below-sfdac = 1\n",
            vec!["`fail-below-sfdac` is given twice"],
        ),
    ] {
        let e = parsed(&format!("{CASE}{extra}")).unwrap_err();
        assert!(e.starts_with("dir/c.toml: case #1 (a): "), "{e}");
        for w in words {
            assert!(e.contains(w), "{extra}: {e}");
        }
    }
    let e = parsed(&format!("fail-below = 1\n{CASE}")).unwrap_err();
    assert!(e.contains("unknown top-level key `fail-below`"), "{e}");
}
