//! Invariants and hand calculations: rigid-body motions, total mass,
//! symmetry, the orientation rule (static tip flexibilities), the sign of ry
//! in a plane analysis, plane vs space agreement, springs and masses.

use crate::model_common::*;
use frfup::model::{build, Dof, FeModel, ModelError, ParameterValues};
use nalgebra::{DVector, Vector3};
use std::f64::consts::PI;

/// A skew 3D frame: mixed theories, materials with and without G, a
/// non-default orient, lumped masses with inertias. Free–free.
const FRAME: &str = "\
title skew frame
analysis space
material al E=7.2e10 rho=2700 nu=0.33
material st E=2.1e11 rho=7850 G=8.1e10
section a A=1e-3 Iy=2e-7 Iz=5e-7 J=3e-7
section b A=4e-4 Iy=3e-8 Iz=1e-8 J=2e-8 ky=0.7 kz=0.9
node 1 0 0 0
node 2 1 0.2 0.1
node 3 1.5 1.1 -0.3
node 4 0.3 0.9 0.8
node 5 0.2 0.1 1.2
beam 1 1 2 al a
beam 2 2 3 st b theory=timoshenko
beam 3 3 4 al b orient=0.3,-0.2,1
beam 4 4 1 st a theory=timoshenko orient=1,1,1
beam 5 4 5 al a
beam 6 2 5 st b
mass 1 3 m=0.5 Ixx=1e-3 Iyy=2e-3 Izz=3e-3
mass 2 5 m=0.25
";

fn frame_total_mass() -> f64 {
    let d = deck(FRAME);
    let mut total = 0.0;
    for b in &d.beams {
        let m = d.material(&b.material).unwrap();
        let s = d.section(&b.section).unwrap();
        let x1 = Vector3::from(d.node(b.nodes[0]).unwrap().xyz);
        let x2 = Vector3::from(d.node(b.nodes[1]).unwrap().xyz);
        total += m.rho * s.a * (x2 - x1).norm();
    }
    total + d.masses.iter().map(|m| m.m).sum::<f64>()
}

/// The nodal vector of a rigid motion: translation `t` plus rotation `w`
/// about the point `x0` (small angles).
fn rigid(
    fe: &FeModel,
    text: &str,
    t: Vector3<f64>,
    w: Vector3<f64>,
    x0: Vector3<f64>,
) -> DVector<f64> {
    let d = deck(text);
    DVector::from_fn(fe.dofs.len(), |i, _| {
        let (node, dof) = fe.dofs.equations[i];
        let x = Vector3::from(d.node(node).unwrap().xyz);
        let u = t + w.cross(&(x - x0));
        match dof {
            Dof::X => u.x,
            Dof::Y => u.y,
            Dof::Z => u.z,
            Dof::Rx => w.x,
            Dof::Ry => w.y,
            Dof::Rz => w.z,
        }
    })
}

#[test]
fn symmetric_and_rigid_motions_have_zero_strain_energy() {
    let fe = model(FRAME);
    let (k, m) = (dense(&fe.stiffness), dense(&fe.mass));
    assert_eq!(amax(&(&k - k.transpose())), 0.0, "K symmetric to the bit");
    assert_eq!(amax(&(&m - m.transpose())), 0.0, "M symmetric to the bit");
    let kmax = amax(&k);
    let cases = [
        (Vector3::new(1.0, 0.0, 0.0), Vector3::zeros()),
        (Vector3::new(0.0, 1.0, 0.0), Vector3::zeros()),
        (Vector3::new(0.0, 0.0, 1.0), Vector3::zeros()),
        (Vector3::zeros(), Vector3::new(1.0, 0.0, 0.0)),
        (Vector3::zeros(), Vector3::new(0.0, 1.0, 0.0)),
        (Vector3::zeros(), Vector3::new(0.0, 0.0, 1.0)),
        (Vector3::new(0.3, -0.2, 0.5), Vector3::new(0.4, -0.7, 0.2)),
    ];
    for (t, w) in cases {
        let u = rigid(&fe, FRAME, t, w, Vector3::new(0.7, -0.4, 2.0));
        let ku = &k * &u;
        // Rounding in the 3×3 rotations: ‖Ku‖ ~ ε·‖K‖·‖u‖ (measured ≲ 1e-15).
        let r = ku.amax() / (kmax * u.amax());
        assert!(
            r < 1e-12,
            "rigid motion t={t:?} w={w:?}: ‖Ku‖/‖K‖‖u‖ = {r:e}"
        );
    }
}

#[test]
fn total_mass_from_a_rigid_translation() {
    let fe = model(FRAME);
    let m = dense(&fe.mass);
    let expected = frame_total_mass();
    for dir in [Vector3::x(), Vector3::y(), Vector3::z()] {
        let u = rigid(&fe, FRAME, dir, Vector3::zeros(), Vector3::zeros());
        let mass = u.dot(&(&m * &u));
        assert!(
            (mass / expected - 1.0).abs() < 1e-13,
            "{mass} vs {expected}"
        );
    }
}

#[test]
fn free_free_frame_has_six_rigid_modes() {
    let fe = model(FRAME);
    assert!(!fe.has_fixed_dofs);
    let ev = eigenvalues(&dense(&fe.stiffness), &dense(&fe.mass));
    for l in &ev[..6] {
        assert!(l.abs() < 1e-9 * ev[6], "{l} vs {}", ev[6]);
    }
}

/// Static tip displacement of a cantilever (node 1 clamped) under a unit
/// load on `load` at node 2.
fn tip(text: &str, load: Dof, measure: Dof) -> f64 {
    let fe = model(text);
    let k = dense(&fe.stiffness);
    let mut f = DVector::zeros(fe.dofs.len());
    f[fe.dofs.index(2, load).unwrap()] = 1.0;
    let u = k.lu().solve(&f).unwrap();
    u[fe.dofs.index(2, measure).unwrap()]
}

const E: f64 = 2.0e11;
const G: f64 = 8.0e10;
const A: f64 = 1e-3;
const IY: f64 = 2e-7;
const IZ: f64 = 8e-7;

fn cantilever(analysis: &str, to: [f64; 3], opts: &str) -> String {
    format!(
        "analysis {analysis}\nmaterial m E={E:e} rho=7800 G={G:e}\nsection s A={A:e} Iy={IY:e} Iz={IZ:e} J=1e-7 ky=0.6 kz=0.9\n\
         node 1 0 0 0\nnode 2 {} {} {}\nbeam 1 1 2 m s {opts}\nfix 1 all\n",
        to[0], to[1], to[2]
    )
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * b.abs()
}

#[test]
fn orientation_rule_and_which_inertia_bends_where() {
    let l: f64 = 2.0;
    let eb = |i: f64| l.powi(3) / (3.0 * E * i);
    // Along +X, default orient +Y: local y = Y, z = Z; Iy governs w (z).
    let d = cantilever("space", [l, 0.0, 0.0], "");
    assert!(close(tip(&d, Dof::Z, Dof::Z), eb(IY)));
    assert!(close(tip(&d, Dof::Y, Dof::Y), eb(IZ)));
    // orient = +Z: local y = Z, local z = x × y = −Y; Iy now bends in y.
    let d = cantilever("space", [l, 0.0, 0.0], "orient=0,0,1");
    assert!(close(tip(&d, Dof::Z, Dof::Z), eb(IZ)));
    assert!(close(tip(&d, Dof::Y, Dof::Y), eb(IY)));
    // Only the part of orient normal to the axis counts: (5,0,1) ≡ +Z.
    let d = cantilever("space", [l, 0.0, 0.0], "orient=5,0,1");
    assert!(close(tip(&d, Dof::Y, Dof::Y), eb(IY)));
    // Along +Y, default orient −X: local y = −X, z = Y × −X = +Z; Iy bends in z.
    let d = cantilever("space", [0.0, l, 0.0], "");
    assert!(close(tip(&d, Dof::Z, Dof::Z), eb(IY)));
    assert!(close(tip(&d, Dof::X, Dof::X), eb(IZ)));
    // Timoshenko: FL³/3EI + FL/(κGA), with kz for bending about y (Iy) and
    // ky for bending about z (Iz).
    let d = cantilever("space", [l, 0.0, 0.0], "theory=timoshenko");
    assert!(close(tip(&d, Dof::Z, Dof::Z), eb(IY) + l / (0.9 * G * A)));
    assert!(close(tip(&d, Dof::Y, Dof::Y), eb(IZ) + l / (0.6 * G * A)));
}

#[test]
fn plane_tip_rotation_sign() {
    // +Fz at the tip of a beam along +x: w > 0 and θy = −dw/dx = −FL²/(2EI)
    // (a right-hand rotation about +y turns +x towards −z).
    let l: f64 = 1.5;
    for analysis in ["plane", "space"] {
        let d = cantilever(analysis, [l, 0.0, 0.0], "");
        assert!(close(tip(&d, Dof::Z, Dof::Z), l.powi(3) / (3.0 * E * IY)));
        assert!(close(tip(&d, Dof::Z, Dof::Ry), -l * l / (2.0 * E * IY)));
        // A tip moment My > 0 lifts the tip the other way: w = −ML²/(2EI).
        assert!(close(tip(&d, Dof::Ry, Dof::Z), -l * l / (2.0 * E * IY)));
    }
    // A beam along −x: +Fz still gives θy = +FL²/(2EI) at the tip (dw/dx < 0).
    let d = cantilever("plane", [-l, 0.0, 0.0], "");
    assert!(close(tip(&d, Dof::Z, Dof::Ry), l * l / (2.0 * E * IY)));
}

/// A portal frame in the x–z plane, columns and girder in 4 elements each.
fn portal(analysis: &str, theory: &str) -> String {
    let mut s = format!(
        "analysis {analysis}\nmaterial m E=2e11 rho=7800\nsection c A=2e-3 Iy=3e-6 Iz=5e-6 J=4e-6\nsection g A=1e-3 Iy=1e-6 Iz=2e-6 J=1e-6\n"
    );
    let mut id = 0;
    let mut node = |s: &mut String, x: f64, z: f64| {
        id += 1;
        s.push_str(&format!("node {id} {x} 0 {z}\n"));
        id
    };
    let mut nodes = vec![];
    for i in 0..=4 {
        nodes.push(node(&mut s, 0.0, 0.75 * i as f64));
    }
    for i in 1..=4 {
        nodes.push(node(&mut s, 0.5 * i as f64, 3.0));
    }
    for i in (0..4).rev() {
        nodes.push(node(&mut s, 2.0, 0.75 * i as f64));
    }
    for (b, w) in nodes.windows(2).enumerate() {
        let sec = if (4..8).contains(&b) { "g" } else { "c" };
        s.push_str(&format!(
            "beam {} {} {} m {sec} {theory}\n",
            b + 1,
            w[0],
            w[1]
        ));
    }
    s.push_str(&format!(
        "fix {} all\nfix {} all\n",
        nodes[0],
        nodes[nodes.len() - 1]
    ));
    s.push_str("mass 1 7 m=12 Iyy=0.4\n");
    if analysis == "space" {
        for n in &nodes {
            s.push_str(&format!("fix {n} y,rx,rz\n"));
        }
    }
    s
}

#[test]
fn plane_and_space_agree_on_a_planar_frame() {
    for theory in ["", "theory=timoshenko"] {
        let fp = frequencies_hz(&model(&portal("plane", theory)));
        let fs = frequencies_hz(&model(&portal("space", theory)));
        assert_eq!(fp.len(), fs.len());
        for (a, b) in fp.iter().zip(&fs) {
            assert!((a - b).abs() < 1e-10 * b, "{a} vs {b}");
        }
        let kp = dense(&model(&portal("plane", theory)).stiffness);
        let ks = dense(&model(&portal("space", theory)).stiffness);
        assert!(amax(&(kp - ks)) < 1e-6, "same DOF order, same matrices");
    }
}

#[test]
fn spring_and_mass_by_hand() {
    // One node, m = 2 kg on a 800 N/m grounded spring in z (plane: x, z, ry;
    // x carries mass only, ry nothing → no equation).
    let fe = model("analysis plane\nnode 1 0 0 0\nmass 1 1 m=2\nspring 1 1 z k=800\n");
    assert_eq!(fe.dofs.equations, vec![(1, Dof::X), (1, Dof::Z)]);
    let f = frequencies_hz(&fe);
    assert_eq!(f[0], 0.0);
    assert!(close(f[1], 20.0 / (2.0 * PI)));
    // Two masses joined by a spring in x: ω² = k(1/m1 + 1/m2).
    let fe =
        model("node 1 0 0 0\nnode 2 1 0 0\nmass 1 1 m=3\nmass 2 2 m=6\nspring 7 1 x k=1e4 to=2\n");
    let f = frequencies_hz(&fe);
    let w = (1e4f64 * (1.0 / 3.0 + 1.0 / 6.0)).sqrt();
    assert!(close(*f.last().unwrap(), w / (2.0 * PI)));
    assert_eq!(f.len(), 6);
    // Rotary inertia on a torsion spring: ω² = k/Iyy; fix removes x, z.
    let fe = model(
        "analysis plane\nnode 4 0 0 0\nmass 1 4 m=1 Iyy=0.02\nspring 1 4 ry k=50\nfix 4 x,z\n",
    );
    assert!(fe.has_fixed_dofs);
    assert_eq!(fe.dofs.equations, vec![(4, Dof::Ry)]);
    assert_eq!(fe.dofs.index(4, Dof::X), None);
    assert!(close(
        frequencies_hz(&fe)[0],
        (50.0f64 / 0.02).sqrt() / (2.0 * PI)
    ));
}

#[test]
fn sensors_and_measured_dofs() {
    let fe = model("analysis plane\nnode 1 0 0 0\nnode 2 1 0 0\nmaterial m E=1e9 rho=1000\nsection s A=1e-2 Iy=1e-6\nbeam 1 1 2 m s\nsensor 101 2\n");
    let iz = fe.dofs.index(2, Dof::Z).unwrap();
    assert_eq!(fe.measured_dof(101, 3), Some((iz, 1.0)));
    assert_eq!(fe.measured_dof(101, -3), Some((iz, -1.0)));
    assert_eq!(fe.measured_dof(101, 2), None, "no y in plane");
    assert_eq!(
        fe.measured_dof(1, 1),
        Some((fe.dofs.index(1, Dof::X).unwrap(), 1.0))
    );
}

#[test]
fn k_and_m_share_one_pattern() {
    let fe = model(&(FRAME.to_string() + "spring 1 3 z k=4000\nspring 2 1 rx k=10 to=5\n"));
    let (k, m) = (fe.stiffness.symbolic(), fe.mass.symbolic());
    assert_eq!(k.col_ptr(), m.col_ptr());
    assert_eq!(k.row_idx(), m.row_idx());
}

#[test]
fn geometry_errors_point_at_the_statement() {
    let base = "material m E=1e9 rho=1000\nsection s A=1e-2 Iy=1e-6 Iz=1e-6 J=1e-6\nnode 1 0 0 0\nnode 2 0 0 0\nnode 3 1 1 1\n";
    let d = deck(&format!("{base}beam 1 1 3 m s\n  beam 2 1 2 m s\n"));
    let e = build(&d, &ParameterValues::new()).err().unwrap();
    assert!(matches!(e, ModelError::ZeroLength { beam: 2, .. }));
    assert_eq!(
        e.to_string().split(':').take(2).collect::<Vec<_>>(),
        ["7", "3"]
    );
    let d = deck(&format!("{base}beam 1 1 3 m s orient=2,2,2\n"));
    let e = build(&d, &ParameterValues::new()).err().unwrap();
    assert!(matches!(e, ModelError::OrientParallel { beam: 1, .. }));
    assert!(e.to_string().starts_with("6:23: "), "{e}");
    // Parameter values: unknown name, p ≤ −1.
    let d = deck(&format!("{base}beam 1 1 3 m s\nparam stiff E 1\n"));
    let v = ParameterValues::from([("nope".to_string(), 0.1)]);
    assert!(matches!(
        build(&d, &v),
        Err(ModelError::UnknownParameter { .. })
    ));
    let v = ParameterValues::from([("stiff".to_string(), -1.0)]);
    let e = build(&d, &v).err().unwrap();
    assert!(e.to_string().starts_with("7:1: "), "{e}");
}

#[test]
fn large_lattice_assembles_quickly() {
    // 29 × 29 × 20 nodes × 6 DOF = 100 920 DOFs, ~49 000 beams, with one
    // parameter over every beam.
    let (nx, ny, nz) = (29, 29, 20);
    let id = |i: usize, j: usize, k: usize| 1 + i + nx * (j + ny * k);
    let mut s =
        String::from("material m E=7e10 rho=2700\nsection s A=1e-4 Iy=1e-9 Iz=2e-9 J=1e-9\n");
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                s += &format!(
                    "node {} {} {} {}\n",
                    id(i, j, k),
                    i as f64 * 0.1,
                    j as f64 * 0.1,
                    k as f64 * 0.1
                );
            }
        }
    }
    let mut b = 0;
    for k in 0..nz {
        for j in 0..ny {
            for i in 0..nx {
                for (di, dj, dk) in [(1, 0, 0), (0, 1, 0), (0, 0, 1)] {
                    if i + di < nx && j + dj < ny && k + dk < nz {
                        b += 1;
                        s += &format!(
                            "beam {b} {} {} m s\n",
                            id(i, j, k),
                            id(i + di, j + dj, k + dk)
                        );
                    }
                }
            }
        }
    }
    s += &format!("param all E 1-{b}\n");
    let d = deck(&s);
    let t = std::time::Instant::now();
    let fe = build(&d, &ParameterValues::new()).unwrap();
    let dt = t.elapsed().as_secs_f64();
    println!(
        "lattice: {} DOFs, {b} beams, nnz(K) = {}, build incl. one all-beam derivative: {dt:.2} s",
        fe.dofs.len(),
        fe.stiffness.compute_nnz()
    );
    assert_eq!(fe.dofs.len(), nx * ny * nz * 6);
    // Target ≤ 1–2 s (test profile opt-level 2); generous bound for a loaded machine.
    assert!(dt < 10.0, "{dt} s");
}
