//! The case generator: a seed → structure, parameters, layout, damping,
//! noise, format and band, then the simulated campaign.

mod diagnose;
mod effects;
mod layout;
mod params;
mod structure;

pub use diagnose::generate_diagnosis;
pub use effects::frf_change;

use std::fmt::Write as _;
use std::path::Path;

use frfup_parsers::deck::{self, Deck};

use super::{
    round_sig, AxisKind, DampingSpec, Effect, LayoutKind, ParamTruth, Rng, StructureKind, Support,
};
use crate::model::{self, ParameterValues};
use crate::simulate::{self, Band, Campaign, NodeDirection, Sensors};
use crate::solvers::eigen::{lowest_modes, EigenOptions};
use crate::testdata::{FrfKind, MeasuredFrfs};

/// What the generator may draw.
#[derive(Clone, Debug)]
pub struct GenOptions {
    /// Model size range in free DOFs (about; the geometry rounds).
    pub min_dofs: usize,
    pub max_dofs: usize,
    /// Write `min=`/`max=`/`sd=` on the `param` lines of about half the cases.
    pub bounds: bool,
    /// The effect applied to the truth.
    pub effect: Effect,
    /// Most frequency lines of a case.
    pub max_lines: usize,
    /// Section sizes × this (1: the update benchmark's slender members).
    pub section_scale: f64,
    /// Largest |p| of a true parameter value (drawn in ±[0.03, this]).
    pub max_param_change: f64,
}

impl Default for GenOptions {
    fn default() -> Self {
        GenOptions {
            min_dofs: 30,
            max_dofs: 600,
            bounds: false,
            effect: Effect::None,
            max_lines: 2000,
            section_scale: 1.0,
            max_param_change: 0.4,
        }
    }
}

impl GenOptions {
    /// The diagnosis benchmark: 30–400 DOFs, at most 1000 lines (a
    /// diagnosis fits many models per case), the deck's parameters wrong by
    /// at most 25 % (`diagnose` calls a change above 30 % implausible, a
    /// sign of missing physics).
    pub fn diagnosis() -> Self {
        GenOptions {
            max_dofs: 400,
            max_lines: 1000,
            max_param_change: 0.25,
            ..GenOptions::default()
        }
    }

    /// Small diagnosis cases for the test suite: 30–60 DOFs, at most 300 lines.
    pub fn small_diagnosis() -> Self {
        GenOptions {
            max_dofs: 60,
            max_lines: 300,
            ..GenOptions::diagnosis()
        }
    }

    /// Small cases for the test suite: 30–90 DOFs, at most 400 lines.
    pub fn small() -> Self {
        GenOptions {
            min_dofs: 30,
            max_dofs: 90,
            max_lines: 400,
            ..GenOptions::default()
        }
    }
}

/// Why a case could not be made (after retries).
#[derive(Debug)]
pub struct GenError(pub String);

impl std::fmt::Display for GenError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "case generation failed: {}", self.0)
    }
}

impl std::error::Error for GenError {}

/// A material: Young's modulus E (Pa), density ρ (kg/m³).
#[derive(Clone, Debug, PartialEq)]
pub struct MaterialProps {
    pub name: String,
    pub e: f64,
    pub rho: f64,
}

/// A section: area A (m²), second moments Iy, Iz (m⁴), torsion constant J (m⁴).
#[derive(Clone, Debug, PartialEq)]
pub struct SectionProps {
    pub name: String,
    pub shape: &'static str,
    pub a: f64,
    pub iy: f64,
    pub iz: f64,
    pub j: f64,
}

/// A beam element: nodes, material and section indices, member index.
#[derive(Clone, Debug, PartialEq)]
pub struct BeamElement {
    pub id: u32,
    pub n1: u32,
    pub n2: u32,
    pub material: usize,
    pub section: usize,
    pub member: usize,
}

/// A structure as the generator builds it, rendered to deck text by
/// [`Structure::deck_text`]. Effects edit the truth copy of it.
#[derive(Clone, Debug, PartialEq)]
pub struct Structure {
    pub kind: StructureKind,
    pub plane: bool,
    pub support: Support,
    pub materials: Vec<MaterialProps>,
    pub sections: Vec<SectionProps>,
    /// Node id, coordinates (m).
    pub nodes: Vec<(u32, [f64; 3])>,
    pub beams: Vec<BeamElement>,
    /// Mass id, node, mass (kg).
    pub masses: Vec<(u32, u32, f64)>,
    /// Spring id, node, DOF name, stiffness (N/m or N·m/rad).
    pub springs: Vec<(u32, u32, &'static str, f64)>,
    /// Springs between two nodes: id, node, DOF, stiffness, other node.
    pub links: Vec<(u32, u32, &'static str, f64, u32)>,
    /// Every beam Timoshenko (`theory=timoshenko`) instead of Euler–Bernoulli.
    pub timoshenko: bool,
    /// Node, DOF list (`all` or `x,z`...).
    pub fixes: Vec<(u32, String)>,
    pub damping: Option<DampingSpec>,
    /// Element ids of each member, in order.
    pub members: Vec<Vec<u32>>,
    /// Nodes a suspension may hang from (ends and corners).
    pub key_nodes: Vec<u32>,
}

impl Structure {
    /// The deck text; `params` are written as `param` lines.
    pub fn deck_text(&self, title: &str, params: &[ParamTruth]) -> String {
        let mut s = String::new();
        let _ = writeln!(s, "title {title}");
        let _ = writeln!(s, "analysis {}", if self.plane { "plane" } else { "space" });
        for m in &self.materials {
            let _ = writeln!(s, "material {} E={:e} rho={:e} nu=0.3", m.name, m.e, m.rho);
        }
        for c in &self.sections {
            let _ = writeln!(
                s,
                "section {} A={:e} Iy={:e} Iz={:e} J={:e}  # {}",
                c.name, c.a, c.iy, c.iz, c.j, c.shape
            );
        }
        for (id, p) in &self.nodes {
            let _ = writeln!(s, "node {id} {:e} {:e} {:e}", p[0], p[1], p[2]);
        }
        for b in &self.beams {
            let _ = writeln!(
                s,
                "beam {} {} {} {} {}{}",
                b.id,
                b.n1,
                b.n2,
                self.materials[b.material].name,
                self.sections[b.section].name,
                if self.timoshenko {
                    " theory=timoshenko"
                } else {
                    ""
                }
            );
        }
        for (id, node, m) in &self.masses {
            let _ = writeln!(s, "mass {id} {node} m={m:e}");
        }
        for (id, node, dof, k) in &self.springs {
            let _ = writeln!(s, "spring {id} {node} {dof} k={k:e}");
        }
        for (id, node, dof, k, to) in &self.links {
            let _ = writeln!(s, "spring {id} {node} {dof} k={k:e} to={to}");
        }
        for (node, dofs) in &self.fixes {
            let _ = writeln!(s, "fix {node} {dofs}");
        }
        if let Some(d) = self.damping {
            let _ = writeln!(s, "{}", d.statement());
        }
        for p in params {
            let _ = write!(s, "param {} {} {}", p.name, p.quantity, p.ids);
            for (key, v) in [("min", p.min), ("max", p.max), ("sd", p.sd)] {
                if let Some(v) = v {
                    let _ = write!(s, " {key}={v}");
                }
            }
            s.push('\n');
        }
        s
    }

    /// Total mass (kg): Σ ρ A L of the beams plus the lumped masses.
    pub fn total_mass(&self) -> f64 {
        let beams: f64 = self
            .beams
            .iter()
            .map(|b| self.materials[b.material].rho * self.sections[b.section].a * self.length(b))
            .sum();
        beams + self.masses.iter().map(|m| m.2).sum::<f64>()
    }

    /// Length of a beam element (m).
    pub fn length(&self, b: &BeamElement) -> f64 {
        let p = |id: u32| {
            self.nodes
                .iter()
                .find(|n| n.0 == id)
                .map(|n| n.1)
                .unwrap_or([0.0; 3])
        };
        let (a, c) = (p(b.n1), p(b.n2));
        ((a[0] - c[0]).powi(2) + (a[1] - c[1]).powi(2) + (a[2] - c[2]).powi(2)).sqrt()
    }
}

/// A generated case: decks, truth and campaign.
#[derive(Clone, Debug)]
pub struct Case {
    pub seed: u64,
    pub structure: StructureKind,
    pub plane: bool,
    pub support: Support,
    /// Free DOFs of the model.
    pub dofs: usize,
    pub params: Vec<ParamTruth>,
    pub layout: LayoutKind,
    /// The exciter (fixed exciter) or the fixed sensor (roving hammer).
    pub fixed: NodeDirection,
    /// Sensors (fixed exciter) or hit points (roving hammer).
    pub points: Vec<NodeDirection>,
    pub damping: DampingSpec,
    /// Noise standard deviation as a fraction of each channel's RMS |H|.
    pub noise: f64,
    pub binary: bool,
    pub single: bool,
    pub axis: AxisKind,
    pub lines_hz: Vec<f64>,
    /// Elastic modes of the truth inside the band (Hz), and those below
    /// (suspension) if any.
    pub elastic_modes_hz: Vec<f64>,
    pub suspension_modes_hz: Vec<f64>,
    /// What the truth has that the deck lacks (`[Effect::None]` for a
    /// parameter-only case), and how visible each is.
    pub effects: Vec<Effect>,
    pub detectability: Vec<Detectability>,
    pub model_deck: String,
    pub truth_deck: String,
    /// A case of the diagnosis benchmark ([`generate_diagnosis`]).
    pub diagnosis: bool,
}

/// How visible an effect is in the case's test, without noise: `frf_change`
/// = RMS over channels c and lines l of |H_effect − H_none| / (noise ×
/// RMS_l |H_none,c|), i.e. the FRF change in units of the noise the case
/// adds (noise alone gives 1; a channel H_none leaves at rounding level
/// counts at 1e-8 of the strongest channel's RMS); `freq_shift` = the largest relative shift of a
/// band mode it causes (0 for damping and data errors).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Detectability {
    pub frf_change: f64,
    pub freq_shift: f64,
}

/// The seed of case `index` of a run with master seed `master`.
pub fn case_seed(master: u64, index: u64) -> u64 {
    let mut r = Rng::new(master ^ index.wrapping_mul(0xD1B5_4A32_D192_ED03));
    r.next_u64()
}

/// Make the case of `seed`. A draw that gives an unusable model (e.g. too few
/// modes) is redrawn from the same generator, up to 20 times.
pub fn generate(seed: u64, opts: &GenOptions) -> Result<Case, GenError> {
    let mut rng = Rng::new(seed);
    let mut last = String::new();
    for _ in 0..20 {
        match try_case(seed, &mut rng, opts) {
            Ok(case) => return Ok(case),
            Err(e) => last = e,
        }
    }
    Err(GenError(format!("seed {seed}: {last}")))
}

/// One attempt of [`generate`].
fn try_case(seed: u64, rng: &mut Rng, opts: &GenOptions) -> Result<Case, String> {
    let kind = *rng.pick(&StructureKind::ALL).ok_or("no kind")?;
    let support = *rng
        .pick(&[Support::FreeFree, Support::Clamped, Support::Pinned])
        .ok_or("no support")?;
    let mut st = structure::build(kind, support, rng, opts)?;
    let n_modes = rng.int(4, 8);
    if support == Support::FreeFree {
        structure::suspend(&mut st, rng)?;
    }
    let Drawn {
        nominal,
        n_rb,
        damping,
        params,
        values,
        ..
    } = draw_damping_and_parameters(&mut st, n_modes, rng, opts)?;
    let mut truth_st = st.clone();
    opts.effect.apply_to_structure(&mut truth_st, rng);
    // The truth deck carries no bounds (only the model deck has them).
    let truth_text = truth_st.deck_text("truth", &effects::bare(&params));
    let truth = parse_deck(&truth_text)?;
    let truth_modes = modes_hz(&truth, &values, n_rb + n_modes + 1)?;
    if truth_modes.len() < n_rb + n_modes + 1 {
        return Err("truth has too few modes".into());
    }
    let model_text = st.deck_text(
        &format!("frfup random benchmark case {seed:016x}: {}", kind.name()),
        &params,
    );
    let fe = model::build(&nominal, &ParameterValues::new()).map_err(|e| e.to_string())?;
    // A fifth of the campaigns leave the driving point unmeasured; drawn
    // from its own stream so that every other draw of a seed is unchanged.
    let omit = Rng::new(seed ^ 0x0D21_F1A7_0000_0001).chance(0.2);
    let (layout, fixed, points) = layout::draw(&st, &fe, rng, omit)?;
    let elastic = truth_modes[n_rb..n_rb + n_modes].to_vec();
    let next = truth_modes[n_rb + n_modes];
    let f_end = round_sig(
        elastic[n_modes - 1] + 0.5 * (next - elastic[n_modes - 1]),
        4,
    );
    let (axis, lines) = draw_axis(rng, &truth_modes[..n_rb], &elastic, f_end, damping, opts);
    let noise = round_sig(rng.range(0.005, 0.03), 3);
    let binary = rng.chance(0.5);
    let single = binary && rng.chance(0.5);
    Ok(Case {
        seed,
        structure: kind,
        plane: st.plane,
        support,
        dofs: fe.dofs.len(),
        params,
        layout,
        fixed,
        points,
        damping,
        noise,
        binary,
        single,
        axis,
        lines_hz: lines,
        elastic_modes_hz: elastic,
        suspension_modes_hz: truth_modes[..n_rb].to_vec(),
        effects: vec![opts.effect.clone()],
        detectability: Vec::new(),
        model_deck: model_text,
        truth_deck: truth_text,
        diagnosis: false,
    })
}

/// Parse generated deck text (an error here is a generator bug).
pub fn parse_deck(text: &str) -> Result<Deck, String> {
    deck::parse(text).map_err(|e| format!("generated deck does not parse: {e}"))
}

/// What every case draws once its structure stands.
struct Drawn {
    /// The structure's deck without parameters.
    nominal: Deck,
    /// Rigid-body (suspension) modes before the first elastic one.
    n_rb: usize,
    /// The damping drawn (also set on the structure).
    damping: DampingSpec,
    /// The deck's parameters with their true values.
    params: Vec<ParamTruth>,
    values: ParameterValues,
}

/// The nominal deck and its modes, the damping (drawn, rescaled to the
/// `n_modes` elastic modes of the band, and set on `st`) and the deck's
/// parameters with their true values, in this order of draws from `rng`.
fn draw_damping_and_parameters(
    st: &mut Structure,
    n_modes: usize,
    rng: &mut Rng,
    opts: &GenOptions,
) -> Result<Drawn, String> {
    let nominal = parse_deck(&st.deck_text("nominal", &[]))?;
    let base = modes_hz(&nominal, &ParameterValues::new(), 40)?;
    let n_rb = match (st.support, st.plane) {
        (Support::FreeFree, true) => 3,
        (Support::FreeFree, false) => 6,
        _ => 0,
    };
    if base.len() < n_rb + n_modes + 1 {
        return Err(format!("only {} modes", base.len()));
    }
    let damping = rescale_rayleigh(draw_damping(rng), base[n_rb], base[n_rb + n_modes - 1]);
    st.damping = Some(damping);
    let params = params::draw(st, &base, n_rb, n_modes, rng, opts)?;
    let values: ParameterValues = params.iter().map(|p| (p.name.clone(), p.value)).collect();
    Ok(Drawn {
        nominal,
        n_rb,
        damping,
        params,
        values,
    })
}

/// The `count` lowest natural frequencies (Hz) of `deck` at `values`.
pub fn modes_hz(deck: &Deck, values: &ParameterValues, count: usize) -> Result<Vec<f64>, String> {
    let fe = model::build(deck, values).map_err(|e| e.to_string())?;
    let opts = EigenOptions {
        count,
        expect_no_rigid_body_modes: fe.has_fixed_dofs,
        ..EigenOptions::default()
    };
    let modes = lowest_modes(&fe.stiffness, &fe.mass, &opts).map_err(|e| e.to_string())?;
    Ok(modes.frequencies_hz())
}

/// Modal ζ 0.5–2 %, hysteretic η 1–4 %, or Rayleigh with ζ 0.5–2 % at two
/// frequencies fixed later by the band: here α, β are drawn for ζ(ω) =
/// α/(2ω) + βω/2 on a unit scale and rescaled in [`rescale_rayleigh`].
fn draw_damping(rng: &mut Rng) -> DampingSpec {
    match rng.int(0, 2) {
        0 => DampingSpec::Modal {
            zeta: round_sig(rng.range(0.005, 0.02), 3),
        },
        1 => DampingSpec::Hysteretic {
            eta: round_sig(rng.range(0.01, 0.04), 3),
        },
        _ => DampingSpec::Rayleigh {
            alpha: round_sig(rng.range(0.005, 0.02), 3),
            beta: round_sig(rng.range(0.005, 0.02), 3),
        },
    }
}

/// Rayleigh α, β giving ζ_a at f_a and ζ_b at f_b (Hz), from the unit draw
/// (α, β stand for ζ_a, ζ_b): β = 2(ζ_b ω_b − ζ_a ω_a)/(ω_b² − ω_a²),
/// α = 2 ω_a ω_b (ζ_a ω_b − ζ_b ω_a)/(ω_b² − ω_a²), both clamped ≥ 0.
pub fn rescale_rayleigh(d: DampingSpec, f_a: f64, f_b: f64) -> DampingSpec {
    let DampingSpec::Rayleigh {
        alpha: za,
        beta: zb,
    } = d
    else {
        return d;
    };
    let (wa, wb) = (
        2.0 * std::f64::consts::PI * f_a,
        2.0 * std::f64::consts::PI * f_b,
    );
    let den = (wb * wb - wa * wa).max(1e-30);
    let beta = (2.0 * (zb * wb - za * wa) / den).max(0.0);
    let alpha = (2.0 * wa * wb * (za * wb - zb * wa) / den).max(0.0);
    DampingSpec::Rayleigh {
        alpha: round_sig(alpha, 4),
        beta: round_sig(beta, 4),
    }
}

/// The frequency lines: even, log-spaced or jittered, enough to put about two
/// lines in the half-power band of the first elastic mode (capped).
fn draw_axis(
    rng: &mut Rng,
    suspension: &[f64],
    elastic: &[f64],
    f_end: f64,
    damping: DampingSpec,
    opts: &GenOptions,
) -> (AxisKind, Vec<f64>) {
    let f1 = elastic[0];
    let bw = 2.0 * damping.zeta_at(f1).max(0.002) * f1;
    let wanted = (f_end / (0.5 * bw)).ceil() as usize;
    let count = wanted.clamp(400.min(opts.max_lines), opts.max_lines);
    let count = (count as f64 * rng.range(0.8, 1.0)).round().max(50.0) as usize;
    let axis = *rng
        .pick(&[
            AxisKind::Even,
            AxisKind::Even,
            AxisKind::Log,
            AxisKind::Jittered,
        ])
        .unwrap_or(&AxisKind::Even);
    // Lines are rounded to what an ASCII 58 record holds (6 digits), so the
    // file's axis is the simulated one.
    let step = round_sig(f_end / count as f64, 5);
    let lines: Vec<f64> = match axis {
        AxisKind::Even => (1..=count).map(|i| step * i as f64).collect(),
        AxisKind::Jittered => (1..=count)
            .map(|i| {
                let j = if i == 1 || i == count {
                    0.0
                } else {
                    rng.range(-0.3, 0.3)
                };
                round_sig(step * (i as f64 + j), 6)
            })
            .collect(),
        AxisKind::Log => {
            let lowest = suspension.first().copied().unwrap_or(f1).max(1e-3 * f_end);
            let lo = round_sig(0.4 * lowest, 4);
            let r = (f_end / lo).ln() / (count - 1) as f64;
            (0..count)
                .map(|i| round_sig(lo * (r * i as f64).exp(), 6))
                .collect()
        }
    };
    (axis, lines)
}

impl Case {
    /// The exciter's DOF (or, for a roving hammer, the fixed sensor's) is
    /// among the measured points.
    pub fn driving_point_measured(&self) -> bool {
        self.points.contains(&self.fixed)
    }

    /// The layout in the benchmark's tables: its kind, and whether the
    /// driving point was left unmeasured.
    pub fn layout_label(&self) -> String {
        if self.driving_point_measured() {
            self.layout.name().to_string()
        } else {
            format!("{}, no driving point", self.layout.name())
        }
    }

    /// The campaign `frfup simulate` would run for this case.
    pub fn campaign(&self) -> Campaign {
        let end = self.lines_hz.last().copied().unwrap_or(0.0);
        Campaign {
            input: self.fixed,
            band: Band {
                start_hz: self.lines_hz.first().copied().unwrap_or(0.0),
                end_hz: end,
                count: self.lines_hz.len(),
            },
            lines_hz: Some(self.lines_hz.clone()),
            response: (self.layout == LayoutKind::RovingHammer).then_some(self.fixed),
            output: FrfKind::Accelerance,
            sensors: Sensors::List(self.points.clone()),
            noise: self.noise,
            seed: self.seed,
        }
    }

    /// The "measured" FRFs: the truth deck at the true p, simulated with
    /// [`simulate::simulate`], then the effect's data changes.
    pub fn simulate(&self) -> Result<MeasuredFrfs, GenError> {
        let truth = parse_deck(&self.truth_deck).map_err(GenError)?;
        let values: ParameterValues = self
            .params
            .iter()
            .map(|p| (p.name.clone(), p.value))
            .collect();
        let mut frfs = simulate::simulate(&truth, &values, &self.campaign())
            .map_err(|e| GenError(e.to_string()))?;
        let mut rng = Rng::new(self.seed ^ 0x5EED_DA7A);
        for e in &self.effects {
            e.apply_to_data(&mut frfs, &mut rng);
        }
        Ok(frfs)
    }

    /// The UFF bytes of `test.uff` (58, or 58b when `binary`).
    pub fn uff_bytes(&self) -> Result<Vec<u8>, GenError> {
        let frfs = self.simulate()?;
        let title = format!("frfup random benchmark case {:016x}", self.seed);
        let records = simulate::to_uff_records(&frfs, &title, !self.single, self.binary);
        let mut out = Vec::new();
        frfup_parsers::uff::write_functions(&mut out, &records)
            .map_err(|e| GenError(e.to_string()))?;
        Ok(out)
    }

    /// `truth.json`.
    pub fn truth_json(&self) -> serde_json::Value {
        layout::truth_json(self)
    }

    /// Write `model.deck`, `truth.deck`, `test.uff` and `truth.json` into `dir`.
    pub fn write(&self, dir: &Path) -> Result<(), GenError> {
        let io = |e: std::io::Error| GenError(format!("{}: {e}", dir.display()));
        std::fs::create_dir_all(dir).map_err(io)?;
        std::fs::write(dir.join("model.deck"), &self.model_deck).map_err(io)?;
        std::fs::write(dir.join("truth.deck"), &self.truth_deck).map_err(io)?;
        std::fs::write(dir.join("test.uff"), self.uff_bytes()?).map_err(io)?;
        let json = serde_json::to_string_pretty(&self.truth_json())
            .map_err(|e| GenError(e.to_string()))?;
        std::fs::write(dir.join("truth.json"), json + "\n").map_err(io)?;
        Ok(())
    }
}
