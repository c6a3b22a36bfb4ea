//! Small helpers on the assembled sparse matrices shared by the solvers.

use faer::sparse::linalg::matmul::sparse_dense_matmul;
use faer::sparse::{Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Accum, Mat, MatRef, Par};

use crate::model::SparseMatrix;

/// Parallelism for large dense kernels (factorisations, dense eigensolver):
/// all threads of the rayon pool.
pub(crate) fn par() -> Par {
    Par::rayon(0)
}

/// Parallelism for the many small, memory-bound kernels of an iteration
/// (triangular solves per supernode, skinny products): thread start-up and
/// barriers cost more than they save there, especially on a loaded machine.
pub(crate) fn par_iter() -> Par {
    Par::Seq
}

/// Why a matrix pair is not usable.
pub(crate) fn check_pair(k: &SparseMatrix, m: &SparseMatrix) -> Result<usize, String> {
    let n = k.nrows();
    if k.ncols() != n {
        return Err(format!("K is {}×{}, not square", k.nrows(), k.ncols()));
    }
    if m.nrows() != n || m.ncols() != n {
        return Err(format!("M is {}×{} but K is {n}×{n}", m.nrows(), m.ncols()));
    }
    if let Some(v) = k.val().iter().find(|v| !v.is_finite()) {
        return Err(format!("K has a non-finite entry ({v})"));
    }
    if let Some(v) = m.val().iter().find(|v| !v.is_finite()) {
        return Err(format!("M has a non-finite entry ({v})"));
    }
    Ok(n)
}

/// Diagonal of a sparse matrix (duplicates summed).
pub(crate) fn diagonal(a: &SparseMatrix) -> Vec<f64> {
    let n = a.nrows().min(a.ncols());
    let mut d = vec![0.0; n];
    let sym = a.symbolic();
    for (j, dj) in d.iter_mut().enumerate() {
        let rows = sym.row_idx_of_col_raw(j);
        let vals = a.val_of_col(j);
        for (&i, &v) in rows.iter().zip(vals) {
            if i == j {
                *dj += v;
            }
        }
    }
    d
}

/// A · X for sparse A and dense X.
pub(crate) fn sp_mul(a: &SparseMatrix, x: MatRef<'_, f64>) -> Mat<f64> {
    let mut y = Mat::<f64>::zeros(a.nrows(), x.ncols());
    sparse_dense_matmul(y.as_mut(), Accum::Replace, a.as_ref(), x, 1.0, par_iter());
    y
}

/// The union sparsity pattern of K and M, with where each of their entries
/// lands, so that αK + βM (real or complex) is assembled without searching.
pub(crate) struct PairPattern {
    symbolic: SymbolicSparseColMat<usize>,
    k_pos: Vec<usize>,
    m_pos: Vec<usize>,
    k_val: Vec<f64>,
    m_val: Vec<f64>,
}

impl PairPattern {
    /// Pattern of K + M (both n × n).
    pub(crate) fn new(k: &SparseMatrix, m: &SparseMatrix) -> Result<Self, String> {
        let n = check_pair(k, m)?;
        let mut pairs = Vec::with_capacity(k.val().len() + m.val().len());
        let mut k_val = Vec::with_capacity(k.val().len());
        let mut m_val = Vec::with_capacity(m.val().len());
        for (a, vals) in [(k, &mut k_val), (m, &mut m_val)] {
            let sym = a.symbolic();
            for j in 0..n {
                for (&i, &v) in sym.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                    pairs.push(Pair { row: i, col: j });
                    vals.push(v);
                }
            }
        }
        let (symbolic, _) = SymbolicSparseColMat::try_new_from_indices(n, n, &pairs)
            .map_err(|e| format!("sparsity pattern of K + M: {e:?}"))?;
        let locate = |p: &Pair<usize, usize>| {
            let range = symbolic.col_range(p.col);
            let rows = &symbolic.row_idx()[range.clone()];
            range.start + rows.partition_point(|&r| r < p.row)
        };
        let nk = k_val.len();
        let k_pos = pairs[..nk].iter().map(locate).collect();
        let m_pos = pairs[nk..].iter().map(locate).collect();
        Ok(PairPattern {
            symbolic,
            k_pos,
            m_pos,
            k_val,
            m_val,
        })
    }

    pub(crate) fn symbolic(&self) -> &SymbolicSparseColMat<usize> {
        &self.symbolic
    }

    /// Values of f(K_ij) + g(M_ij) on the union pattern.
    pub(crate) fn values_with<T: Copy + Default + std::ops::AddAssign>(
        &self,
        f: impl Fn(f64) -> T,
        g: impl Fn(f64) -> T,
    ) -> Vec<T> {
        let mut out = vec![T::default(); self.symbolic.row_idx().len()];
        for (&p, &v) in self.k_pos.iter().zip(&self.k_val) {
            out[p] += f(v);
        }
        for (&p, &v) in self.m_pos.iter().zip(&self.m_val) {
            out[p] += g(v);
        }
        out
    }

    /// αK + βM.
    pub(crate) fn combine(&self, alpha: f64, beta: f64) -> SparseMatrix {
        let vals = self.values_with(|k| alpha * k, |m| beta * m);
        SparseColMat::new(self.symbolic.clone(), vals)
    }
}
