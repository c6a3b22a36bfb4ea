//! One MAC shape source: the MAC chart and mac.csv use the test shapes that
//! paired the resonances, so their outlined (paired) cells equal the MAC of
//! the frequency table, and both name the source.

use std::collections::HashMap;

use crate::cli_support::{cantilever_case, frfup, workdir};

fn rows(path: &std::path::Path) -> Vec<HashMap<String, String>> {
    let mut r = csv::Reader::from_path(path).unwrap();
    let header: Vec<String> = r.headers().unwrap().iter().map(String::from).collect();
    r.records()
        .map(|rec| {
            header
                .iter()
                .cloned()
                .zip(rec.unwrap().iter().map(String::from))
                .collect()
        })
        .collect()
}

#[test]
fn the_mac_chart_and_the_frequency_table_agree() {
    let dir = workdir("mac");
    let (deck, uff) = cantilever_case(&dir);
    // The cantilever's undamped FRFs admit no pole fit: peaks and their
    // deflection shapes, whatever the method; the demo's are fitted.
    let demo = crate::cli_support::demo_dir().to_path_buf();
    let mut cases = vec![(demo, "fitted")];
    for method in ["robust", "paper"] {
        let out = dir.join(method);
        let o = frfup(&[
            "update",
            "--method",
            method,
            &deck,
            &uff,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(matches!(o.status.code(), Some(0 | 1)), "{method}");
        cases.push((out, "ods"));
    }
    for (out, shapes) in cases {
        check_one_source(&out, shapes);
    }
}

/// Paired cells of mac.csv equal the frequency table's MAC; the shapes are
/// `shapes` and the chart and the page name them.
fn check_one_source(out: &std::path::Path, shapes: &str) {
    let freq = rows(&out.join("frequencies.csv"));
    let mac = rows(&out.join("mac.csv"));
    let mut paired = 0;
    for m in &mac {
        assert_eq!(m["test_shapes"], shapes, "{}", out.display());
    }
    for m in mac.iter().filter(|m| m["paired"] == "true") {
        let t: usize = m["test_resonance"].parse().unwrap();
        let column = match m["model"].as_str() {
            "initial model" => "initial_mac",
            _ => "updated_mac",
        };
        let table: f64 = freq[t - 1][column].parse().unwrap();
        let chart: f64 = m["mac"].parse().unwrap();
        // frequencies.csv has 4 decimals, mac.csv 6.
        assert!(
            (table - chart).abs() <= 5e-5 + 1e-9,
            "{} R{t} {column}: table {table} vs chart {chart}",
            out.display()
        );
        paired += 1;
    }
    assert!(paired >= 6, "{}: {paired} paired cells", out.display());
    let words = match shapes {
        "fitted" => "fitted mode shapes",
        _ => "operating deflection shapes (ODS)",
    };
    let svg = std::fs::read_to_string(out.join("mac.svg")).unwrap();
    // The SVG escapes the apostrophe.
    let title = format!("MAC of the test&apos;s {words} vs FE modes");
    assert!(svg.contains(&title), "{}: {title}", out.display());
    let short = if shapes == "fitted" {
        "fitted shapes"
    } else {
        "ODS"
    };
    let scale = format!("MAC of the {short} (dimensionless)");
    assert!(svg.contains(&scale), "{}: {scale}", out.display());
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(
        html.contains(&format!("MAC of the {words}")),
        "{}",
        out.display()
    );
}
