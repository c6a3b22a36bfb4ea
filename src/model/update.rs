//! The updated deck: parameter values multiplied out into the deck's numbers.

use std::collections::BTreeSet;

use frfup_parsers::deck::{Deck, Material, Section};

use super::properties::{factors, Indices};
use super::ParameterValues;

/// The names of the deck's updating parameters, in deck order.
pub fn parameter_names(deck: &Deck) -> Vec<String> {
    deck.params.iter().map(|p| p.name.clone()).collect()
}

/// Group `items` (beam index, key) by key bits in order of first appearance.
fn groups(items: &[(usize, Vec<f64>)]) -> Vec<(Vec<f64>, Vec<usize>)> {
    let mut out: Vec<(Vec<f64>, Vec<usize>)> = Vec::new();
    for (b, key) in items {
        let bits = |k: &Vec<f64>| k.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        match out.iter_mut().find(|(k, _)| bits(k) == bits(key)) {
            Some((_, v)) => v.push(*b),
            None => out.push((key.clone(), vec![*b])),
        }
    }
    out
}

/// A fresh name `{base}_u{k}` not in `taken`.
fn derived_name(base: &str, taken: &mut BTreeSet<String>) -> String {
    let mut k = 1;
    loop {
        let name = format!("{base}_u{k}");
        if taken.insert(name.clone()) {
            return name;
        }
        k += 1;
    }
}

fn scaled_material(m: &Material, f: &[f64]) -> Material {
    let (fe, fg, frho) = (f[0], f[1], f[2]);
    // Without an explicit G, G = E/(2(1+ν)) follows E; keep it that way (so
    // that ∂/∂E stays the same when the deck is updated again) by folding the
    // factor on G into ν: E/(2(1+ν')) = f_G·E/(2(1+ν)) ⇔ 1+ν' = (1+ν)/f_G.
    let (g, nu) = match m.g {
        Some(g) => (Some(g * fg), m.nu),
        None if fg != 1.0 => (None, Some((1.0 + m.nu()) / fg - 1.0)),
        None => (None, m.nu),
    };
    Material {
        e: m.e * fe,
        rho: m.rho * frho,
        g,
        nu,
        ..m.clone()
    }
}

fn scaled_section(s: &Section, f: &[f64]) -> Section {
    Section {
        a: s.a * f[0],
        iy: s.iy * f[1],
        iz: s.iz.map(|v| v * f[2]),
        j: s.j.map(|v| v * f[3]),
        ..s.clone()
    }
}

/// The values that update a deck as `a` then `b` (relative to the deck
/// `a` gave) do in one step: (1 + p̄) = (1 + a)(1 + b) per parameter, as
/// [`updated_deck`] multiplies the factors of every parameter.
pub fn composed_values(a: &ParameterValues, b: &ParameterValues) -> ParameterValues {
    let mut out = a.clone();
    for (name, &vb) in b {
        let va = a.get(name).copied().unwrap_or(0.0);
        out.insert(name.clone(), (1.0 + va) * (1.0 + vb) - 1.0);
    }
    out
}

/// The deck with `values` multiplied out: every quantity a parameter touches
/// becomes (1 + p̄)·(deck value). Where a parameter touches some of the beams
/// sharing a material (section), the touched beams get a new material
/// (section) named `{name}_u{k}`; the group of untouched beams (or else the
/// first group in beam order) keeps the original. The `param` statements are
/// kept, so the result can be updated again (new values are relative to the
/// updated numbers). For a material without `G` a change of G goes into ν
/// (G keeps following E). Unknown names in `values` are ignored. The
/// parameters' `min`/`max` are re-expressed so that they bound the same
/// physical values ([`rebase_bounds`]).
pub fn updated_deck(deck: &Deck, values: &ParameterValues) -> Deck {
    let idx = Indices::new(deck);
    let f = factors(deck, &idx, values);
    let mut out = deck.clone();
    let mut taken: BTreeSet<String> = deck
        .materials
        .iter()
        .map(|m| m.name.clone())
        .chain(deck.sections.iter().map(|s| s.name.clone()))
        .collect();

    // Materials.
    let mut materials = Vec::with_capacity(deck.materials.len());
    for m in &deck.materials {
        let users: Vec<(usize, Vec<f64>)> = deck
            .beams
            .iter()
            .enumerate()
            .filter(|(_, b)| b.material == m.name)
            .map(|(i, _)| (i, f.beam[i][0..3].to_vec()))
            .collect();
        let gs = groups(&users);
        let keeper = gs
            .iter()
            .position(|(k, _)| k.iter().all(|v| *v == 1.0))
            .unwrap_or(0);
        if gs.is_empty() {
            materials.push(m.clone());
            continue;
        }
        materials.push(scaled_material(m, &gs[keeper].0));
        for (gi, (key, beams)) in gs.iter().enumerate() {
            if gi == keeper {
                continue;
            }
            let name = derived_name(&m.name, &mut taken);
            materials.push(Material {
                name: name.clone(),
                ..scaled_material(m, key)
            });
            for &b in beams {
                out.beams[b].material = name.clone();
            }
        }
    }
    out.materials = materials;

    // Sections.
    let mut sections = Vec::with_capacity(deck.sections.len());
    for s in &deck.sections {
        let users: Vec<(usize, Vec<f64>)> = deck
            .beams
            .iter()
            .enumerate()
            .filter(|(_, b)| b.section == s.name)
            .map(|(i, _)| (i, f.beam[i][3..7].to_vec()))
            .collect();
        let gs = groups(&users);
        if gs.is_empty() {
            sections.push(s.clone());
            continue;
        }
        let keeper = gs
            .iter()
            .position(|(k, _)| k.iter().all(|v| *v == 1.0))
            .unwrap_or(0);
        sections.push(scaled_section(s, &gs[keeper].0));
        for (gi, (key, beams)) in gs.iter().enumerate() {
            if gi == keeper {
                continue;
            }
            let name = derived_name(&s.name, &mut taken);
            sections.push(Section {
                name: name.clone(),
                ..scaled_section(s, key)
            });
            for &b in beams {
                out.beams[b].section = name.clone();
            }
        }
    }
    out.sections = sections;

    for (i, m) in out.masses.iter_mut().enumerate() {
        m.m *= f.mass[i];
    }
    for (i, s) in out.springs.iter_mut().enumerate() {
        s.k *= f.spring[i];
    }
    rebase_bounds(&mut out.params, values);
    out
}

/// The `min`/`max` bounds of each `param` re-expressed against the updated
/// values, so that they bound the same physical values: a property bounded
/// to (1 + min)·v₀ is (1 + min')·(1 + p̄)·v₀ with 1 + min' = (1 + min)/(1 + p̄).
/// A prior `sd` is kept as written; its centre, the original value, moves
/// the same way in memory (`Param::prior_centre`), which the deck format
/// cannot write.
fn rebase_bounds(params: &mut [frfup_parsers::deck::Param], values: &ParameterValues) {
    for p in params {
        let v = values.get(&p.name).copied().unwrap_or(0.0);
        if v != 0.0 && v > -1.0 {
            let rebase = |b: f64| (1.0 + b) / (1.0 + v) - 1.0;
            p.min = p.min.map(rebase);
            p.max = p.max.map(rebase);
            p.prior_centre = rebase(p.prior_centre);
        }
    }
}
