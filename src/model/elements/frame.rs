//! Local axes of a beam and rotation of element matrices (deck spec, `beam`).
//!
//! Local x runs N1→N2; local y is the part of `orient` normal to x; local
//! z = x × y. The default `orient` is global +Y, or global −X for an element
//! parallel to Y.

use nalgebra::{Matrix3, SMatrix, Vector3};

/// Below this sine of the angle between the element and `orient`, the two
/// are parallel (and for the default orient, the element is "parallel to Y").
pub const PARALLEL_TOLERANCE: f64 = 1e-6;

/// Relative tolerance on the element length against the coordinates' size.
pub const ZERO_LENGTH_TOLERANCE: f64 = 1e-12;

/// The length and local axes of a beam.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalFrame {
    /// Element length L (m).
    pub length: f64,
    /// Rows are the local x, y, z unit vectors in global coordinates, so
    /// that u_local = R u_global.
    pub rotation: Matrix3<f64>,
}

/// Why local axes could not be formed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum FrameError {
    /// N1 and N2 coincide (to `ZERO_LENGTH_TOLERANCE` relative).
    ZeroLength { length: f64 },
    /// `orient` is parallel to the element axis.
    OrientParallel,
}

/// Local axes of the beam from `x1` to `x2` with an optional `orient` vector.
pub fn local_frame(
    x1: [f64; 3],
    x2: [f64; 3],
    orient: Option<[f64; 3]>,
) -> Result<LocalFrame, FrameError> {
    let a = Vector3::from(x1);
    let b = Vector3::from(x2);
    let d = b - a;
    let length = d.norm();
    let scale = a.amax().max(b.amax());
    if !length.is_finite() || length <= ZERO_LENGTH_TOLERANCE * scale {
        return Err(FrameError::ZeroLength { length });
    }
    let ex = d / length;
    let o = match orient {
        Some(v) => {
            let o = Vector3::from(v);
            let n = o.norm();
            if !(n > 0.0 && n.is_finite()) {
                return Err(FrameError::OrientParallel);
            }
            let o = o / n;
            if ex.cross(&o).norm() < PARALLEL_TOLERANCE {
                return Err(FrameError::OrientParallel);
            }
            o
        }
        None => {
            let y = Vector3::y();
            if ex.cross(&y).norm() < PARALLEL_TOLERANCE {
                -Vector3::x()
            } else {
                y
            }
        }
    };
    let ey = (o - ex * ex.dot(&o)).normalize();
    let ez = ex.cross(&ey);
    let rotation = Matrix3::from_rows(&[ex.transpose(), ey.transpose(), ez.transpose()]);
    Ok(LocalFrame { length, rotation })
}

/// Tᵀ·K_local·T with T = diag(R, R, R, R), computed by 3×3 blocks, then
/// symmetrised (the result is symmetric up to rounding; both triangles are
/// stored, so make them equal).
pub fn to_global(local: &SMatrix<f64, 12, 12>, r: &Matrix3<f64>) -> SMatrix<f64, 12, 12> {
    let mut g = SMatrix::<f64, 12, 12>::zeros();
    let rt = r.transpose();
    for bi in 0..4 {
        for bj in 0..4 {
            let block: Matrix3<f64> = local.fixed_view::<3, 3>(3 * bi, 3 * bj).into_owned();
            if block.iter().all(|v| *v == 0.0) {
                continue;
            }
            let gb = rt * block * r;
            g.fixed_view_mut::<3, 3>(3 * bi, 3 * bj).copy_from(&gb);
        }
    }
    (g + g.transpose()) * 0.5
}
