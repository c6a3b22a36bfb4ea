//! `support-flexibility` (a fixed DOF of a support node freed and held by a
//! spring k) and `suspension` (grounded springs k, same value at each node,
//! on a free-free model whose test shows rigid-body modes above 0 Hz).

use frfup_parsers::deck::{DeckDof, FixDofs};

use super::{stiffness_scale, Context, Extension, Hypothesis, ParamSpec, Physics};

/// One hypothesis per fixed DOF of every support node.
pub fn support_flexibility(ctx: &Context) -> Vec<Hypothesis> {
    let deck = ctx.deck;
    let mut out = Vec::new();
    let mut seen = Vec::new();
    for f in &deck.fixes {
        let dofs: Vec<DeckDof> = match &f.dofs {
            FixDofs::All => deck.analysis.dofs().to_vec(),
            FixDofs::List(l) => l.clone(),
        };
        for dof in dofs {
            if seen.contains(&(f.node, dof)) || !deck.analysis.has_dof(dof) {
                continue;
            }
            seen.push((f.node, dof));
            let k = stiffness_scale(deck, f.node, dof);
            let unit = if matches!(dof, DeckDof::Rx | DeckDof::Ry | DeckDof::Rz) {
                "N·m/rad"
            } else {
                "N/m"
            };
            out.push(Hypothesis {
                physics: Physics::SupportFlexibility,
                nodes: vec![f.node],
                dofs: vec![dof.name().to_string()],
                param: Some(ParamSpec {
                    name: "k",
                    lo: 1e-4 * k,
                    hi: 1e3 * k,
                    probe: k,
                    unit,
                }),
                extension: Extension::GroundSprings {
                    nodes: vec![f.node],
                    dof,
                    unfix: true,
                },
                label: format!("support-flexibility at node {} ({})", f.node, dof.name()),
            });
        }
    }
    out
}

/// Suspension spring parameter for `n` springs: bounds from the rigid-body
/// frequency they would give, 0.3 %–100 % of the first elastic frequency.
fn suspension_spec(ctx: &Context, n: usize) -> ParamSpec {
    let kw = ctx.total_mass * ctx.first_elastic_omega.powi(2) / n.max(1) as f64;
    ParamSpec {
        name: "k",
        lo: 1e-5 * kw,
        hi: 1.0 * kw,
        probe: 0.01 * kw,
        unit: "N/m",
    }
}

/// Single grounded springs on each translational DOF of each beam node
/// (free-free decks only): the screening set.
pub fn suspension_single(ctx: &Context) -> Vec<Hypothesis> {
    if !ctx.free_free {
        return Vec::new();
    }
    let mut out = Vec::new();
    for dof in [DeckDof::X, DeckDof::Y, DeckDof::Z] {
        if !ctx.deck.analysis.has_dof(dof) {
            continue;
        }
        for n in ctx.beam_nodes() {
            out.push(suspension(ctx, vec![n], dof));
        }
    }
    out
}

/// Springs with the same k at each of `nodes` on `dof`.
pub fn suspension(ctx: &Context, nodes: Vec<u32>, dof: DeckDof) -> Hypothesis {
    let list = nodes
        .iter()
        .map(|n| n.to_string())
        .collect::<Vec<_>>()
        .join(", ");
    Hypothesis {
        physics: Physics::Suspension,
        param: Some(suspension_spec(ctx, nodes.len())),
        dofs: vec![dof.name().to_string()],
        extension: Extension::GroundSprings {
            nodes: nodes.clone(),
            dof,
            unfix: false,
        },
        label: format!("suspension springs ({}) at node(s) {list}", dof.name()),
        nodes,
    }
}
