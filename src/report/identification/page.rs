//! `report.html` of `frfup identify`: one self-contained page (inline SVG
//! and CSS, no network): what was fitted, the modes, the charts, the
//! pairing with the deck and the mode-shape viewer (its one script).

use std::fmt::Write as _;

use super::{Charts, IdentifyReport};
use crate::identification::ModeKind;
use crate::report::charts::fmt_fixed;
use crate::report::html::{chart, esc, CSS};
use crate::report::viewer;
use crate::testdata::dof_label;

fn header(s: &mut String, r: &IdentifyReport) {
    let id = r.id;
    let d = &id.data;
    let refs: Vec<String> = d
        .inputs
        .iter()
        .map(|i| dof_label(i.node, i.direction))
        .collect();
    let _ = writeln!(
        s,
        "<h1>Modal identification</h1>\n<p>{} ({}): {} output(s) × {} reference(s) [{}], \
         {} lines {}–{} Hz, model orders 1–{}. {} mode(s) selected automatically; fit \
         residual {}&nbsp;% of the data (RMS, each output weighted by its inverse RMS).</p>",
        esc(r.test_name),
        esc(r.test.kind.name()),
        d.n_outputs(),
        d.n_inputs(),
        esc(&refs.join(", ")),
        d.n_lines(),
        fmt_fixed(d.frequencies_hz[0], 3),
        fmt_fixed(d.frequencies_hz[d.n_lines() - 1], 3),
        id.diagram.max_order,
        id.modes.len(),
        fmt_fixed(100.0 * id.relative_residual, 2)
    );
    s.push_str(
        "<p>Method: poles by poly-reference least-squares complex frequency (PolyMAX) for \
         every order; poles stable in frequency (1&nbsp;%), damping (5&nbsp;%) and shape \
         (MAC ≥ 0.98) clustered across orders; residues by least squares in the frequency \
         domain with upper and lower residuals, the poles refined on the same residual.</p>\n",
    );
}

fn modes_table(s: &mut String, r: &IdentifyReport) {
    s.push_str(
        "<h2>Modes</h2>\n<table><tr><th>mode</th><th>frequency (Hz)</th><th>damping (%)</th>\
         <th>MPC</th><th>MPD (°)</th><th>complexity</th><th>kind</th><th>stable orders</th>\
         <th>significance</th></tr>\n",
    );
    for (k, m) in r.id.modes.iter().enumerate() {
        let kind = match m.kind {
            ModeKind::Elastic => "elastic",
            ModeKind::RigidBody => "<b>rigid-body / suspension</b>",
        };
        let _ = writeln!(
            s,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
             <td>{}</td><td>{}</td></tr>",
            k + 1,
            fmt_fixed(m.frequency_hz, 4),
            fmt_fixed(100.0 * m.damping_ratio, 3),
            fmt_fixed(m.quality.mpc, 4),
            fmt_fixed(m.quality.mpd_deg, 2),
            fmt_fixed(m.quality.complexity, 3),
            kind,
            m.stable_orders,
            fmt_fixed(m.significance, 1)
        );
    }
    s.push_str("</table>\n");
    if r.id.modes.is_empty() {
        s.push_str("<p class=\"warn\">No mode is stable across orders: the data may be noise, or the band holds no resonance.</p>\n");
    }
}

fn pairs_table(s: &mut String, r: &IdentifyReport, charts: &Charts) {
    let Some((deck, p)) = r.pairing else {
        return;
    };
    let _ = writeln!(
        s,
        "<h2>Pairing with {}</h2>\n<p>{} measured DOFs in common; pairs by MAC ≥ {}, each mode used once.</p>\n<table><tr><th>test mode</th><th>test (Hz)</th><th>FE mode</th><th>FE (Hz)</th><th>FE − test (%)</th><th>MAC</th></tr>",
        esc(deck),
        p.common_dofs,
        crate::identification::PAIR_MAC
    );
    for &(t, f) in &p.pairs {
        let (ft, ff) = (r.id.modes[t].frequency_hz, p.fe_frequencies_hz[f]);
        let _ = writeln!(
            s,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            t + 1,
            fmt_fixed(ft, 3),
            f + 1,
            fmt_fixed(ff, 3),
            fmt_fixed(100.0 * (ff - ft) / ft, 2),
            fmt_fixed(p.mac[t][f], 3)
        );
    }
    s.push_str("</table>\n");
    if let Some(mac) = &charts.mac {
        chart(s, mac);
    }
}

/// The page.
pub fn html(r: &IdentifyReport, charts: &Charts) -> String {
    let mut s = format!(
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>Modal identification: {}</title>\n<style>{CSS}</style>\n</head>\n<body>\n",
        esc(r.test_name)
    );
    header(&mut s, r);
    modes_table(&mut s, r);
    s.push_str("<h2>Stabilisation diagram</h2>\n");
    chart(&mut s, &charts.stabilisation);
    s.push_str("<h2>Synthesis</h2>\n");
    chart(&mut s, &charts.synthesis);
    pairs_table(&mut s, r, charts);
    if let (Some(v), Some(still)) = (r.viewer, &charts.shapes) {
        s.push_str(&viewer::section(
            v,
            "The paired modes above, animated: the identified test mode (the real part of its shape, as in <code>shapes.csv</code>) and its FE partner.",
            still,
        ));
    }
    if !r.notes.is_empty() {
        s.push_str("<h2>Notes on the inputs</h2>\n<ul>\n");
        for n in r.notes {
            let _ = writeln!(s, "<li>{}</li>", esc(n));
        }
        s.push_str("</ul>\n");
    }
    s.push_str("</body>\n</html>\n");
    s
}
