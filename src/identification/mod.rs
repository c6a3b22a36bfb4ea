//! Experimental modal analysis: natural frequencies, damping ratios and mode
//! shapes identified from measured FRFs, with no user picking.
//!
//! Stage of the pipeline testdata → identification → updating/diagnosis: it
//! uses [`crate::testdata`] and faer; only [`pairing`] (test modes against a
//! deck's) also builds the model and solves its modes.
//!
//! 1. [`prepare`]: the FRFs in the band as an output × input matrix per line
//!    (several references when every response is measured for each of them,
//!    else the references' most common one), each output weighted by the
//!    inverse RMS of its FRFs so that every sensor's noise weighs alike.
//! 2. [`lscf`]: poles by the poly-reference least-squares complex-frequency
//!    method ("PolyMAX", Guillaume et al., IMAC 2003; Peeters et al., Shock
//!    Vib. 11, 2004): a right matrix-fraction model H(ω) = N(z) D(z)⁻¹ in
//!    z = e^{iωΔt} with real coefficients, its numerators eliminated (reduced
//!    normal equations), the denominator's block companion matrix giving the
//!    poles λ = ln z / Δt and their participation vectors. Chosen over the
//!    common-denominator LSCF of sdypy-EMA (which it contains: one reference
//!    gives it exactly) because a denominator per reference separates modes
//!    closer than their bandwidths when the campaign has several references,
//!    and over time-domain fits (LSCE) because it needs no inverse FFT of a
//!    band-limited FRF. All orders up to the maximum come from one set of
//!    Toeplitz sums (O(lines × order) per FRF), not a new fit per order.
//! 3. [`stabilisation`]: poles per model order, each marked stable in
//!    frequency, damping and shape (MAC of its numerator vector) against the
//!    nearest pole of the previous order.
//! 4. [`select`]: the physical poles: stable poles clustered across orders
//!    (distance in the complex plane relative to the half-power bandwidth and
//!    1 − MAC); clusters present in too few orders (noise, computational
//!    poles) dropped; one pole per cluster.
//! 5. [`lsfd`]: residues by least squares in the frequency domain with the
//!    selected poles fixed, plus upper and lower residuals per FRF; then the
//!    poles refined by Gauss–Newton on the same residual (variable
//!    projection), which removes the bias of the linearised LSCF fit under
//!    noise; a pole that leaves a residual near it far above the noise is
//!    tried as two ([`split`]: close modes that one reference shows as one
//!    peak); modes whose contribution does not stand out of the fit residual
//!    are dropped.
//! 6. [`quality`]: modal phase collinearity (MPC), mean phase deviation
//!    (MPD), complexity; [`classify`]: rigid-body/suspension modes (far below
//!    the first elastic mode) told from elastic ones.
//! 7. [`pairing`] (with a deck): the test modes paired with the deck's FE
//!    modes by MAC at the measured DOFs.
//!
//! Units: frequencies in Hz at the interface, ω in rad/s inside; residues in
//! the units of receptance × rad/s (m/N/s) whatever the FRF kind.

pub mod classify;
pub mod column;
pub mod lscf;
pub mod lsfd;
pub mod pairing;
pub mod prepare;
pub mod quality;
pub mod refine;
pub mod select;
pub mod split;
pub mod stabilisation;
pub mod tall;

use faer::c64;

use crate::testdata::MeasuredFrfs;

pub use classify::ModeKind;
pub use column::{identify_column, ColumnMode};
pub use pairing::{identify_and_pair, pair_with_deck, PairedModes, Pairing, PAIR_MAC};
pub use prepare::{Dof, Prepared};
pub use quality::Quality;
pub use stabilisation::{Diagram, DiagramPole, Stability};

/// Why an identification could not be made.
#[derive(Clone, Debug, PartialEq)]
pub enum IdentifyError {
    /// The test has no FRF or fewer lines in the band than the fit needs.
    NotEnoughData(String),
    /// A setting is out of its range.
    BadOption(String),
    /// A linear system of the fit was singular.
    Singular(&'static str),
}

impl std::fmt::Display for IdentifyError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            IdentifyError::NotEnoughData(m) => write!(f, "not enough data: {m}"),
            IdentifyError::BadOption(m) => write!(f, "bad option: {m}"),
            IdentifyError::Singular(what) => write!(f, "singular system in {what}"),
        }
    }
}

impl std::error::Error for IdentifyError {}

/// Settings of [`identify`].
#[derive(Clone, Debug, PartialEq)]
pub struct IdentifyOptions {
    /// Band (Hz); `None`: every line of the test.
    pub band_hz: Option<(f64, f64)>,
    /// Highest model order of the stabilisation diagram (≥ 4); `None`: from
    /// the number of peaks of the summed FRF.
    pub max_order: Option<usize>,
    /// Stability tolerances between consecutive orders.
    pub stability: stabilisation::Tolerances,
    /// Cluster selection settings.
    pub select: select::SelectOptions,
    /// Refine the selected poles by nonlinear least squares.
    pub refine: bool,
}

impl Default for IdentifyOptions {
    fn default() -> Self {
        IdentifyOptions {
            band_hz: None,
            max_order: None,
            stability: stabilisation::Tolerances::default(),
            select: select::SelectOptions::default(),
            refine: true,
        }
    }
}

/// One identified mode.
#[derive(Clone, Debug, PartialEq)]
pub struct Mode {
    /// Pole λ = ω_n(−ζ + i√(1−ζ²)) (rad/s).
    pub pole: c64,
    /// Undamped natural frequency |λ|/2π (Hz).
    pub frequency_hz: f64,
    /// Viscous damping ratio −Re λ/|λ|.
    pub damping_ratio: f64,
    /// Complex shape at the outputs (largest magnitude 1, rotated to be most
    /// nearly real).
    pub shape: Vec<c64>,
    /// Participation of each input (largest magnitude 1).
    pub participation: Vec<c64>,
    /// Residue of each FRF, channel order of [`Prepared::channels`]
    /// (receptance residue, m/N/s).
    pub residues: Vec<c64>,
    pub quality: Quality,
    pub kind: ModeKind,
    /// Orders of the diagram in which the mode's cluster is stable.
    pub stable_orders: usize,
    /// The cluster's poles (indices in [`Diagram::poles`]).
    pub cluster: Vec<usize>,
    /// Peak modal contribution ÷ RMS of the fit residual.
    pub significance: f64,
}

impl Mode {
    /// The real shape: the real part of [`Mode::shape`].
    pub fn real_shape(&self) -> Vec<f64> {
        self.shape.iter().map(|v| v.re).collect()
    }
}

/// The result of [`identify`].
#[derive(Clone, Debug)]
pub struct Identification {
    pub data: Prepared,
    pub diagram: Diagram,
    /// Modes by ascending frequency.
    pub modes: Vec<Mode>,
    /// Upper and lower residuals of each FRF (receptance: U in m/N, L in
    /// m/N·rad²/s²).
    pub residuals: Vec<lsfd::Residual>,
    /// RMS of the weighted fit residual ÷ RMS of the weighted data.
    pub relative_residual: f64,
    /// Wall time of each stage (name, seconds), for `--verbose`; never
    /// written to an output file (outputs stay the same bytes run to run).
    pub timings: Vec<(&'static str, f64)>,
}

impl Identification {
    /// The fitted FRF of channel `c` (in the test's kind) at every ω of
    /// `omega` (rad/s).
    pub fn synthesise_lines(&self, c: usize, omega: &[f64]) -> Vec<c64> {
        let poles: Vec<c64> = self.modes.iter().map(|m| m.pole).collect();
        let residues: Vec<c64> = self.modes.iter().map(|m| m.residues[c]).collect();
        omega
            .iter()
            .map(|&w| {
                lsfd::evaluate(
                    &poles,
                    &residues,
                    &self.residuals[c],
                    w,
                    self.data.kind_order,
                )
            })
            .collect()
    }
}

/// Identifies the modes of `test`: LSCF poles over orders, automatic
/// selection, LSFD residues (see the module doc).
pub fn identify(
    test: &MeasuredFrfs,
    opts: &IdentifyOptions,
) -> Result<Identification, IdentifyError> {
    let mut timings = Vec::new();
    let mut clock = std::time::Instant::now();
    let mut lap = |name: &'static str, timings: &mut Vec<(&'static str, f64)>| {
        timings.push((name, clock.elapsed().as_secs_f64()));
        clock = std::time::Instant::now();
    };
    let data = prepare::prepare(test, opts.band_hz)?;
    let max_order = match opts.max_order {
        Some(n) if n < 4 => {
            return Err(IdentifyError::BadOption(format!(
                "max order {n} must be at least 4"
            )))
        }
        Some(n) => n,
        None => prepare::default_max_order(&data),
    };
    lap("prepare the FRFs", &mut timings);
    let sums = lscf::Sums::new(&data, max_order)?;
    let diagram = stabilisation::diagram(&data, &sums, &opts.stability)?;
    lap("poles per order (diagram)", &mut timings);
    let picked = select::select(&diagram, &data, &opts.select);
    lap("select the physical poles", &mut timings);
    let fit = lsfd::fit_modes(&data, &picked, opts.refine, &opts.select)?;
    lap("residues, refinement (LSFD)", &mut timings);
    let mut modes: Vec<Mode> = fit
        .modes
        .into_iter()
        .map(|m| {
            let (shape, participation) = quality::shape_and_participation(&data, &m.residues);
            Mode {
                pole: m.pole,
                frequency_hz: m.pole.norm() / (2.0 * std::f64::consts::PI),
                damping_ratio: -m.pole.re / m.pole.norm(),
                quality: quality::Quality::of(&shape),
                shape: quality::rotate_real(&shape),
                participation,
                residues: m.residues,
                kind: ModeKind::Elastic,
                stable_orders: m.stable_orders,
                cluster: m.cluster,
                significance: m.significance,
            }
        })
        .collect();
    modes.sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
    classify::mark_rigid_body(&mut modes);
    lap("shapes and quality", &mut timings);
    Ok(Identification {
        data,
        diagram,
        modes,
        residuals: fit.residuals,
        relative_residual: fit.relative_residual,
        timings,
    })
}
