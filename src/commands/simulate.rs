//! `frfup simulate MODEL.deck --input NODE:DIR --band F0:F1:N --out TEST.uff ...`.

use std::path::PathBuf;

use super::convert::parse_direction;
use super::modes::check_settings;
use super::{read_deck, CommandError};
use crate::fsio::write_atomic_with;
use crate::model::ParameterValues;
use crate::simulate::{self, Band, Campaign, NodeDirection, Sensors};

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
    let bad = || {
        CommandError::input(format!(
            "--band {s:?}: expected F0:F1:N in Hz, e.g. 0:200:801"
        ))
    };
    let parts: Vec<&str> = s.split(':').collect();
    if parts.len() != 3 {
        return Err(bad());
    }
    let start_hz: f64 = parts[0].trim().parse().map_err(|_| bad())?;
    let end_hz: f64 = parts[1].trim().parse().map_err(|_| bad())?;
    let count: usize = parts[2].trim().parse().map_err(|_| bad())?;
    if !(start_hz >= 0.0 && end_hz >= start_hz && end_hz.is_finite() && count >= 1) {
        return Err(bad());
    }
    Ok(Band {
        start_hz,
        end_hz,
        count,
    })
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

/// Run `frfup simulate`: returns how many records were written.
pub fn run(opts: &SimulateOptions) -> Result<usize, CommandError> {
    let deck = read_deck(&opts.deck)?;
    check_settings(&opts.deck, &deck, &opts.values)?;
    let frfs = simulate::simulate(&deck, &opts.values, &opts.campaign)
        .map_err(|e| CommandError::input(format!("{}: {e}", opts.deck.display())))?;
    let title = deck_title(&deck, &opts.deck);
    let records = simulate::to_uff_records(&frfs, &title, !opts.single, opts.binary);
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
