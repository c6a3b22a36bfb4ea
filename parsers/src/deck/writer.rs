//! Deck writer: [`Deck`] → deck text that parses back to the same deck
//! (positions aside). Deterministic: statements grouped by kind in a fixed
//! order, each kind in the deck's order; numbers in shortest round-trip form.

use std::fmt::Write as _;

use super::{DampingModel, Deck, FixDofs};

/// Shortest text that parses back to exactly `x` (Rust's float formatting is
/// round-trip exact): plain decimal for 1e-4 ≤ |x| < 1e7, else `1.5e-5` style.
pub fn format_number(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || (1e-4..1e7).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// Names cannot carry blanks, `=`, `,` or `#` in a deck; replace them by `_`.
fn name(s: &str) -> String {
    let cleaned: String = s
        .chars()
        .map(|c| {
            if c.is_whitespace() || matches!(c, '=' | ',' | '#') {
                '_'
            } else {
                c
            }
        })
        .collect();
    if cleaned.is_empty() {
        "_".to_string()
    } else {
        cleaned
    }
}

/// Write a deck as text: titles, `analysis`, then one group of statements
/// per kind, each group after a blank line.
pub fn write(deck: &Deck) -> String {
    let mut s = String::new();
    titles(&mut s, deck);
    let _ = writeln!(s, "analysis {}", deck.analysis.name());
    type Group = fn(&mut String, &Deck);
    let groups: [(bool, Group); 8] = [
        (!deck.materials.is_empty(), materials),
        (!deck.sections.is_empty(), sections),
        (!deck.nodes.is_empty(), nodes),
        (!deck.beams.is_empty(), beams),
        (
            !deck.masses.is_empty() || !deck.springs.is_empty(),
            masses_and_springs,
        ),
        (
            !deck.fixes.is_empty() || deck.damping.is_some(),
            fixes_and_damping,
        ),
        (!deck.params.is_empty(), params),
        (!deck.sensors.is_empty(), sensors),
    ];
    for (present, group) in groups {
        if present {
            s.push('\n');
            group(&mut s, deck);
        }
    }
    s
}

/// `title` lines, one per line of each title (`#` would start a comment).
fn titles(s: &mut String, deck: &Deck) {
    for t in &deck.titles {
        for line in t.text.split('\n') {
            let line = line.replace('#', "_");
            let line = line.trim();
            if line.is_empty() {
                s.push_str("title\n");
            } else {
                let _ = writeln!(s, "title {line}");
            }
        }
    }
}

fn materials(s: &mut String, deck: &Deck) {
    let n = format_number;
    for m in &deck.materials {
        let _ = write!(
            s,
            "material {} E={} rho={}",
            name(&m.name),
            n(m.e),
            n(m.rho)
        );
        if let Some(nu) = m.nu {
            let _ = write!(s, " nu={}", n(nu));
        }
        if let Some(g) = m.g {
            let _ = write!(s, " G={}", n(g));
        }
        s.push('\n');
    }
}

fn sections(s: &mut String, deck: &Deck) {
    let n = format_number;
    for c in &deck.sections {
        let _ = write!(s, "section {} A={} Iy={}", name(&c.name), n(c.a), n(c.iy));
        for (key, v) in [("Iz", c.iz), ("J", c.j), ("ky", c.ky), ("kz", c.kz)] {
            if let Some(v) = v {
                let _ = write!(s, " {key}={}", n(v));
            }
        }
        s.push('\n');
    }
}

fn nodes(s: &mut String, deck: &Deck) {
    let n = format_number;
    for nd in &deck.nodes {
        let [x, y, z] = nd.xyz;
        let _ = writeln!(s, "node {} {} {} {}", nd.id, n(x), n(y), n(z));
    }
}

fn beams(s: &mut String, deck: &Deck) {
    let n = format_number;
    for b in &deck.beams {
        let _ = write!(
            s,
            "beam {} {} {} {} {}",
            b.id,
            b.nodes[0],
            b.nodes[1],
            name(&b.material),
            name(&b.section)
        );
        if let Some(o) = &b.orient {
            let [x, y, z] = o.vector;
            let _ = write!(s, " orient={},{},{}", n(x), n(y), n(z));
        }
        if let Some(t) = b.theory {
            let _ = write!(s, " theory={}", t.name());
        }
        s.push('\n');
    }
}

fn masses_and_springs(s: &mut String, deck: &Deck) {
    let n = format_number;
    for m in &deck.masses {
        let _ = write!(s, "mass {} {} m={}", m.id, m.node, n(m.m));
        for (key, v) in [("Ixx", m.ixx), ("Iyy", m.iyy), ("Izz", m.izz)] {
            if let Some(v) = v {
                let _ = write!(s, " {key}={}", n(v));
            }
        }
        s.push('\n');
    }
    for sp in &deck.springs {
        let _ = write!(
            s,
            "spring {} {} {} k={}",
            sp.id,
            sp.node,
            sp.dof.name(),
            n(sp.k)
        );
        if let Some(to) = sp.to {
            let _ = write!(s, " to={to}");
        }
        s.push('\n');
    }
}

fn fixes_and_damping(s: &mut String, deck: &Deck) {
    let n = format_number;
    for f in &deck.fixes {
        let dofs = match &f.dofs {
            FixDofs::All => "all".to_string(),
            FixDofs::List(l) => l.iter().map(|d| d.name()).collect::<Vec<_>>().join(","),
        };
        let _ = writeln!(s, "fix {} {dofs}", f.node);
    }
    if let Some(d) = &deck.damping {
        let _ = match d.model {
            DampingModel::Modal { zeta } => writeln!(s, "damping modal {}", n(zeta)),
            DampingModel::Rayleigh { alpha, beta } => {
                writeln!(s, "damping rayleigh {} {}", n(alpha), n(beta))
            }
            DampingModel::Hysteretic { eta } => writeln!(s, "damping hysteretic {}", n(eta)),
        };
    }
}

fn params(s: &mut String, deck: &Deck) {
    for p in &deck.params {
        let ids = p
            .ids
            .iter()
            .map(|r| {
                if r.first == r.last {
                    r.first.to_string()
                } else {
                    format!("{}-{}", r.first, r.last)
                }
            })
            .collect::<Vec<_>>()
            .join(",");
        let mut bounds = String::new();
        for (key, v) in [("min", p.min), ("max", p.max), ("sd", p.sd)] {
            if let Some(v) = v {
                bounds.push_str(&format!(" {key}={}", format_number(v)));
            }
        }
        let _ = writeln!(
            s,
            "param {} {} {ids}{bounds}",
            name(&p.name),
            p.quantity.name()
        );
    }
}

fn sensors(s: &mut String, deck: &Deck) {
    for se in &deck.sensors {
        let _ = writeln!(s, "sensor {} {}", se.test_node, se.node);
    }
}
