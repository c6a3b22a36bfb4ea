//! `frfup simulate MODEL.deck --input NODE:DIR --band F0:F1:N --out TEST.uff ...`.

use std::path::PathBuf;

use super::convert::parse_direction;
use super::modes::check_settings;
use crate::fsio::write_atomic_with;
use crate::model::ParameterValues;
use crate::simulate::{self, Band, Campaign, NodeDirection, Sensors};
use crate::tasks::{read_deck, CommandError};

/// Options of `frfup simulate`.
#[derive(Clone, Debug)]
pub struct SimulateOptions {
    pub deck: PathBuf,
    pub out: PathBuf,
    pub campaign: Campaign,
    pub values: ParameterValues,
    pub binary: bool,
    /// Complex single precision (ordinate type 5) instead of double (6).
    pub single: bool,
}

/// `NODE:DIR`, DIR a UFF code (3, -3) or a name (+z, -ry).
pub fn parse_node_direction(s: &str, what: &str) -> Result<NodeDirection, CommandError> {
    let bad = || {
        CommandError::input(format!(
            "{what} {s:?}: expected NODE:DIR such as 112:3, 112:-3 or 112:+z"
        ))
    };
    let (node, dir) = s.split_once(':').ok_or_else(bad)?;
    let node: u32 = node.trim().parse().map_err(|_| bad())?;
    let direction = parse_direction(dir).ok_or_else(bad)?;
    Ok(NodeDirection { node, direction })
}

/// `F0:F1:N`.
pub fn parse_band(s: &str) -> Result<Band, CommandError> {
    let bad = |why: &str| {
        CommandError::input(format!(
            "--band {s:?}: {why}; expected F0:F1:N in Hz, e.g. 0:200:801"
        ))
    };
    let parts: Vec<&str> = s.split(':').collect();
    if parts.len() != 3 {
        return Err(bad("not three fields"));
    }
    let number = |t: &str, what: &str| {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|x| x.is_finite())
            .ok_or_else(|| bad(&format!("{what} {t:?} is not a finite number")))
    };
    let start_hz = number(parts[0], "F0")?;
    let end_hz = number(parts[1], "F1")?;
    let count: usize = parts[2]
        .trim()
        .parse()
        .map_err(|_| bad(&format!("N {:?} is not a whole number of lines", parts[2])))?;
    if start_hz < 0.0 {
        return Err(bad("F0 is negative"));
    }
    if end_hz < start_hz {
        return Err(bad("F1 is below F0"));
    }
    if count == 0 {
        return Err(bad("N is 0"));
    }
    if count > MAX_LINES {
        return Err(bad(&format!(
            "N = {count} lines is more than {MAX_LINES} (measured FRFs have at most a few 10^5)"
        )));
    }
    Ok(Band {
        start_hz,
        end_hz,
        count,
    })
}

/// Most frequency lines `--band` accepts.
pub const MAX_LINES: usize = 1_000_000;

/// Most bytes of FRF values (lines × channels × 16) `simulate` will compute
/// and hold: checked before anything is allocated.
pub const MAX_VALUE_BYTES: u128 = 4 << 30;

/// Refuse a campaign whose values (lines × channels) would not fit in memory.
fn check_size(deck: &frfup_parsers::deck::Deck, campaign: &Campaign) -> Result<(), CommandError> {
    let channels = match &campaign.sensors {
        Sensors::All => deck.nodes.len() * 3,
        Sensors::List(list) => list.len(),
    } as u128;
    let bytes = campaign.band.count as u128 * channels.max(1) * 16;
    if bytes > MAX_VALUE_BYTES {
        return Err(CommandError::input(format!(
            "--band with {} lines × {channels} channel(s) is {:.1} GiB of FRF values, more than the {} GiB frfup simulate holds: use fewer lines or sensors",
            campaign.band.count,
            bytes as f64 / (1u64 << 30) as f64,
            MAX_VALUE_BYTES >> 30
        )));
    }
    Ok(())
}

/// `all` or a comma list of NODE:DIR.
pub fn parse_sensors(s: &str) -> Result<Sensors, CommandError> {
    if s.trim().eq_ignore_ascii_case("all") {
        return Ok(Sensors::All);
    }
    s.split(',')
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .map(|t| parse_node_direction(t, "--sensors"))
        .collect::<Result<Vec<_>, _>>()
        .map(Sensors::List)
}

/// Run `frfup simulate`, telling `stage` what it is doing: returns how many records were written.
pub fn run(opts: &SimulateOptions, stage: &dyn Fn(&str)) -> Result<usize, CommandError> {
    let deck = read_deck(&opts.deck)?;
    check_settings(&opts.deck, &deck, &opts.values)?;
    check_size(&deck, &opts.campaign)?;
    stage(&format!(
        "computing the FRFs of {} at {} line(s)",
        opts.deck.display(),
        opts.campaign.band.count
    ));
    let frfs = simulate::simulate(&deck, &opts.values, &opts.campaign)
        .map_err(|e| CommandError::input(format!("{}: {e}", opts.deck.display())))?;
    let title = deck_title(&deck, &opts.deck);
    let records = simulate::to_uff_records(&frfs, &title, !opts.single, opts.binary);
    stage(&format!(
        "writing {} record(s) to {}",
        records.len(),
        opts.out.display()
    ));
    write_atomic_with(&opts.out, |mut w| {
        frfup_parsers::uff::write_functions(&mut w, &records)
    })
    .map_err(|e| CommandError::output(&opts.out, e))?;
    Ok(records.len())
}

fn deck_title(deck: &frfup_parsers::deck::Deck, path: &std::path::Path) -> String {
    deck.titles
        .first()
        .map(|t| t.text.clone())
        .unwrap_or_else(|| {
            path.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        })
}
