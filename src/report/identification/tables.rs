//! The CSV tables of `frfup identify`: `modes.csv`, `shapes.csv`,
//! `pairs.csv`.

use std::fmt::Write as _;

use crate::fsio::csv_number;
use crate::identification::{Identification, Pairing};
use crate::testdata::dof_label;

/// `mode,frequency_hz,damping_ratio,complexity,mpc,mpd_deg,kind,stable_orders,significance`.
pub fn modes_csv(id: &Identification) -> String {
    let mut s = String::from(
        "mode,frequency_hz,damping_ratio,complexity,mpc,mpd_deg,kind,stable_orders,significance\n",
    );
    for (r, m) in id.modes.iter().enumerate() {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{}",
            r + 1,
            csv_number(m.frequency_hz),
            csv_number(m.damping_ratio),
            csv_number(m.quality.complexity),
            csv_number(m.quality.mpc),
            csv_number(m.quality.mpd_deg),
            m.kind.name(),
            m.stable_orders,
            csv_number(m.significance)
        );
    }
    s
}

/// One row per measured DOF: `node,direction,dof`, then per mode the real
/// shape and the complex one (`mode1_real,mode1_re,mode1_im,…`), each mode
/// scaled to largest magnitude 1.
pub fn shapes_csv(id: &Identification) -> String {
    let mut s = String::from("node,direction,dof");
    for r in 1..=id.modes.len() {
        let _ = write!(s, ",mode{r}_real,mode{r}_re,mode{r}_im");
    }
    s.push('\n');
    for (o, d) in id.data.outputs.iter().enumerate() {
        let _ = write!(
            s,
            "{},{},{}",
            d.node,
            d.direction,
            dof_label(d.node, d.direction)
        );
        for m in &id.modes {
            let v = m.shape[o];
            let _ = write!(
                s,
                ",{},{},{}",
                csv_number(v.re),
                csv_number(v.re),
                csv_number(v.im)
            );
        }
        s.push('\n');
    }
    s
}

/// `test_mode,test_hz,fe_mode,fe_hz,frequency_error_pct,mac`.
pub fn pairs_csv(id: &Identification, p: &Pairing) -> String {
    let mut s = String::from("test_mode,test_hz,fe_mode,fe_hz,frequency_error_pct,mac\n");
    for &(t, f) in &p.pairs {
        let (ft, ff) = (id.modes[t].frequency_hz, p.fe_frequencies_hz[f]);
        let _ = writeln!(
            s,
            "{},{},{},{},{},{}",
            t + 1,
            csv_number(ft),
            f + 1,
            csv_number(ff),
            csv_number(100.0 * (ff - ft) / ft),
            csv_number(p.mac[t][f])
        );
    }
    s
}
