//! A measured-style test campaign computed from a deck: the FRFs of the model
//! (optionally with changed parameter values, i.e. known defects) at chosen
//! sensor DOFs for one excitation DOF, with reproducible complex Gaussian noise.
//! This is how fixtures and benchmarks are made (`frfup simulate`).
//!
//! Two layouts: a fixed exciter (one column of the FRF matrix: every record
//! has the input as reference) or, with [`Campaign::response`], a roving
//! hammer (one row: a fixed sensor, the hammer moved over the `sensors`
//! points; record i has reference = hit point i and response = the fixed
//! sensor, computed by reciprocity H_ij = H_ji from one solve).

use faer::c64;
use frfup_parsers::deck::Deck;
use frfup_parsers::uff::{Abscissa, AxisCharacteristics, Function58, Ordinate};

use crate::model::{self, Dof, FeModel, ParameterValues};
use crate::solvers::frf;
use crate::testdata::{Channel, FrfKind, MeasuredFrfs};

/// A node and UFF direction code (±1..±6).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NodeDirection {
    pub node: u32,
    pub direction: i32,
}

/// Evenly spaced frequency lines: `count` lines from `start_hz` to `end_hz` inclusive.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Band {
    pub start_hz: f64,
    pub end_hz: f64,
    pub count: usize,
}

impl Band {
    pub fn step_hz(&self) -> f64 {
        if self.count > 1 {
            (self.end_hz - self.start_hz) / (self.count - 1) as f64
        } else {
            0.0
        }
    }
    pub fn lines_hz(&self) -> Vec<f64> {
        (0..self.count)
            .map(|i| self.start_hz + self.step_hz() * i as f64)
            .collect()
    }
}

/// Which DOFs carry a sensor.
#[derive(Clone, Debug, PartialEq)]
pub enum Sensors {
    /// Every free translational DOF (x, y, z) of every node, in node order.
    All,
    List(Vec<NodeDirection>),
}

/// What to simulate.
#[derive(Clone, Debug, PartialEq)]
pub struct Campaign {
    /// Excitation DOF (test node id and direction). Ignored when `response`
    /// is set (the hit points are then the `sensors`).
    pub input: NodeDirection,
    pub band: Band,
    /// Explicit frequency lines (Hz, ascending, ≥ 0) instead of `band`'s even
    /// ones: an uneven axis, written as an uneven-abscissa 58 record.
    pub lines_hz: Option<Vec<f64>>,
    /// Roving hammer: the fixed sensor. Record i then has this response and
    /// reference = `sensors[i]` (the hit point).
    pub response: Option<NodeDirection>,
    pub output: FrfKind,
    pub sensors: Sensors,
    /// Noise standard deviation as a fraction of each channel's RMS |H|.
    pub noise: f64,
    pub seed: u64,
}

/// Why a campaign could not be simulated.
#[derive(Debug)]
pub enum SimulateError {
    Model(model::ModelError),
    /// A sensor or the input names a DOF the model does not have (or fixes).
    UnknownDof {
        what: String,
        dof: NodeDirection,
    },
    Invalid(String),
}

impl std::fmt::Display for SimulateError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SimulateError::Model(e) => write!(f, "{e}"),
            SimulateError::UnknownDof { what, dof } => write!(
                f,
                "{what} {}:{} is not a free DOF of the model (unknown node, fixed DOF, or a direction the analysis lacks)",
                dof.node, dof.direction
            ),
            SimulateError::Invalid(s) => write!(f, "{s}"),
        }
    }
}

impl std::error::Error for SimulateError {}

/// Simulate the campaign on `deck` with parameter values `values`.
pub fn simulate(
    deck: &Deck,
    values: &ParameterValues,
    campaign: &Campaign,
) -> Result<MeasuredFrfs, SimulateError> {
    if campaign.band.count == 0
        || !(campaign.band.end_hz >= campaign.band.start_hz)
        || campaign.band.start_hz < 0.0
    {
        return Err(SimulateError::Invalid(format!(
            "band {}:{}:{} must have 0 <= F0 <= F1 and N >= 1",
            campaign.band.start_hz, campaign.band.end_hz, campaign.band.count
        )));
    }
    if !(campaign.noise >= 0.0 && campaign.noise.is_finite()) {
        return Err(SimulateError::Invalid(format!(
            "noise fraction {} must be >= 0",
            campaign.noise
        )));
    }
    let lines = campaign_lines(campaign)?;
    let fe = model::build(deck, values).map_err(SimulateError::Model)?;
    // With a roving hammer the fixed sensor takes the place of the input: by
    // reciprocity H(sensor, hit) = H(hit, sensor), one solve for all hits.
    let (driven, what) = match campaign.response {
        Some(r) => (r, "response"),
        None => (campaign.input, "input"),
    };
    let (input_eq, input_sign) =
        fe.measured_dof(driven.node, driven.direction)
            .ok_or(SimulateError::UnknownDof {
                what: what.into(),
                dof: driven,
            })?;
    let sensors = sensor_list(&fe, &campaign.sensors)?;
    let mut outputs = Vec::with_capacity(sensors.len());
    let mut signs = Vec::with_capacity(sensors.len());
    for s in &sensors {
        let (eq, sign) = fe
            .measured_dof(s.node, s.direction)
            .ok_or(SimulateError::UnknownDof {
                what: "sensor".into(),
                dof: *s,
            })?;
        outputs.push(eq);
        signs.push(sign);
    }
    let omegas: Vec<f64> = lines
        .iter()
        .map(|f| 2.0 * std::f64::consts::PI * f)
        .collect();
    let receptance = frf::direct_receptance(
        &fe.stiffness,
        &fe.mass,
        fe.damping,
        &omegas,
        input_eq,
        &outputs,
    );
    let mut rng = Gaussian::new(campaign.seed);
    let kind = campaign.output;
    let channels = sensors
        .iter()
        .enumerate()
        .map(|(row, s)| {
            let mut values: Vec<c64> = omegas
                .iter()
                .enumerate()
                .map(|(col, &w)| {
                    receptance[(row, col)] * (signs[row] * input_sign) * kind.from_receptance(w)
                })
                .collect();
            if campaign.noise > 0.0 {
                let rms =
                    (values.iter().map(|v| v.norm_sqr()).sum::<f64>() / values.len() as f64).sqrt();
                let sigma = campaign.noise * rms / std::f64::consts::SQRT_2;
                for v in &mut values {
                    *v += c64::new(sigma * rng.next(), sigma * rng.next());
                }
            }
            let (response, reference) = match campaign.response {
                Some(r) => (r, *s),
                None => (*s, campaign.input),
            };
            Channel {
                response_node: response.node as i64,
                response_direction: response.direction,
                reference_node: reference.node as i64,
                reference_direction: reference.direction,
                values,
            }
        })
        .collect();
    Ok(MeasuredFrfs {
        frequencies_hz: lines,
        kind: campaign.output,
        channels,
    })
}

/// The frequency lines of a campaign: the explicit list if given (checked
/// finite, ≥ 0 and strictly ascending), else the band's even lines.
fn campaign_lines(campaign: &Campaign) -> Result<Vec<f64>, SimulateError> {
    let Some(lines) = &campaign.lines_hz else {
        return Ok(campaign.band.lines_hz());
    };
    if lines.is_empty() {
        return Err(SimulateError::Invalid(
            "the list of frequency lines is empty".into(),
        ));
    }
    if let Some(i) = (0..lines.len()).find(|&i| {
        !(lines[i].is_finite() && lines[i] >= 0.0) || (i > 0 && !(lines[i] > lines[i - 1]))
    }) {
        return Err(SimulateError::Invalid(format!(
            "frequency line {} ({} Hz) must be finite, >= 0 and above the previous one",
            i + 1,
            lines[i]
        )));
    }
    Ok(lines.clone())
}

/// The abscissa of a frequency axis: `Even` when every step equals the first
/// to 1e-9 of the span, else the explicit `Uneven` list.
fn abscissa_of(lines: &[f64]) -> Abscissa {
    let start = lines.first().copied().unwrap_or(0.0);
    let step = if lines.len() > 1 {
        lines[1] - lines[0]
    } else {
        0.0
    };
    let span = lines.last().copied().unwrap_or(0.0).abs().max(1e-300);
    let even = lines
        .iter()
        .enumerate()
        .all(|(i, f)| (f - (start + step * i as f64)).abs() <= 1e-9 * span);
    if even {
        Abscissa::Even { start, step }
    } else {
        Abscissa::Uneven(lines.to_vec())
    }
}

/// The sensors of a campaign as test node/direction pairs.
fn sensor_list(fe: &FeModel, sensors: &Sensors) -> Result<Vec<NodeDirection>, SimulateError> {
    match sensors {
        Sensors::List(list) => Ok(list.clone()),
        Sensors::All => {
            let to_test: std::collections::BTreeMap<u32, u32> = fe
                .sensors
                .iter()
                .map(|(&test, &node)| (node, test))
                .collect();
            Ok(fe
                .dofs
                .equations
                .iter()
                .filter(|(_, dof)| matches!(dof, Dof::X | Dof::Y | Dof::Z))
                .map(|&(node, dof)| NodeDirection {
                    node: to_test.get(&node).copied().unwrap_or(node),
                    direction: dof.uff_code(),
                })
                .collect())
        }
    }
}

/// Dataset 58 records of a set of FRFs (function type 4, SI units), complex
/// double (ordinate type 6) or single (5).
pub fn to_uff_records(
    frfs: &MeasuredFrfs,
    title: &str,
    double: bool,
    binary: bool,
) -> Vec<Function58> {
    let abscissa = abscissa_of(&frfs.frequencies_hz);
    let (label, units) = match frfs.kind {
        FrfKind::Receptance => ("Displacement", "m"),
        FrfKind::Mobility => ("Velocity", "m/s"),
        FrfKind::Accelerance => ("Acceleration", "m/s^2"),
    };
    frfs.channels
        .iter()
        .enumerate()
        .map(|(i, ch)| Function58 {
            id_lines: [
                format!("{} {}", frfs.kind.name(), ch.label()),
                title.to_string(),
                "written by frfup simulate".to_string(),
                "NONE".to_string(),
                "NONE".to_string(),
            ],
            function_type: 4,
            function_id: i as i32 + 1,
            version: 0,
            load_case: 0,
            response_entity: "NONE".to_string(),
            response_node: ch.response_node,
            response_direction: ch.response_direction,
            reference_entity: "NONE".to_string(),
            reference_node: ch.reference_node,
            reference_direction: ch.reference_direction,
            ordinate_type: if double { 6 } else { 5 },
            abscissa: abscissa.clone(),
            z_axis_value: 0.0,
            abscissa_axis: axis(18, 0, 0, "Frequency", "Hz"),
            numerator_axis: axis(frfs.kind.uff_data_type(), 1, 0, label, units),
            denominator_axis: axis(13, 0, 1, "Force", "N"),
            z_axis: axis(0, 0, 0, "NONE", "NONE"),
            ordinate: Ordinate::Complex(ch.values.clone()),
            binary,
        })
        .collect()
}

fn axis(data_type: i32, length: i32, force: i32, label: &str, units: &str) -> AxisCharacteristics {
    AxisCharacteristics {
        data_type,
        length_exponent: length,
        force_exponent: force,
        temperature_exponent: 0,
        label: label.to_string(),
        units_label: units.to_string(),
    }
}

/// Standard normal deviates from a seeded xoshiro256** generator (Box–Muller),
/// so that the same seed gives the same noise on every machine.
pub struct Gaussian {
    state: [u64; 4],
    spare: Option<f64>,
}

impl Gaussian {
    pub fn new(seed: u64) -> Self {
        // splitmix64 expands the seed into the generator state.
        let mut z = seed;
        let mut next = || {
            z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut x = z;
            x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            x ^ (x >> 31)
        };
        Gaussian {
            state: [next(), next(), next(), next()],
            spare: None,
        }
    }

    fn next_u64(&mut self) -> u64 {
        let s = &mut self.state;
        let result = s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = s[1] << 17;
        s[2] ^= s[0];
        s[3] ^= s[1];
        s[1] ^= s[2];
        s[0] ^= s[3];
        s[2] ^= t;
        s[3] = s[3].rotate_left(45);
        result
    }

    /// Uniform in (0, 1].
    fn uniform(&mut self) -> f64 {
        ((self.next_u64() >> 11) as f64 + 1.0) / (1u64 << 53) as f64
    }

    /// A standard normal deviate.
    #[allow(clippy::should_implement_trait)]
    pub fn next(&mut self) -> f64 {
        if let Some(v) = self.spare.take() {
            return v;
        }
        let r = (-2.0 * self.uniform().ln()).sqrt();
        let theta = 2.0 * std::f64::consts::PI * self.uniform();
        self.spare = Some(r * theta.sin());
        r * theta.cos()
    }
}
