//! Small helpers on the assembled sparse matrices shared by the solvers.

use faer::sparse::{Pair, SparseColMat, SymbolicSparseColMat};
use faer::{Mat, MatRef, Par};

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

// The diagonal is the model's (the model layer is below the solvers).
pub(crate) use crate::model::diagonal;

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

/// A sparse matrix stored by rows (CSR), for products with a few dense
/// columns: each nonzero updates all columns of a row at once, from a
/// row-major copy of the right-hand side (one contiguous load per nonzero
/// instead of one per column).
pub struct RowMatrix {
    row_ptr: Vec<usize>,
    col: Vec<usize>,
    val: Vec<f64>,
}

impl RowMatrix {
    /// B = P A Pᵀ with (P v)_i = v_{fwd[i]}, i.e. B_ij = A_{fwd[i], fwd[j]};
    /// columns sorted within each row.
    pub fn permuted(a: &SparseMatrix, fwd: &[usize]) -> Self {
        let n = a.nrows();
        let sym = a.symbolic();
        // Rows of A by a counting sort of its columns (CSC → CSR).
        let mut a_ptr = vec![0usize; n + 1];
        for j in 0..a.ncols() {
            for &i in sym.row_idx_of_col_raw(j) {
                a_ptr[i + 1] += 1;
            }
        }
        for i in 0..n {
            a_ptr[i + 1] += a_ptr[i];
        }
        let nnz = a_ptr[n];
        let mut a_col = vec![0usize; nnz];
        let mut a_val = vec![0.0; nnz];
        let mut next = a_ptr.clone();
        for j in 0..a.ncols() {
            for (&i, &v) in sym.row_idx_of_col_raw(j).iter().zip(a.val_of_col(j)) {
                a_col[next[i]] = j;
                a_val[next[i]] = v;
                next[i] += 1;
            }
        }
        let mut inv = vec![0usize; n];
        for (i, &f) in fwd.iter().enumerate() {
            inv[f] = i;
        }
        let mut row_ptr = Vec::with_capacity(n + 1);
        row_ptr.push(0);
        let mut col = Vec::with_capacity(nnz);
        let mut val = Vec::with_capacity(nnz);
        let mut row: Vec<(usize, f64)> = Vec::new();
        for &f in fwd {
            row.clear();
            row.extend((a_ptr[f]..a_ptr[f + 1]).map(|p| (inv[a_col[p]], a_val[p])));
            row.sort_unstable_by_key(|e| e.0);
            col.extend(row.iter().map(|e| e.0));
            val.extend(row.iter().map(|e| e.1));
            row_ptr.push(col.len());
        }
        RowMatrix { row_ptr, col, val }
    }

    /// B x for x with a few columns.
    pub fn mul(&self, x: MatRef<'_, f64>) -> Mat<f64> {
        let n = self.row_ptr.len() - 1;
        let b = x.ncols();
        let mut xr = vec![0.0; n * b];
        for c in 0..b {
            for (j, &v) in x.col(c).iter().enumerate() {
                xr[j * b + c] = v;
            }
        }
        let mut y = Mat::<f64>::zeros(n, b);
        match b {
            8 => self.mul_rows::<8>(&xr, &mut y),
            4 => self.mul_rows::<4>(&xr, &mut y),
            _ => {
                let mut acc = vec![0.0; b];
                for i in 0..n {
                    acc.fill(0.0);
                    for p in self.row_ptr[i]..self.row_ptr[i + 1] {
                        let (v, xs) = (self.val[p], &xr[self.col[p] * b..][..b]);
                        acc.iter_mut().zip(xs).for_each(|(a, x)| *a += v * x);
                    }
                    for (c, a) in acc.iter().enumerate() {
                        y[(i, c)] = *a;
                    }
                }
            }
        }
        y
    }

    fn mul_rows<const B: usize>(&self, xr: &[f64], y: &mut Mat<f64>) {
        for i in 0..self.row_ptr.len() - 1 {
            let mut acc = [0.0; B];
            for p in self.row_ptr[i]..self.row_ptr[i + 1] {
                let v = self.val[p];
                let xs: &[f64; B] = xr[self.col[p] * B..][..B]
                    .try_into()
                    .expect("B values per row");
                for c in 0..B {
                    acc[c] += v * xs[c];
                }
            }
            for (c, a) in acc.iter().enumerate() {
                y[(i, c)] = *a;
            }
        }
    }
}
