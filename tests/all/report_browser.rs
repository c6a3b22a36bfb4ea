//! The reports in a real browser: headless Chromium (Debian's `chromium`)
//! loads the demo's `report.html` and a diagnosis' `report.html` at 1400 px
//! and at 500 px, the narrowest window headless Chromium lays out (phones
//! are narrower: the page has no fixed width). Each page must load with no
//! console message, no
//! failed resource and no request leaving the machine (every host name
//! resolves to nothing), and must not be wider than the window (tables
//! scroll inside their own box). A copy of the page carries a small script
//! that writes these measurements into the DOM, read back with `--dump-dom`.
//!
//! Without Chromium a developer's run skips with a note; under CI
//! (`CI=true`, as `.ci/run` sets it, which installs `chromium`) it fails.

use std::path::{Path, PathBuf};

use crate::png_support::{fresh_dir, tool_present};
use std::process::Command;

pub const CHROMIUM: &str = "/usr/bin/chromium";

/// The measuring script, run on `load`.
const PROBE: &str = r#"<script>
(function(){var errs=[];
window.addEventListener('error',function(e){var t=e.target;errs.push(String(e.message||(t&&(t.src||t.href))||'error'));},true);
window.addEventListener('load',function(){
var ext=performance.getEntriesByType('resource').map(function(r){return r.name;}).filter(function(n){return !/^(file|data|about):/.test(n);});
var d=document.documentElement;
var r={scrollWidth:d.scrollWidth,innerWidth:window.innerWidth,errors:errs,external:ext,svgs:document.querySelectorAll('svg').length};
var p=document.createElement('pre');p.id='frfup-probe';p.textContent=JSON.stringify(r);document.body.appendChild(p);});})();
</script>"#;

pub fn chromium_available() -> bool {
    tool_present(
        Path::new(CHROMIUM).exists(),
        CHROMIUM,
        "chromium",
        "browser checks",
    )
}

fn out_dir(name: &str) -> PathBuf {
    fresh_dir("report_browser", name)
}

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

/// What the probe measured.
#[derive(Debug)]
struct Probe {
    scroll_width: u64,
    inner_width: u64,
    errors: Vec<String>,
    external: Vec<String>,
    svgs: u64,
}

impl Probe {
    fn parse(json: &str) -> Probe {
        let v: serde_json::Value = serde_json::from_str(json).unwrap();
        let list = |k: &str| -> Vec<String> {
            v[k].as_array()
                .unwrap()
                .iter()
                .map(|x| x.to_string())
                .collect()
        };
        Probe {
            scroll_width: v["scrollWidth"].as_u64().unwrap(),
            inner_width: v["innerWidth"].as_u64().unwrap(),
            errors: list("errors"),
            external: list("external"),
            svgs: v["svgs"].as_u64().unwrap(),
        }
    }
}

/// Load `page` (a copy with the probe, beside it) at `width` px; returns the
/// probe and the console messages Chromium logged.
fn load(page: &Path, width: u64) -> (Probe, Vec<String>) {
    let html = std::fs::read_to_string(page).unwrap();
    // The only scripts: the mode-shape viewer's data blob and code, inline.
    assert!(
        html.matches("<script").count() <= 2 && !html.contains("<script src"),
        "the report carries a script besides the viewer's"
    );
    let probe_page = page.with_file_name("browser-probe.html");
    std::fs::write(
        &probe_page,
        html.replace("</body>", &format!("{PROBE}</body>")),
    )
    .unwrap();
    let profile = page.with_file_name(format!("chromium-profile-{width}"));
    let _ = std::fs::remove_dir_all(&profile);
    let out = Command::new(CHROMIUM)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--enable-logging=stderr",
            "--v=0",
            "--host-resolver-rules=MAP * ~NOTFOUND",
            "--dump-dom",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("--window-size={width},900"))
        .arg(format!("file://{}", probe_page.display()))
        .output()
        .unwrap();
    let _ = std::fs::remove_dir_all(&profile);
    assert!(
        out.status.success(),
        "chromium failed on {}",
        page.display()
    );
    let dom = String::from_utf8_lossy(&out.stdout);
    let start = dom
        .find("<pre id=\"frfup-probe\">")
        .unwrap_or_else(|| panic!("{}: the probe did not run", page.display()))
        + "<pre id=\"frfup-probe\">".len();
    let end = start + dom[start..].find("</pre>").unwrap();
    let json = dom[start..end]
        .replace("&amp;", "&")
        .replace("&quot;", "\"");
    let probe = Probe::parse(&json);
    let console = String::from_utf8_lossy(&out.stderr)
        .lines()
        .filter(|l| l.contains(":CONSOLE"))
        .map(str::to_string)
        .collect();
    (probe, console)
}

fn check(page: &Path, min_svgs: u64) {
    for width in [1400, 500] {
        let (p, console) = load(page, width);
        let at = format!("{} at {width} px", page.display());
        assert!(console.is_empty(), "{at}: console: {console:?}");
        assert!(p.errors.is_empty(), "{at}: errors: {:?}", p.errors);
        assert!(p.external.is_empty(), "{at}: requests: {:?}", p.external);
        assert_eq!(p.inner_width, width, "{at}: window");
        assert!(
            p.scroll_width <= p.inner_width,
            "{at}: the page is {} px wide",
            p.scroll_width
        );
        assert!(p.svgs >= min_svgs, "{at}: {} charts", p.svgs);
    }
}

#[test]
fn demo_report_loads_cleanly_and_fits_the_window() {
    if !chromium_available() {
        return;
    }
    // A copy of the shared demo: the probe page is written beside it.
    let dir = out_dir("demo");
    crate::cli_support::copy_dir(crate::cli_support::demo_dir(), &dir);
    // Convergence, SFDAC, frequencies, MAC, FRF sheet and 26 channels.
    check(&dir.join("report.html"), 31);
}

#[test]
fn diagnosis_report_loads_cleanly_and_fits_the_window() {
    if !chromium_available() {
        return;
    }
    let dir = out_dir("diagnosis");
    frfup(&[
        "--quiet",
        "diagnose",
        "fixtures/diagnose/two_effects.deck",
        "fixtures/diagnose/two_effects.uff",
        "--out",
        dir.to_str().unwrap(),
    ]);
    check(&dir.join("report.html"), 2);
}
