//! Test matrices built by hand, independent of `frfup::model`.
#![allow(dead_code)]

use faer::sparse::{SparseColMat, Triplet};
use frfup::model::SparseMatrix;

/// Symmetric sparse matrix from upper-or-lower triplets (i, j, v): both
/// triangles stored, duplicates summed.
pub fn sym(n: usize, entries: &[(usize, usize, f64)]) -> SparseMatrix {
    let mut t = Vec::new();
    for &(i, j, v) in entries {
        t.push(Triplet::new(i, j, v));
        if i != j {
            t.push(Triplet::new(j, i, v));
        }
    }
    SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
}

/// Sparse copy of a dense symmetric matrix (exact zeros dropped).
pub fn from_dense(a: &nalgebra::DMatrix<f64>) -> SparseMatrix {
    let n = a.nrows();
    let mut t = Vec::new();
    for j in 0..n {
        for i in 0..n {
            if a[(i, j)] != 0.0 {
                t.push(Triplet::new(i, j, a[(i, j)]));
            }
        }
    }
    SparseColMat::try_new_from_triplets(n, n, &t).unwrap()
}

/// Spring–mass chain: n equal masses m, springs k between neighbours and, if
/// `grounded`, one spring from mass 0 to ground (fixed–free chain).
pub fn chain(n: usize, k: f64, m: f64, grounded: bool) -> (SparseMatrix, SparseMatrix) {
    let mut ke = Vec::new();
    if grounded {
        ke.push((0, 0, k));
    }
    for i in 0..n - 1 {
        ke.push((i, i, k));
        ke.push((i + 1, i + 1, k));
        ke.push((i, i + 1, -k));
    }
    let me: Vec<_> = (0..n).map(|i| (i, i, m)).collect();
    (sym(n, &ke), sym(n, &me))
}

/// Fixed–free chain: ω_j = 2√(k/m) sin((2j−1)π / (2(2n+1))), j = 1..n.
pub fn fixed_free_omega(n: usize, k: f64, m: f64, j: usize) -> f64 {
    2.0 * (k / m).sqrt()
        * ((2 * j - 1) as f64 * std::f64::consts::PI / (2.0 * (2 * n + 1) as f64)).sin()
}

/// Free–free chain: ω_j = 2√(k/m) sin((j−1)π / (2n)), j = 1..n (j = 1 rigid).
pub fn free_free_omega(n: usize, k: f64, m: f64, j: usize) -> f64 {
    2.0 * (k / m).sqrt() * ((j - 1) as f64 * std::f64::consts::PI / (2.0 * n as f64)).sin()
}

/// Euler–Bernoulli beam in one plane (DOFs w, θ per node), `ne` elements of a
/// beam of length `len`, consistent mass. Node 0 clamped if `clamped`.
pub fn eb_beam(
    ne: usize,
    len: f64,
    ei: f64,
    rho_a: f64,
    clamped: bool,
) -> (SparseMatrix, SparseMatrix) {
    let h = len / ne as f64;
    let ke = [
        [12.0, 6.0 * h, -12.0, 6.0 * h],
        [6.0 * h, 4.0 * h * h, -6.0 * h, 2.0 * h * h],
        [-12.0, -6.0 * h, 12.0, -6.0 * h],
        [6.0 * h, 2.0 * h * h, -6.0 * h, 4.0 * h * h],
    ];
    let me = [
        [156.0, 22.0 * h, 54.0, -13.0 * h],
        [22.0 * h, 4.0 * h * h, 13.0 * h, -3.0 * h * h],
        [54.0, 13.0 * h, 156.0, -22.0 * h],
        [-13.0 * h, -3.0 * h * h, -22.0 * h, 4.0 * h * h],
    ];
    let kf = ei / h.powi(3);
    let mf = rho_a * h / 420.0;
    let off = if clamped { 2 } else { 0 };
    let n = 2 * (ne + 1) - off;
    let (mut kt, mut mt) = (Vec::new(), Vec::new());
    for e in 0..ne {
        for a in 0..4 {
            for b in 0..4 {
                let (ga, gb) = (2 * e + a, 2 * e + b);
                if ga < off || gb < off || gb < ga {
                    continue;
                }
                kt.push((ga - off, gb - off, kf * ke[a][b]));
                mt.push((ga - off, gb - off, mf * me[a][b]));
            }
        }
    }
    (sym(n, &kt), sym(n, &mt))
}

/// Deterministic pseudo-random numbers in [−1, 1).
pub struct Lcg(pub u64);
impl Lcg {
    pub fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// Random SPD pencil (K, M) of size n, bandwidth `band`, well conditioned.
pub fn random_pencil(
    n: usize,
    band: usize,
    seed: u64,
) -> (nalgebra::DMatrix<f64>, nalgebra::DMatrix<f64>) {
    let mut rng = Lcg(seed);
    let mut mk = |diag: f64| {
        let mut b = nalgebra::DMatrix::<f64>::zeros(n, n);
        for i in 0..n {
            for j in i.saturating_sub(band)..=i {
                b[(i, j)] = rng.next();
            }
            b[(i, i)] += diag;
        }
        &b * b.transpose()
    };
    let k = mk(2.0);
    let m = mk(3.0);
    (k, m)
}

/// Reference generalised eigenvalues by nalgebra: M = LLᵀ, eig(L⁻¹KL⁻ᵀ), ascending.
pub fn reference_eigenvalues(k: &nalgebra::DMatrix<f64>, m: &nalgebra::DMatrix<f64>) -> Vec<f64> {
    let l = m.clone().cholesky().unwrap().l();
    let li = l.clone().try_inverse().unwrap();
    let c = &li * k * li.transpose();
    let c = (&c + c.transpose()) * 0.5;
    let mut ev: Vec<f64> = c.symmetric_eigen().eigenvalues.iter().copied().collect();
    ev.sort_by(f64::total_cmp);
    ev
}

/// ‖ΦᵀMΦ − I‖_max.
pub fn mass_orthonormality_error(m: &SparseMatrix, phi: &faer::Mat<f64>) -> f64 {
    let md = m.to_dense();
    let g = phi.transpose() * &md * phi;
    let mut e = 0.0f64;
    for i in 0..g.nrows() {
        for j in 0..g.ncols() {
            let target = if i == j { 1.0 } else { 0.0 };
            e = e.max((g[(i, j)] - target).abs());
        }
    }
    e
}
