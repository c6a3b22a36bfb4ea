//! The test with its data errors undone: reversed channels turned round,
//! scaled channels divided by their factor, swapped channels exchanged and
//! dead channels dropped. The rest of the diagnosis runs on this.

use super::super::data::TestData;
use super::{DataError, DataErrorKind};
use crate::testdata::MeasuredFrfs;

/// Indices into `test.channels` of channel `c` of `data` (its response DOF,
/// driven at `data`'s excitation).
fn records(test: &MeasuredFrfs, data: &TestData, c: usize) -> Vec<usize> {
    let ch = &data.channels[c];
    test.channels
        .iter()
        .enumerate()
        .filter(|(_, r)| {
            r.response_node == i64::from(ch.node)
                && r.response_direction == ch.direction
                && r.reference_node == i64::from(data.input.0)
                && r.reference_direction == data.input.1
        })
        .map(|(i, _)| i)
        .collect()
}

/// `test` (the campaign `data` was prepared from) with `errors` undone.
pub fn corrected(test: &MeasuredFrfs, data: &TestData, errors: &[DataError]) -> MeasuredFrfs {
    let mut out = test.clone();
    let mut drop = vec![false; test.channels.len()];
    for e in errors {
        let mine = records(test, data, e.channel);
        match &e.kind {
            DataErrorKind::Dead { .. } => mine.iter().for_each(|&i| drop[i] = true),
            DataErrorKind::Reversed { .. } => {
                for &i in &mine {
                    out.channels[i].values.iter_mut().for_each(|v| *v = -*v);
                }
            }
            DataErrorKind::Scale { factor, .. } => {
                for &i in &mine {
                    out.channels[i]
                        .values
                        .iter_mut()
                        .for_each(|v| *v /= *factor);
                }
            }
            DataErrorKind::Swapped { other } => {
                // Each pair is listed for both channels: exchange once.
                if e.channel > *other {
                    continue;
                }
                let theirs = records(test, data, *other);
                if let (Some(&a), Some(&b)) = (mine.first(), theirs.first()) {
                    out.channels[a].values = test.channels[b].values.clone();
                    out.channels[b].values = test.channels[a].values.clone();
                }
            }
        }
    }
    let mut i = 0;
    out.channels.retain(|_| {
        i += 1;
        !drop[i - 1]
    });
    out
}
