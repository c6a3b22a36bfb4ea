//! `frfup demo`: the built-in GARTEUR-like case runs end to end and improves the correlation.

#[test]
fn demo_runs_end_to_end_and_improves_the_correlation() {
    let run = crate::cli_support::demo();
    assert!(run.status.success(), "{}", run.stderr);
    let out_dir = &run.dir;
    readme_quotes_the_demo(&run.stdout);
    for f in [
        "input/garteur.deck",
        "input/campaign.uff",
        "report.json",
        "report.md",
        "report.html",
        "updated.deck",
        "convergence.svg",
        "frf-overlay.svg",
    ] {
        assert!(out_dir.join(f).exists(), "{f} missing");
    }
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("report.json")).unwrap())
            .unwrap();
    assert_eq!(report["options"]["resonance_method"], "fit");
    let its = report["iterations"].as_array().unwrap();
    let before = its[0]["sfdac_mean"].as_f64().unwrap();
    let fin = report["final_iteration"].as_u64().unwrap() as usize;
    let after = its[fin]["sfdac_mean"].as_f64().unwrap();
    // Issue target: mean SFDAC > 0.99. Measured 0.2992 -> 0.99910: the
    // initial value is fixed by the deck, the campaign and the identified
    // resonances the updating frequencies sit around (to 1e-3; 0.2539 while
    // the identification gave the 2.53/2.58 Hz pair as 2.518 Hz, now
    // 2.550 Hz), the final one must keep at least half its closeness to 1.
    assert!((before - 0.2992).abs() < 1e-3, "SFDAC before {before}");
    assert!(after > 0.998, "SFDAC after {after}");
    // The full-band estimate's Levenberg–Marquardt iterations: measured 16
    // (10 + 6 over its two passes) with a parameter's step limited to its
    // deck value; 32 when the general limit of 2 let the weakly seen
    // tail_Iz walk out to +8 and back.
    let est_iterations = report["estimate"]["iterations"].as_u64().unwrap();
    assert!(est_iterations <= 20, "estimate iterations {est_iterations}");

    // Mean |df/f| over the first 10 elastic test modes (issue target
    // 0.5 %): measured 0.0141 % (frequencies.csv prints 0.001 % steps);
    // the 2.55 Hz suspension mode is not elastic (below 5 Hz). Since the
    // identification separates the 36.78/37.43 Hz pair, both of it (0.013,
    // 0.024 %) and its 38.7 Hz neighbour (0.066 %) are among the ten; with
    // the pair merged the ten gave 0.0015 %.
    let freqs = std::fs::read_to_string(out_dir.join("frequencies.csv")).unwrap();
    let mut devs = Vec::new();
    for line in freqs.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let (Ok(test_hz), Ok(dev)) = (f[1].parse::<f64>(), f[5].parse::<f64>()) else {
            continue;
        };
        if test_hz > 5.0 {
            devs.push(dev.abs());
        }
    }
    assert!(devs.len() >= 10, "{freqs}");
    let mean = devs[..10].iter().sum::<f64>() / 10.0;
    assert!(mean < 0.02, "mean |df/f| {mean} % over {devs:?}");

    // Parameters within 1e-3 of the truth where identifiable: a 10 % change
    // moves one of the first 10 elastic modes by at least 0.1 % (see the
    // README; the root, tail, tailplane, fin-joint and fuselage-torsion
    // parameters move none by more than 0.05 %). Measured: all within 5.2e-4
    // (lw_J).
    let truth: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/garteur/truth.json"),
        )
        .unwrap(),
    )
    .unwrap();
    let identifiable = [
        "fus_Iy",
        "rw_Iy",
        "rw_J",
        "rw_Iz",
        "lw_Iy",
        "lw_J",
        "lw_Iz",
        "fin_Iz",
        "fin_J",
        "wingbody_J",
    ];
    for name in identifiable {
        let got = report["parameters"][name].as_f64().unwrap();
        let want = truth["parameters"][name].as_f64().unwrap();
        assert!((got - want).abs() < 1e-3, "{name}: {got} vs truth {want}");
    }
    // Every parameter the estimate calls identified is near the truth (see
    // below); the wing-root torsions are reported as not identified and keep
    // the deck's value.
    let estimates = report["parameter_estimates"].as_array().unwrap();
    let mut unidentified = Vec::new();
    for p in estimates {
        let name = p["name"].as_str().unwrap();
        let got = p["value"].as_f64().unwrap();
        let want = truth["parameters"][name].as_f64().unwrap();
        if p["identified"].as_bool().unwrap() {
            // Within 0.03, or within three of its reported standard
            // deviations where the data determine it less well (measured:
            // finjoint_J 0.040 ± 0.028, the others within 0.03).
            let sd = p["sd"].as_f64().unwrap();
            assert!(
                (got - want).abs() < 0.03f64.max(3.0 * sd),
                "{name}: {got} ± {sd} vs truth {want}"
            );
        } else {
            assert_eq!(got, 0.0, "{name} not identified keeps the deck's value");
            unidentified.push(name.to_string());
        }
    }
    assert_eq!(unidentified, ["rroot_J", "lroot_J"]);
    reports_say_not_identified(out_dir, &unidentified);
    assert_eq!(report["converged"], true);
    assert_eq!(report["method"], "robust");
    // the updated deck is a valid deck
    let deck = std::fs::read_to_string(out_dir.join("updated.deck")).unwrap();
    frfup_parsers::deck::parse(&deck).expect("updated.deck parses");
}

/// The reports say "not identified" in words, not as a value 0.0000: the
/// estimate table of report.html and report.md, the convergence chart's
/// panel titles; the chart also marks where the frequencies-first stage
/// hands over to the FRF equations.
fn reports_say_not_identified(out_dir: &std::path::Path, unidentified: &[String]) {
    let html = std::fs::read_to_string(out_dir.join("report.html")).unwrap();
    let md = std::fs::read_to_string(out_dir.join("report.md")).unwrap();
    let svg = std::fs::read_to_string(out_dir.join("convergence.svg")).unwrap();
    for name in unidentified {
        assert!(
            html.contains(&format!(
                "<td class=\"l\">{name}</td><td>not identified</td>"
            )),
            "{name} in report.html"
        );
        // And in the model table (quantity, IDs, then the value).
        let model_row = html
            .split("<tr>")
            .filter(|r| r.contains(&format!("<td class=\"l\">{name}</td><td class=\"l\">")))
            .count();
        assert!(
            model_row == 1 && html.contains("<td>not identified</td><td>1 (deck)</td>"),
            "{name} in report.html's model table"
        );
        assert!(
            md.contains(&format!("| {name} | not identified |")),
            "{name} in report.md"
        );
        assert!(
            svg.contains(&format!("{name}: not identified")),
            "{name} in convergence.svg"
        );
    }
    // The convergence chart marks where the frequencies-first stage hands
    // over to the FRF equations (the first FRF step's record).
    assert!(
        svg.contains("FRF stage after frequencies first from iteration"),
        "no handover mark in convergence.svg"
    );
}

/// The README's demo figures are the ones `frfup demo` prints: SFDAC mean
/// and mean |df/f| before → after, the fit's noise ratio and finjoint_J.
fn readme_quotes_the_demo(stdout: &str) {
    let readme =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/README.md")).unwrap();
    let readme = readme.split_whitespace().collect::<Vec<_>>().join(" ");
    let line = |start: &str| {
        stdout
            .lines()
            .find(|l| l.trim_start().starts_with(start) || l.contains(start))
            .unwrap_or_else(|| panic!("{start:?} not printed:\n{stdout}"))
            .to_string()
    };
    let summary = line("SFDAC mean");
    let between = |text: &str, a: &str, b: &str| -> String {
        let from = text.find(a).unwrap() + a.len();
        text[from..].split(b).next().unwrap().trim().to_string()
    };
    let sfdac = between(&summary, "SFDAC mean ", ",").replace("->", "→");
    let df = between(&summary, "mean |df/f| ", "\n").replace("->", "→");
    let fit = between(
        &line("full-band fit at"),
        "full-band fit at ",
        "x the noise",
    );
    let fj = line("finjoint_J");
    let fj: Vec<&str> = fj.split_whitespace().collect();
    for quoted in [
        format!("SFDAC mean {sfdac}"),
        format!("mean |df/f| {df}"),
        format!("fit at {fit}× the noise level"),
        format!("finjoint_J ({} ± {}", fj[1], fj[3]),
    ] {
        assert!(
            readme.contains(&quoted),
            "README does not quote the demo: {quoted:?}"
        );
    }
}

/// The same bytes on one thread as on three: the dense kernels of
/// `solvers::dense` run on the calling thread (faer's implicit ones follow
/// its process-wide parallelism, whose parallel variants sum in another
/// order: the demo's finjoint_J was +0.03814 on 2 threads, +0.03813 on 1),
/// and the parallel steps split their work independently of the number of
/// threads.
#[test]
fn the_demo_writes_the_same_bytes_on_one_and_on_three_threads() {
    // Folders' names of one length: files quote their inputs' paths in
    // fixed-width fields.
    let run = |threads: &str| {
        let dir = crate::cli_support::scratch_root()
            .join(format!("frfup-demo-t{threads}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        crate::cli_support::frfup_ok_on_threads(&["demo", "--out", dir.to_str().unwrap()], threads);
        dir
    };
    let (one, three) = (run("1"), run("3"));
    let files = files_under(&one);
    assert_eq!(files, files_under(&three), "other files");
    let read = |root: &std::path::Path, f: &str| {
        let bytes = std::fs::read(root.join(f)).unwrap();
        String::from_utf8_lossy(&bytes).replace(root.to_str().unwrap(), "OUT")
    };
    for f in &files {
        assert!(read(&one, f) == read(&three, f), "{f} differs");
    }
    for d in [one, three] {
        let _ = std::fs::remove_dir_all(d);
    }
}

/// Every file under `root`, relative, sorted.
fn files_under(root: &std::path::Path) -> Vec<String> {
    let mut out = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(d) = stack.pop() {
        for e in std::fs::read_dir(&d).unwrap() {
            let p = e.unwrap().path();
            if p.is_dir() {
                stack.push(p);
            } else {
                out.push(p.strip_prefix(root).unwrap().display().to_string());
            }
        }
    }
    out.sort();
    out
}
