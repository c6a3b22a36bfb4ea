//! `shear-deformation`: Timoshenko instead of Euler–Bernoulli theory for the
//! beams of one section (one member family), or for all beams. No free
//! parameter: only the damping is refitted.

use frfup_parsers::deck::Theory;

use super::{Context, Extension, Hypothesis, Physics};

pub fn shear_deformation(ctx: &Context) -> Vec<Hypothesis> {
    let deck = ctx.deck;
    let eb: Vec<_> = deck
        .beams
        .iter()
        .filter(|b| b.theory() == Theory::EulerBernoulli)
        .collect();
    if eb.is_empty() {
        return Vec::new();
    }
    let mut sections: Vec<&str> = eb.iter().map(|b| b.section.as_str()).collect();
    sections.sort_unstable();
    sections.dedup();
    let mut out = Vec::new();
    let mut groups: Vec<(String, Vec<u32>)> = Vec::new();
    if sections.len() > 1 {
        for s in &sections {
            groups.push((
                format!("section {s}"),
                eb.iter()
                    .filter(|b| b.section == *s)
                    .map(|b| b.id)
                    .collect(),
            ));
        }
    }
    groups.push(("all beams".into(), eb.iter().map(|b| b.id).collect()));
    for (what, beams) in groups {
        let mut nodes: Vec<u32> = deck
            .beams
            .iter()
            .filter(|b| beams.contains(&b.id))
            .flat_map(|b| b.nodes)
            .collect();
        nodes.sort_unstable();
        nodes.dedup();
        out.push(Hypothesis {
            physics: Physics::ShearDeformation,
            nodes,
            dofs: vec![],
            param: None,
            label: format!("shear-deformation (Timoshenko) for {what}"),
            extension: Extension::Timoshenko { beams },
        });
    }
    out
}
