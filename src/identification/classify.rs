//! Rigid-body and suspension modes told from elastic ones.
//!
//! A free or softly suspended structure has up to six modes far below its
//! first elastic mode (a suspension is designed to put them there, 1/5 to
//! 1/10 of it). The lowest modes, up to six of them, are marked rigid-body
//! when the next mode lies at least `RIGID_GAP` times higher. Above 6.3
//! because a cantilever's second mode is 6.27 times its first (the first is
//! elastic).

use super::Mode;

/// Least ratio between the first elastic mode and the highest rigid-body one.
pub const RIGID_GAP: f64 = 6.5;

/// What a mode is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ModeKind {
    Elastic,
    /// Rigid-body or suspension mode.
    RigidBody,
}

impl ModeKind {
    pub fn name(self) -> &'static str {
        match self {
            ModeKind::Elastic => "elastic",
            ModeKind::RigidBody => "rigid-body",
        }
    }
}

/// Marks the rigid-body modes of `modes` (ascending in frequency).
pub fn mark_rigid_body(modes: &mut [Mode]) {
    let limit = modes.len().saturating_sub(1).min(6);
    let gap = (0..limit).find(|&k| modes[k + 1].frequency_hz >= RIGID_GAP * modes[k].frequency_hz);
    for (k, mode) in modes.iter_mut().enumerate() {
        mode.kind = match gap {
            Some(g) if k <= g => ModeKind::RigidBody,
            _ => ModeKind::Elastic,
        };
    }
}
