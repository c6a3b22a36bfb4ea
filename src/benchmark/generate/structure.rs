//! Random structures: geometry, sections, materials, lumped masses, supports.

use super::{
    modes_hz, parse_deck, BeamElement, GenOptions, MaterialProps, SectionProps, Structure,
};
use crate::benchmark::{round_sig, Rng, StructureKind, Support};
use crate::model::ParameterValues;

/// Nodes and elements as they are added.
struct Builder {
    st: Structure,
}

impl Builder {
    fn node(&mut self, p: [f64; 3]) -> u32 {
        let id = self.st.nodes.len() as u32 + 1;
        let r = |x: f64| round_sig(x, 9);
        self.st.nodes.push((id, [r(p[0]), r(p[1]), r(p[2])]));
        id
    }

    fn pos(&self, id: u32) -> [f64; 3] {
        self.st.nodes[id as usize - 1].1
    }

    /// A straight member from node `a` to node `b` in `n_el` elements
    /// (intermediate nodes evenly spaced); material and section drawn from
    /// the pools.
    fn member(&mut self, a: u32, b: u32, n_el: usize, rng: &mut Rng) {
        let (pa, pb) = (self.pos(a), self.pos(b));
        let material = rng.int(0, self.st.materials.len() - 1);
        let section = rng.int(0, self.st.sections.len() - 1);
        let member = self.st.members.len();
        let mut ids = Vec::with_capacity(n_el);
        let mut prev = a;
        for i in 1..=n_el {
            let next = if i == n_el {
                b
            } else {
                let t = i as f64 / n_el as f64;
                self.node([
                    pa[0] + t * (pb[0] - pa[0]),
                    pa[1] + t * (pb[1] - pa[1]),
                    pa[2] + t * (pb[2] - pa[2]),
                ])
            };
            let id = self.st.beams.len() as u32 + 1;
            self.st.beams.push(BeamElement {
                id,
                n1: prev,
                n2: next,
                material,
                section,
                member,
            });
            ids.push(id);
            prev = next;
        }
        self.st.members.push(ids);
    }
}

/// Steel-, aluminium- or titanium-like: E and ρ each within ±10 % of
/// (210 GPa, 7850), (70 GPa, 2700), (110 GPa, 4430).
fn draw_material(name: &str, rng: &mut Rng) -> MaterialProps {
    let (e, rho) = *rng
        .pick(&[(210e9, 7850.0), (70e9, 2700.0), (110e9, 4430.0)])
        .unwrap_or(&(210e9, 7850.0));
    MaterialProps {
        name: name.to_string(),
        e: round_sig(e * rng.range(0.9, 1.1), 4),
        rho: round_sig(rho * rng.range(0.9, 1.1), 4),
    }
}

/// A solid or hollow rectangle or circle of characteristic size `d` (m).
/// Rectangle b (local y) × h (local z): A = bh, Iy = bh³/12, Iz = hb³/12,
/// J = a c³(1/3 − 0.21 (c/a)(1 − c⁴/(12a⁴))) with a ≥ c the sides; thin-wall
/// box J = 2t(b−t)²(h−t)²/(b+h−2t); circle I = πD⁴/64, J = 2I.
fn draw_section(name: &str, d: f64, rng: &mut Rng) -> SectionProps {
    let pi = std::f64::consts::PI;
    let (shape, a, iy, iz, j) = match rng.int(0, 3) {
        0 | 1 => {
            let (b, h) = (d * rng.range(0.5, 1.5), d);
            let (big, small) = (b.max(h), b.min(h));
            let j_solid = big
                * small.powi(3)
                * (1.0 / 3.0 - 0.21 * (small / big) * (1.0 - small.powi(4) / (12.0 * big.powi(4))));
            let solid = (b * h, b * h.powi(3) / 12.0, h * b.powi(3) / 12.0, j_solid);
            if rng.chance(0.5) {
                ("solid rectangle", solid.0, solid.1, solid.2, solid.3)
            } else {
                let t = small * rng.range(0.06, 0.15);
                let (bi, hi) = (b - 2.0 * t, h - 2.0 * t);
                (
                    "hollow rectangle",
                    b * h - bi * hi,
                    (b * h.powi(3) - bi * hi.powi(3)) / 12.0,
                    (h * b.powi(3) - hi * bi.powi(3)) / 12.0,
                    2.0 * t * (b - t).powi(2) * (h - t).powi(2) / (b + h - 2.0 * t),
                )
            }
        }
        2 => {
            let i = pi * d.powi(4) / 64.0;
            ("solid circle", pi * d * d / 4.0, i, i, 2.0 * i)
        }
        _ => {
            let di = d * (1.0 - 2.0 * rng.range(0.06, 0.15));
            let i = pi * (d.powi(4) - di.powi(4)) / 64.0;
            ("tube", pi * (d * d - di * di) / 4.0, i, i, 2.0 * i)
        }
    };
    SectionProps {
        name: name.to_string(),
        shape,
        a: round_sig(a, 5),
        iy: round_sig(iy, 5),
        iz: round_sig(iz, 5),
        j: round_sig(j, 5),
    }
}

/// Build a structure of `kind` with its supports (suspension springs are
/// added by [`suspend`]), lumped masses and pools of 1–2 materials/sections.
pub fn build(
    kind: StructureKind,
    support: Support,
    rng: &mut Rng,
    opts: &GenOptions,
) -> Result<Structure, String> {
    let plane = match kind {
        StructureKind::Beam => rng.chance(0.5),
        StructureKind::SpaceFrame => false,
        _ => true,
    };
    let scale = rng.range(0.5, 1.5);
    let mut b = Builder {
        st: Structure {
            kind,
            plane,
            support,
            materials: Vec::new(),
            sections: Vec::new(),
            nodes: Vec::new(),
            beams: Vec::new(),
            masses: Vec::new(),
            springs: Vec::new(),
            links: Vec::new(),
            timoshenko: false,
            fixes: Vec::new(),
            damping: None,
            members: Vec::new(),
            key_nodes: Vec::new(),
        },
    };
    for i in 0..rng.int(1, 2) {
        b.st.materials
            .push(draw_material(&format!("mat{}", i + 1), rng));
    }
    for i in 0..rng.int(1, 2) {
        let d = scale * opts.section_scale * rng.range(1.0 / 40.0, 1.0 / 15.0);
        b.st.sections
            .push(draw_section(&format!("sec{}", i + 1), d, rng));
    }
    let per_node = if plane { 3 } else { 6 };
    let dofs = rng.int(opts.min_dofs, opts.max_dofs.max(opts.min_dofs));
    let nodes_wanted = (dofs / per_node).max(4);
    let supports = geometry(&mut b, kind, scale, nodes_wanted, rng);
    add_masses(&mut b.st, rng);
    apply_supports(&mut b.st, support, &supports);
    Ok(b.st)
}

/// Lay out the members of `kind`; returns the support nodes with the DOFs a
/// pinned support fixes at each (clamped fixes `all` at the first ones).
fn geometry(
    b: &mut Builder,
    kind: StructureKind,
    scale: f64,
    nodes_wanted: usize,
    rng: &mut Rng,
) -> Vec<(u32, &'static str, bool)> {
    let table = rng.chance(0.5);
    let mut len = |lo: f64, hi: f64| scale * rng.range(lo, hi);
    // (start, end) points of each member, by node index into `points`.
    let (points, members): (Vec<[f64; 3]>, Vec<(usize, usize)>) = match kind {
        StructureKind::Beam => (vec![[0.0; 3], [len(0.8, 3.0), 0.0, 0.0]], vec![(0, 1)]),
        StructureKind::LFrame => {
            let (h, w) = (len(0.5, 1.5), len(0.5, 1.5));
            (
                vec![[0.0; 3], [0.0, 0.0, h], [w, 0.0, h]],
                vec![(0, 1), (1, 2)],
            )
        }
        StructureKind::TFrame => {
            let (w, h) = (len(0.5, 1.2), len(0.5, 1.5));
            let p = vec![[-w, 0.0, h], [0.0, 0.0, h], [w, 0.0, h], [0.0; 3]];
            (p, vec![(0, 1), (1, 2), (3, 1)])
        }
        StructureKind::Portal => {
            let (h, w) = (len(0.5, 1.5), len(0.8, 2.0));
            let p = vec![[0.0; 3], [0.0, 0.0, h], [w, 0.0, h], [w, 0.0, 0.0]];
            (p, vec![(0, 1), (1, 2), (2, 3)])
        }
        StructureKind::SpaceFrame if table => {
            let (a, c, h) = (len(0.6, 1.5), len(0.6, 1.5), len(0.4, 1.0));
            let feet = [[0.0, 0.0, 0.0], [a, 0.0, 0.0], [a, c, 0.0], [0.0, c, 0.0]];
            let mut p: Vec<[f64; 3]> = feet.to_vec();
            p.extend(feet.iter().map(|f| [f[0], f[1], h]));
            let m = vec![
                (0, 4),
                (1, 5),
                (2, 6),
                (3, 7),
                (4, 5),
                (5, 6),
                (6, 7),
                (7, 4),
            ];
            (p, m)
        }
        StructureKind::SpaceFrame => {
            let (x, y, z) = (len(0.5, 1.2), len(0.5, 1.2), len(0.5, 1.2));
            let p = vec![[0.0; 3], [x, 0.0, 0.0], [x, y, 0.0], [x, y, z]];
            (p, vec![(0, 1), (1, 2), (2, 3)])
        }
    };
    let dist = |a: [f64; 3], c: [f64; 3]| {
        ((a[0] - c[0]).powi(2) + (a[1] - c[1]).powi(2) + (a[2] - c[2]).powi(2)).sqrt()
    };
    let total: f64 = members
        .iter()
        .map(|&(i, j)| dist(points[i], points[j]))
        .sum();
    let h = total / nodes_wanted.saturating_sub(points.len()).max(members.len()) as f64;
    let ids: Vec<u32> = points.iter().map(|&p| b.node(p)).collect();
    for &(i, j) in &members {
        let n_el = ((dist(points[i], points[j]) / h).round() as usize).max(2);
        b.member(ids[i], ids[j], n_el, rng);
    }
    let plane = b.st.plane;
    let pin_main = if plane { "x,z" } else { "x,y,z" };
    // (node, DOFs fixed when pinned, clamped here too?)
    let (supports, key): (Vec<(u32, &'static str, bool)>, Vec<u32>) = match kind {
        StructureKind::Beam if plane => (
            vec![(ids[0], "x,z", true), (ids[1], "z", false)],
            vec![ids[0], ids[1]],
        ),
        StructureKind::Beam => (
            vec![(ids[0], "x,y,z,rx", true), (ids[1], "y,z", false)],
            vec![ids[0], ids[1]],
        ),
        StructureKind::LFrame => (
            vec![(ids[0], "x,z", true), (ids[2], "x,z", false)],
            vec![ids[0], ids[2]],
        ),
        StructureKind::TFrame => (
            vec![
                (ids[3], "x,z", true),
                (ids[0], "z", false),
                (ids[2], "z", false),
            ],
            vec![ids[0], ids[2]],
        ),
        StructureKind::Portal => (
            vec![(ids[0], "x,z", true), (ids[3], "x,z", true)],
            vec![ids[0], ids[3]],
        ),
        StructureKind::SpaceFrame if ids.len() == 8 => (
            (0..4).map(|i| (ids[i], pin_main, true)).collect(),
            vec![ids[0], ids[1], ids[2]],
        ),
        StructureKind::SpaceFrame => (
            vec![(ids[0], "x,y,z,rx", true), (ids[3], "x,y,z", false)],
            vec![ids[0], ids[2], ids[3]],
        ),
    };
    b.st.key_nodes = key;
    supports
}

/// 0–2 lumped masses of 2–10 % of the structure's mass at random nodes.
fn add_masses(st: &mut Structure, rng: &mut Rng) {
    let total = st.total_mass();
    for i in 0..rng.int(0, 2) {
        let node = rng.int(1, st.nodes.len()) as u32;
        let m = round_sig(total * rng.range(0.02, 0.1), 4);
        st.masses.push((i as u32 + 1, node, m));
    }
}

/// `fix` statements: clamped fixes `all` at the support nodes marked so,
/// pinned fixes the listed DOFs at every support node; free-free none.
fn apply_supports(st: &mut Structure, support: Support, supports: &[(u32, &'static str, bool)]) {
    st.fixes = match support {
        Support::FreeFree => Vec::new(),
        Support::Clamped => supports
            .iter()
            .filter(|s| s.2)
            .map(|s| (s.0, "all".to_string()))
            .collect(),
        Support::Pinned => supports.iter().map(|s| (s.0, s.1.to_string())).collect(),
    };
}

/// Soft suspension springs on every translational DOF of the key nodes (and
/// a torsion spring for a straight space beam), so that the suspension modes
/// sit a factor r ∈ [6, 12] below the first elastic mode f₁ of the free
/// structure: k = M ω_s² / n with ω_s = 2π f₁ / r, n the key nodes; the
/// torsion spring k_rx = ρ(Iy + Iz)L ω_s².
pub fn suspend(st: &mut Structure, rng: &mut Rng) -> Result<(), String> {
    let free = parse_deck(&st.deck_text("free", &[]))?;
    let n_rb = if st.plane { 3 } else { 6 };
    let modes = modes_hz(&free, &ParameterValues::new(), n_rb + 1)?;
    let f1 = *modes.get(n_rb).ok_or("free structure has too few modes")?;
    let ws = 2.0 * std::f64::consts::PI * f1 / rng.range(6.0, 12.0);
    let n = st.key_nodes.len() as f64;
    let k = round_sig(st.total_mass() * ws * ws / n, 4);
    let dirs: &[&'static str] = if st.plane {
        &["x", "z"]
    } else {
        &["x", "y", "z"]
    };
    let mut id = 1;
    for &node in &st.key_nodes.clone() {
        for &d in dirs {
            st.springs.push((id, node, d, k));
            id += 1;
        }
    }
    if !st.plane && st.kind == StructureKind::Beam {
        let polar: f64 = st
            .beams
            .iter()
            .map(|b| {
                let s = &st.sections[b.section];
                st.materials[b.material].rho * (s.iy + s.iz) * st.length(b)
            })
            .sum();
        st.springs
            .push((id, st.key_nodes[0], "rx", round_sig(polar * ws * ws, 4)));
    }
    Ok(())
}
