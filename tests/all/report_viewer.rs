//! The mode-shape viewer of the reports.
//!
//! * Its data round-trip: the JSON blob of `identify --deck` (GARTEUR-like
//!   campaign) and of the demo's update carries every node of the deck, one
//!   entry per pair of the report's tables, and the MAC recomputed from the
//!   drawn shapes at the measured translations equals the table's MAC: to
//!   1e-3 for the update (real shapes; the JSON keeps 4 decimals), within
//!   the bound the modal phase collinearity sets for identified (complex)
//!   shapes, of which the real part is drawn. The page and the still
//!   images are the same bytes on a second run.
//! * In headless Chromium (as `report_browser`): the page loads with no
//!   console message, no error and no request leaving the machine; a pair is
//!   selected and drawn; the canvases' pixels read back at two times differ
//!   (moving geometry), after "pause" they do not; the page is no wider than
//!   the window. Screenshots after two virtual times, only the canvases
//!   visible, differ.

use std::path::Path;
use std::process::Command;

use crate::png_support::fresh_dir;
use crate::report_browser::{chromium_available, CHROMIUM};

fn frfup(args: &[&str]) {
    let out = Command::new(env!("CARGO_BIN_EXE_frfup"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "frfup {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
}

fn identify_garteur(dir: &Path) {
    frfup(&[
        "--quiet",
        "identify",
        "fixtures/garteur/campaign.uff",
        "--deck",
        "fixtures/garteur/garteur.deck",
        "--out",
        dir.to_str().unwrap(),
    ]);
}

/// The viewer's JSON blob in `report.html`.
fn blob(page: &Path) -> serde_json::Value {
    let html = std::fs::read_to_string(page).unwrap();
    let tag = "<script type=\"application/json\" id=\"frfup-viewer-data\">";
    let start = html.find(tag).expect("no viewer data") + tag.len();
    let end = start + html[start..].find("</script>").unwrap();
    serde_json::from_str(&html[start..end]).unwrap()
}

fn nodes_in(deck: &str) -> usize {
    std::fs::read_to_string(Path::new(env!("CARGO_MANIFEST_DIR")).join(deck))
        .unwrap()
        .lines()
        .filter(|l| l.split_whitespace().next() == Some("node"))
        .count()
}

/// MAC of a pair's drawn test and FE shapes at the measured translations.
fn drawn_mac(v: &serde_json::Value, pair: &serde_json::Value) -> f64 {
    let (mut tf, mut tt, mut ff) = (0.0, 0.0, 0.0);
    for (i, m) in v["measured"].as_array().unwrap().iter().enumerate() {
        for a in 0..3 {
            if m[a].as_u64() == Some(1) {
                let t = pair["test"][i][a].as_f64().unwrap();
                let f = pair["fe"][i][a].as_f64().unwrap();
                tf += t * f;
                tt += t * t;
                ff += f * f;
            }
        }
    }
    tf * tf / (tt * ff)
}

fn check_geometry(v: &serde_json::Value, deck: &str) {
    let n = nodes_in(deck);
    assert_eq!(v["ids"].as_array().unwrap().len(), n);
    assert_eq!(v["xyz"].as_array().unwrap().len(), n);
    assert_eq!(v["measured"].as_array().unwrap().len(), n);
    for p in v["pairs"].as_array().unwrap() {
        assert_eq!(p["test"].as_array().unwrap().len(), n);
        assert_eq!(p["fe"].as_array().unwrap().len(), n);
    }
}

#[test]
fn identify_viewer_data_round_trips_with_the_pairs_table() {
    let dir = fresh_dir("report_viewer", "identify");
    identify_garteur(&dir);
    let v = blob(&dir.join("report.html"));
    check_geometry(&v, "fixtures/garteur/garteur.deck");
    let csv = std::fs::read_to_string(dir.join("pairs.csv")).unwrap();
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    let pairs = v["pairs"].as_array().unwrap();
    assert!(rows.len() >= 10, "{} pairs", rows.len());
    assert_eq!(pairs.len(), rows.len());
    let mpc: Vec<f64> = std::fs::read_to_string(dir.join("modes.csv"))
        .unwrap()
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(4).unwrap().parse().unwrap())
        .collect();
    for (p, r) in pairs.iter().zip(&rows) {
        assert_eq!(p["test_mode"].as_f64().unwrap(), r[0]);
        assert_eq!(p["fe_mode"].as_f64().unwrap(), r[2]);
        assert!((p["mac"].as_f64().unwrap() - r[5]).abs() <= 0.5e-4, "{r:?}");
        // The drawn test shape is the real part x of ψ = x + iy (rotated
        // so that x·y = 0); the table's MAC uses ψ. With a = (x·φ)²/|φ|²,
        // b = (y·φ)²/|φ|²: MAC(x) − MAC(ψ) = a/|x|² − (a + b)/|ψ|², within
        // ±|y|²/|ψ|² = ±(1 − √MPC)/2 (MPC = ((|x|² − |y|²)/|ψ|²)²),
        // plus the JSON's 4 decimals.
        let m = mpc[r[0] as usize - 1];
        let tol = 0.5 * (1.0 - m.sqrt()) + 1e-3;
        let mac = drawn_mac(&v, p);
        assert!(
            (mac - r[5]).abs() <= tol,
            "pair {r:?}: drawn MAC {mac}, tolerance {tol}"
        );
    }
    let again = fresh_dir("report_viewer", "identify-again");
    identify_garteur(&again);
    for f in ["report.html", "mode-shapes.svg"] {
        let (a, b) = (
            std::fs::read(dir.join(f)).unwrap(),
            std::fs::read(again.join(f)).unwrap(),
        );
        assert!(a == b, "{f} differs between two runs");
    }
}

#[test]
fn update_viewer_data_round_trips_with_the_frequency_table() {
    let dir = crate::cli_support::demo_dir();
    let v = blob(&dir.join("report.html"));
    check_geometry(&v, "fixtures/garteur/garteur.deck");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    let table = &report["frequencies"]["updated_mac"];
    let pairs = v["pairs"].as_array().unwrap();
    let paired = table.as_array().unwrap().iter().filter(|m| m.is_f64());
    assert_eq!(pairs.len(), paired.count());
    assert!(pairs.len() >= 10);
    for p in pairs {
        let t = p["test_mode"].as_u64().unwrap() as usize - 1;
        let want = table[t].as_f64().unwrap();
        let mac = drawn_mac(&v, p);
        assert!((mac - want).abs() < 1e-3, "test {t}: {mac} vs {want}");
    }
    assert!(dir.join("mode-shapes.svg").exists());
}

/// Measures the viewer in the page: after `load`, selects the second pair;
/// reads both canvases back at 300 ms and 700 ms (virtual time; an `input`
/// event on the azimuth slider makes the viewer draw at once, at the
/// clock's phase), presses "pause", and reads them back at once and at
/// 1100 ms.
const PROBE: &str = r#"<script>
(function(){var errs=[];
window.addEventListener('error',function(e){var t=e.target;errs.push(String(e.message||(t&&(t.src||t.href))||'error'));},true);
function part(n){return document.querySelector('#frfup-viewer [data-v="'+n+'"]');}
function grab(){part('az').dispatchEvent(new Event('input'));return [part('test').toDataURL(),part('fe').toDataURL()];}
window.addEventListener('load',function(){
var pick=part('pair');pick.value='1';pick.dispatchEvent(new Event('change'));
var a,b,c;
setTimeout(function(){a=grab();},300);
setTimeout(function(){b=grab();part('play').click();c=grab();},700);
setTimeout(function(){var d=grab();
var ext=performance.getEntriesByType('resource').map(function(r){return r.name;}).filter(function(n){return !/^(file|data|about):/.test(n);});
var cv=part('fe'),blank=document.createElement('canvas');blank.width=cv.width;blank.height=cv.height;
var r={errors:errs,external:ext,caption:part('fe-caption').textContent,drawn:a[1]!==blank.toDataURL(),moving:[a[0]!==b[0],a[1]!==b[1]],paused:[c[0]===d[0],c[1]===d[1]],scrollWidth:document.documentElement.scrollWidth,innerWidth:window.innerWidth};
var p=document.createElement('pre');p.id='frfup-probe';p.textContent=JSON.stringify(r);document.body.appendChild(p);},1100);
});})();
</script>"#;

/// For the screenshots: the second pair selected, the page before the
/// viewer removed and everything but the two canvases invisible, so that
/// any pixel that differs is in the canvases.
const STAGE: &str = r#"<script>(function(){var r=document.getElementById('frfup-viewer');
var s=r.querySelector('[data-v=pair]');s.value='1';s.dispatchEvent(new Event('change'));
var h=document.getElementById('shapes');for(var e=document.body.firstElementChild;e&&e!==h;e=e.nextElementSibling){e.style.display='none';}
var st=document.createElement('style');st.textContent='body *{visibility:hidden}#frfup-viewer canvas{visibility:visible}';document.head.appendChild(st);})();</script>"#;

/// Chromium's command with the flags of every run here.
fn chromium(profile: &Path, width: u32, budget_ms: u32) -> Command {
    let mut c = Command::new(CHROMIUM);
    c.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--hide-scrollbars",
        // One raster thread, canvas drawn in software: the same picture
        // gives the same bytes.
        "--num-raster-threads=1",
        "--disable-accelerated-2d-canvas",
        "--enable-logging=stderr",
        "--v=0",
        "--host-resolver-rules=MAP * ~NOTFOUND",
    ])
    .arg(format!("--virtual-time-budget={budget_ms}"))
    .arg(format!("--user-data-dir={}", profile.display()))
    .arg(format!("--window-size={width},900"));
    c
}

/// A screenshot of `page` staged by [`STAGE`] after `budget_ms` of
/// virtual time: the PNG's bytes.
fn screenshot(page: &Path, budget_ms: u32) -> Vec<u8> {
    let html = std::fs::read_to_string(page).unwrap();
    let staged = page.with_file_name("viewer-stage.html");
    std::fs::write(&staged, html.replace("</body>", &format!("{STAGE}</body>"))).unwrap();
    let png = page.with_file_name(format!("viewer-{budget_ms}.png"));
    let profile = page.with_file_name("chromium-viewer-shot");
    let _ = std::fs::remove_dir_all(&profile);
    let out = chromium(&profile, 1400, budget_ms)
        .arg(format!("--screenshot={}", png.display()))
        .arg(format!("file://{}", staged.display()))
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&profile);
    assert!(out.status.success(), "chromium failed");
    std::fs::read(png).unwrap()
}

fn run_probe(page: &Path, width: u32) -> (serde_json::Value, Vec<String>) {
    let html = std::fs::read_to_string(page).unwrap();
    let probe_page = page.with_file_name("viewer-probe.html");
    std::fs::write(
        &probe_page,
        html.replace("</body>", &format!("{PROBE}</body>")),
    )
    .unwrap();
    let profile = page.with_file_name(format!("chromium-viewer-{width}"));
    let _ = std::fs::remove_dir_all(&profile);
    let out = chromium(&profile, width, 3000)
        .arg("--dump-dom")
        .arg(format!("file://{}", probe_page.display()))
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&profile);
    assert!(out.status.success(), "chromium failed");
    let dom = String::from_utf8_lossy(&out.stdout);
    let tag = "<pre id=\"frfup-probe\">";
    let start = dom.find(tag).expect("the probe did not run") + tag.len();
    let end = start + dom[start..].find("</pre>").unwrap();
    let json = dom[start..end]
        .replace("&amp;", "&")
        .replace("&quot;", "\"");
    let console = String::from_utf8_lossy(&out.stderr)
        .lines()
        .filter(|l| l.contains(":CONSOLE"))
        .map(str::to_string)
        .collect();
    (serde_json::from_str(&json).unwrap(), console)
}

#[test]
fn viewer_animates_the_selected_pair_in_chromium() {
    if !chromium_available() {
        return;
    }
    let dir = fresh_dir("report_viewer", "browser");
    identify_garteur(&dir);
    let v = blob(&dir.join("report.html"));
    let second = &v["pairs"][1];
    for width in [1400, 500] {
        let (p, console) = run_probe(&dir.join("report.html"), width);
        let at = format!("at {width} px");
        assert!(console.is_empty(), "{at}: console: {console:?}");
        assert_eq!(p["errors"], serde_json::json!([]), "{at}");
        assert_eq!(p["external"], serde_json::json!([]), "{at}");
        let caption = p["caption"].as_str().unwrap();
        assert!(
            caption.contains(&format!("FE mode {} ·", second["fe_mode"])),
            "{at}: the selected pair is not drawn: {caption}"
        );
        assert_eq!(p["drawn"], true, "{at}: empty canvas");
        assert_eq!(p["moving"], serde_json::json!([true, true]), "{at}");
        assert_eq!(p["paused"], serde_json::json!([true, true]), "{at}");
        assert!(
            p["scrollWidth"].as_u64() <= p["innerWidth"].as_u64(),
            "{at}: {p}"
        );
    }
    // Screenshots 0.3 s and 0.7 s into a 1.6 s swing (displacements
    // cos(67.5°) and cos(157.5°) of the extreme) differ. Two paused ones
    // are not always the same bytes (the compositor's raster varies), so
    // the exact check is the canvases' own pixels, above.
    let page = dir.join("report.html");
    assert!(screenshot(&page, 300) != screenshot(&page, 700));
}
