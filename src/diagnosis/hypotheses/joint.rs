//! `joint-flexibility`: at a node where members meet at an angle, the branch
//! member(s) are moved to a copy of the node and reconnected by springs:
//! k (N·m/rad) on one rotation, 10³ × the local stiffness scale on the others.

use frfup_parsers::deck::DeckDof;

use super::{
    beam_direction, stiffness_scale, Context, Extension, Hypothesis, ParamSpec, Physics,
    STRAIGHT_ON,
};

/// One hypothesis per joint node and rotational DOF.
pub fn joint_flexibility(ctx: &Context) -> Vec<Hypothesis> {
    let deck = ctx.deck;
    let mut out = Vec::new();
    for n in ctx.beam_nodes() {
        if deck.fixes.iter().any(|f| f.node == n) {
            continue;
        }
        let beams: Vec<_> = deck.beams.iter().filter(|b| b.nodes.contains(&n)).collect();
        if beams.len() < 2 {
            continue;
        }
        let dirs: Vec<[f64; 3]> = beams
            .iter()
            .map(|b| beam_direction(deck, b, n).unwrap_or([1.0, 0.0, 0.0]))
            .collect();
        // The main member: the first beam and any beam running straight on from it.
        let main: Vec<usize> = (0..beams.len())
            .filter(|&i| {
                i == 0 || {
                    let d = dirs[i];
                    let c = d[0] * dirs[0][0] + d[1] * dirs[0][1] + d[2] * dirs[0][2];
                    c < -STRAIGHT_ON
                }
            })
            .collect();
        let moved: Vec<u32> = (0..beams.len())
            .filter(|i| !main.contains(i))
            .map(|i| beams[i].id)
            .collect();
        if moved.is_empty() {
            continue;
        }
        let all: Vec<DeckDof> = deck.analysis.dofs().to_vec();
        for soft in all
            .iter()
            .copied()
            .filter(|d| matches!(d, DeckDof::Rx | DeckDof::Ry | DeckDof::Rz))
        {
            let k = stiffness_scale(deck, n, soft);
            let rigid = all
                .iter()
                .copied()
                .filter(|d| *d != soft)
                .map(|d| (d, 1e3 * stiffness_scale(deck, n, d)))
                .collect();
            out.push(Hypothesis {
                physics: Physics::JointFlexibility,
                nodes: vec![n],
                dofs: vec![soft.name().to_string()],
                param: Some(ParamSpec {
                    name: "k",
                    lo: 1e-4 * k,
                    hi: 1e2 * k,
                    probe: 0.3 * k,
                    unit: "N·m/rad",
                }),
                extension: Extension::Joint {
                    node: n,
                    moved: moved.clone(),
                    soft,
                    rigid,
                },
                label: format!("joint-flexibility at node {n} ({})", soft.name()),
            });
        }
    }
    out
}
