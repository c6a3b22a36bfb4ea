//! 12×12 local stiffness and consistent mass of a two-node 3D frame beam.
//!
//! Local DOFs per node: u, v, w (along local x, y, z), θx, θy, θz; node 1
//! first. Blocks (deck spec, "Element matrices"):
//!
//! - axial (u): EA/L·[1 −1; −1 1], ρAL/6·[2 1; 1 2];
//! - torsion (θx): GJ/L·[1 −1; −1 1], ρ(Iy+Iz)L/6·[2 1; 1 2];
//! - bending in the local x–y plane (v, θz = dv/dx): E·Iz, shear coefficient ky;
//! - bending in the local x–z plane (w, θy = −dw/dx): E·Iy, shear coefficient kz.
//!
//! Euler–Bernoulli: cubic Hermite stiffness and consistent translational mass,
//! no rotary inertia. Timoshenko (Przemieniecki, *Theory of Matrix Structural
//! Analysis*, 1968, §5.6 and §11.7): Φ = 12EI/(κGAL²), stiffness
//! EI/((1+Φ)L³)·[12, 6L, −12, 6L; …, (4+Φ)L², …, (2−Φ)L²; …] and the consistent
//! mass with translational and rotary inertia; Φ = 0 gives back the
//! Euler–Bernoulli matrices (plus rotary inertia).
//!
//! The functions are generic over the scalar so that parameter derivatives
//! can be taken by complex step (see `model::sensitivity`).

use nalgebra::{ComplexField, SMatrix};

use frfup_parsers::deck::Theory;

/// Real or complex scalars whose real field is f64.
pub trait Scalar: ComplexField<RealField = f64> + Copy {}
impl<T: ComplexField<RealField = f64> + Copy> Scalar for T {}

pub type Matrix12<T> = SMatrix<T, 12, 12>;

/// Section and material properties of one beam (SI units).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeamProperties<T> {
    /// Young's modulus E (Pa).
    pub e: T,
    /// Shear modulus G (Pa).
    pub g: T,
    /// Density ρ (kg/m³).
    pub rho: T,
    /// Area A (m²).
    pub a: T,
    /// Second moment about local y (m⁴): bending in the local x–z plane.
    pub iy: T,
    /// Second moment about local z (m⁴): bending in the local x–y plane.
    pub iz: T,
    /// Torsion constant J (m⁴).
    pub j: T,
    /// Shear coefficient for bending about z (shear along y).
    pub ky: f64,
    /// Shear coefficient for bending about y (shear along z).
    pub kz: f64,
}

fn c<T: Scalar>(x: f64) -> T {
    T::from_real(x)
}

/// Local DOF indices of the two bending planes: (v1, θz1, v2, θz2) and
/// (w1, θy1, w2, θy2), with the sign that maps them onto the textbook
/// (deflection, slope) convention: θy = −dw/dx, so θy enters with −1.
const XY_PLANE: ([usize; 4], [f64; 4]) = ([1, 5, 7, 11], [1.0, 1.0, 1.0, 1.0]);
const XZ_PLANE: ([usize; 4], [f64; 4]) = ([2, 4, 8, 10], [1.0, -1.0, 1.0, -1.0]);

fn place<T: Scalar>(m: &mut Matrix12<T>, plane: ([usize; 4], [f64; 4]), block: &[[T; 4]; 4]) {
    let (idx, sign) = plane;
    for i in 0..4 {
        for j in 0..4 {
            m[(idx[i], idx[j])] += block[i][j] * c::<T>(sign[i] * sign[j]);
        }
    }
}

fn place2<T: Scalar>(m: &mut Matrix12<T>, i: usize, j: usize, block: [[T; 2]; 2]) {
    m[(i, i)] += block[0][0];
    m[(i, j)] += block[0][1];
    m[(j, i)] += block[1][0];
    m[(j, j)] += block[1][1];
}

/// Φ = 12EI/(κGAL²) of one bending plane (0 for Euler–Bernoulli).
fn shear_parameter<T: Scalar>(
    p: &BeamProperties<T>,
    i: T,
    kappa: f64,
    l: f64,
    theory: Theory,
) -> T {
    match theory {
        Theory::EulerBernoulli => c(0.0),
        Theory::Timoshenko => c::<T>(12.0) * p.e * i / (c::<T>(kappa * l * l) * p.g * p.a),
    }
}

/// Bending stiffness in (deflection, slope) form, θ = d(deflection)/dx.
fn bending_stiffness<T: Scalar>(ei: T, phi: T, l: f64) -> [[T; 4]; 4] {
    let f = ei / ((c::<T>(1.0) + phi) * c::<T>(l * l * l));
    let k11 = c::<T>(12.0);
    let k12 = c::<T>(6.0 * l);
    let k22 = (c::<T>(4.0) + phi) * c::<T>(l * l);
    let k24 = (c::<T>(2.0) - phi) * c::<T>(l * l);
    [
        [k11 * f, k12 * f, -k11 * f, k12 * f],
        [k12 * f, k22 * f, -k12 * f, k24 * f],
        [-k11 * f, -k12 * f, k11 * f, -k12 * f],
        [k12 * f, k24 * f, -k12 * f, k22 * f],
    ]
}

/// Consistent bending mass (Przemieniecki) in (deflection, slope) form:
/// translational inertia ρA, plus rotary inertia ρI if given.
fn bending_mass<T: Scalar>(rho_a: T, rho_i: Option<T>, phi: T, l: f64) -> [[T; 4]; 4] {
    let one = c::<T>(1.0);
    let d = (one + phi) * (one + phi);
    let p2 = phi * phi;
    let poly = |a: f64, b: f64, cc: f64| c::<T>(a) + c::<T>(b) * phi + c::<T>(cc) * p2;
    let ft = rho_a * c::<T>(l) / d;
    let m11 = poly(13.0 / 35.0, 7.0 / 10.0, 1.0 / 3.0) * ft;
    let m12 = poly(11.0 / 210.0, 11.0 / 120.0, 1.0 / 24.0) * c::<T>(l) * ft;
    let m13 = poly(9.0 / 70.0, 3.0 / 10.0, 1.0 / 6.0) * ft;
    let m14 = -poly(13.0 / 420.0, 3.0 / 40.0, 1.0 / 24.0) * c::<T>(l) * ft;
    let m22 = poly(1.0 / 105.0, 1.0 / 60.0, 1.0 / 120.0) * c::<T>(l * l) * ft;
    let m24 = -poly(1.0 / 140.0, 1.0 / 60.0, 1.0 / 120.0) * c::<T>(l * l) * ft;
    let mut m = [
        [m11, m12, m13, m14],
        [m12, m22, -m14, m24],
        [m13, -m14, m11, -m12],
        [m14, m24, -m12, m22],
    ];
    if let Some(rho_i) = rho_i {
        let fr = rho_i / (d * c::<T>(l));
        let r11 = c::<T>(6.0 / 5.0) * fr;
        let r12 = poly(1.0 / 10.0, -1.0 / 2.0, 0.0) * c::<T>(l) * fr;
        let r22 = poly(2.0 / 15.0, 1.0 / 6.0, 1.0 / 3.0) * c::<T>(l * l) * fr;
        let r24 = poly(-1.0 / 30.0, -1.0 / 6.0, 1.0 / 6.0) * c::<T>(l * l) * fr;
        let r = [
            [r11, r12, -r11, r12],
            [r12, r22, -r12, r24],
            [-r11, -r12, r11, -r12],
            [r12, r24, -r12, r22],
        ];
        for i in 0..4 {
            for j in 0..4 {
                m[i][j] += r[i][j];
            }
        }
    }
    m
}

/// Local 12×12 stiffness (N/m, N, N·m/rad) of a beam of length `l`.
pub fn local_stiffness<T: Scalar>(p: &BeamProperties<T>, l: f64, theory: Theory) -> Matrix12<T> {
    let mut k = Matrix12::<T>::zeros();
    let ea = p.e * p.a / c::<T>(l);
    place2(&mut k, 0, 6, [[ea, -ea], [-ea, ea]]);
    let gj = p.g * p.j / c::<T>(l);
    place2(&mut k, 3, 9, [[gj, -gj], [-gj, gj]]);
    let phi_y = shear_parameter(p, p.iz, p.ky, l, theory);
    place(&mut k, XY_PLANE, &bending_stiffness(p.e * p.iz, phi_y, l));
    let phi_z = shear_parameter(p, p.iy, p.kz, l, theory);
    place(&mut k, XZ_PLANE, &bending_stiffness(p.e * p.iy, phi_z, l));
    k
}

/// Local 12×12 consistent mass (kg, kg·m, kg·m²) of a beam of length `l`.
pub fn local_mass<T: Scalar>(p: &BeamProperties<T>, l: f64, theory: Theory) -> Matrix12<T> {
    let mut m = Matrix12::<T>::zeros();
    let rho_a = p.rho * p.a;
    let ax = rho_a * c::<T>(l / 6.0);
    place2(
        &mut m,
        0,
        6,
        [[ax * c::<T>(2.0), ax], [ax, ax * c::<T>(2.0)]],
    );
    let tor = p.rho * (p.iy + p.iz) * c::<T>(l / 6.0);
    place2(
        &mut m,
        3,
        9,
        [[tor * c::<T>(2.0), tor], [tor, tor * c::<T>(2.0)]],
    );
    let rotary = theory == Theory::Timoshenko;
    let phi_y = shear_parameter(p, p.iz, p.ky, l, theory);
    let rot_y = rotary.then(|| p.rho * p.iz);
    place(&mut m, XY_PLANE, &bending_mass(rho_a, rot_y, phi_y, l));
    let phi_z = shear_parameter(p, p.iy, p.kz, l, theory);
    let rot_z = rotary.then(|| p.rho * p.iy);
    place(&mut m, XZ_PLANE, &bending_mass(rho_a, rot_z, phi_z, l));
    m
}
