//! The model of the full-band estimate on a Ritz basis fixed at an anchor.
//!
//! T = [Φ | S] (n × m): the lowest modes Φ at the anchor p̄ₐ (up to 4·ω_max,
//! as [`fit::modal_solution`]) and the static responses to a unit load at
//! the excitation and at each channel, x = (K − σM)⁻¹ P e with P = I − MΦΦᵀ
//! (σ < 0 tiny, as [`frf::static_residual_terms`]), with the excitation's
//! second Krylov vector (K − σM)⁻¹ M x̄; S is deflated of Φ and
//! M-orthonormalised. With K(p̄) = Kₐ + Σ_j (p̄_j − p̄ₐ_j) ∂K/∂p̄_j (exact
//! where the properties enter linearly: Euler–Bernoulli beams, masses,
//! springs) and likewise M, the reduced pencil is K_r = TᵀK(p̄)T,
//! M_r = TᵀM(p̄)T (m × m).
//!
//! At the anchor its lowest eigenpairs are the modes Φ and its upper ones
//! carry the left-out modes' static residual at every channel (R0) and its
//! first frequency term at the excitation (R1): its FRFs are those of
//! [`fit::predict`]. Its eigenvector derivatives, expanded over all m of its
//! modes, are exact for the reduced model and hold the static part of ∂φ at
//! the channels (the channels' static responses are in the basis), which a
//! modal expansion over Φ alone misses. Away from the anchor it is a
//! Rayleigh–Ritz approximation (eigenvalues to second order in p̄ − p̄ₐ), so
//! the estimate moves its anchor as it goes ([`super::estimate`]).

use faer::linalg::matmul::matmul;
use faer::sparse::linalg::matmul::sparse_dense_matmul;
use faer::{Accum, Mat, MatRef, Par};
use frfup_parsers::deck::Deck;

use super::data::TestData;
use super::fit::{self, ModalModel};
use super::ritz::RitzBasis;
use super::FitError;
use crate::model::{self, ParameterValues, SparseMatrix};
use crate::solvers::dense::{cholesky_lower, product, symmetric_eigen};
use crate::solvers::eigen::{self, lanczos::ShiftedCholesky};

/// The reduced pencil and its derivatives at one anchor.
pub struct ReducedModel {
    /// p̄ of the anchor (deck order).
    pub anchor: Vec<f64>,
    k: Mat<f64>,
    m: Mat<f64>,
    /// Tᵀ(∂K/∂p̄_j)T and Tᵀ(∂M/∂p̄_j)T per parameter (`None`: ∂M/∂p̄_j is
    /// zero, as for every stiffness property).
    dk: Vec<Mat<f64>>,
    dm: Vec<Option<Mat<f64>>>,
    /// DOFs of the full model.
    dofs: usize,
    /// T, its rows at the channels and the excitation, the columns of Φ.
    ritz: RitzBasis,
}

/// The eigen solution of the reduced pencil at some p̄.
pub struct ReducedModes {
    /// The modal model (every reduced mode, no residual terms).
    pub model: ModalModel,
    /// Ψ (m × m), M_r-orthonormal, ascending eigenvalues.
    pub shapes: Mat<f64>,
    /// The modes at the channels and the excitation: rows of T times Ψ.
    pub at_dofs: Mat<f64>,
}

impl ReducedModel {
    /// Build the deck at p̄ = `p` (names in deck order) and its basis.
    pub fn new(
        deck: &Deck,
        names: &[String],
        p: &[f64],
        data: &TestData,
    ) -> Result<ReducedModel, FitError> {
        let fe = built_model(deck, names, p)?;
        let place = fit::placement(&fe, data)?;
        let ritz = RitzBasis::on_modes(&fe, fit::band_modes(&fe, data)?, &place)?;
        Ok(ReducedModel::on_basis(&fe, p, ritz))
    }

    /// The reduced model moved to p̄ = `p` from the one it leaves, whose
    /// solution there is `at_p`: Φ from one block inverse iteration of the
    /// full pencil on the old basis's Ritz vectors at p̄, X = (K − σM)⁻¹ M T Ψ,
    /// and a Rayleigh–Ritz solution on X, instead of a new eigen solution of
    /// the full model. A mode's error shrinks by ω_r²/ω²_{m+1} on top of the
    /// old basis's Rayleigh–Ritz accuracy at p̄ (second order in the drift):
    /// close to exact for the band's modes, not exact. Used between steps of
    /// a minimisation, whose last anchor [`ReducedModel::new`] solves anew.
    pub fn moved(
        &self,
        deck: &Deck,
        names: &[String],
        p: &[f64],
        data: &TestData,
        at_p: &ReducedModes,
    ) -> Result<ReducedModel, FitError> {
        let fe = built_model(deck, names, p)?;
        let n = fe.dofs.len();
        if self.ritz.band_modes >= n || fe.dofs.len() != self.dofs {
            return ReducedModel::new(deck, names, p, data);
        }
        let place = fit::placement(&fe, data)?;
        let chol = shifted_cholesky(&fe)?;
        let ritz = product(self.ritz.basis.as_ref(), at_p.shapes.as_ref());
        let mut x = chol.solve(sparse_times(&fe.mass, ritz.as_ref()).as_ref());
        let Some(phi) = rayleigh_ritz(&fe, &mut x, self.ritz.band_modes) else {
            return ReducedModel::new(deck, names, p, data);
        };
        let ritz = RitzBasis::on_shapes(&fe, &phi, &place, Some(&chol))?;
        Ok(ReducedModel::on_basis(&fe, p, ritz))
    }

    /// The reduced model on the basis `ritz` ([Φ | S]) of `fe` at p̄ = `p`.
    fn on_basis(fe: &crate::model::FeModel, p: &[f64], ritz: RitzBasis) -> ReducedModel {
        let project = |s: &SparseMatrix, scale: f64| project(s, ritz.basis.as_ref(), scale);
        // ∂K/∂p̄ = ∂K/∂q · ∂q/∂p̄ with q the relative change of the deck as
        // built: (1 + q) = (1 + p̄)/(1 + p̄ₐ).
        let chain: Vec<f64> = p.iter().map(|v| 1.0 / (1.0 + v)).collect();
        ReducedModel {
            anchor: p.to_vec(),
            k: project(&fe.stiffness, 1.0),
            m: project(&fe.mass, 1.0),
            dk: fe
                .parameters
                .iter()
                .zip(&chain)
                .map(|(q, &c)| project(&q.dk, c))
                .collect(),
            dm: fe
                .parameters
                .iter()
                .zip(&chain)
                .map(|(q, &c)| (q.dm.compute_nnz() > 0).then(|| project(&q.dm, c)))
                .collect(),
            dofs: fe.dofs.len(),
            ritz,
        }
    }

    /// Number of basis vectors m.
    pub fn size(&self) -> usize {
        self.k.nrows()
    }

    /// Tᵀ(∂K/∂p̄_j)T and Tᵀ(∂M/∂p̄_j)T (`None` where ∂M/∂p̄_j is zero).
    pub fn derivative(&self, j: usize) -> (MatRef<'_, f64>, Option<MatRef<'_, f64>>) {
        (self.dk[j].as_ref(), self.dm[j].as_ref().map(|m| m.as_ref()))
    }

    /// Largest relative change of a property between the anchor and `p`:
    /// max_j |p̄_j − p̄ₐ_j| / (1 + p̄ₐ_j).
    pub fn drift(&self, p: &[f64]) -> f64 {
        p.iter()
            .zip(&self.anchor)
            .map(|(v, a)| (v - a).abs() / (1.0 + a))
            .fold(0.0, f64::max)
    }

    /// Eigen solution of K_r(p̄) ψ = λ M_r(p̄) ψ ([`pencil_eigen`]); `None`
    /// if M_r is not positive definite.
    pub fn solve(&self, p: &[f64]) -> Option<ReducedModes> {
        let mut k = self.k.clone();
        let mut m = self.m.clone();
        for (j, (&v, &a)) in p.iter().zip(&self.anchor).enumerate() {
            let d = v - a;
            if d != 0.0 {
                k += &self.dk[j] * d;
                if let Some(dm) = &self.dm[j] {
                    m += dm * d;
                }
            }
        }
        let (omega2, shapes) = pencil_eigen(k, &m)?;
        let at_dofs = product(self.ritz.rows.as_ref(), shapes.as_ref());
        let nc = at_dofs.nrows() - 1;
        let coeff = (0..nc)
            .map(|c| {
                (0..shapes.ncols())
                    .map(|r| at_dofs[(c, r)] * at_dofs[(nc, r)])
                    .collect()
            })
            .collect();
        let frequencies_hz = omega2
            .iter()
            .map(|w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect();
        Some(ReducedModes {
            model: ModalModel {
                omega2,
                coeff,
                residual: vec![0.0; nc],
                residual_mass: vec![0.0; nc],
                frequencies_hz,
                dofs: self.dofs,
            },
            shapes,
            at_dofs,
        })
    }
}

/// The deck built at p̄ = `p` (names in deck order).
fn built_model(
    deck: &Deck,
    names: &[String],
    p: &[f64],
) -> Result<crate::model::FeModel, FitError> {
    let values: ParameterValues = names.iter().cloned().zip(p.iter().copied()).collect();
    let built = model::updated_deck(deck, &values);
    model::build(&built, &ParameterValues::new()).map_err(FitError::Model)
}

/// K − σM factored, σ = −1e-8 of the largest K_ii/M_ii (positive definite
/// with rigid-body modes).
pub(super) fn shifted_cholesky(fe: &crate::model::FeModel) -> Result<ShiftedCholesky, FitError> {
    let (k, m) = (&fe.stiffness, &fe.mass);
    let eig_err = |e: String| FitError::Eigen(e);
    let scale = eigen::pencil_scale(k, m).map_err(|e| eig_err(e.to_string()))?;
    ShiftedCholesky::new(k, m, -1e-8 * scale.max_ratio).map_err(|e| eig_err(e.to_string()))
}

/// S x for a sparse S.
fn sparse_times(m: &SparseMatrix, x: MatRef<'_, f64>) -> Mat<f64> {
    let mut y = Mat::<f64>::zeros(m.nrows(), x.ncols());
    sparse_dense_matmul(y.as_mut(), Accum::Replace, m.as_ref(), x, 1.0, Par::Seq);
    y
}

/// The `count` lowest Rayleigh–Ritz vectors of (K, M) on the span of `x`
/// (columns scaled to unit M-norm first: inverse iteration spreads them by
/// orders of magnitude), M-orthonormal; `None` if XᵀMX is not positive
/// definite or the span is too small.
fn rayleigh_ritz(fe: &crate::model::FeModel, x: &mut Mat<f64>, count: usize) -> Option<Mat<f64>> {
    if x.ncols() < count {
        return None;
    }
    let mx = sparse_times(&fe.mass, x.as_ref());
    for c in 0..x.ncols() {
        let norm = (0..x.nrows()).map(|i| x[(i, c)] * mx[(i, c)]).sum::<f64>();
        if !(norm > 0.0 && norm.is_finite()) {
            return None;
        }
        let s = 1.0 / norm.sqrt();
        x.col_mut(c).iter_mut().for_each(|v| *v *= s);
    }
    let kr = symmetrise(product(
        x.transpose(),
        sparse_times(&fe.stiffness, x.as_ref()).as_ref(),
    ));
    let mr = symmetrise(product(
        x.transpose(),
        sparse_times(&fe.mass, x.as_ref()).as_ref(),
    ));
    let (_, shapes) = pencil_eigen(kr, &mr)?;
    let y = shapes.subcols(0, count);
    let phi = product(x.as_ref(), y);
    let finite = phi.col_iter().all(|c| c.iter().all(|v| v.is_finite()));
    finite.then_some(phi)
}

/// Every mode of `fe` (a small model).
pub(super) fn all_modes(fe: &crate::model::FeModel) -> Result<eigen::Modes, FitError> {
    let opts = eigen::EigenOptions {
        count: fe.dofs.len(),
        expect_no_rigid_body_modes: fe.has_fixed_dofs,
        ..eigen::EigenOptions::default()
    };
    eigen::lowest_modes(&fe.stiffness, &fe.mass, &opts).map_err(|e| FitError::Eigen(e.to_string()))
}

/// scale·TᵀST for a sparse symmetric S: only the rows of T where S has
/// entries take part (a parameter's ∂K touches a few elements).
pub(super) fn project(s: &SparseMatrix, t: MatRef<'_, f64>, scale: f64) -> Mat<f64> {
    let sym = s.symbolic();
    let mut support: Vec<usize> = (0..s.ncols())
        .flat_map(|c| sym.row_idx_of_col_raw(c).iter().copied())
        .collect();
    support.sort_unstable();
    support.dedup();
    // (S T) on the support rows only: S's entries lie in support × support
    // (S symmetric), so only T's support rows take part, and no n × m
    // product is formed (a parameter's ∂K touches a few elements; building
    // and zeroing the whole product cost most of a re-anchoring).
    let mut position = vec![usize::MAX; s.nrows()];
    for (i, &r) in support.iter().enumerate() {
        position[r] = i;
    }
    let position = &position;
    let entries: Vec<(usize, usize, f64)> = support
        .iter()
        .enumerate()
        .flat_map(|(jc, &c)| {
            let rows = sym.row_idx_of_col_raw(c).iter();
            rows.zip(s.val_of_col(c))
                .map(move |(&r, &v)| (position[r], jc, v))
        })
        .collect();
    let tr = Mat::from_fn(support.len(), t.ncols(), |i, k| t[(support[i], k)]);
    // Row i of S T is Σ v·(row jc of T) over S's entries (i, jc, v) in
    // their order: each entry of S T sums the same terms in the same order
    // as column by column, but along rows, which are contiguous here.
    let m = t.ncols();
    let rows_of_t: Vec<f64> = support
        .iter()
        .flat_map(|&r| (0..m).map(move |k| t[(r, k)]))
        .collect();
    let mut rows_of_st = vec![0.0; support.len() * m];
    for &(i, jc, v) in &entries {
        let src = &rows_of_t[jc * m..(jc + 1) * m];
        for (d, s) in rows_of_st[i * m..(i + 1) * m].iter_mut().zip(src) {
            *d += v * s;
        }
    }
    let sr = Mat::from_fn(support.len(), m, |i, k| rows_of_st[i * m + k]);
    let mut out = Mat::<f64>::zeros(t.ncols(), t.ncols());
    matmul(
        out.as_mut(),
        Accum::Replace,
        tr.transpose(),
        sr.as_ref(),
        scale,
        Par::Seq,
    );
    symmetrise(out)
}

/// Eigenpairs of the dense symmetric pencil K ψ = λ M ψ: Cholesky M = LLᵀ,
/// the symmetric C = L⁻¹KL⁻ᵀ, ψ = L⁻ᵀ(eigenvectors of C): ascending λ,
/// M-orthonormal ψ. `None` if M is not positive definite or a λ is not
/// finite.
pub(super) fn pencil_eigen(k: Mat<f64>, m: &Mat<f64>) -> Option<(Vec<f64>, Mat<f64>)> {
    use faer::linalg::triangular_solve::{
        solve_lower_triangular_in_place, solve_upper_triangular_in_place,
    };
    let l = cholesky_lower(m.as_ref())?;
    let mut x = k;
    solve_lower_triangular_in_place(l.as_ref(), x.as_mut(), Par::Seq);
    let mut c = x.transpose().to_owned();
    solve_lower_triangular_in_place(l.as_ref(), c.as_mut(), Par::Seq);
    let (lambda, mut shapes) = symmetric_eigen(symmetrise(c).as_ref())?;
    solve_upper_triangular_in_place(l.transpose(), shapes.as_mut(), Par::Seq);
    lambda
        .iter()
        .all(|v| v.is_finite())
        .then_some((lambda, shapes))
}

/// (A + Aᵀ)/2: a projected symmetric matrix, symmetric to rounding.
fn symmetrise(a: Mat<f64>) -> Mat<f64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}

/// T = [Φ | S] with S the M-orthonormal static block (see the module doc).
pub(super) fn ritz_basis(
    m: &SparseMatrix,
    phi: &Mat<f64>,
    place: &fit::Placement,
    chol: &ShiftedCholesky,
) -> Result<Mat<f64>, FitError> {
    let n = m.nrows();
    let eig_err = |e: String| FitError::Eigen(e);
    let mass = |x: MatRef<'_, f64>| sparse_times(m, x);
    // x ← x − Φ(ΦᵀMx): M-orthogonal to the computed modes.
    let deflate = |x: &mut Mat<f64>| {
        let c = product(phi.transpose(), mass(x.as_ref()).as_ref());
        *x -= product(phi.as_ref(), c.as_ref());
    };
    let mut dofs = vec![place.input];
    dofs.extend(place.outputs.iter().copied());
    let mut e = Mat::<f64>::zeros(n, dofs.len());
    for (c, &d) in dofs.iter().enumerate() {
        e[(d, c)] = 1.0;
    }
    // P e = e − MΦ(Φᵀe): the load the left-out modes carry.
    let mphi = mass(phi.as_ref());
    e -= product(mphi.as_ref(), product(phi.transpose(), e.as_ref()).as_ref());
    let mut x = chol.solve(e.as_ref());
    // Directions of S whose M-norm after deflation is below 1e-10 of the
    // largest before it lie in the span of Φ (to rounding): dropped.
    let before = symmetrise(product(x.transpose(), mass(x.as_ref()).as_ref()));
    let norm0 = (0..before.nrows()).fold(0.0f64, |a, i| a.max(before[(i, i)]));
    deflate(&mut x);
    let mut second = chol.solve(mass(x.as_ref().subcols(0, 1)).as_ref());
    deflate(&mut second);
    let s = Mat::from_fn(n, x.ncols() + 1, |i, c| {
        if c < x.ncols() {
            x[(i, c)]
        } else {
            second[(i, 0)]
        }
    });
    // M-orthonormalise S: G = SᵀMS = VDVᵀ, S ← S V D^{-1/2}, dropping
    // directions with D below 1e-10 of the largest M-norm before deflation
    // (repeated DOFs, e.g. a driving point, or a static response the modes
    // already span).
    let g = symmetrise(product(s.transpose(), mass(s.as_ref()).as_ref()));
    let (d, u) = symmetric_eigen(g.as_ref()).ok_or_else(|| {
        eig_err("the static block's Gram matrix has no eigen decomposition".into())
    })?;
    let top = d.iter().fold(norm0, |a, v| a.max(*v));
    let keep: Vec<usize> = (0..d.len()).filter(|&i| d[i] > 1e-10 * top).collect();
    let v = Mat::from_fn(g.nrows(), keep.len(), |i, k| {
        u[(i, keep[k])] / d[keep[k]].sqrt()
    });
    let mut s = product(s.as_ref(), v.as_ref());
    deflate(&mut s);
    Ok(Mat::from_fn(n, phi.ncols() + s.ncols(), |i, c| {
        if c < phi.ncols() {
            phi[(i, c)]
        } else {
            s[(i, c - phi.ncols())]
        }
    }))
}
