//! Rendering report charts (SVG) to PNG with `rsvg-convert` (Debian's
//! librsvg2-bin, installed by scripts/render_png.sh) and checking the PNG.

use std::path::Path;
use std::process::Command;

/// True when `rsvg-convert` runs. When it does not, a developer's run skips
/// the rendering with a note, but under CI (`CI=true`, as `.ci/run` sets it)
/// the test fails: a chart check that silently does nothing is not a check.
pub fn rsvg_available() -> bool {
    let ok = Command::new("rsvg-convert")
        .arg("--version")
        .output()
        .map(|o| o.status.success())
        .unwrap_or(false);
    tool_present(ok, "rsvg-convert", "librsvg2-bin", "PNG rendering")
}

/// `found` as is, with a note naming the skipped `checks` when false; under
/// CI (`CI=true`) a missing tool fails the test instead: a check that
/// silently does nothing is not a check.
pub fn tool_present(found: bool, tool: &str, package: &str, checks: &str) -> bool {
    if !found {
        let under_ci = std::env::var("CI").is_ok_and(|v| v == "true");
        assert!(
            !under_ci,
            "{tool} not found under CI=true: install Debian's {package} (.ci/run does)"
        );
        eprintln!("note: {tool} not found, {checks} skipped (apt-get install {package})");
    }
    found
}

/// An empty folder `group/name` under the tests' temporary folder.
pub fn fresh_dir(group: &str, name: &str) -> std::path::PathBuf {
    let d = std::path::PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
        .join(group)
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Render `svg` to `png` on white; the PNG must be more than 8 kB (a chart,
/// not an empty frame) and exactly the SVG's width × height.
pub fn render_and_check(svg: &Path, png: &Path) {
    let out = Command::new("rsvg-convert")
        .arg("--background-color=white")
        .arg("-o")
        .arg(png)
        .arg(svg)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}: {}",
        svg.display(),
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(png).unwrap();
    assert!(
        bytes.len() > 8_000,
        "{}: only {} bytes",
        png.display(),
        bytes.len()
    );
    let text = std::fs::read_to_string(svg).unwrap();
    assert_eq!(png_size(&bytes), svg_size(&text), "{}", png.display());
}

/// (width, height) of a PNG from its IHDR chunk.
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "not a PNG");
    let be = |i: usize| u32::from_be_bytes([bytes[i], bytes[i + 1], bytes[i + 2], bytes[i + 3]]);
    (be(16), be(20))
}

/// `width="…" height="…"` of the SVG root.
fn svg_size(svg: &str) -> (u32, u32) {
    let head = &svg[..svg.find('>').unwrap()];
    let attr = |name: &str| -> u32 {
        let i = head.find(&format!("{name}=\"")).unwrap() + name.len() + 2;
        head[i..].split('"').next().unwrap().parse().unwrap()
    };
    (attr("width"), attr("height"))
}
