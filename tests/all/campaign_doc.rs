//! The campaign format's documentation follows its one definition: every key
//! a campaign case accepts (the update options and thresholds, read from the
//! same structs as the command line's flags) is listed in docs/campaign.md,
//! and the README's campaign example parses.

use std::path::Path;

use frfup::tasks::update::Thresholds;
use frfup::updating::options::long_names;
use frfup::updating::UpdateSettings;

fn doc() -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/campaign.md");
    std::fs::read_to_string(path).unwrap()
}

#[test]
fn every_key_is_documented() {
    let text = doc();
    let keys = UpdateSettings::names()
        .into_iter()
        .chain(long_names::<Thresholds>())
        .chain(["name", "model", "test"].map(String::from));
    let mut n = 0;
    for key in keys {
        assert!(
            text.contains(&format!("| `{key}` |")),
            "docs/campaign.md has no table row for `{key}`"
        );
        n += 1;
    }
    // 14 update options, 2 thresholds and the case's name, model and test.
    assert_eq!(n, 19);
}

#[test]
fn the_documented_example_parses() {
    let text = doc();
    let start = text.find("```toml\n").expect("an example") + "```toml\n".len();
    let end = start + text[start..].find("```").unwrap();
    let c = frfup::batch::campaign::parse(&text[start..end], Path::new("c.toml")).unwrap();
    assert_eq!(c.cases.len(), 1);
    assert_eq!(c.thresholds.min_sfdac, Some(0.9));
    assert_eq!(c.cases[0].thresholds.min_sfdac, Some(0.95));
    assert_eq!(c.cases[0].options.frequencies_hz, Some(vec![6.0, 24.0]));
}
