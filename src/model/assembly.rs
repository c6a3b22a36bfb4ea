//! Deck → assembled sparse K and M over the free DOFs.
//!
//! DOF numbering: nodes in ascending ID, each node's DOFs in the order
//! x y z rx ry rz (those of the analysis). A DOF is *active* if an element
//! reaches it (every analysis DOF of a beam's nodes; the translations of a
//! `mass` with m ≠ 0 and the rotations with a non-zero inertia; the DOF of a
//! spring); inactive DOFs would be empty rows of both K and M and get no
//! equation. Fixed DOFs get none either.
//!
//! K and M are built from one list of (row, col) pairs, so they share one
//! sparsity pattern (explicit zeros included): solvers may combine them by
//! their value arrays.

use std::collections::{BTreeMap, HashMap};

use faer::sparse::{Pair, SymbolicSparseColMat, Triplet};
use frfup_parsers::deck::{Analysis, Deck, DeckDof, FixDofs, Pos};

use super::elements::beam::{local_mass, local_stiffness, Matrix12};
use super::elements::frame::{local_frame, to_global, FrameError, LocalFrame};
use super::elements::lumped::{mass_terms, spring_pair};
use super::properties::{beam_properties, check_values, factors, Factors, Indices};
use super::{
    sensitivity, Damping, Dof, DofMap, FeModel, ModelError, ParameterValues, SparseMatrix,
};

/// No equation.
pub(crate) const NONE: usize = usize::MAX;

/// The model DOF of a deck DOF name.
pub fn dof_of(d: DeckDof) -> Dof {
    match d {
        DeckDof::X => Dof::X,
        DeckDof::Y => Dof::Y,
        DeckDof::Z => Dof::Z,
        DeckDof::Rx => Dof::Rx,
        DeckDof::Ry => Dof::Ry,
        DeckDof::Rz => Dof::Rz,
    }
}

/// Everything the assembly of K, M and their derivatives needs.
pub(crate) struct Layout {
    pub analysis: Analysis,
    /// Node ID → index in `deck.nodes`.
    pub node_index: HashMap<u32, usize>,
    /// Per node (deck order): equation of x y z rx ry rz, or `NONE`.
    pub equations: Vec<[usize; 6]>,
    /// Per beam (deck order): length and local axes.
    pub frames: Vec<LocalFrame>,
    pub indices: Indices,
    pub factors: Factors,
}

impl Layout {
    /// Local 12×12 rows that the analysis keeps (plane: x, z, ry of each node).
    pub fn kept_rows(&self) -> &'static [usize] {
        match self.analysis {
            Analysis::Space => &[0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11],
            Analysis::Plane => &[0, 2, 4, 6, 8, 10],
        }
    }
    /// (local row, equation) of the free DOFs of beam `b`.
    pub fn beam_equations(&self, deck: &Deck, b: usize) -> Vec<(usize, usize)> {
        let beam = &deck.beams[b];
        let mut out = Vec::with_capacity(12);
        for &r in self.kept_rows() {
            let node = beam.nodes[r / 6];
            let eq = self
                .node_index
                .get(&node)
                .map(|&i| self.equations[i][r % 6])
                .unwrap_or(NONE);
            if eq != NONE {
                out.push((r, eq));
            }
        }
        out
    }
    /// Equation of DOF `d` at node ID `node`, or `NONE`.
    pub fn equation(&self, node: u32, d: DeckDof) -> usize {
        self.node_index
            .get(&node)
            .map(|&i| self.equations[i][d.index()])
            .unwrap_or(NONE)
    }
}

/// Local axes of every beam; the first geometric error in source order.
fn frames(deck: &Deck, node_index: &HashMap<u32, usize>) -> Result<Vec<LocalFrame>, ModelError> {
    let mut out = Vec::with_capacity(deck.beams.len());
    let mut first: Option<(Pos, ModelError)> = None;
    for b in &deck.beams {
        let xyz = |id: u32| {
            node_index
                .get(&id)
                .map(|&i| deck.nodes[i].xyz)
                .unwrap_or([0.0; 3])
        };
        match local_frame(xyz(b.nodes[0]), xyz(b.nodes[1]), b.orient.map(|o| o.vector)) {
            Ok(f) => out.push(f),
            Err(e) => {
                let (pos, err) = match e {
                    FrameError::ZeroLength { length } => (
                        b.pos,
                        ModelError::ZeroLength {
                            beam: b.id,
                            pos: b.pos,
                            length,
                        },
                    ),
                    FrameError::OrientParallel => {
                        let pos = b.orient.map(|o| o.pos).unwrap_or(b.pos);
                        (pos, ModelError::OrientParallel { beam: b.id, pos })
                    }
                };
                if first.as_ref().is_none_or(|(p, _)| pos < *p) {
                    first = Some((pos, err));
                }
            }
        }
    }
    match first {
        Some((_, e)) => Err(e),
        None => Ok(out),
    }
}

/// Active and fixed DOFs → equation numbers and the DOF map.
fn number_dofs(deck: &Deck, node_index: &HashMap<u32, usize>) -> (Vec<[usize; 6]>, DofMap, bool) {
    let n = deck.nodes.len();
    let mut active = vec![[false; 6]; n];
    let analysis_dofs = deck.analysis.dofs();
    let mut touch = |node: u32, d: DeckDof| {
        if let Some(&i) = node_index.get(&node) {
            active[i][d.index()] = true;
        }
    };
    for b in &deck.beams {
        for &node in &b.nodes {
            for &d in analysis_dofs {
                touch(node, d);
            }
        }
    }
    for m in &deck.masses {
        for (d, _) in mass_terms(m, 1.0) {
            touch(m.node, d);
        }
    }
    for s in &deck.springs {
        touch(s.node, s.dof);
        if let Some(to) = s.to {
            touch(to, s.dof);
        }
    }
    let mut fixed = vec![[false; 6]; n];
    for f in &deck.fixes {
        if let Some(&i) = node_index.get(&f.node) {
            match &f.dofs {
                FixDofs::All => fixed[i] = [true; 6],
                FixDofs::List(l) => {
                    for d in l {
                        fixed[i][d.index()] = true;
                    }
                }
            }
        }
    }
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by_key(|&i| deck.nodes[i].id);
    let mut equations = vec![[NONE; 6]; n];
    let mut map = DofMap::default();
    let mut has_fixed = false;
    for i in order {
        let id = deck.nodes[i].id;
        for &d in analysis_dofs {
            let k = d.index();
            if !active[i][k] {
                continue;
            }
            if fixed[i][k] {
                has_fixed = true;
                continue;
            }
            let eq = map.equations.len();
            equations[i][k] = eq;
            map.equations.push((id, dof_of(d)));
            map.lookup.insert((id, dof_of(d)), eq);
        }
    }
    (equations, map, has_fixed)
}

/// Global 12×12 stiffness and mass of beam `b` at the layout's factors.
pub(crate) fn beam_matrices(
    deck: &Deck,
    layout: &Layout,
    b: usize,
) -> (Matrix12<f64>, Matrix12<f64>) {
    let beam = &deck.beams[b];
    let frame = &layout.frames[b];
    let (Some(mat), Some(sec)) = (deck.material(&beam.material), deck.section(&beam.section))
    else {
        // Unreachable after validation; an empty element keeps this panic-free.
        return (Matrix12::zeros(), Matrix12::zeros());
    };
    let p = beam_properties::<f64>(mat, sec, layout.factors.beam[b]);
    let k = local_stiffness(&p, frame.length, beam.theory());
    let m = local_mass(&p, frame.length, beam.theory());
    (
        to_global(&k, &frame.rotation),
        to_global(&m, &frame.rotation),
    )
}

/// Check the deck and values, number the DOFs, form the local axes.
pub(crate) fn layout(
    deck: &Deck,
    values: &ParameterValues,
) -> Result<(Layout, DofMap, bool), ModelError> {
    deck.validate()?;
    check_values(deck, values)?;
    let node_index: HashMap<u32, usize> = deck
        .nodes
        .iter()
        .enumerate()
        .map(|(i, n)| (n.id, i))
        .collect();
    let frames = frames(deck, &node_index)?;
    let (equations, dofs, has_fixed) = number_dofs(deck, &node_index);
    if dofs.is_empty() {
        return Err(ModelError::NoDofs);
    }
    let indices = Indices::new(deck);
    let factors = factors(deck, &indices, values);
    Ok((
        Layout {
            analysis: deck.analysis,
            node_index,
            equations,
            frames,
            indices,
            factors,
        },
        dofs,
        has_fixed,
    ))
}

/// Build the FE model of `deck` at parameter values `values` (relative
/// changes p̄; updated value = (1 + p̄)·deck value).
///
/// Errors: the deck's own checks ([`ModelError::Deck`]), zero-length beams,
/// `orient` parallel to a beam, unknown/non-finite parameter values or values
/// ≤ −1, and a model without free DOFs.
pub fn build(deck: &Deck, values: &ParameterValues) -> Result<FeModel, ModelError> {
    check_magnitudes(deck)?;
    let (layout, dofs, has_fixed_dofs) = layout(deck, values)?;
    let n = dofs.len();

    let mut pairs: Vec<Pair<usize, usize>> = Vec::new();
    let mut kv: Vec<f64> = Vec::new();
    let mut mv: Vec<f64> = Vec::new();
    let entries: usize = deck.beams.len() * layout.kept_rows().len().pow(2);
    pairs.reserve(entries);
    kv.reserve(entries);
    mv.reserve(entries);
    for b in 0..deck.beams.len() {
        let (k, m) = beam_matrices(deck, &layout, b);
        let eqs = layout.beam_equations(deck, b);
        for &(ri, row) in &eqs {
            for &(ci, col) in &eqs {
                let (kij, mij) = (k[(ri, ci)], m[(ri, ci)]);
                if kij != 0.0 || mij != 0.0 {
                    pairs.push(Pair { row, col });
                    kv.push(kij);
                    mv.push(mij);
                }
            }
        }
    }
    for (i, mass) in deck.masses.iter().enumerate() {
        for (d, v) in mass_terms(mass, layout.factors.mass[i]) {
            let eq = layout.equation(mass.node, d);
            if eq != NONE {
                pairs.push(Pair { row: eq, col: eq });
                kv.push(0.0);
                mv.push(v);
            }
        }
    }
    for (i, s) in deck.springs.iter().enumerate() {
        let k = s.k * layout.factors.spring[i];
        for (row, col, v) in spring_entries(&layout, s, k) {
            pairs.push(Pair { row, col });
            kv.push(v);
            mv.push(0.0);
        }
    }
    let (symbolic, argsort) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
        .map_err(|e| ModelError::Sparse(format!("{e:?}")))?;
    drop(pairs);
    let mut stiffness = SparseMatrix::new_from_argsort(symbolic.clone(), &argsort, &kv)
        .map_err(|e| ModelError::Sparse(format!("{e:?}")))?;
    let mut mass = SparseMatrix::new_from_argsort(symbolic, &argsort, &mv)
        .map_err(|e| ModelError::Sparse(format!("{e:?}")))?;
    mirror_upper(&mut stiffness);
    mirror_upper(&mut mass);

    let parameters = sensitivity::derivatives(deck, &layout, n)?;
    let damping = Damping::of_deck(deck);
    let sensors: BTreeMap<u32, u32> = deck.sensors.iter().map(|s| (s.test_node, s.node)).collect();
    Ok(FeModel {
        dofs,
        stiffness,
        mass,
        damping,
        parameters,
        has_fixed_dofs,
        sensors,
    })
}

/// (row, col, value) of a spring of stiffness `k` on the free DOFs.
pub(crate) fn spring_entries(
    layout: &Layout,
    s: &frfup_parsers::deck::Spring,
    k: f64,
) -> Vec<(usize, usize, f64)> {
    let a = layout.equation(s.node, s.dof);
    let mut out = Vec::with_capacity(4);
    match s.to {
        None => {
            if a != NONE {
                out.push((a, a, k));
            }
        }
        Some(to) => {
            let b = layout.equation(to, s.dof);
            let kk = spring_pair(k);
            let eqs = [a, b];
            for i in 0..2 {
                for j in 0..2 {
                    if eqs[i] != NONE && eqs[j] != NONE {
                        out.push((eqs[i], eqs[j], kk[i][j]));
                    }
                }
            }
        }
    }
    out
}

/// Make a structurally symmetric matrix symmetric to the bit: copy each
/// upper-triangle value onto its lower-triangle mirror. (Duplicate entries
/// are summed in sort order, which can differ between (i, j) and (j, i) and
/// leave differences of one rounding.)
pub(crate) fn mirror_upper(a: &mut SparseMatrix) {
    let moves: Vec<(usize, usize)> = {
        let sym = a.symbolic();
        let (cp, ri) = (sym.col_ptr(), sym.row_idx());
        let mut moves = Vec::new();
        for j in 0..sym.ncols() {
            for k in cp[j]..cp[j + 1] {
                let i = ri[k];
                if i > j {
                    // The mirror (j, i) lives in column i.
                    let col = &ri[cp[i]..cp[i + 1]];
                    if let Ok(pos) = col.binary_search(&j) {
                        moves.push((k, cp[i] + pos));
                    }
                }
            }
        }
        moves
    };
    let val = a.val_mut();
    for (dst, src) in moves {
        val[dst] = val[src];
    }
}

/// A sparse matrix from triplets (duplicates summed), symmetric to the bit.
pub(crate) fn from_triplets(
    n: usize,
    t: &[Triplet<usize, usize, f64>],
) -> Result<SparseMatrix, ModelError> {
    let mut a = SparseMatrix::try_new_from_triplets(n, n, t)
        .map_err(|e| ModelError::Sparse(format!("{e:?}")))?;
    mirror_upper(&mut a);
    Ok(a)
}

/// Largest coordinate (m) a deck may give: beyond it squares of lengths lose
/// all precision (and overflow near 1e154), so it can only be a unit error.
const MAX_COORDINATE: f64 = 1e9;
/// Largest E (Pa): diamond is about 1.2e12 Pa, and a "rigid" link is stiff
/// enough well below this; 1e308 gives frequencies of 1e148 Hz.
const MAX_MODULUS: f64 = 1e20;
/// Largest G (Pa): higher than E, as a shear-rigid Timoshenko beam (the
/// Rayleigh limit) is modelled with G = 1e22.
const MAX_SHEAR_MODULUS: f64 = 1e30;
/// Largest density (kg/m³): osmium is 2.26e4; lumped masses are given as `mass`.
const MAX_DENSITY: f64 = 1e7;

/// Refuse coordinates and material values no structure has, naming the statement.
fn check_magnitudes(deck: &Deck) -> Result<(), ModelError> {
    for n in &deck.nodes {
        if let Some(x) = n.xyz.iter().find(|x| x.abs() > MAX_COORDINATE) {
            return Err(ModelError::Implausible {
                pos: n.pos,
                message: format!(
                    "node {} has the coordinate {x:e} m, beyond {MAX_COORDINATE:e} m: coordinates are in metres (a unit or typing error?)",
                    n.id
                ),
            });
        }
    }
    for m in &deck.materials {
        let checks = [
            ("E", Some(m.e), MAX_MODULUS, "Pa"),
            ("G", m.g, MAX_SHEAR_MODULUS, "Pa"),
            ("rho", Some(m.rho), MAX_DENSITY, "kg/m^3"),
        ];
        for (name, value, max, unit) in checks {
            if let Some(v) = value.filter(|v| v.abs() > max) {
                return Err(ModelError::Implausible {
                    pos: m.pos,
                    message: format!(
                        "material {}: {name} = {v:e} {unit} is beyond {max:e} {unit}, far more than any material or rigid link needs: values are in SI units (a unit or typing error?)",
                        m.name
                    ),
                });
            }
        }
    }
    Ok(())
}

/// For an eigen solve every free DOF needs mass: name the first that has none
/// (a direct FRF solve does not need it, so `build` does not ask).
pub fn check_mass(fe: &FeModel) -> Result<(), ModelError> {
    let (mass, dofs) = (&fe.mass, &fe.dofs);
    let diag = super::diagonal(mass);
    match diag.iter().position(|m| !(*m > 0.0)) {
        Some(i) => {
            let (node, dof) = dofs.equations[i];
            Err(ModelError::NoMass {
                node,
                dof: dof.name(),
            })
        }
        None => Ok(()),
    }
}
