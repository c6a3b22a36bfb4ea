//! The dictionary of physical model extensions. Each hypothesis is a small
//! change of the deck with at most one free parameter (SI units), fitted on
//! a log scale within physical bounds; damping is a nuisance model fitted
//! along with every hypothesis (see [`damping`]).

pub mod damping;
pub mod joint;
pub mod masses;
pub mod prior;
pub mod shear;
pub mod springs;

use frfup_parsers::deck::{
    Deck, DeckDof, FixDofs, IdRange, Mass, Node, Param, Pos, Quantity, Spring, Theory,
};

/// The physics classes, named as in `diagnosis.json`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Physics {
    Damping,
    SensorMass,
    SupportFlexibility,
    JointFlexibility,
    Suspension,
    ShearDeformation,
    AddedMass,
    /// Data errors, found before any physics ([`crate::diagnosis::data_errors`]).
    ReversedChannel,
    SwappedChannels,
    ChannelScale,
    DeadChannel,
}

impl Physics {
    pub fn name(self) -> &'static str {
        match self {
            Physics::Damping => "damping",
            Physics::SensorMass => "sensor-mass",
            Physics::SupportFlexibility => "support-flexibility",
            Physics::JointFlexibility => "joint-flexibility",
            Physics::Suspension => "suspension",
            Physics::ShearDeformation => "shear-deformation",
            Physics::AddedMass => "added-mass",
            Physics::ReversedChannel => "reversed-channel",
            Physics::SwappedChannels => "swapped-channels",
            Physics::ChannelScale => "channel-scale",
            Physics::DeadChannel => "dead-channel",
        }
    }

    /// A data error (a channel's record), not a physical model extension.
    pub fn is_data_error(self) -> bool {
        matches!(
            self,
            Physics::ReversedChannel
                | Physics::SwappedChannels
                | Physics::ChannelScale
                | Physics::DeadChannel
        )
    }
}

/// The free parameter of a hypothesis: name (`m` in kg, `k` in N/m or
/// N·m/rad), bounds and a probe value for screening.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamSpec {
    pub name: &'static str,
    pub lo: f64,
    pub hi: f64,
    pub probe: f64,
    pub unit: &'static str,
}

/// What a hypothesis changes in the deck.
#[derive(Clone, Debug, PartialEq)]
pub enum Extension {
    /// A lumped mass m (kg) at each node.
    Masses { nodes: Vec<u32> },
    /// A grounded spring k on `dof` at each node; `unfix` frees a fixed DOF first.
    GroundSprings {
        nodes: Vec<u32>,
        dof: DeckDof,
        unfix: bool,
    },
    /// Node split: `moved` beams go to a copy of `node`, reconnected by
    /// springs, k on `soft` and `rigid` stiffness on the other DOFs.
    Joint {
        node: u32,
        moved: Vec<u32>,
        soft: DeckDof,
        rigid: Vec<(DeckDof, f64)>,
    },
    /// Timoshenko theory for these beams (no free parameter).
    Timoshenko { beams: Vec<u32> },
}

/// A candidate model extension at a location.
#[derive(Clone, Debug, PartialEq)]
pub struct Hypothesis {
    pub physics: Physics,
    pub nodes: Vec<u32>,
    pub dofs: Vec<String>,
    pub param: Option<ParamSpec>,
    pub extension: Extension,
    /// Short description, e.g. `support-flexibility at node 1 (ry)`.
    pub label: String,
}

impl Hypothesis {
    /// The deck with this extension at parameter value `value` (SI units).
    pub fn apply(&self, deck: &Deck, value: Option<f64>) -> Deck {
        let v = value.unwrap_or(0.0);
        let mut d = deck.clone();
        match &self.extension {
            Extension::Masses { nodes } => {
                for &n in nodes {
                    let id = d.masses.iter().map(|m| m.id).max().unwrap_or(0) + 1;
                    d.masses.push(Mass {
                        id,
                        node: n,
                        m: v,
                        ixx: None,
                        iyy: None,
                        izz: None,
                        pos: Pos::default(),
                    });
                }
            }
            Extension::GroundSprings { nodes, dof, unfix } => {
                for &n in nodes {
                    if *unfix {
                        unfix_dof(&mut d, n, *dof);
                    }
                    push_spring(&mut d, n, *dof, v, None);
                }
            }
            Extension::Joint {
                node,
                moved,
                soft,
                rigid,
            } => {
                let new_id = d.nodes.iter().map(|n| n.id).max().unwrap_or(0) + 1;
                let xyz = d.node(*node).map(|n| n.xyz).unwrap_or([0.0; 3]);
                d.nodes.push(Node {
                    id: new_id,
                    xyz,
                    pos: Pos::default(),
                });
                for b in d.beams.iter_mut().filter(|b| moved.contains(&b.id)) {
                    for n in b.nodes.iter_mut() {
                        if *n == *node {
                            *n = new_id;
                        }
                    }
                }
                push_spring(&mut d, *node, *soft, v, Some(new_id));
                for &(dof, k) in rigid {
                    push_spring(&mut d, *node, dof, k, Some(new_id));
                }
            }
            Extension::Timoshenko { beams } => {
                for b in d.beams.iter_mut().filter(|b| beams.contains(&b.id)) {
                    b.theory = Some(Theory::Timoshenko);
                }
            }
        }
        d
    }
}

impl Hypothesis {
    /// This added mass or suspension spring set with its node `from` moved
    /// to `to` (same parameter, same direction); `None` for the other
    /// classes (a sensor mass sits on the sensors, a support's or a
    /// joint's spring at its support or junction) or when `from` is not
    /// one of its nodes or `to` already is.
    pub fn moved(&self, from: u32, to: u32) -> Option<Hypothesis> {
        if !self.nodes.contains(&from) || self.nodes.contains(&to) {
            return None;
        }
        let swap = |nodes: &[u32]| -> Vec<u32> {
            nodes
                .iter()
                .map(|&n| if n == from { to } else { n })
                .collect()
        };
        let nodes = swap(&self.nodes);
        let (extension, label) = match (&self.physics, &self.extension) {
            (Physics::AddedMass, Extension::Masses { .. }) => (
                Extension::Masses {
                    nodes: nodes.clone(),
                },
                format!("added-mass at node {to}"),
            ),
            (
                Physics::Suspension,
                Extension::GroundSprings {
                    dof, unfix: false, ..
                },
            ) => {
                let list: Vec<String> = nodes.iter().map(|n| n.to_string()).collect();
                (
                    Extension::GroundSprings {
                        nodes: nodes.clone(),
                        dof: *dof,
                        unfix: false,
                    },
                    format!(
                        "suspension springs ({}) at node(s) {}",
                        dof.name(),
                        list.join(", ")
                    ),
                )
            }
            _ => return None,
        };
        Some(Hypothesis {
            nodes,
            extension,
            label,
            ..self.clone()
        })
    }

    /// [`Hypothesis::apply`] with the extension's value a parameter of the
    /// deck named `name` (`param NAME m|k IDS` on the masses or springs it
    /// adds; of a joint, its soft spring only), so that an update fits it
    /// along with the deck's own parameters: its value is then
    /// (1 + p̄)·`value`. `None` when the hypothesis has no value.
    pub fn apply_as_parameter(&self, deck: &Deck, value: Option<f64>, name: &str) -> Option<Deck> {
        value?;
        self.param.as_ref()?;
        let mut d = self.apply(deck, value);
        let (quantity, ids): (Quantity, Vec<u32>) = match &self.extension {
            Extension::Masses { .. } => (Quantity::M, added_ids(&deck.masses, &d.masses, |m| m.id)),
            Extension::GroundSprings { .. } => {
                (Quantity::K, added_ids(&deck.springs, &d.springs, |s| s.id))
            }
            Extension::Joint { .. } => {
                let ids = added_ids(&deck.springs, &d.springs, |s| s.id);
                (Quantity::K, ids.into_iter().take(1).collect())
            }
            Extension::Timoshenko { .. } => return None,
        };
        if ids.is_empty() {
            return None;
        }
        d.params.push(Param {
            name: name.to_string(),
            quantity,
            ids: ids
                .iter()
                .map(|&id| IdRange {
                    first: id,
                    last: id,
                    pos: Pos::default(),
                })
                .collect(),
            min: None,
            max: None,
            sd: None,
            prior_centre: 0.0,
            pos: Pos::default(),
        });
        Some(d)
    }
}

/// The IDs of `after`'s elements that `before` does not have.
fn added_ids<T>(before: &[T], after: &[T], id: impl Fn(&T) -> u32) -> Vec<u32> {
    let old: std::collections::BTreeSet<u32> = before.iter().map(&id).collect();
    after.iter().map(id).filter(|i| !old.contains(i)).collect()
}

fn push_spring(d: &mut Deck, node: u32, dof: DeckDof, k: f64, to: Option<u32>) {
    let id = d.springs.iter().map(|s| s.id).max().unwrap_or(0) + 1;
    d.springs.push(Spring {
        id,
        node,
        dof,
        k,
        to,
        pos: Pos::default(),
    });
}

/// Remove `dof` from every `fix` of `node` (an emptied `fix` is dropped).
fn unfix_dof(d: &mut Deck, node: u32, dof: DeckDof) {
    let all: Vec<DeckDof> = d.analysis.dofs().to_vec();
    for f in d.fixes.iter_mut().filter(|f| f.node == node) {
        let list = match &f.dofs {
            FixDofs::All => all.clone(),
            FixDofs::List(l) => l.clone(),
        };
        f.dofs = FixDofs::List(list.into_iter().filter(|x| *x != dof).collect());
    }
    d.fixes
        .retain(|f| !matches!(&f.dofs, FixDofs::List(l) if l.is_empty()));
}

/// What the generators need to know about the model and the test.
#[derive(Clone, Debug)]
pub struct Context<'a> {
    pub deck: &'a Deck,
    /// FE nodes carrying a measured channel (ascending, unique).
    pub sensor_nodes: Vec<u32>,
    /// Total mass of the model (kg): beams ρAL plus lumped masses.
    pub total_mass: f64,
    /// True when the deck fixes no DOF.
    pub free_free: bool,
    /// First elastic natural frequency of the current model (rad/s).
    pub first_elastic_omega: f64,
}

impl Context<'_> {
    /// Nodes reached by at least one beam (ascending).
    pub fn beam_nodes(&self) -> Vec<u32> {
        let mut v: Vec<u32> = self.deck.beams.iter().flat_map(|b| b.nodes).collect();
        v.sort_unstable();
        v.dedup();
        v
    }
}

/// Total mass of a deck (kg): Σ ρAL over beams plus the lumped masses.
pub fn total_mass(deck: &Deck) -> f64 {
    let mut m: f64 = deck.masses.iter().map(|m| m.m).sum();
    for b in &deck.beams {
        let (Some(mat), Some(sec)) = (deck.material(&b.material), deck.section(&b.section)) else {
            continue;
        };
        m += mat.rho * sec.a * beam_length(deck, b.nodes);
    }
    m
}

fn beam_length(deck: &Deck, nodes: [u32; 2]) -> f64 {
    match (deck.node(nodes[0]), deck.node(nodes[1])) {
        (Some(a), Some(b)) => (0..3)
            .map(|i| (a.xyz[i] - b.xyz[i]).powi(2))
            .sum::<f64>()
            .sqrt(),
        _ => 0.0,
    }
}

/// Stiffness scale (N/m or N·m/rad) of the beams meeting at `node` for `dof`:
/// Σ 12EI/L³ (translations) or Σ max(4EI/L, GJ/L) (rotations), I the larger
/// second moment.
pub fn stiffness_scale(deck: &Deck, node: u32, dof: DeckDof) -> f64 {
    let rot = matches!(dof, DeckDof::Rx | DeckDof::Ry | DeckDof::Rz);
    let mut k = 0.0;
    for b in deck.beams.iter().filter(|b| b.nodes.contains(&node)) {
        let (Some(mat), Some(sec)) = (deck.material(&b.material), deck.section(&b.section)) else {
            continue;
        };
        let l = beam_length(deck, b.nodes);
        if l <= 0.0 {
            continue;
        }
        let i = sec.iy.max(sec.iz.unwrap_or(0.0));
        k += if rot {
            (4.0 * mat.e * i / l).max(mat.shear_modulus() * sec.j.unwrap_or(0.0) / l)
        } else {
            12.0 * mat.e * i / l.powi(3)
        };
    }
    if k > 0.0 {
        k
    } else {
        1.0
    }
}

/// Two beams from a node whose directions have a cosine below minus this
/// run straight on through it (one member); otherwise the node is a corner.
pub const STRAIGHT_ON: f64 = 0.95;

/// Unit vector of a beam from `node` to its other end.
pub fn beam_direction(
    deck: &Deck,
    beam: &frfup_parsers::deck::Beam,
    node: u32,
) -> Option<[f64; 3]> {
    let other = if beam.nodes[0] == node {
        beam.nodes[1]
    } else {
        beam.nodes[0]
    };
    let a = deck.node(node)?.xyz;
    let b = deck.node(other)?.xyz;
    let v = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    (n > 0.0).then(|| [v[0] / n, v[1] / n, v[2] / n])
}
