//! Measured FRFs: dataset 58 records gathered into channels on a common
//! frequency axis, in SI units, and converted between FRF kinds.
//!
//! CONTRACT (shared with `updating` and the CLI): items marked CONTRACT keep
//! their names and meaning.

use faer::c64;

/// CONTRACT. Which motion an FRF relates to force.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrfKind {
    /// Displacement / force (m/N).
    Receptance,
    /// Velocity / force (m/s/N).
    Mobility,
    /// Acceleration / force (m/s²/N).
    Accelerance,
}

/// CONTRACT. One measured FRF: response at a node/direction for a force at the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    pub response_node: i64,
    /// UFF direction code ±1..±6.
    pub response_direction: i32,
    pub reference_node: i64,
    pub reference_direction: i32,
    /// One complex value per frequency line, SI units of `MeasuredFrfs::kind`.
    pub values: Vec<c64>,
}

/// CONTRACT. A set of FRFs sharing one frequency axis.
#[derive(Clone, Debug, PartialEq)]
pub struct MeasuredFrfs {
    /// Frequency lines (Hz), ascending.
    pub frequencies_hz: Vec<f64>,
    pub kind: FrfKind,
    pub channels: Vec<Channel>,
}
