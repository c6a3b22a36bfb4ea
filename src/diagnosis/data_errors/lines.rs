//! The channel checks line by line: each measured FRF against the
//! prediction of the deck updated on the test (its parameters and damping
//! fitted on all channels, the modal checks' corrections applied).
//!
//! The modal checks ([`super::gains`], [`super::swap`]) judge a channel on
//! the test modes the pole fit finds, where the deck predicts a large
//! modal constant: a campaign with few modes in its band, or a channel near
//! a nodal point of those modes, leaves a wrong channel without evidence,
//! and two wrong channels in one campaign can hide each other. Here every
//! line above the noise floor is evidence. With z_l = H_test(l)/H_model(l)
//! on a channel's lines l:
//!
//! - its gain is ln g = median ln|z_l| (less the median over the channels,
//!   so that a deck wrong by a common factor flags nothing), its spread the
//!   median |ln|z_l| − ln g|;
//! - its opposition is the share of lines with Re z_l < 0 (the measured and
//!   predicted FRFs more than 90° apart).
//!
//! An updated deck that lacks some physics still fits most lines of every
//! channel to tens of percent, and its sign errors sit in narrow bands
//! between shifted resonances and antiresonances; missing physics does not
//! multiply a channel by one constant over the band, nor turn it round.
//! So a channel is **reversed** when at least [`OPPOSED`] of its lines are
//! opposed; **scaled** when its gain is within [`UNIT_MATCH`] of a unit
//! conversion ([`super::gains::unit_of`]) with a spread under ln
//! [`UNIFORM`] (a physical effect does not pick a unit factor, nor scale
//! every line alike); **sound** when its gain is within ln [`SOUND_GAIN`] and at most
//! [`SOUND_OPPOSED`] of its lines are opposed. Two channels whose misfit
//! (their share of the full-band cost) stands out are **swapped** when
//! exchanging them cuts their summed misfit by a factor 4 or more: missing
//! physics does not make one channel's data fit another sensor's place.
//! Anything else leaves the verdict to the modal checks.

use faer::c64;

use super::super::data::TestData;
use super::gains::unit_of;
use super::{median, DataError, DataErrorKind};

/// Lines above the noise floor a channel needs to be judged here.
pub const MIN_LINES: usize = 20;
/// Share of opposed lines from which a channel is reversed.
pub const OPPOSED: f64 = 0.8;
/// Largest |ln g − ln unit| of a scaled channel (the deck is updated, so its
/// gain is known to a few percent).
pub const UNIT_MATCH: f64 = 0.15;
/// A scaled channel's lines are within this factor of its gain (median):
/// the updated deck fits a sound channel's lines to a few percent.
pub const UNIFORM: f64 = 1.25;
/// A sound channel's gain is within this factor of the others'.
pub const SOUND_GAIN: f64 = 1.5;
/// At most this share of a sound channel's lines is opposed.
pub const SOUND_OPPOSED: f64 = 0.2;
/// A channel whose misfit exceeds this many times the median channel's may
/// be one of a swapped pair.
pub const OUTLIER: f64 = 4.0;
/// Channels of largest misfit tried in pairs.
pub const SWAP_SUSPECTS: usize = 6;
/// Two channels are swapped when exchanging them brings their summed
/// misfit under this share of what it was.
pub const SWAP_GAIN: f64 = 0.25;
/// Two outlying channels whose exchange brings their summed misfit under
/// this share of what it was, but not under [`SWAP_GAIN`], are judged
/// again against a deck updated without them ([`Judged::doubtful`]).
pub const DOUBT_GAIN: f64 = 0.5;

/// One channel's measured FRF against a predicted one, over the lines
/// above the measured channel's noise floor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineRatio {
    /// Median ln|H_test/H_model| (not yet centred on the other channels).
    pub log_gain: f64,
    /// Median |ln|z_l| − log_gain|.
    pub spread: f64,
    /// Share of lines with Re z_l < 0.
    pub opposed: f64,
    /// Mean of w_l² |ln z_l|² (w the fit's weights): the channel's share of
    /// the full-band cost.
    pub misfit: f64,
}

/// The ratio of `test` to `model` on the lines where `weight` > 0 (`None`
/// with fewer than [`MIN_LINES`] such lines where the model responds).
pub fn line_ratio(test: &[c64], model: &[c64], weight: &[f64]) -> Option<LineRatio> {
    let mut logs = Vec::new();
    let mut opposed = 0usize;
    let mut cost = 0.0;
    for ((t, m), w) in test.iter().zip(model).zip(weight) {
        if *w <= 0.0 || m.norm() == 0.0 {
            continue;
        }
        let z = t / m;
        let l = z.norm().ln();
        if !l.is_finite() {
            continue;
        }
        logs.push(l);
        opposed += usize::from(z.re < 0.0);
        cost += w * w * (l * l + z.arg() * z.arg());
    }
    if logs.len() < MIN_LINES {
        return None;
    }
    let log_gain = median(&logs)?;
    let dev: Vec<f64> = logs.iter().map(|l| (l - log_gain).abs()).collect();
    Some(LineRatio {
        log_gain,
        spread: median(&dev)?,
        opposed: opposed as f64 / logs.len() as f64,
        misfit: cost / logs.len() as f64,
    })
}

/// What the lines say of one channel.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict {
    Sound,
    Wrong(DataErrorKind),
    /// Not enough lines, or neither sound nor a known error.
    Undecided,
}

/// The verdict on a channel whose ratio is `r`, the other channels' median
/// gain being `centre`.
fn judge(r: Option<LineRatio>, centre: f64) -> Verdict {
    let Some(r) = r else {
        return Verdict::Undecided;
    };
    let gain = r.log_gain - centre;
    let reversed = r.opposed >= OPPOSED;
    let unit = unit_of(gain.exp()).filter(|u| (gain - u.1.ln()).abs() <= UNIT_MATCH);
    match unit {
        Some((words, factor)) if r.spread <= UNIFORM.ln() => Verdict::Wrong(DataErrorKind::Scale {
            factor: if reversed { -factor } else { factor },
            unit: Some(words),
        }),
        _ if reversed => Verdict::Wrong(DataErrorKind::Reversed {
            agreement: 1.0 - 2.0 * r.opposed,
            over: "its lines above the noise",
        }),
        _ if gain.abs() < SOUND_GAIN.ln() && r.opposed <= SOUND_OPPOSED => Verdict::Sound,
        _ => Verdict::Undecided,
    }
}

/// The line-by-line verdict on every channel of `data` (`live` ones; the
/// others [`Verdict::Undecided`]) against `model` (`[channel][line]`, the
/// same lines): swapped pairs first, then each channel's gain and sign.
pub fn verdicts(data: &TestData, model: &[Vec<c64>], live: &[bool]) -> Vec<Verdict> {
    judge_channels(data, model, live).verdicts
}

/// The verdicts of [`verdicts`], and the channels they leave in doubt.
pub struct Judged {
    pub verdicts: Vec<Verdict>,
    /// Outlying channels (see [`swapped_pairs`]) that two by two come close
    /// to the swap test without passing it: exchanging them lowers their
    /// misfit below [`DOUBT_GAIN`] of what it was, but not below
    /// [`SWAP_GAIN`]. A model fitted on those channels as measured is no
    /// fair judge of them: wrong data pull the update towards them.
    pub doubtful: Vec<usize>,
}

/// [`verdicts`], with the channels they leave in doubt.
pub fn judge_channels(data: &TestData, model: &[Vec<c64>], live: &[bool]) -> Judged {
    let nc = data.channels.len();
    let ratio = |t: usize, m: usize| line_ratio(&data.values[t], &model[m], &data.weight[t]);
    let own: Vec<Option<LineRatio>> = (0..nc)
        .map(|c| if live[c] { ratio(c, c) } else { None })
        .collect();
    let gains: Vec<f64> = own.iter().flatten().map(|r| r.log_gain).collect();
    let Some(centre) = median(&gains) else {
        return Judged {
            verdicts: vec![Verdict::Undecided; nc],
            doubtful: Vec::new(),
        };
    };
    let mut out: Vec<Verdict> = own.iter().map(|r| judge(*r, centre)).collect();
    let (pairs, doubtful) = swapped_pairs(&own, &ratio);
    for (a, b) in pairs {
        out[a] = Verdict::Wrong(DataErrorKind::Swapped { other: b });
        out[b] = Verdict::Wrong(DataErrorKind::Swapped { other: a });
    }
    Judged {
        verdicts: out,
        doubtful,
    }
}

/// Channels that fit each other's place: among the [`SWAP_SUSPECTS`]
/// channels of largest misfit that stand out (above [`OUTLIER`] × the
/// median of the others but the two largest), the pairs whose misfits exchanged fall below
/// [`SWAP_GAIN`] × their own, the clearest first, each channel in one pair;
/// and the suspects of pairs below [`DOUBT_GAIN`] that none of those
/// pairs takes ([`Judged::doubtful`]).
/// `ratio(t, m)`: measured channel t against predicted channel m.
fn swapped_pairs(
    own: &[Option<LineRatio>],
    ratio: &dyn Fn(usize, usize) -> Option<LineRatio>,
) -> (Vec<(usize, usize)>, Vec<usize>) {
    // The typical misfit is the median without the two largest (a swapped
    // pair is two of a campaign's few channels).
    let mut misfits: Vec<f64> = own.iter().flatten().map(|r| r.misfit).collect();
    misfits.sort_by(|a, b| a.total_cmp(b));
    misfits.truncate(misfits.len().saturating_sub(2));
    let Some(typical) = median(&misfits) else {
        return (Vec::new(), Vec::new());
    };
    let mut suspects: Vec<(f64, usize)> = own
        .iter()
        .enumerate()
        .filter_map(|(c, r)| r.map(|r| (r.misfit, c)))
        .filter(|(m, _)| *m > OUTLIER * typical)
        .collect();
    suspects.sort_by(|x, y| y.0.total_cmp(&x.0));
    suspects.truncate(SWAP_SUSPECTS);
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (i, &(ma, a)) in suspects.iter().enumerate() {
        for &(mb, b) in &suspects[i + 1..] {
            if let (Some(ab), Some(ba)) = (ratio(a, b), ratio(b, a)) {
                let gain = (ab.misfit + ba.misfit) / (ma + mb);
                if gain < DOUBT_GAIN {
                    pairs.push((gain, a.min(b), a.max(b)));
                }
            }
        }
    }
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
    let mut taken: Vec<usize> = Vec::new();
    let mut out = Vec::new();
    for &(_, a, b) in pairs.iter().filter(|p| p.0 < SWAP_GAIN) {
        if !taken.contains(&a) && !taken.contains(&b) {
            taken.extend([a, b]);
            out.push((a, b));
        }
    }
    let mut doubtful: Vec<usize> = pairs
        .iter()
        .filter(|p| p.0 >= SWAP_GAIN)
        .flat_map(|p| [p.1, p.2])
        .filter(|c| !taken.contains(c))
        .collect();
    doubtful.sort_unstable();
    doubtful.dedup();
    (out, doubtful)
}

/// The data errors of `data` from the modal checks (`modal`) and the line
/// verdicts (`lines`, one per channel): a dead channel stays dead; else a
/// channel the lines decide (sound or wrong) takes their verdict, the
/// others keep the modal checks'. "Sound" does not overrule a modal swap:
/// two neighbouring channels fit each other's place nearly as well as their
/// own, and the lines' own swap test has then decided nothing. A swapped
/// pair is kept only whole.
pub fn reconcile(modal: &[DataError], lines: &[Verdict]) -> Vec<DataError> {
    let modal_of = |c: usize| {
        modal
            .iter()
            .find(|e| e.channel == c)
            .map(|e| e.kind.clone())
    };
    let mut kinds: Vec<Option<DataErrorKind>> = (0..lines.len())
        .map(|c| match (modal_of(c), &lines[c]) {
            (Some(k @ DataErrorKind::Dead { .. }), _) => Some(k),
            (Some(k @ DataErrorKind::Swapped { .. }), Verdict::Sound) => Some(k),
            (_, Verdict::Sound) => None,
            (_, Verdict::Wrong(k)) => Some(k.clone()),
            (m, Verdict::Undecided) => m,
        })
        .collect();
    for c in 0..kinds.len() {
        if let Some(DataErrorKind::Swapped { other }) = kinds[c] {
            let whole = matches!(kinds.get(other), Some(Some(DataErrorKind::Swapped { other: o })) if *o == c);
            if !whole {
                kinds[c] = None;
            }
        }
    }
    kinds
        .into_iter()
        .enumerate()
        .filter_map(|(channel, k)| k.map(|kind| DataError { channel, kind }))
        .collect()
}
