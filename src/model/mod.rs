//! The FE model: built from a deck, assembled sparse, with the derivative of
//! K and M with respect to every updating parameter.
//!
//! - [`build`]: [`Deck`](frfup_parsers::deck::Deck) + [`ParameterValues`] →
//!   [`FeModel`] (K, M over the free DOFs, ∂K/∂p and ∂M/∂p of every `param`);
//! - [`updated_deck`], [`composed_values`], [`parameter_names`]: the deck
//!   with values multiplied out;
//! - [`elements`]: the element matrices (3D frame beam, Euler–Bernoulli or
//!   Timoshenko; the plane x–z frame as its restriction to x, z, ry; lumped
//!   masses and springs);
//! - [`sensitivity`]: the parameter derivatives (complex step on the element
//!   matrices; Eq. 30–31 of Yan & Golinval).
//!
//! Conventions (see `docs/deck.md`): SI units; right-hand rotations about the
//! global axes, so in a plane analysis θy = −dw/dx; equations numbered by
//! ascending node ID, then x y z rx ry rz.
//!
//! The public items of this file are used by `solvers` and `updating`.

use std::collections::BTreeMap;

use faer::sparse::SparseColMat;

mod assembly;
pub mod elements;
mod error;
mod properties;
pub mod sensitivity;
mod update;

pub use assembly::{build, check_mass, dof_of};
pub use error::ModelError;
pub use update::{composed_values, parameter_names, updated_deck};

/// Global sparse matrices: free DOFs only, both triangles stored.
pub type SparseMatrix = SparseColMat<usize, f64>;

/// Diagonal of a sparse matrix (duplicates summed).
pub fn diagonal(a: &SparseMatrix) -> Vec<f64> {
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

/// A nodal degree of freedom; UFF direction codes 1..6 = x y z rx ry rz.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Dof {
    X,
    Y,
    Z,
    Rx,
    Ry,
    Rz,
}

impl Dof {
    /// UFF direction code (±1..±6) → DOF and sign (−1.0 for a reversed sense).
    pub fn from_uff_code(code: i32) -> Option<(Dof, f64)> {
        let dof = match code.abs() {
            1 => Dof::X,
            2 => Dof::Y,
            3 => Dof::Z,
            4 => Dof::Rx,
            5 => Dof::Ry,
            6 => Dof::Rz,
            _ => return None,
        };
        Some((dof, if code < 0 { -1.0 } else { 1.0 }))
    }

    /// The UFF direction code (1..6) of this DOF, positive sense.
    pub fn uff_code(self) -> i32 {
        match self {
            Dof::X => 1,
            Dof::Y => 2,
            Dof::Z => 3,
            Dof::Rx => 4,
            Dof::Ry => 5,
            Dof::Rz => 6,
        }
    }

    /// The deck's name of this DOF (`x y z rx ry rz`).
    pub fn name(self) -> &'static str {
        match self {
            Dof::X => "x",
            Dof::Y => "y",
            Dof::Z => "z",
            Dof::Rx => "rx",
            Dof::Ry => "ry",
            Dof::Rz => "rz",
        }
    }
}

/// Global damping model of the deck (`damping ...`).
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub enum Damping {
    #[default]
    None,
    /// Same viscous damping ratio ζ for every mode.
    Modal { zeta: f64 },
    /// C = αM + βK.
    Rayleigh { alpha: f64, beta: f64 },
    /// Structural damping: K(1 + iη).
    Hysteretic { eta: f64 },
}

/// Relative changes p̄ of the deck's parameters (`param NAME ...`):
/// updated value = (1 + p̄) × deck value. A parameter absent from the map is 0.
impl Damping {
    /// The damping of a deck's `damping` statement (none: undamped).
    pub fn of_deck(deck: &frfup_parsers::deck::Deck) -> Damping {
        use frfup_parsers::deck::DampingModel;
        match deck.damping.map(|d| d.model) {
            None => Damping::None,
            Some(DampingModel::Modal { zeta }) => Damping::Modal { zeta },
            Some(DampingModel::Rayleigh { alpha, beta }) => Damping::Rayleigh { alpha, beta },
            Some(DampingModel::Hysteretic { eta }) => Damping::Hysteretic { eta },
        }
    }

    /// Equivalent viscous damping ratio of a mode at `f_hz` (Hz): 0 (none),
    /// ζ (modal), α/(2ω) + βω/2 (Rayleigh), η/2 (hysteretic, at resonance).
    pub fn ratio_at(self, f_hz: f64) -> f64 {
        let w = (2.0 * std::f64::consts::PI * f_hz).max(1e-12);
        match self {
            Damping::None => 0.0,
            Damping::Modal { zeta } => zeta,
            Damping::Rayleigh { alpha, beta } => alpha / (2.0 * w) + beta * w / 2.0,
            Damping::Hysteretic { eta } => eta / 2.0,
        }
    }

    /// d_r(ω) of a mass-normalised mode in the modal FRF
    /// H_jk(ω) = Σ_r φ_jr φ_kr / d_r(ω): d_r = ω_r² − ω² + i c_r(ω) with
    /// c_r = 0 (none), 2ζω_rω (modal), ω(α + βω_r²) (Rayleigh, C = αM + βK)
    /// or ηω_r² (hysteretic, K(1 + iη)); `omega2` = ω_r² (rad²/s²), `omega`
    /// = ω (rad/s). A slightly negative ω_r² (round-off of a rigid-body
    /// mode) counts as 0 in c_r, so damping never changes sign.
    pub fn modal_denominator(self, omega2: f64, omega: f64) -> faer::c64 {
        self.modal_term(omega2).at(omega2, omega)
    }

    /// The damping term of one mode, c_r(ω) = slope·ω + constant, computed
    /// once per mode for sweeps over many lines ([`Self::modal_denominator`]).
    pub fn modal_term(self, omega2: f64) -> ModalDampingTerm {
        let w2 = omega2.max(0.0);
        let (slope, constant) = match self {
            Damping::None => (0.0, 0.0),
            Damping::Modal { zeta } => (2.0 * zeta * w2.sqrt(), 0.0),
            Damping::Rayleigh { alpha, beta } => (alpha + beta * w2, 0.0),
            Damping::Hysteretic { eta } => (0.0, w2 * eta),
        };
        ModalDampingTerm { slope, constant }
    }
}

/// c_r(ω) = slope·ω + constant of one mode: slope 2ζω_r or α + βω_r² (s⁻¹
/// · rad²/s² per rad/s), constant ηω_r² (rad²/s²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ModalDampingTerm {
    pub slope: f64,
    pub constant: f64,
}

impl ModalDampingTerm {
    /// d_r(ω) = ω_r² − ω² + i c_r(ω), `omega2` = ω_r² (rad²/s²), `omega` = ω (rad/s).
    pub fn at(self, omega2: f64, omega: f64) -> faer::c64 {
        faer::c64::new(omega2 - omega * omega, self.slope * omega + self.constant)
    }
}

/// A number with four significant digits (plain, or in `e` notation outside
/// 1e-3..1e6).
pub fn sig(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    // The decade of x rounded to four digits: 0.0099998 is 0.01000, not 0.010000.
    let rounded: f64 = format!("{x:.3e}").parse().unwrap_or(x);
    let e = rounded.abs().log10().floor() as i32;
    if (-3..6).contains(&e) {
        let d = (3 - e).max(0) as usize;
        format!("{x:.d$}")
    } else {
        format!("{x:.3e}")
    }
}

/// A damping model in words with its values and units.
pub fn describe_damping(d: Damping) -> String {
    match d {
        Damping::None => "none".into(),
        Damping::Modal { zeta } => format!("modal zeta = {}", sig(zeta)),
        Damping::Rayleigh { alpha, beta } => {
            format!(
                "rayleigh alpha = {} 1/s, beta = {} s",
                sig(alpha),
                sig(beta)
            )
        }
        Damping::Hysteretic { eta } => format!("hysteretic eta = {}", sig(eta)),
    }
}

pub type ParameterValues = BTreeMap<String, f64>;

/// ∂K/∂p and ∂M/∂p of one updating parameter (Eq. 30–31), where p is
/// the relative change about the *current* value (X = (1 + p)·X_current), taken at p = 0.
/// Units: those of K (N/m, N, N·m/rad) and M (kg, kg·m, kg·m²).
pub struct ParameterSensitivity {
    pub name: String,
    pub dk: SparseMatrix,
    pub dm: SparseMatrix,
}

/// Numbering of the free DOFs: (node id, DOF) ↔ equation index.
#[derive(Clone, Debug, Default)]
pub struct DofMap {
    /// Equation index → (node id, DOF), in equation order.
    pub equations: Vec<(u32, Dof)>,
    /// (node id, DOF) → equation index, for free DOFs only.
    pub lookup: BTreeMap<(u32, Dof), usize>,
}

impl DofMap {
    /// "node N dof" of each equation (0-based) that exists, in order.
    pub fn labels(&self, equations: &[usize]) -> Vec<String> {
        equations
            .iter()
            .filter_map(|&i| self.equations.get(i))
            .map(|(node, dof)| format!("node {node} {}", dof.name()))
            .collect()
    }

    /// Equation index of a free DOF; `None` if fixed or absent.
    pub fn index(&self, node: u32, dof: Dof) -> Option<usize> {
        self.lookup.get(&(node, dof)).copied()
    }
    /// Number of free DOFs.
    pub fn len(&self) -> usize {
        self.equations.len()
    }
    pub fn is_empty(&self) -> bool {
        self.equations.is_empty()
    }
}

/// An assembled FE model at given parameter values.
pub struct FeModel {
    pub dofs: DofMap,
    /// K over the free DOFs (N/m, N/rad, N·m/rad).
    pub stiffness: SparseMatrix,
    /// M over the free DOFs (kg, kg·m, kg·m²).
    pub mass: SparseMatrix,
    pub damping: Damping,
    /// One entry per deck `param`, in deck order.
    pub parameters: Vec<ParameterSensitivity>,
    /// True if the deck fixes at least one DOF (then zero-energy modes are mechanisms).
    pub has_fixed_dofs: bool,
    /// Test node id → FE node id, from the deck's `sensor` statements.
    pub sensors: BTreeMap<u32, u32>,
}

impl FeModel {
    /// The equation index and sign of a measured channel: test node id
    /// (mapped through `sensor`) and UFF direction code (negative flips the sign).
    pub fn measured_dof(&self, test_node: u32, uff_direction: i32) -> Option<(usize, f64)> {
        let node = self.sensors.get(&test_node).copied().unwrap_or(test_node);
        let (dof, sign) = Dof::from_uff_code(uff_direction)?;
        Some((self.dofs.index(node, dof)?, sign))
    }
}
