//! ∂K/∂p, ∂M/∂p of every quantity type against a central finite difference
//! of `build` at p = p0 ± 1e-6, and the updated deck.
//!
//! Tolerance: the central difference has truncation error O(h²) ≈ 1e-12
//! (relative) and rounding error ≈ ε·‖K‖/h ≈ 2e-10·‖K‖, so differences are
//! compared with 1e-8·‖K‖ (resp. ‖M‖) in the max norm.

use crate::model_common::*;
use frfup::model::{
    build, composed_values, parameter_names, updated_deck, FeModel, ParameterValues,
};
use frfup::parsers::deck::{parse, write};

/// Skew 3D frame, both theories, G given and derived, masses and springs,
/// and one parameter per quantity type (several sharing elements).
const DECK: &str = "\
analysis space
material al E=7.2e10 rho=2700 nu=0.33
material st E=2.1e11 rho=7850 G=8.1e10
section a A=1e-3 Iy=2e-7 Iz=5e-7 J=3e-7
section b A=4e-4 Iy=3e-8 Iz=1e-8 J=2e-8 ky=0.7 kz=0.9
node 1 0 0 0
node 2 1 0.2 0.1
node 3 1.5 1.1 -0.3
node 4 0.3 0.9 0.8
node 5 0.2 0.1 0.4
beam 1 1 2 al a
beam 2 2 3 st b theory=timoshenko
beam 3 3 4 al b orient=0.3,-0.2,1 theory=timoshenko
beam 4 4 1 st a
beam 5 4 5 al a theory=timoshenko
mass 1 3 m=0.5 Ixx=1e-3 Iyy=2e-3 Izz=3e-3
mass 2 5 m=0.25
spring 1 1 z k=4000
spring 2 2 rx k=10 to=5
fix 1 x,y
param pE E 1-3
param pE5 E 5
param pG G 2-4
param pGal G 1,5
param prho rho 1,2,5
param pA A 1-5
param pIy Iy 2,3
param pIz Iz 1,4,5
param pJ J 1-5
param pm m 1-2
param pk k 1,2
";

const H: f64 = 1e-6;

fn at(values: &ParameterValues, name: &str, p: f64) -> ParameterValues {
    let mut v = values.clone();
    *v.entry(name.to_string()).or_insert(0.0) += p;
    v
}

fn check(deck_text: &str, p0: &ParameterValues) {
    let d = parse(deck_text).unwrap();
    let fe = build(&d, p0).unwrap();
    let (kn, mn) = (amax(&dense(&fe.stiffness)), amax(&dense(&fe.mass)));
    for (i, name) in parameter_names(&d).iter().enumerate() {
        let s = &fe.parameters[i];
        assert_eq!(&s.name, name);
        let base = p0.get(name).copied().unwrap_or(0.0);
        let plus: FeModel = build(&d, &at(p0, name, H)).unwrap();
        let minus: FeModel = build(&d, &at(p0, name, -H)).unwrap();
        // FD in the deck-relative p̄; the contract's p is relative to the
        // current value: ∂/∂p = (1 + p̄0)·∂/∂p̄.
        let scale = (1.0 + base) / (2.0 * H);
        let dk_fd = (dense(&plus.stiffness) - dense(&minus.stiffness)) * scale;
        let dm_fd = (dense(&plus.mass) - dense(&minus.mass)) * scale;
        let (dk, dm) = (dense(&s.dk), dense(&s.dm));
        let ek = amax(&(&dk - &dk_fd)) / kn;
        let em = amax(&(&dm - &dm_fd)) / mn;
        println!(
            "{name:5} (p̄0 = {base}): ‖dK−FD‖/‖K‖ = {ek:.1e}, ‖dM−FD‖/‖M‖ = {em:.1e}, ‖dK‖/‖K‖ = {:.1e}, ‖dM‖/‖M‖ = {:.1e}",
            amax(&dk) / kn,
            amax(&dm) / mn
        );
        assert!(ek < 1e-8 && em < 1e-8, "{name}: {ek:e} {em:e}");
        assert!(amax(&dk) + amax(&dm) > 0.0, "{name} has an effect");
        assert_eq!(amax(&(&dk - dk.transpose())), 0.0);
        assert_eq!(amax(&(&dm - dm.transpose())), 0.0);
    }
}

#[test]
fn derivatives_match_central_differences_at_zero() {
    check(DECK, &ParameterValues::new());
}

#[test]
fn derivatives_are_relative_to_the_current_value() {
    let p0: ParameterValues = [
        ("pE", 0.2),
        ("pIy", -0.3),
        ("pG", 0.5),
        ("pm", 0.1),
        ("pk", -0.4),
        ("pA", 0.05),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect();
    check(DECK, &p0);
}

#[test]
fn plane_derivatives() {
    let plane = "analysis plane\nmaterial m E=2e11 rho=7800\nsection s A=1e-2 Iy=1e-5\n\
                 node 1 0 0 0\nnode 2 0.3 0 0.1\nnode 3 0.5 0 0.5\n\
                 beam 1 1 2 m s theory=timoshenko\nbeam 2 2 3 m s\nfix 1 all\n\
                 param E E 1-2\nparam G G 1\nparam I Iy 1,2\nparam A A 1\nparam r rho 2\n";
    check(plane, &ParameterValues::new());
}

#[test]
fn euler_bernoulli_derivatives_are_the_proportional_parts() {
    // Eq. 31: for EB beams, Iy only reaches the x–z bending terms and the
    // torsional inertia; E (G derived from E) scales all of K: ∂K/∂E = K.
    let d = "material m E=2e11 rho=7800\nsection s A=1e-3 Iy=2e-7 Iz=5e-7 J=3e-7\n\
             node 1 0 0 0\nnode 2 1 0.5 0.2\nbeam 1 1 2 m s\nparam E E 1\nparam r rho 1\n";
    let fe = model(d);
    let k = dense(&fe.stiffness);
    assert!(amax(&(dense(&fe.parameters[0].dk) - &k)) <= 1e-14 * amax(&k));
    assert_eq!(amax(&dense(&fe.parameters[0].dm)), 0.0);
    let m = dense(&fe.mass);
    assert!(amax(&(dense(&fe.parameters[1].dm) - &m)) <= 1e-14 * amax(&m));
}

#[test]
fn updated_deck_multiplies_values_out() {
    let values: ParameterValues = [
        ("pE", 0.2),
        ("pIy", -0.3),
        ("pG", 0.5),
        ("pm", 0.1),
        ("pk", -0.4),
    ]
    .into_iter()
    .map(|(k, v)| (k.to_string(), v))
    .collect();
    let d = parse(DECK).unwrap();
    let up = updated_deck(&d, &values);
    // Same matrices from the updated deck at zero as from the deck at `values`.
    let a = build(&d, &values).unwrap();
    let text = write(&up);
    let b = build(&parse(&text).unwrap(), &ParameterValues::new()).unwrap();
    let (ka, kb) = (dense(&a.stiffness), dense(&b.stiffness));
    let (ma, mb) = (dense(&a.mass), dense(&b.mass));
    assert!(amax(&(&ka - &kb)) <= 1e-14 * amax(&ka));
    assert!(amax(&(&ma - &mb)) <= 1e-14 * amax(&ma));
    // The param statements are kept, and derivatives agree too (same current values).
    assert_eq!(parameter_names(&up), parameter_names(&d));
    for (pa, pb) in a.parameters.iter().zip(&b.parameters) {
        let (x, y) = (dense(&pa.dk), dense(&pb.dk));
        assert!(amax(&(&x - &y)) <= 1e-13 * amax(&ka), "{}", pa.name);
    }
    // pE touches beams 1–3: al (1, 3) splits from beam 5, st (2) from beam 4.
    let names: Vec<&str> = up.materials.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(names, ["al", "al_u1", "al_u2", "st", "st_u1"], "{text}");
    // Deterministic and re-updatable.
    assert_eq!(write(&updated_deck(&d, &values)), text);
    let again = updated_deck(&parse(&text).unwrap(), &ParameterValues::new());
    assert_eq!(write(&again), text);
}

/// Updating by `a`, then by `b` on the result, gives the matrices of one
/// update by the composed values, (1 + a)(1 + b) − 1 per parameter (the
/// diagnosis keeps its decks' values relative to the deck as given this
/// way); parameters in only one of the two keep their value.
#[test]
fn composed_values_update_in_one_step_as_in_two() {
    let vals = |v: &[(&str, f64)]| -> ParameterValues {
        v.iter().map(|(k, x)| (k.to_string(), *x)).collect()
    };
    let a = vals(&[("pE", 0.2), ("pm", 0.1), ("pk", -0.4)]);
    let b = vals(&[("pE", -0.3), ("pIy", 0.25), ("pk", 0.5)]);
    let c = composed_values(&a, &b);
    assert_eq!(c.len(), 4);
    assert!((c["pE"] - (1.2 * 0.7 - 1.0)).abs() < 1e-15);
    assert!((c["pk"] - (0.6 * 1.5 - 1.0)).abs() < 1e-15);
    assert_eq!((c["pm"], c["pIy"]), (0.1, 0.25));
    let d = parse(DECK).unwrap();
    let two = build(
        &updated_deck(&updated_deck(&d, &a), &b),
        &ParameterValues::new(),
    )
    .unwrap();
    let one = build(&updated_deck(&d, &c), &ParameterValues::new()).unwrap();
    let (k2, k1) = (dense(&two.stiffness), dense(&one.stiffness));
    let (m2, m1) = (dense(&two.mass), dense(&one.mass));
    assert!(amax(&(&k2 - &k1)) <= 1e-14 * amax(&k1));
    assert!(amax(&(&m2 - &m1)) <= 1e-14 * amax(&m1));
}

/// Bounds written against the deck's values bound the same physical values
/// after an update: E may go from 0.5× to 1.5× the deck's value; updated by
/// +20 %, the same range is 0.5/1.2 − 1 … 1.5/1.2 − 1 of the updated value.
#[test]
fn updated_deck_keeps_the_physical_bounds_of_each_parameter() {
    let deck = DECK.replace("param pE E 1-3", "param pE E 1-3 min=-0.5 max=0.5 sd=0.1");
    let d = parse(&deck).unwrap();
    let values: ParameterValues = [("pE".to_string(), 0.2)].into_iter().collect();
    let up = parse(&write(&updated_deck(&d, &values))).unwrap();
    let p = up.params.iter().find(|p| p.name == "pE").unwrap();
    let (min, max) = (p.min.unwrap(), p.max.unwrap());
    assert!((min - (0.5 / 1.2 - 1.0)).abs() < 1e-12, "{min}");
    assert!((max - (1.5 / 1.2 - 1.0)).abs() < 1e-12, "{max}");
    assert_eq!(p.sd, Some(0.1));
    // In memory the prior stays centred on the written value: c = −v/(1 + v)
    // with sd s/(1 + v); a written deck cannot say so and starts at 0.
    assert_eq!(p.prior_centre, 0.0);
    let in_memory = updated_deck(&d, &values);
    let prior = frfup::updating::fullband::prior::ParameterPrior::of_deck(&in_memory)[0];
    assert!(
        (prior.centre - (1.0 / 1.2 - 1.0)).abs() < 1e-15,
        "{prior:?}"
    );
    assert!((prior.sd.unwrap() - 0.1 / 1.2).abs() < 1e-15, "{prior:?}");
    // Unchanged parameters keep their bounds as written.
    let unchanged = updated_deck(&d, &ParameterValues::new());
    assert_eq!(write(&unchanged), write(&d));
}
