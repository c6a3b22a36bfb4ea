//! Measured FRFs: dataset 58 records gathered into channels on a common
//! frequency axis, in SI units, and converted between FRF kinds.
//!
//! Used by `updating`, `diagnosis` and the command line.

use faer::c64;

/// Which motion an FRF relates to force.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrfKind {
    /// Displacement / force (m/N).
    Receptance,
    /// Velocity / force (m/s/N).
    Mobility,
    /// Acceleration / force (m/s²/N).
    Accelerance,
}

/// One measured FRF: response at a node/direction for a force at the reference.
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

/// A set of FRFs sharing one frequency axis.
#[derive(Clone, Debug, PartialEq)]
pub struct MeasuredFrfs {
    /// Frequency lines (Hz), ascending.
    pub frequencies_hz: Vec<f64>,
    pub kind: FrfKind,
    pub channels: Vec<Channel>,
}

pub mod checks;
pub mod convert;
pub mod layout;
pub mod load;

pub use convert::{signed_real, signed_real_displacement};
pub use load::{
    from_uff, from_uff_with_notes, load, load_with_notes, open_uff, parse_uff, LoadedTest,
    TestDataError,
};

impl FrfKind {
    /// Power of iω that turns receptance into this kind: 0, 1 or 2.
    pub fn order(self) -> i32 {
        match self {
            FrfKind::Receptance => 0,
            FrfKind::Mobility => 1,
            FrfKind::Accelerance => 2,
        }
    }

    /// (iω)ⁿ with n = [`FrfKind::order`]: the factor that turns a receptance
    /// at ω (rad/s) into this kind.
    pub fn from_receptance(self, omega: f64) -> c64 {
        i_omega_power(omega, self.order())
    }

    /// The UFF specific data type of the response (records 9): 8, 11 or 12.
    pub fn uff_data_type(self) -> i32 {
        match self {
            FrfKind::Receptance => 8,
            FrfKind::Mobility => 11,
            FrfKind::Accelerance => 12,
        }
    }

    /// The kind whose response has UFF specific data type `code` (8, 11, 12).
    pub fn from_uff_data_type(code: i32) -> Option<FrfKind> {
        match code {
            8 => Some(FrfKind::Receptance),
            11 => Some(FrfKind::Mobility),
            12 => Some(FrfKind::Accelerance),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            FrfKind::Receptance => "receptance",
            FrfKind::Mobility => "mobility",
            FrfKind::Accelerance => "accelerance",
        }
    }

    /// SI units of this kind.
    pub fn units(self) -> &'static str {
        match self {
            FrfKind::Receptance => "m/N",
            FrfKind::Mobility => "m/s/N",
            FrfKind::Accelerance => "m/s^2/N",
        }
    }
}

impl Channel {
    /// A short label such as `112+z/112+z` (response / reference).
    pub fn label(&self) -> String {
        format!(
            "{}/{}",
            dof_label(self.response_node, self.response_direction),
            dof_label(self.reference_node, self.reference_direction)
        )
    }
}

/// `NODE±dir`, e.g. `112+z`, `7-ry`; unknown codes print as numbers.
pub fn dof_label(node: i64, direction: i32) -> String {
    let name = match direction.abs() {
        1 => "x",
        2 => "y",
        3 => "z",
        4 => "rx",
        5 => "ry",
        6 => "rz",
        _ => return format!("{node}:{direction}"),
    };
    format!("{node}{}{name}", if direction < 0 { '-' } else { '+' })
}

/// The label of a record-6 DOF: `dof_label` of its node and direction, or,
/// for a channel identified only by an entity name (node 0, as some
/// acquisition software writes, e.g. `.1.Z-`), that name.
pub fn entity_dof_label(entity: &str, node: i64, direction: i32) -> String {
    let name = entity.trim();
    if node == 0 && !name.is_empty() && !name.eq_ignore_ascii_case("none") {
        name.to_string()
    } else {
        dof_label(node, direction)
    }
}

/// Node and UFF direction code from an entity name of the form
/// `[.]NODE.DIR` with DIR one of x, y, z, rx, ry, rz and a sign before or after
/// (`.1.Z-`, `.56.Z`, `12.+y`, `3:RX`); `None` for any other name.
pub fn node_direction_from_entity(entity: &str) -> Option<(i64, i32)> {
    let parts: Vec<&str> = entity
        .trim()
        .split(['.', ':'])
        .filter(|p| !p.is_empty())
        .collect();
    let [node, dir] = parts.as_slice() else {
        return None;
    };
    let node: i64 = node.parse().ok().filter(|n| *n > 0)?;
    let (sign, name) = if let Some(rest) = dir.strip_prefix('-').or_else(|| dir.strip_suffix('-')) {
        (-1, rest)
    } else {
        (1, dir.trim_start_matches('+').trim_end_matches('+'))
    };
    let code = match name.to_ascii_lowercase().as_str() {
        "x" => 1,
        "y" => 2,
        "z" => 3,
        "rx" => 4,
        "ry" => 5,
        "rz" => 6,
        _ => return None,
    };
    Some((node, sign * code))
}

/// Name of a UFF function type (record 6, field 1).
pub fn function_type_name(code: i32) -> &'static str {
    match code {
        0 => "general",
        1 => "time",
        2 => "auto spectrum",
        3 => "cross spectrum",
        4 => "FRF",
        5 => "transmissibility",
        6 => "coherence",
        7 => "auto correlation",
        8 => "cross correlation",
        9 => "PSD",
        10 => "ESD",
        11 => "probability density",
        12 => "spectrum",
        13 => "cumulative distribution",
        14 => "peaks valley",
        15 => "stress/cycles",
        16 => "strain/cycles",
        17 => "orbit",
        18 => "mode indicator",
        19 => "force pattern",
        20 => "partial power",
        21 => "partial coherence",
        22 => "eigenvalue",
        23 => "eigenvector",
        24 => "shock response spectrum",
        25 => "FIR filter",
        26 => "multiple coherence",
        27 => "order function",
        _ => "other",
    }
}

/// (iω)^power for power in −2..=2, ω in rad/s: the one conversion between FRF
/// kinds (mobility = iω·receptance, accelerance = (iω)²·receptance). A
/// negative power at ω = 0 is infinite; callers treat that line.
pub fn i_omega_power(omega: f64, power: i32) -> c64 {
    match power {
        0 => c64::new(1.0, 0.0),
        1 => c64::new(0.0, omega),
        // 0 − ω², not −ω²: at ω = 0 the factor is +0, so a 0 Hz line reads 0, never −0.
        2 => c64::new(0.0 - omega * omega, 0.0),
        -1 => c64::new(0.0, -1.0 / omega),
        -2 => c64::new(-1.0 / (omega * omega), 0.0),
        _ => unreachable!("FRF kinds differ by at most two orders"),
    }
}
