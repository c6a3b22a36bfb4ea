//! Modal models of nearby FE models on one Ritz basis: what a
//! forward-difference Jacobian needs, at the price of a projection and a
//! small eigen solution per column instead of a full one.
//!
//! T = [Φ | S] is the basis of [`super::reduced`] at a point x: the band's
//! modes Φ (up to 4·ω_max) and the static responses at the excitation and
//! the channels, M-orthonormal. A model built at x + h·e_j with the same
//! DOFs (any change of its properties, masses or springs: a deck parameter
//! or an extension's) is projected, K_r = TᵀKT and M_r = TᵀMT (m × m), and
//! solved. Its lowest nb = dim Φ eigenpairs are the band's modes (exact at
//! x, Rayleigh–Ritz with an error second order in h at x + h·e_j); the
//! upper m − nb, all above ω_{nb+1} ≥ 4·ω_max, are folded into the static
//! terms the full model carries for the modes it leaves out:
//! R0_c = Σ a_cr/ω_r², R1_c = Σ a_cr/ω_r⁴ (1/(ω_r² − ω²) to first order in
//! ω²/ω_r²). The modal model then has the form of [`fit::modal_solution`]'s,
//! so the damping and the predictions treat both alike, and differences of
//! two such models are differences of like with like.

use faer::Mat;

use super::data::TestData;
use super::fit::{self, ModalModel, ModalSolution, Placement};
use super::reduced::{all_modes, pencil_eigen, project, ritz_basis, shifted_cholesky};
use super::FitError;
use crate::model::FeModel;
use crate::solvers::dense::product;
use crate::solvers::eigen::lanczos::ShiftedCholesky;
use crate::solvers::eigen::Modes;

/// The Ritz basis of one FE model, and where the test sits on it.
pub struct RitzBasis {
    /// T (n × m).
    pub(super) basis: Mat<f64>,
    /// Rows of T at each channel's DOF (times the channel's sign), then at
    /// the excitation: (channels + 1) × m.
    pub(super) rows: Mat<f64>,
    /// Columns of Φ in T: the modes kept as modes.
    pub(super) band_modes: usize,
    /// The DOF numbering the basis belongs to.
    equations: Vec<(u32, crate::model::Dof)>,
}

impl RitzBasis {
    /// The basis of `fe` at the channels of `data`: one full eigen solution.
    pub fn at(fe: &FeModel, data: &TestData) -> Result<RitzBasis, FitError> {
        let place = fit::placement(fe, data)?;
        RitzBasis::on_modes(fe, fit::band_modes(fe, data)?, &place)
    }

    /// The basis of `fe` from its modal solution `sol` (no eigen solution
    /// more, unless the model is so small that all its modes are wanted).
    pub fn of_solution(fe: &FeModel, sol: &ModalSolution) -> Result<RitzBasis, FitError> {
        let place = Placement {
            input: sol.input,
            outputs: sol.outputs.clone(),
            signs: sol.signs.clone(),
        };
        RitzBasis::on_modes(fe, sol.modes.clone(), &place)
    }

    /// The basis on the band's modes `modes` of `fe` (every mode instead
    /// when the static block would fill nearly all that they leave: that
    /// is cheaper and exact).
    pub(super) fn on_modes(
        fe: &FeModel,
        mut modes: Modes,
        place: &Placement,
    ) -> Result<RitzBasis, FitError> {
        let n = fe.dofs.len();
        if modes.len() < n && modes.len() + place.outputs.len() + 2 >= n {
            modes = all_modes(fe)?;
        }
        let chol = if modes.len() < n {
            Some(shifted_cholesky(fe)?)
        } else {
            None
        };
        RitzBasis::on_shapes(fe, &modes.shapes, place, chol.as_ref())
    }

    /// T = [Φ | S] on the M-orthonormal mode shapes `phi` of `fe` (with
    /// `chol`, K − σM factored, the static block S; without, Φ alone).
    pub(super) fn on_shapes(
        fe: &FeModel,
        phi: &Mat<f64>,
        place: &Placement,
        chol: Option<&ShiftedCholesky>,
    ) -> Result<RitzBasis, FitError> {
        let basis = match chol {
            Some(chol) => ritz_basis(&fe.mass, phi, place, chol)?,
            None => phi.clone(),
        };
        let nc = place.outputs.len();
        let rows = Mat::from_fn(nc + 1, basis.ncols(), |c, r| {
            if c < nc {
                place.signs[c] * basis[(place.outputs[c], r)]
            } else {
                basis[(place.input, r)]
            }
        });
        Ok(RitzBasis {
            basis,
            rows,
            band_modes: phi.ncols(),
            equations: fe.dofs.equations.clone(),
        })
    }

    /// The modal model of `fe` on this basis (see the module doc); `None`
    /// when `fe` has other DOFs than the model the basis was built on, or
    /// its projected pencil has no eigen solution.
    pub fn modal_model(&self, fe: &FeModel) -> Option<ModalModel> {
        if fe.dofs.equations != self.equations {
            return None;
        }
        let k = project(&fe.stiffness, self.basis.as_ref(), 1.0);
        let m = project(&fe.mass, self.basis.as_ref(), 1.0);
        let (omega2, shapes) = pencil_eigen(k, &m)?;
        let at = product(self.rows.as_ref(), shapes.as_ref());
        let nc = at.nrows() - 1;
        let nb = self.band_modes.min(omega2.len());
        let a = |c: usize, r: usize| at[(c, r)] * at[(nc, r)];
        let coeff = (0..nc)
            .map(|c| (0..nb).map(|r| a(c, r)).collect())
            .collect();
        let upper = |c: usize, power: i32| -> f64 {
            (nb..omega2.len())
                .map(|r| a(c, r) / omega2[r].powi(power))
                .sum()
        };
        let residual = (0..nc).map(|c| upper(c, 1)).collect();
        let residual_mass = (0..nc).map(|c| upper(c, 2)).collect();
        let omega2: Vec<f64> = omega2[..nb].to_vec();
        let frequencies_hz = omega2
            .iter()
            .map(|w2| w2.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect();
        Some(ModalModel {
            omega2,
            coeff,
            residual,
            residual_mass,
            frequencies_hz,
            dofs: fe.dofs.len(),
        })
    }
}
