//! Shared helper of the test modules that simulate "measured" campaigns.
#![allow(dead_code)]

use frfup::simulate::{Band, Campaign, NodeDirection, Sensors};
use frfup::testdata::FrfKind;

/// Noise-free accelerance at z of `nodes` for a unit force at `input` z.
pub fn z_campaign(input: u32, nodes: &[u32], band: Band) -> Campaign {
    let z = |node: u32| NodeDirection { node, direction: 3 };
    Campaign {
        input: z(input),
        band,
        lines_hz: None,
        response: None,
        output: FrfKind::Accelerance,
        sensors: Sensors::List(nodes.iter().map(|&n| z(n)).collect()),
        noise: 0.0,
        seed: 1,
    }
}

/// `count` lines from 0 to `end_hz`.
pub fn band(end_hz: f64, count: usize) -> Band {
    Band {
        start_hz: 0.0,
        end_hz,
        count,
    }
}
