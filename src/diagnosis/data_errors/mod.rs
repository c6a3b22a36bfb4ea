//! Data errors before physics: each channel is checked against the others
//! and the deck before the diagnosis trusts it.
//!
//! - [`dead`]: a channel that holds noise only, where the deck predicts a
//!   clear response (`dead-channel`), unless a channel the deck predicts
//!   silent holds that response (then the two are `swapped-channels`);
//! - [`table`]: the test's modes (the pole fit of
//!   [`crate::updating::identify`]) paired with the deck's, and per channel
//!   the ratio of measured to predicted modal constants;
//! - [`gains`]: a channel whose ratio has the wrong sign on most modes
//!   (`reversed-channel`) or is off by a constant factor
//!   (`channel-scale`: 9.81, 1000, 25.4, …);
//! - [`swap`]: two channels whose data fit each other's place
//!   (`swapped-channels`);
//! - [`lines`]: the same errors judged line by line against the deck
//!   updated on the corrected test (the second pass, which overrules these
//!   checks where its evidence decides);
//! - [`correct`]: the test with the errors undone (dead channels dropped).
//!
//! The checks compare *patterns over modes*, not values: a deck whose
//! frequencies are off by tens of percent, or which lacks some physics,
//! still predicts which channels move together and by how much at each
//! mode, to well within the factor 3 and the sign majority the checks ask
//! for. With fewer than four live channels only dead channels are looked
//! for: a channel is judged against at least three others.

pub mod correct;
pub mod dead;
pub mod gains;
pub mod lines;
pub mod swap;
pub mod table;

use super::data::TestData;
use super::fit::ModalModel;

/// What is wrong with one or two channels.
#[derive(Clone, Debug, PartialEq)]
pub enum DataErrorKind {
    /// The channel holds noise only (99 % of its lines under 5 σ of its own noise).
    Dead { snr: f64 },
    /// The channel's sign is reversed (`agreement`: the weighted share of
    /// the evidence whose sign agrees with the deck, −1 … 1; `over`: what
    /// that evidence is, in words).
    Reversed { agreement: f64, over: &'static str },
    /// The channel is `factor` times what it should be (negative: also reversed).
    Scale {
        factor: f64,
        /// The unit conversion it matches, if any (e.g. "g → m/s² (9.81)").
        unit: Option<&'static str>,
    },
    /// The channel holds the data of `other` (an index into the channels)
    /// and the other its.
    Swapped { other: usize },
}

/// Channels `a` and `b` holding each other's data: the error of each, as
/// the checks report a swap (once for each channel).
pub fn swapped_pair(a: usize, b: usize) -> [DataError; 2] {
    [
        DataError {
            channel: a,
            kind: DataErrorKind::Swapped { other: b },
        },
        DataError {
            channel: b,
            kind: DataErrorKind::Swapped { other: a },
        },
    ]
}

/// One data error: the channel (index into [`TestData::channels`]) and what
/// is wrong with it.
#[derive(Clone, Debug, PartialEq)]
pub struct DataError {
    pub channel: usize,
    pub kind: DataErrorKind,
}

/// The data errors of `data` against the deck's modal model `mm` (built at
/// the same channels), by channel.
///
/// Dead channels first (or, where a channel the deck predicts silent holds
/// what it predicts at the dead one, the two swapped); then, one at a
/// time, the clearest remaining error (a swapped pair before a sign or
/// scale error) is found and undone in the table before the next search,
/// so that one wrong channel does not make a sound one look wrong. More
/// errors than a third of the channels means the deck, not the channels,
/// disagrees with the test: none is reported then.
pub fn check(data: &TestData, mm: &ModalModel) -> Vec<DataError> {
    let mut errors = dead::swaps_with_silent(data, mm, dead::dead_channels(data, mm));
    let live: Vec<bool> = (0..data.channels.len())
        .map(|c| !errors.iter().any(|e| e.channel == c))
        .collect();
    let n_live = live.iter().filter(|l| **l).count();
    if n_live < 4 {
        return errors;
    }
    let mut table = table::ModalTable::new(data, &live, mm);
    let mut found: Vec<DataError> = Vec::new();
    // Errors found so far (a swapped pair is one).
    let mut events = 0;
    while 3 * events < n_live {
        let swaps = swap::swapped_pairs(&table);
        let next = if swaps.is_empty() {
            gains::clearest(&table).into_iter().collect()
        } else {
            swaps
        };
        if next.is_empty() {
            break;
        }
        for e in &next {
            table.undo(e);
        }
        found.extend(next);
        events += 1;
    }
    if 3 * events >= n_live {
        found.clear();
    }
    errors.extend(found);
    errors.sort_by_key(|e| e.channel);
    errors
}

/// Median of the finite values of `v` (`None` if there are none).
pub(crate) fn median(v: &[f64]) -> Option<f64> {
    let mut v: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return None;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    let n = v.len();
    Some(if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    })
}

/// `e` as a finding of the diagnosis (`None` for the second channel of a
/// swapped pair, reported with the first). `before`/`after`: the deck's FRF
/// error (1 = noise level) on the data as measured and as corrected.
pub fn finding(e: &DataError, data: &TestData, before: f64, after: f64) -> Option<super::Finding> {
    use super::hypotheses::Physics;
    use std::collections::BTreeMap;
    let ch = &data.channels[e.channel];
    let mut nodes = vec![ch.node];
    let mut dofs = vec![ch.label.clone()];
    let mut parameters = BTreeMap::new();
    let (physics, label) = match &e.kind {
        DataErrorKind::Dead { snr } if *snr > 0.0 => (
            Physics::DeadChannel,
            format!(
                "channel {} holds noise only (99 % of its lines under {} × its noise) where the deck predicts a response; left out",
                ch.label,
                super::sig(*snr)
            ),
        ),
        DataErrorKind::Dead { .. } => (
            Physics::DeadChannel,
            format!(
                "channel {} holds zeros only where the deck predicts a response; left out",
                ch.label
            ),
        ),
        DataErrorKind::Reversed { agreement, over } => (
            Physics::ReversedChannel,
            format!(
                "channel {} has the opposite sign to the deck on {:.0} % of {over}; turned round",
                ch.label,
                50.0 * (1.0 - agreement)
            ),
        ),
        DataErrorKind::Scale { factor, unit } => {
            parameters.insert("factor".to_string(), *factor);
            (
                Physics::ChannelScale,
                format!(
                    "channel {} is {} × what the other channels and the deck imply{}; divided by it",
                    ch.label,
                    super::sig(*factor),
                    unit.map(|u| format!(", a mix-up of {u}"))
                        .unwrap_or_default()
                ),
            )
        }
        DataErrorKind::Swapped { other } => {
            if e.channel > *other {
                return None;
            }
            let o = &data.channels[*other];
            nodes.push(o.node);
            dofs.push(o.label.clone());
            (
                Physics::SwappedChannels,
                format!(
                    "channels {} and {} hold each other's data; exchanged",
                    ch.label, o.label
                ),
            )
        }
    };
    Some(super::Finding {
        physics,
        nodes,
        dofs,
        parameters,
        uncertainty: BTreeMap::new(),
        validation_error_before: before,
        validation_error_after: after,
        label,
        alternatives: Vec::new(),
        tell_apart: None,
    })
}
