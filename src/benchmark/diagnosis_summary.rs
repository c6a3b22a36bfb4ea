//! The summary of a diagnosis benchmark run: the three rates of the issue,
//! a confusion matrix (true class × reported class), the rates by class and
//! by detectability, and times.

use std::collections::{BTreeMap, BTreeSet};

use super::effect::CLASSES;
use super::score_diagnosis::DiagScore;

/// One case of a diagnosis run: what it was and how it went.
#[derive(Clone, Debug, Default)]
pub struct DiagRecord {
    pub case: String,
    pub seed: u64,
    pub structure: String,
    pub support: String,
    pub layout: String,
    pub dofs: usize,
    pub channels: usize,
    pub lines: usize,
    pub noise: f64,
    /// Exit code of `frfup diagnose` (None: killed or did not start).
    pub exit_code: Option<i32>,
    pub seconds: f64,
    pub score: DiagScore,
    /// The last stderr line of a failed run.
    pub message: String,
}

impl DiagRecord {
    pub const CSV_HEADER: [&'static str; 16] = [
        "case",
        "seed",
        "structure",
        "support",
        "layout",
        "dofs",
        "channels",
        "lines",
        "noise",
        "truth",
        "reported",
        "right",
        "false_findings",
        "values",
        "exit_code",
        "seconds",
    ];
    /// The CSV row: the truth as `class@nodes(frf change)`, the findings as
    /// `class@nodes`, per effect `class:ok|place|physics|miss` and the value
    /// ratios.
    pub fn csv_fields(&self) -> Vec<String> {
        let nodes = |n: &[u32]| n.iter().map(u32::to_string).collect::<Vec<_>>().join(",");
        let s = &self.score;
        let truth: Vec<String> = s
            .effects
            .iter()
            .map(|e| format!("{}@{}(D={:.3})", e.class, nodes(&e.nodes), e.frf_change))
            .collect();
        let reported: Vec<String> = s
            .reported
            .iter()
            .map(|(c, n)| format!("{c}@{}", nodes(n)))
            .collect();
        let values: Vec<String> = s
            .effects
            .iter()
            .filter_map(|e| Some(format!("{}:{:.3}", e.class, e.value_ratio?)))
            .collect();
        vec![
            self.case.clone(),
            self.seed.to_string(),
            self.structure.clone(),
            self.support.clone(),
            self.layout.clone(),
            self.dofs.to_string(),
            self.channels.to_string(),
            self.lines.to_string(),
            format!("{}", self.noise),
            truth.join(" "),
            reported.join(" "),
            s.right().to_string(),
            s.false_findings.join(" "),
            values.join(" "),
            self.exit_code.map(|c| c.to_string()).unwrap_or_default(),
            format!("{:.3}", self.seconds),
        ]
    }
}

fn pct(a: usize, n: usize) -> String {
    if n == 0 {
        "n/a".into()
    } else {
        format!("{:.1} % ({a}/{n})", 100.0 * a as f64 / n as f64)
    }
}

/// The three rates and the times.
fn rates(rows: &[DiagRecord]) -> String {
    let effect_cases: Vec<&DiagRecord> = rows.iter().filter(|r| !r.score.is_control()).collect();
    let controls: Vec<&DiagRecord> = rows.iter().filter(|r| r.score.is_control()).collect();
    let right = effect_cases.iter().filter(|r| r.score.right()).count();
    let tied = effect_cases
        .iter()
        .filter(|r| r.score.right_or_tied())
        .count();
    let effects: Vec<_> = effect_cases.iter().flat_map(|r| &r.score.effects).collect();
    let placed = effects.iter().filter(|e| e.place).count();
    let false_any = rows
        .iter()
        .filter(|r| !r.score.false_findings.is_empty())
        .count();
    let false_ctrl = controls
        .iter()
        .filter(|r| !r.score.false_findings.is_empty())
        .count();
    let valued: Vec<_> = effects.iter().filter_map(|e| e.value_ok).collect();
    let within = valued.iter().filter(|v| **v).count();
    let mut t: Vec<f64> = rows.iter().map(|r| r.seconds).collect();
    t.sort_by(f64::total_cmp);
    let median = t.get(t.len() / 2).copied().unwrap_or(0.0);
    let worst = t.last().copied().unwrap_or(0.0);
    let mut exits: BTreeMap<String, usize> = BTreeMap::new();
    for r in rows {
        let k = r.exit_code.map_or("none".into(), |c| c.to_string());
        *exits.entry(k).or_default() += 1;
    }
    let exits: Vec<String> = exits
        .iter()
        .map(|(k, n)| format!("exit {k}: {n}"))
        .collect();
    format!(
        "| figure | target | measured |\n|---|---|---|\n\
         | cases with an effect: every effect's physics and place right | ≥ 95 % | {} |\n\
         | (per effect) | | {} |\n\
         | … or every effect not placed named among alternatives the data cannot tell apart | | {} |\n\
         | cases with a false finding, all | ≤ 2 % | {} |\n\
         | cases with a false finding, controls | ≤ 2 % | {} |\n\
         | fitted values within tolerance (of the effects found with a value) | ≥ 90 % | {} |\n\
         | median / worst time | | {median:.1} s / {worst:.1} s |\n\
         | exit codes | | {} |\n",
        pct(right, effect_cases.len()),
        pct(placed, effects.len()),
        pct(tied, effect_cases.len()),
        pct(false_any, rows.len()),
        pct(false_ctrl, controls.len()),
        pct(within, valued.len()),
        exits.join(", ")
    )
}

/// The confusion matrix: a case adds 1 to (true class, reported class) for
/// each of its true classes (`nothing` for a control) and each distinct
/// class it reports (`nothing` when it reports none).
fn confusion(rows: &[DiagRecord]) -> String {
    let mut cols: Vec<String> = CLASSES.iter().map(|c| c.to_string()).collect();
    for r in rows {
        for (c, _) in &r.score.reported {
            if !cols.contains(c) {
                cols.push(c.clone());
            }
        }
    }
    cols.push("nothing".into());
    let mut cells: BTreeMap<(String, String), usize> = BTreeMap::new();
    let mut n_row: BTreeMap<String, usize> = BTreeMap::new();
    for r in rows {
        let truth: Vec<String> = if r.score.is_control() {
            vec!["nothing".into()]
        } else {
            r.score.effects.iter().map(|e| e.class.clone()).collect()
        };
        let reported: BTreeSet<String> = if r.score.reported.is_empty() {
            ["nothing".to_string()].into()
        } else {
            r.score.reported.iter().map(|(c, _)| c.clone()).collect()
        };
        for t in &truth {
            *n_row.entry(t.clone()).or_default() += 1;
            for c in &reported {
                *cells.entry((t.clone(), c.clone())).or_default() += 1;
            }
        }
    }
    let short = |c: &str| {
        c.replace("-flexibility", "-flex.")
            .replace("-deformation", "")
    };
    let mut s = String::from("| true \\ reported | n |");
    for c in &cols {
        s.push_str(&format!(" {} |", short(c)));
    }
    s.push_str("\n|---|---|");
    s.push_str(&"---|".repeat(cols.len()));
    s.push('\n');
    let mut row_names: Vec<String> = CLASSES.iter().map(|c| c.to_string()).collect();
    row_names.push("nothing".into());
    for t in row_names {
        let n = n_row.get(&t).copied().unwrap_or(0);
        s.push_str(&format!("| {} | {n} |", short(&t)));
        for c in &cols {
            let v = cells.get(&(t.clone(), c.clone())).copied().unwrap_or(0);
            if v == 0 {
                s.push_str(" · |");
            } else if t == *c {
                s.push_str(&format!(" **{v}** |"));
            } else {
                s.push_str(&format!(" {v} |"));
            }
        }
        s.push('\n');
    }
    s
}

/// Per true class: effects, physics right, place right, value within
/// tolerance; then by detectability (FRF change in noise units).
fn by_class(rows: &[DiagRecord]) -> String {
    let mut s = String::from(
        "| true class | effects | physics right | physics and place right | value within tolerance | median FRF change (noise units) |\n|---|---|---|---|---|---|\n",
    );
    let effects: Vec<_> = rows.iter().flat_map(|r| &r.score.effects).collect();
    for class in CLASSES {
        let e: Vec<_> = effects.iter().filter(|e| e.class == class).collect();
        let phys = e.iter().filter(|e| e.physics).count();
        let place = e.iter().filter(|e| e.place).count();
        let vals: Vec<bool> = e.iter().filter_map(|e| e.value_ok).collect();
        let mut d: Vec<f64> = e.iter().map(|e| e.frf_change).collect();
        d.sort_by(f64::total_cmp);
        let med = d.get(d.len() / 2).map_or("-".into(), |v| format!("{v:.3}"));
        s.push_str(&format!(
            "| {class} | {} | {} | {} | {} | {med} |\n",
            e.len(),
            pct(phys, e.len()),
            pct(place, e.len()),
            pct(vals.iter().filter(|v| **v).count(), vals.len())
        ));
    }
    s.push_str(
        "\n| FRF change (noise units) | effects | physics and place right |\n|---|---|---|\n",
    );
    for (lo, hi) in [
        (0.0, 10.0),
        (10.0, 30.0),
        (30.0, 100.0),
        (100.0, f64::INFINITY),
    ] {
        let e: Vec<_> = effects
            .iter()
            .filter(|e| e.frf_change >= lo && e.frf_change < hi)
            .collect();
        s.push_str(&format!(
            "| {lo}–{hi} | {} | {} |\n",
            e.len(),
            pct(e.iter().filter(|e| e.place).count(), e.len())
        ));
    }
    s
}

/// Cases by layout and by support: every effect right, a false finding.
fn by_group(rows: &[DiagRecord]) -> String {
    let mut s = String::from(
        "| cases | n | every effect's physics and place right (cases with an effect) | a false finding |\n|---|---|---|---|\n",
    );
    for key in [
        |r: &DiagRecord| r.layout.clone(),
        |r: &DiagRecord| r.support.clone(),
    ] {
        let mut groups: BTreeMap<String, Vec<&DiagRecord>> = BTreeMap::new();
        for r in rows {
            groups.entry(key(r)).or_default().push(r);
        }
        for (name, g) in groups {
            let eff: Vec<_> = g.iter().filter(|r| !r.score.is_control()).collect();
            let right = eff.iter().filter(|r| r.score.right()).count();
            let fals = g
                .iter()
                .filter(|r| !r.score.false_findings.is_empty())
                .count();
            s.push_str(&format!(
                "| {name} | {} | {} | {} |\n",
                g.len(),
                pct(right, eff.len()),
                pct(fals, g.len())
            ));
        }
    }
    s
}

/// The Markdown summary of a diagnosis run.
pub fn diagnosis_summary_markdown(rows: &[DiagRecord]) -> String {
    let controls = rows.iter().filter(|r| r.score.is_control()).count();
    let pairs = rows.iter().filter(|r| r.score.effects.len() == 2).count();
    format!(
        "{} cases: {} with one effect, {pairs} with two, {controls} controls.\n\n{}\n\
         Confusion matrix (a case counts once per true class × reported class):\n\n{}\n{}\n{}",
        rows.len(),
        rows.len() - controls - pairs,
        rates(rows),
        confusion(rows),
        by_class(rows),
        by_group(rows)
    )
}
