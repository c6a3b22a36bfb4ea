//! The model deck (`.deck`, version 1): see `docs/deck.md` and
//! `docs/spec/deck.md` (the contract).
//!
//! [`parse`] reads a deck into a typed [`Deck`] in two passes: a nom-based
//! syntax pass (one statement per line) and a semantic pass ([`Deck::validate`])
//! that checks identifiers, cross references and admissible values. Every
//! statement keeps the [`Pos`] (line, column; both 1-based) of its keyword so
//! that later stages (the FE model's geometry checks) can point at it.
//! [`write`] turns a [`Deck`] back into deck text that parses to the same deck.
//!
//! This module does no numerics beyond the checks the spec asks for.

mod lexer;
mod statements;
mod validate;
mod writer;

use std::fmt;

pub use writer::{format_number, write};

/// A source position: 1-based line and column (columns count characters).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Pos {
    pub line: u32,
    pub column: u32,
}

impl Pos {
    pub fn new(line: u32, column: u32) -> Self {
        Pos { line, column }
    }
}

impl fmt::Display for Pos {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.line, self.column)
    }
}

/// A deck error at a source position. The caller prefixes the file name,
/// e.g. `format!("{file}:{err}")` gives `file:line:column: message`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct DeckError {
    pub line: u32,
    pub column: u32,
    pub message: String,
}

impl DeckError {
    pub fn new(pos: Pos, message: impl Into<String>) -> Self {
        DeckError {
            line: pos.line,
            column: pos.column,
            message: message.into(),
        }
    }
    pub fn pos(&self) -> Pos {
        Pos::new(self.line, self.column)
    }
}

impl fmt::Display for DeckError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.line, self.column, self.message)
    }
}

impl std::error::Error for DeckError {}

/// `analysis plane` (frame in the global x–z plane; DOFs x, z, ry) or
/// `analysis space` (6 DOF per node). Default `space`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Analysis {
    Plane,
    #[default]
    Space,
}

impl Analysis {
    pub fn name(self) -> &'static str {
        match self {
            Analysis::Plane => "plane",
            Analysis::Space => "space",
        }
    }
    /// The nodal DOFs of this analysis, in equation order.
    pub fn dofs(self) -> &'static [DeckDof] {
        match self {
            Analysis::Plane => &[DeckDof::X, DeckDof::Z, DeckDof::Ry],
            Analysis::Space => &[
                DeckDof::X,
                DeckDof::Y,
                DeckDof::Z,
                DeckDof::Rx,
                DeckDof::Ry,
                DeckDof::Rz,
            ],
        }
    }
    pub fn has_dof(self, dof: DeckDof) -> bool {
        self.dofs().contains(&dof)
    }
}

/// A nodal DOF name of the deck: `x y z rx ry rz`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DeckDof {
    X,
    Y,
    Z,
    Rx,
    Ry,
    Rz,
}

impl DeckDof {
    pub const ALL: [DeckDof; 6] = [
        DeckDof::X,
        DeckDof::Y,
        DeckDof::Z,
        DeckDof::Rx,
        DeckDof::Ry,
        DeckDof::Rz,
    ];
    pub fn name(self) -> &'static str {
        match self {
            DeckDof::X => "x",
            DeckDof::Y => "y",
            DeckDof::Z => "z",
            DeckDof::Rx => "rx",
            DeckDof::Ry => "ry",
            DeckDof::Rz => "rz",
        }
    }
    pub fn from_name(s: &str) -> Option<DeckDof> {
        DeckDof::ALL.into_iter().find(|d| d.name() == s)
    }
    /// 0..6 in the order x y z rx ry rz.
    pub fn index(self) -> usize {
        self as usize
    }
}

/// `title TEXT…` (several title lines are allowed; an extension).
#[derive(Clone, Debug, PartialEq)]
pub struct Title {
    pub text: String,
    pub pos: Pos,
}

/// `material NAME E=… rho=… [nu=…] [G=…]` (Pa, kg/m³).
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    pub name: String,
    pub e: f64,
    pub rho: f64,
    pub nu: Option<f64>,
    pub g: Option<f64>,
    pub pos: Pos,
}

impl Material {
    /// Poisson's ratio, default 0.3.
    pub fn nu(&self) -> f64 {
        self.nu.unwrap_or(0.3)
    }
    /// Shear modulus: `G` if given, else E/(2(1+ν)).
    pub fn shear_modulus(&self) -> f64 {
        self.g.unwrap_or(self.e / (2.0 * (1.0 + self.nu())))
    }
}

/// Default shear coefficient κ of Timoshenko beams.
pub const DEFAULT_SHEAR_COEFFICIENT: f64 = 5.0 / 6.0;

/// `section NAME A=… Iy=… [Iz=…] [J=…] [ky=…] [kz=…]` (m², m⁴).
#[derive(Clone, Debug, PartialEq)]
pub struct Section {
    pub name: String,
    pub a: f64,
    pub iy: f64,
    pub iz: Option<f64>,
    pub j: Option<f64>,
    pub ky: Option<f64>,
    pub kz: Option<f64>,
    pub pos: Pos,
}

impl Section {
    /// Shear coefficient for bending about local z (shear along y), default 5/6.
    pub fn ky(&self) -> f64 {
        self.ky.unwrap_or(DEFAULT_SHEAR_COEFFICIENT)
    }
    /// Shear coefficient for bending about local y (shear along z), default 5/6.
    pub fn kz(&self) -> f64 {
        self.kz.unwrap_or(DEFAULT_SHEAR_COEFFICIENT)
    }
}

/// `node ID X Y Z` (m).
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    pub id: u32,
    pub xyz: [f64; 3],
    pub pos: Pos,
}

/// Beam theory of a `beam` (`theory=eb|timoshenko`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Theory {
    #[default]
    EulerBernoulli,
    Timoshenko,
}

impl Theory {
    pub fn name(self) -> &'static str {
        match self {
            Theory::EulerBernoulli => "eb",
            Theory::Timoshenko => "timoshenko",
        }
    }
}

/// The `orient=VX,VY,VZ` vector of a beam and where it was written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Orient {
    pub vector: [f64; 3],
    pub pos: Pos,
}

/// `beam ID N1 N2 MATERIAL SECTION [orient=VX,VY,VZ] [theory=eb|timoshenko]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Beam {
    pub id: u32,
    pub nodes: [u32; 2],
    pub material: String,
    pub section: String,
    pub orient: Option<Orient>,
    /// `None` when not written (then Euler–Bernoulli).
    pub theory: Option<Theory>,
    pub pos: Pos,
}

impl Beam {
    pub fn theory(&self) -> Theory {
        self.theory.unwrap_or_default()
    }
}

/// `mass ID NODE m=… [Ixx=…] [Iyy=…] [Izz=…]` (kg, kg·m²).
#[derive(Clone, Debug, PartialEq)]
pub struct Mass {
    pub id: u32,
    pub node: u32,
    pub m: f64,
    pub ixx: Option<f64>,
    pub iyy: Option<f64>,
    pub izz: Option<f64>,
    pub pos: Pos,
}

/// `spring ID NODE DOF k=… [to=NODE2]` (N/m or N·m/rad).
#[derive(Clone, Debug, PartialEq)]
pub struct Spring {
    pub id: u32,
    pub node: u32,
    pub dof: DeckDof,
    pub k: f64,
    /// Second node; `None` means grounded.
    pub to: Option<u32>,
    pub pos: Pos,
}

/// DOFS of a `fix` statement.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum FixDofs {
    All,
    List(Vec<DeckDof>),
}

/// `fix NODE DOFS`.
#[derive(Clone, Debug, PartialEq)]
pub struct Fix {
    pub node: u32,
    pub dofs: FixDofs,
    pub pos: Pos,
}

/// The global damping model of `damping …`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DampingModel {
    Modal { zeta: f64 },
    Rayleigh { alpha: f64, beta: f64 },
    Hysteretic { eta: f64 },
}

/// A `damping` statement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DampingStatement {
    pub model: DampingModel,
    pub pos: Pos,
}

/// The quantity an updating parameter changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Quantity {
    E,
    G,
    Rho,
    A,
    Iy,
    Iz,
    J,
    M,
    K,
}

impl Quantity {
    pub const ALL: [Quantity; 9] = [
        Quantity::E,
        Quantity::G,
        Quantity::Rho,
        Quantity::A,
        Quantity::Iy,
        Quantity::Iz,
        Quantity::J,
        Quantity::M,
        Quantity::K,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Quantity::E => "E",
            Quantity::G => "G",
            Quantity::Rho => "rho",
            Quantity::A => "A",
            Quantity::Iy => "Iy",
            Quantity::Iz => "Iz",
            Quantity::J => "J",
            Quantity::M => "m",
            Quantity::K => "k",
        }
    }
    pub fn from_name(s: &str) -> Option<Quantity> {
        Quantity::ALL.into_iter().find(|q| q.name() == s)
    }
    /// Which kind of statement the IDs of a `param` on this quantity refer to.
    pub fn target(self) -> Target {
        match self {
            Quantity::M => Target::Mass,
            Quantity::K => Target::Spring,
            _ => Target::Beam,
        }
    }
    /// True for the material quantities (E, G, rho).
    pub fn is_material(self) -> bool {
        matches!(self, Quantity::E | Quantity::G | Quantity::Rho)
    }
    /// True for the section quantities (A, Iy, Iz, J).
    pub fn is_section(self) -> bool {
        matches!(
            self,
            Quantity::A | Quantity::Iy | Quantity::Iz | Quantity::J
        )
    }
}

/// The statements whose IDs a `param` lists.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Target {
    Beam,
    Mass,
    Spring,
}

impl Target {
    pub fn name(self) -> &'static str {
        match self {
            Target::Beam => "beam",
            Target::Mass => "mass",
            Target::Spring => "spring",
        }
    }
}

/// An inclusive ID range `a-b` (a single ID is `a-a`) and where it was written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct IdRange {
    pub first: u32,
    pub last: u32,
    pub pos: Pos,
}

/// `param NAME QTY IDS`: relative change p of QTY on the listed IDs.
#[derive(Clone, Debug, PartialEq)]
pub struct Param {
    pub name: String,
    pub quantity: Quantity,
    pub ids: Vec<IdRange>,
    /// `min=P`: hard lower bound on the relative change p (`None`: the
    /// physical bound 1 + p > 0).
    pub min: Option<f64>,
    /// `max=P`: hard upper bound on p (`None`: no bound).
    pub max: Option<f64>,
    /// `sd=S`: one standard deviation of a zero-mean prior on p (`None`: no
    /// prior).
    pub sd: Option<f64>,
    /// Where the prior is centred, as a relative change of this deck's
    /// value: 0 as written; a deck updated in memory by v moves it to the
    /// written value, (1 + c)/(1 + v) − 1 (the deck format has no word for
    /// it, so a written deck loses it).
    pub prior_centre: f64,
    pub pos: Pos,
}

impl Param {
    /// The listed IDs in the order written (ranges expanded).
    pub fn ids(&self) -> impl Iterator<Item = u32> + '_ {
        self.ids.iter().flat_map(|r| r.first..=r.last)
    }
    /// Whether `id` is listed.
    pub fn contains(&self, id: u32) -> bool {
        self.ids.iter().any(|r| r.first <= id && id <= r.last)
    }
}

/// `sensor TESTNODE NODE`.
#[derive(Clone, Debug, PartialEq)]
pub struct Sensor {
    pub test_node: u32,
    pub node: u32,
    pub pos: Pos,
}

/// A parsed deck: every statement with its source position, in source order
/// within each kind.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Deck {
    pub titles: Vec<Title>,
    pub analysis: Analysis,
    /// Where `analysis` was written (`None`: defaulted to `space`).
    pub analysis_pos: Option<Pos>,
    pub materials: Vec<Material>,
    pub sections: Vec<Section>,
    pub nodes: Vec<Node>,
    pub beams: Vec<Beam>,
    pub masses: Vec<Mass>,
    pub springs: Vec<Spring>,
    pub fixes: Vec<Fix>,
    pub damping: Option<DampingStatement>,
    pub params: Vec<Param>,
    pub sensors: Vec<Sensor>,
}

/// Most characters of the title that [`Deck::title`] gives.
pub const TITLE_ECHO_CHARS: usize = 1000;

impl Deck {
    /// The title lines joined with newlines (empty if none), as reports echo
    /// it: at most [`TITLE_ECHO_CHARS`] characters (a 200 MB title line must not
    /// become a gigabyte of reports); the rest is said, not copied.
    pub fn title(&self) -> String {
        let full = self
            .titles
            .iter()
            .map(|t| t.text.as_str())
            .collect::<Vec<_>>()
            .join("\n");
        match full.char_indices().nth(TITLE_ECHO_CHARS) {
            None => full,
            Some((cut, _)) => {
                let rest = full[cut..].chars().count();
                format!("{} … ({rest} more characters)", &full[..cut])
            }
        }
    }
    pub fn material(&self, name: &str) -> Option<&Material> {
        self.materials.iter().find(|m| m.name == name)
    }
    pub fn section(&self, name: &str) -> Option<&Section> {
        self.sections.iter().find(|s| s.name == name)
    }
    pub fn node(&self, id: u32) -> Option<&Node> {
        self.nodes.iter().find(|n| n.id == id)
    }
    pub fn beam(&self, id: u32) -> Option<&Beam> {
        self.beams.iter().find(|b| b.id == id)
    }
    pub fn param(&self, name: &str) -> Option<&Param> {
        self.params.iter().find(|p| p.name == name)
    }

    /// The semantic checks of the spec (IDs, references, admissible values,
    /// analysis restrictions), returning the first error in source order.
    /// [`parse`] calls it; call it again after editing a deck in code.
    pub fn validate(&self) -> Result<(), DeckError> {
        validate::validate(self)
    }
}

/// Parse deck text: syntax, then [`Deck::validate`]. The first error in
/// source order is returned.
pub fn parse(text: &str) -> Result<Deck, DeckError> {
    // A UTF-8 byte-order mark is not part of the first line's text.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    // Line ends of CR alone (classic Mac OS) are line ends too.
    let normalised;
    let text = if !text.contains('\n') && text.contains('\r') {
        normalised = text.replace('\r', "\n");
        normalised.as_str()
    } else {
        text
    };
    check_characters(text)?;
    let deck = statements::parse_statements(text)?;
    validate::first_error(&deck, Some(text))?;
    Ok(deck)
}

/// Characters that look like spaces or are invisible, outside comments and
/// titles, named where they are (a NUL byte, a non-breaking space pasted from a
/// document, a stray control character), rather than reported as a missing field.
fn check_characters(text: &str) -> Result<(), DeckError> {
    for (i, line) in text.split('\n').enumerate() {
        let code = lexer::strip_comment(line);
        if code.trim_start().starts_with("title") {
            continue;
        }
        for (col, c) in code.chars().enumerate() {
            let what = match c {
                '\t' | '\r' | ' ' => continue,
                '\0' => "a NUL byte (is this a binary file?)".to_string(),
                '\u{a0}' => "a non-breaking space (U+00A0): use a plain space".to_string(),
                c if c.is_whitespace() => {
                    format!("the space character U+{:04X}: use a plain space", c as u32)
                }
                c if c.is_control() => format!("the control character U+{:04X}", c as u32),
                _ => continue,
            };
            let line_no = u32::try_from(i + 1).unwrap_or(u32::MAX);
            let col = u32::try_from(col + 1).unwrap_or(u32::MAX);
            return Err(DeckError::new(
                Pos::new(line_no, col),
                format!("{what} where tokens are separated by spaces or tabs"),
            ));
        }
    }
    Ok(())
}
