//! Semantic pass: IDs, cross references, admissible values, and the
//! restrictions of `analysis plane` / `analysis space`.
//!
//! Issues are raised against a statement and, where one is at fault, one of
//! its arguments; [`refine`] turns that into the argument's column when the
//! source text is at hand (in [`super::parse`]).

use std::collections::{BTreeMap, BTreeSet};

use super::lexer::{strip_comment, tokenize};
use super::{Analysis, DampingModel, Deck, DeckError, FixDofs, Pos, Quantity, Target};

/// Which part of a statement an issue is about.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Arg {
    /// The statement as a whole (its keyword).
    Statement,
    /// The i-th positional argument after the keyword (0-based).
    Positional(usize),
    /// The value of `key=value`.
    Key(&'static str),
    /// A position stored in the deck itself (ID ranges, orient).
    At(Pos),
}

#[derive(Clone, Debug)]
pub(crate) struct Issue {
    pub pos: Pos,
    pub arg: Arg,
    pub message: String,
}

struct Issues(Vec<Issue>);

impl Issues {
    fn push(&mut self, pos: Pos, arg: Arg, message: impl Into<String>) {
        self.0.push(Issue {
            pos,
            arg,
            message: message.into(),
        });
    }
    /// Raise an issue unless `v > 0` (NaN is rejected too).
    fn positive(&mut self, pos: Pos, key: &'static str, what: &str, v: f64) {
        if !(v > 0.0 && v.is_finite()) {
            self.push(
                pos,
                Arg::Key(key),
                format!("{what} `{key}` must be positive, found {v}"),
            );
        }
    }
    /// Raise an issue unless `v >= 0`.
    fn non_negative(&mut self, pos: Pos, arg: Arg, what: &str, v: f64) {
        if !(v >= 0.0 && v.is_finite()) {
            self.push(pos, arg, format!("{what} must not be negative, found {v}"));
        }
    }
}

/// All issues of a deck (unordered; raised statement kind by statement kind,
/// in this order, which decides between issues at the same position).
pub(crate) fn issues(deck: &Deck) -> Vec<Issue> {
    let mut check = Checker {
        deck,
        plane: deck.analysis == Analysis::Plane,
        out: Issues(Vec::new()),
    };
    let materials = check.materials();
    let sections = check.sections();
    let nodes = check.nodes();
    let beams = check.beams(&nodes, &materials, &sections);
    let masses = check.masses(&nodes);
    let springs = check.springs(&nodes);
    check.fixes(&nodes);
    check.damping();
    check.params([
        (Target::Beam, ids(&beams)),
        (Target::Mass, ids(&masses)),
        (Target::Spring, ids(&springs)),
    ]);
    check.sensors(&nodes);
    check.out.0
}

/// Names (or IDs) seen so far, with the position of their first statement.
type Seen<K> = BTreeMap<K, Pos>;

/// The IDs of a kind of statement, ascending.
fn ids(seen: &Seen<u32>) -> Vec<u32> {
    seen.keys().copied().collect()
}

/// The checks of one deck, one method per statement kind.
struct Checker<'d> {
    deck: &'d Deck,
    plane: bool,
    out: Issues,
}

impl<'d> Checker<'d> {
    fn materials(&mut self) -> Seen<&'d str> {
        let out = &mut self.out;
        let mut materials = BTreeMap::new();
        for m in &self.deck.materials {
            bad_name(out, m.pos, "material", &m.name);
            if let Some(prev) = materials.insert(m.name.as_str(), m.pos) {
                out.push(
                    m.pos,
                    Arg::Positional(0),
                    format!(
                        "duplicate material `{}` (first at line {})",
                        m.name, prev.line
                    ),
                );
            }
            out.positive(m.pos, "E", "Young's modulus", m.e);
            out.positive(m.pos, "rho", "density", m.rho);
            if let Some(g) = m.g {
                out.positive(m.pos, "G", "shear modulus", g);
            }
            if let Some(nu) = m.nu {
                // ν ≤ 0.5 for a physical isotropic solid, but updated decks may
                // carry equivalent values; only G = E/(2(1+ν)) > 0 is required.
                if !(nu > -1.0 && nu.is_finite()) {
                    out.push(
                        m.pos,
                        Arg::Key("nu"),
                        format!("Poisson's ratio `nu` must exceed -1 (so that G = E/(2(1+nu)) > 0), found {nu}"),
                    );
                }
            }
        }
        materials
    }

    fn sections(&mut self) -> Seen<&'d str> {
        let (out, plane) = (&mut self.out, self.plane);
        let mut sections = BTreeMap::new();
        for s in &self.deck.sections {
            bad_name(out, s.pos, "section", &s.name);
            if let Some(prev) = sections.insert(s.name.as_str(), s.pos) {
                out.push(
                    s.pos,
                    Arg::Positional(0),
                    format!(
                        "duplicate section `{}` (first at line {})",
                        s.name, prev.line
                    ),
                );
            }
            out.positive(s.pos, "A", "area", s.a);
            out.positive(s.pos, "Iy", "second moment of area", s.iy);
            for (key, v, what) in [
                ("Iz", s.iz, "second moment of area"),
                ("J", s.j, "torsion constant"),
                ("ky", s.ky, "shear coefficient"),
                ("kz", s.kz, "shear coefficient"),
            ] {
                if let Some(v) = v {
                    out.positive(s.pos, key, what, v);
                }
            }
            if !plane {
                for (key, v) in [("Iz", s.iz), ("J", s.j)] {
                    if v.is_none() {
                        out.push(
                            s.pos,
                            Arg::Statement,
                            format!(
                                "section `{}` lacks `{key}=…`, required for `analysis space`",
                                s.name
                            ),
                        );
                    }
                }
            }
        }
        sections
    }

    fn nodes(&mut self) -> Seen<u32> {
        let (out, plane) = (&mut self.out, self.plane);
        let mut nodes = BTreeMap::new();
        for n in &self.deck.nodes {
            if let Some(prev) = nodes.insert(n.id, n.pos) {
                out.push(
                    n.pos,
                    Arg::Positional(0),
                    format!("duplicate node ID {} (first at line {})", n.id, prev.line),
                );
            }
            for (i, c) in n.xyz.iter().enumerate() {
                if !c.is_finite() {
                    out.push(n.pos, Arg::Positional(i + 1), "coordinate must be finite");
                }
            }
            if plane && n.xyz[1] != 0.0 {
                out.push(
                    n.pos,
                    Arg::Positional(2),
                    format!(
                        "node {} has y = {} but `analysis plane` requires y = 0",
                        n.id, n.xyz[1]
                    ),
                );
            }
        }
        nodes
    }

    fn beams(
        &mut self,
        nodes: &Seen<u32>,
        materials: &Seen<&str>,
        sections: &Seen<&str>,
    ) -> Seen<u32> {
        let out = &mut self.out;
        let mut beams = BTreeMap::new();
        for b in &self.deck.beams {
            if let Some(prev) = beams.insert(b.id, b.pos) {
                out.push(
                    b.pos,
                    Arg::Positional(0),
                    format!("duplicate beam ID {} (first at line {})", b.id, prev.line),
                );
            }
            for (i, n) in b.nodes.iter().enumerate() {
                if !nodes.contains_key(n) {
                    out.push(
                        b.pos,
                        Arg::Positional(i + 1),
                        format!("beam {} uses undefined node {n}", b.id),
                    );
                }
            }
            if b.nodes[0] == b.nodes[1] {
                out.push(
                    b.pos,
                    Arg::Positional(2),
                    format!("beam {} connects node {} to itself", b.id, b.nodes[0]),
                );
            }
            if !materials.contains_key(b.material.as_str()) {
                out.push(
                    b.pos,
                    Arg::Positional(3),
                    format!("beam {} uses undefined material `{}`", b.id, b.material),
                );
            }
            if !sections.contains_key(b.section.as_str()) {
                out.push(
                    b.pos,
                    Arg::Positional(4),
                    format!("beam {} uses undefined section `{}`", b.id, b.section),
                );
            }
            if let Some(o) = &b.orient {
                orient(out, b.pos, o, self.plane);
            }
        }
        beams
    }

    fn masses(&mut self, nodes: &Seen<u32>) -> Seen<u32> {
        let out = &mut self.out;
        let mut masses = BTreeMap::new();
        for m in &self.deck.masses {
            if let Some(prev) = masses.insert(m.id, m.pos) {
                out.push(
                    m.pos,
                    Arg::Positional(0),
                    format!("duplicate mass ID {} (first at line {})", m.id, prev.line),
                );
            }
            if !nodes.contains_key(&m.node) {
                out.push(
                    m.pos,
                    Arg::Positional(1),
                    format!("mass {} is on undefined node {}", m.id, m.node),
                );
            }
            out.non_negative(m.pos, Arg::Key("m"), "mass `m`", m.m);
            for (key, v) in [("Ixx", m.ixx), ("Iyy", m.iyy), ("Izz", m.izz)] {
                if let Some(v) = v {
                    out.non_negative(m.pos, Arg::Key(key), &format!("rotary inertia `{key}`"), v);
                }
            }
        }
        masses
    }

    fn springs(&mut self, nodes: &Seen<u32>) -> Seen<u32> {
        let (out, analysis) = (&mut self.out, self.deck.analysis);
        let mut springs = BTreeMap::new();
        for s in &self.deck.springs {
            if let Some(prev) = springs.insert(s.id, s.pos) {
                out.push(
                    s.pos,
                    Arg::Positional(0),
                    format!("duplicate spring ID {} (first at line {})", s.id, prev.line),
                );
            }
            if !nodes.contains_key(&s.node) {
                out.push(
                    s.pos,
                    Arg::Positional(1),
                    format!("spring {} is on undefined node {}", s.id, s.node),
                );
            }
            if !analysis.has_dof(s.dof) {
                out.push(s.pos, Arg::Positional(2), missing_dof(s.dof));
            }
            out.positive(s.pos, "k", "spring stiffness", s.k);
            if let Some(to) = s.to {
                if !nodes.contains_key(&to) {
                    out.push(
                        s.pos,
                        Arg::Key("to"),
                        format!("spring {} goes to undefined node {to}", s.id),
                    );
                } else if to == s.node {
                    out.push(
                        s.pos,
                        Arg::Key("to"),
                        format!("spring {} connects node {to} to itself", s.id),
                    );
                }
            }
        }
        springs
    }

    fn fixes(&mut self, nodes: &Seen<u32>) {
        let (out, analysis) = (&mut self.out, self.deck.analysis);
        for f in &self.deck.fixes {
            if !nodes.contains_key(&f.node) {
                out.push(
                    f.pos,
                    Arg::Positional(0),
                    format!("`fix` on undefined node {}", f.node),
                );
            }
            if let FixDofs::List(list) = &f.dofs {
                if list.is_empty() {
                    out.push(f.pos, Arg::Positional(1), "`fix` lists no DOF");
                }
                for d in list {
                    if !analysis.has_dof(*d) {
                        out.push(f.pos, Arg::Positional(1), missing_dof(*d));
                    }
                }
            }
        }
    }

    fn damping(&mut self) {
        let Some(d) = &self.deck.damping else { return };
        let values: Vec<(&str, f64)> = match d.model {
            DampingModel::Modal { zeta } => vec![("ZETA", zeta)],
            DampingModel::Rayleigh { alpha, beta } => vec![("ALPHA", alpha), ("BETA", beta)],
            DampingModel::Hysteretic { eta } => vec![("ETA", eta)],
        };
        for (i, (name, v)) in values.into_iter().enumerate() {
            self.out
                .non_negative(d.pos, Arg::Positional(i + 1), &format!("damping {name}"), v);
        }
    }

    /// `param` statements; `target_ids`: the IDs of each kind of statement
    /// a quantity applies to, ascending.
    fn params(&mut self, target_ids: [(Target, Vec<u32>); 3]) {
        let (out, deck, plane) = (&mut self.out, self.deck, self.plane);
        let mut params = BTreeMap::new();
        for p in &deck.params {
            bad_name(out, p.pos, "parameter", &p.name);
            if let Some(prev) = params.insert(p.name.as_str(), p.pos) {
                out.push(
                    p.pos,
                    Arg::Positional(0),
                    format!(
                        "duplicate parameter `{}` (first at line {})",
                        p.name, prev.line
                    ),
                );
            }
            if plane && matches!(p.quantity, Quantity::Iz | Quantity::J) {
                out.push(
                    p.pos,
                    Arg::Positional(1),
                    format!(
                        "quantity `{}` does not apply in `analysis plane` (only bending in x–z, governed by Iy)",
                        p.quantity.name()
                    ),
                );
            }
            if p.ids.is_empty() {
                out.push(p.pos, Arg::Positional(2), "`param` lists no ID");
            }
            param_bounds(out, p);
            let target = p.quantity.target();
            let ids = target_ids
                .iter()
                .find(|(t, _)| *t == target)
                .map(|(_, v)| v.as_slice())
                .unwrap_or(&[]);
            param_ids(out, deck, p, ids);
        }
    }

    fn sensors(&mut self, nodes: &Seen<u32>) {
        let out = &mut self.out;
        let mut sensors = BTreeMap::new();
        for s in &self.deck.sensors {
            if let Some(prev) = sensors.insert(s.test_node, s.pos) {
                out.push(
                    s.pos,
                    Arg::Positional(0),
                    format!(
                        "duplicate sensor for test node {} (first at line {})",
                        s.test_node, prev.line
                    ),
                );
            }
            if !nodes.contains_key(&s.node) {
                out.push(
                    s.pos,
                    Arg::Positional(1),
                    format!(
                        "sensor maps test node {} to undefined node {}",
                        s.test_node, s.node
                    ),
                );
            }
        }
    }
}

/// The message for a DOF that `analysis plane` does not have.
fn missing_dof(dof: super::DeckDof) -> String {
    format!(
        "DOF `{}` does not exist in `analysis plane` (DOFs x, z, ry)",
        dof.name()
    )
}

/// A beam's `orient`: a finite non-zero vector, along global y in a plane
/// analysis.
fn orient(out: &mut Issues, pos: Pos, o: &super::Orient, plane: bool) {
    let v = o.vector;
    if v.iter().any(|c| !c.is_finite()) || v.iter().all(|c| *c == 0.0) {
        out.push(
            pos,
            Arg::At(o.pos),
            "orient must be a finite, non-zero vector",
        );
    } else if plane && (v[0] != 0.0 || v[2] != 0.0) {
        out.push(
            pos,
            Arg::At(o.pos),
            "in `analysis plane` the local y axis is normal to the x–z plane: orient must be along global y (0,±1,0)",
        );
    }
}

/// Every ID range of a `param` names existing statements of its target
/// kind (`ids`, ascending).
fn param_ids(out: &mut Issues, deck: &Deck, p: &super::Param, ids: &[u32]) {
    let target = p.quantity.target();
    for r in &p.ids {
        let lo = ids.partition_point(|&i| i < r.first);
        let hi = ids.partition_point(|&i| i <= r.last);
        let present = (hi - lo) as u64;
        let wanted = u64::from(r.last) - u64::from(r.first) + 1;
        if r.first > r.last || present != wanted {
            let missing = (r.first..=r.last)
                .find(|i| ids.binary_search(i).is_err())
                .unwrap_or(r.first);
            out.push(
                p.pos,
                Arg::At(r.pos),
                format!(
                    "parameter `{}` on `{}` lists {} ID {missing}, which does not exist{}",
                    p.name,
                    p.quantity.name(),
                    target.name(),
                    other_kind_hint(deck, target, missing)
                ),
            );
        }
    }
}

/// Names are non-empty and free of blanks, `=`, `,` and `#` (so they can be written).
fn bad_name(out: &mut Issues, pos: Pos, what: &str, name: &str) {
    if name.is_empty()
        || name
            .chars()
            .any(|c| c.is_whitespace() || matches!(c, '=' | ',' | '#'))
    {
        out.push(
            pos,
            Arg::Positional(0),
            format!("{what} name `{name}` must be non-empty without blanks, `=`, `,` or `#`"),
        );
    }
}

/// A hint when the ID exists as another kind of statement (e.g. `m` on a beam ID).
fn other_kind_hint(deck: &Deck, target: Target, id: u32) -> String {
    let kinds: BTreeSet<&str> = [
        (Target::Beam, deck.beams.iter().any(|b| b.id == id)),
        (Target::Mass, deck.masses.iter().any(|m| m.id == id)),
        (Target::Spring, deck.springs.iter().any(|s| s.id == id)),
    ]
    .into_iter()
    .filter(|(t, present)| *t != target && *present)
    .map(|(t, _)| t.name())
    .collect();
    if kinds.is_empty() {
        String::new()
    } else {
        format!(
            " (there is a {} {id}: this quantity does not apply to it)",
            kinds.into_iter().collect::<Vec<_>>().join("/")
        )
    }
}

/// The position of an issue's argument, found in the source line if given.
pub(crate) fn refine(issue: &Issue, source: Option<&str>) -> Pos {
    if let Arg::At(p) = issue.arg {
        return p;
    }
    let Some(text) = source else { return issue.pos };
    let Some(line) = text
        .split('\n')
        .nth(issue.pos.line.saturating_sub(1) as usize)
    else {
        return issue.pos;
    };
    let toks = tokenize(strip_comment(line), issue.pos.line);
    match issue.arg {
        Arg::Statement | Arg::At(_) => issue.pos,
        Arg::Positional(i) => toks.get(i + 1).map(|t| t.pos).unwrap_or(issue.pos),
        Arg::Key(key) => toks
            .iter()
            .skip(1)
            .find(|t| t.text.split_once('=').map(|(k, _)| k) == Some(key))
            .map(|t| t.pos_at(key.len() + 1))
            .unwrap_or(issue.pos),
    }
}

/// The first issue in source order, positioned with `source` if given.
pub(crate) fn first_error(deck: &Deck, source: Option<&str>) -> Result<(), DeckError> {
    let mut all: Vec<DeckError> = issues(deck)
        .iter()
        .map(|i| DeckError::new(refine(i, source), i.message.clone()))
        .collect();
    all.sort_by_key(|e| e.pos());
    match all.into_iter().next() {
        Some(e) => Err(e),
        None => Ok(()),
    }
}

pub(crate) fn validate(deck: &Deck) -> Result<(), DeckError> {
    first_error(deck, None)
}

/// `min`, `max` and `sd` of a `param`: finite; min > −1 (a property must stay
/// positive), min < max, 0 inside [min, max] (the deck's value is admissible),
/// sd > 0.
fn param_bounds(out: &mut Issues, p: &super::Param) {
    for (key, v) in [("min", p.min), ("max", p.max), ("sd", p.sd)] {
        if v.is_some_and(|x| !x.is_finite()) {
            out.push(
                p.pos,
                Arg::Key(key),
                format!("`{key}` must be a finite number"),
            );
            return;
        }
    }
    if let Some(lo) = p.min {
        if lo <= -1.0 {
            out.push(
                p.pos,
                Arg::Key("min"),
                format!("`min={lo}` allows 1 + p ≤ 0 (a zero or negative property); use min > −1"),
            );
        } else if lo > 0.0 {
            out.push(
                p.pos,
                Arg::Key("min"),
                format!("`min={lo}` excludes the deck's own value (p = 0)"),
            );
        }
    }
    if let Some(hi) = p.max {
        if hi < 0.0 {
            out.push(
                p.pos,
                Arg::Key("max"),
                format!("`max={hi}` excludes the deck's own value (p = 0)"),
            );
        } else if p.min.is_some_and(|lo| lo >= hi) {
            out.push(p.pos, Arg::Key("max"), "`max` must be greater than `min`");
        }
    }
    if let Some(sd) = p.sd {
        if sd <= 0.0 {
            out.push(p.pos, Arg::Key("sd"), format!("`sd={sd}` must be > 0"));
        }
    }
}
