//! `frfup convert IN... OUT [--to KIND] [--channels SPEC] [--binary]`: the
//! records of every input, in order, into one CSV or UFF file (`-`: CSV on
//! stdout). With several inputs each CSV column names its file.

use std::path::{Path, PathBuf};

use frfup_parsers::uff::{Abscissa, Dataset, Function58, Ordinate, UffFile};

use super::{progress::Progress, read_uff};
use crate::fsio::{csv_number, write_atomic_with};
use crate::tasks::{warn_notes, CommandError};
use crate::testdata::{self, FrfKind, MeasuredFrfs};

/// Target of `--to`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    Kind(FrfKind),
    /// Eq. 50 / §3.6: signed real displacement FRF (m/N).
    DisplacementReal,
}

/// Options of `frfup convert`.
#[derive(Clone, Debug)]
pub struct ConvertOptions {
    /// One or more UFF files, read in order.
    pub inputs: Vec<PathBuf>,
    /// `.csv`, `.uff`, `.unv`, or `-` (CSV on stdout).
    pub output: PathBuf,
    pub to: Option<Target>,
    /// Channel selection (see [`select`]), applied to each input; `None`
    /// keeps every dataset 58.
    pub channels: Option<String>,
    pub binary: bool,
    pub progress: Progress,
    /// `--strict`: a warning about the input is an error.
    pub strict: bool,
}

/// What `convert` did, for the one-line summary.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvertSummary {
    pub records: usize,
    pub lines: usize,
    pub notes: Vec<String>,
}

enum OutputFormat {
    Csv,
    Uff,
    /// CSV on stdout (`-`).
    Stdout,
}

/// The output `-`: CSV on stdout.
pub fn is_stdout(path: &Path) -> bool {
    path.as_os_str() == "-"
}

fn output_format(path: &Path) -> Result<OutputFormat, CommandError> {
    if is_stdout(path) {
        return Ok(OutputFormat::Stdout);
    }
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "csv" => Ok(OutputFormat::Csv),
        "uff" | "unv" => Ok(OutputFormat::Uff),
        _ => Err(CommandError::input(format!(
            "{}: output must end in .csv, .uff or .unv (or be - for CSV on stdout)",
            path.display()
        ))),
    }
}

/// Select dataset 58 records by a channel SPEC: a comma list of 1-based
/// positions among the file's dataset 58 records or ranges (`1-4,7`), or of
/// response DOFs `NODE:DIR` (`112:3`, `112:+z`, `5:-ry`).
pub fn select<'a>(
    file: &'a UffFile,
    spec: Option<&str>,
) -> Result<Vec<&'a Function58>, CommandError> {
    let all: Vec<&Function58> = file
        .datasets
        .iter()
        .filter_map(|d| match d {
            Dataset::Function(f) => Some(f.as_ref()),
            _ => None,
        })
        .collect();
    let Some(spec) = spec else { return Ok(all) };
    let bad = |item: &str, why: &str| {
        CommandError::input(format!(
            "--channels {spec:?}: {item:?} {why}; expected 1-based positions or ranges among the {} dataset 58 record(s) (e.g. 1-4,7) or response DOFs NODE:DIR (e.g. 112:3 or 112:+z)",
            all.len()
        ))
    };
    let mut chosen: Vec<usize> = Vec::new();
    for item in spec.split(',').map(str::trim).filter(|s| !s.is_empty()) {
        if let Some((node, dir)) = item.split_once(':') {
            let node: i64 = node
                .trim()
                .parse()
                .map_err(|_| bad(item, "has no node number"))?;
            let dir = parse_direction(dir).ok_or_else(|| bad(item, "has no direction"))?;
            let before = chosen.len();
            for (i, f) in all.iter().enumerate() {
                if f.response_node == node && f.response_direction == dir && !chosen.contains(&i) {
                    chosen.push(i);
                }
            }
            if chosen.len() == before {
                return Err(bad(item, "matches no record"));
            }
        } else {
            let (a, b) = match item.split_once('-') {
                Some((a, b)) => (a.trim(), b.trim()),
                None => (item, item),
            };
            let a: usize = a.parse().map_err(|_| bad(item, "is not a position"))?;
            let b: usize = b.parse().map_err(|_| bad(item, "is not a position"))?;
            if a == 0 || b < a || b > all.len() {
                return Err(bad(item, "is out of range"));
            }
            for i in a - 1..b {
                if !chosen.contains(&i) {
                    chosen.push(i);
                }
            }
        }
    }
    Ok(chosen.into_iter().map(|i| all[i]).collect())
}

/// A UFF direction code from `3`, `-3`, `+z`, `z`, `-ry` ...
pub fn parse_direction(s: &str) -> Option<i32> {
    let s = s.trim();
    if let Ok(code) = s.parse::<i32>() {
        return (code != 0 && code.abs() <= 6).then_some(code);
    }
    let (sign, name) = match s.as_bytes().first()? {
        b'+' => (1, &s[1..]),
        b'-' => (-1, &s[1..]),
        _ => (1, s),
    };
    let code = match name.to_ascii_lowercase().as_str() {
        "x" => 1,
        "y" => 2,
        "z" => 3,
        "rx" => 4,
        "ry" => 5,
        "rz" => 6,
        _ => return None,
    };
    Some(sign * code)
}

/// Run `frfup convert`.
pub fn run(opts: &ConvertOptions) -> Result<ConvertSummary, CommandError> {
    let format = output_format(&opts.output)?;
    let mut notes = Vec::new();
    let mut records = Vec::new();
    let mut sources = Vec::new();
    for input in &opts.inputs {
        let mut own = Vec::new();
        let converted = read_selected(opts, input, &mut own)?;
        sources.extend(std::iter::repeat_n(
            input.display().to_string(),
            converted.len(),
        ));
        records.extend(converted);
        notes.extend(own.into_iter().map(|n| match opts.inputs.len() {
            1 => n,
            _ => format!("{}: {n}", input.display()),
        }));
    }
    let lines = records.first().map(|f| f.len()).unwrap_or(0);
    let count = records.len();
    let sources = (opts.inputs.len() > 1).then_some(sources.as_slice());
    let units: Vec<Option<String>> = records.iter().map(|f| value_units(f, opts.to)).collect();
    let csv = || {
        csv_text_from(&records, sources, Some(&units))
            .map_err(|e| CommandError::input(format!("{}: {e}", opts.inputs[0].display())))
    };
    let written = match format {
        OutputFormat::Csv => {
            let csv = csv()?;
            write_atomic_with(&opts.output, |w| w.write_all(csv.as_bytes()))
        }
        OutputFormat::Stdout => {
            let csv = csv()?;
            std::io::Write::write_all(&mut std::io::stdout().lock(), csv.as_bytes())
        }
        OutputFormat::Uff => {
            let records: Vec<Function58> = records
                .into_iter()
                .map(|mut f| {
                    f.binary = opts.binary;
                    f
                })
                .collect();
            write_atomic_with(&opts.output, |mut w| {
                frfup_parsers::uff::write_functions(&mut w, &records)
            })
        }
    };
    written.map_err(|e| CommandError::output(&opts.output, e))?;
    Ok(ConvertSummary {
        records: count,
        lines,
        notes,
    })
}

/// The records of one input chosen by `--channels` and converted by `--to`.
fn read_selected(
    opts: &ConvertOptions,
    input: &Path,
    notes: &mut Vec<String>,
) -> Result<Vec<Function58>, CommandError> {
    let file = read_uff(input, opts.progress)?;
    // The loader's notes too (values no FRF has, channels measured twice ...)
    // where the file holds FRFs; the parser's alone otherwise.
    let read_notes = testdata::from_uff_with_notes(&file, input)
        .map(|l| l.notes)
        .unwrap_or_else(|_| file.notes.clone());
    warn_notes(input, &read_notes, opts.strict)?;
    let selected = select(&file, opts.channels.as_deref())?;
    if selected.is_empty() {
        return Err(CommandError::input(format!(
            "{}: no dataset 58 record to convert",
            input.display()
        )));
    }
    match opts.to {
        None => Ok(selected.into_iter().cloned().collect()),
        Some(target) => convert_selected(&selected, target, input, notes),
    }
}

/// The selected records with their FRFs (function type 4) converted to
/// `target`; any other dataset 58 (coherence, a time record ...) is carried
/// unchanged, in its place, with a note naming it.
fn convert_selected(
    selected: &[&Function58],
    target: Target,
    input: &Path,
    notes: &mut Vec<String>,
) -> Result<Vec<Function58>, CommandError> {
    let is_frf = |f: &Function58| f.function_type == testdata::load::FUNCTION_TYPE_FRF;
    let frf_records: Vec<&Function58> = selected.iter().copied().filter(|f| is_frf(f)).collect();
    if frf_records.is_empty() {
        return Err(CommandError::input(format!(
            "{}: --to converts FRFs (dataset 58 with function type 4) and none of the {} selected record(s) is one",
            input.display(),
            selected.len()
        )));
    }
    let subset = UffFile {
        datasets: frf_records
            .iter()
            .map(|f| Dataset::Function(Box::new((*f).clone())))
            .collect(),
        notes: Vec::new(),
    };
    let frfs =
        testdata::from_uff(&subset, input).map_err(|e| CommandError::input(e.to_string()))?;
    let mut converted = converted_records(&frf_records, &frfs, target, notes).into_iter();
    let mut out = Vec::with_capacity(selected.len());
    for (i, f) in selected.iter().enumerate() {
        if is_frf(f) {
            out.extend(converted.next());
        } else {
            notes.push(format!(
                "selected record {} ({} {}) is not an FRF: carried unconverted",
                i + 1,
                crate::testdata::entity_dof_label(
                    &f.response_entity,
                    f.response_node,
                    f.response_direction
                ),
                crate::testdata::function_type_name(f.function_type)
            ));
            out.push((*f).clone());
        }
    }
    Ok(out)
}

/// Records carrying the converted values, headers taken from the originals.
fn converted_records(
    originals: &[&Function58],
    frfs: &MeasuredFrfs,
    target: Target,
    notes: &mut Vec<String>,
) -> Vec<Function58> {
    let (values_real, kind): (Option<Vec<Vec<f64>>>, FrfKind) = match target {
        Target::Kind(kind) => (None, kind),
        Target::DisplacementReal => (
            Some(testdata::signed_real_displacement(frfs)),
            FrfKind::Receptance,
        ),
    };
    let converted = match target {
        Target::Kind(kind) => {
            let c = frfs.to_kind(kind);
            if !c.zeroed_lines.is_empty() {
                notes.push(format!(
                    "{} zero-frequency line(s) set to 0: {} is undefined there when derived from {}",
                    c.zeroed_lines.len(),
                    kind.name(),
                    frfs.kind.name()
                ));
            }
            Some(c.frfs)
        }
        Target::DisplacementReal => {
            if frfs.kind != FrfKind::Receptance && frfs.frequencies_hz.first() == Some(&0.0) {
                notes.push("the 0 Hz line is set to 0: displacement is undefined there when derived from motion rates".into());
            }
            None
        }
    };
    let (label, units) = match kind {
        FrfKind::Receptance => ("Displacement", "m"),
        FrfKind::Mobility => ("Velocity", "m/s"),
        FrfKind::Accelerance => ("Acceleration", "m/s^2"),
    };
    originals
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let mut f = (*f).clone();
            f.numerator_axis.data_type = kind.uff_data_type();
            f.numerator_axis.label = label.to_string();
            f.numerator_axis.units_label = units.to_string();
            f.numerator_axis.length_exponent = 1;
            f.numerator_axis.force_exponent = 0;
            match (&values_real, &converted) {
                (Some(real), _) => {
                    f.ordinate_type = 4;
                    f.ordinate = Ordinate::Real(real[i].clone());
                }
                (None, Some(c)) => {
                    f.ordinate_type = if f.ordinate_type == 2 || f.ordinate_type == 5 {
                        5
                    } else {
                        6
                    };
                    f.ordinate = Ordinate::Complex(c.channels[i].values.clone());
                }
                (None, None) => {}
            }
            f
        })
        .collect()
}

/// CSV: `frequency_hz` (or the abscissa's name) then, per record, `<resp>/<ref> re`
/// and `im`, or one column for real data. All records must share the abscissa.
pub fn csv_text(records: &[Function58]) -> Result<String, String> {
    csv_text_from(records, None, None)
}

/// The unit of a record's values for a CSV header: `kind`'s SI unit when
/// convert made them SI (`--to`), else the file's axis labels (info's
/// `units`), `None` when the file gives none.
pub fn value_units(f: &Function58, to: Option<Target>) -> Option<String> {
    match to {
        Some(Target::Kind(kind)) => Some(kind.units().to_string()),
        Some(Target::DisplacementReal) => Some(FrfKind::Receptance.units().to_string()),
        None => Some(super::info::units(f)).filter(|u| u != "-"),
    }
}

/// The name of a record's column(s): `resp/ref` (a channel without a
/// reference, such as a time record: `resp` alone), `FILE:` first when
/// `source` is given.
fn column_label(f: &Function58, source: Option<&str>) -> String {
    let label = |e: &str, n: i64, d: i32| crate::testdata::entity_dof_label(e, n, d);
    let response = label(&f.response_entity, f.response_node, f.response_direction);
    let entity = f.reference_entity.trim();
    let no_reference =
        f.reference_node == 0 && (entity.is_empty() || entity.eq_ignore_ascii_case("none"));
    let channel = if no_reference {
        response
    } else {
        let reference = label(&f.reference_entity, f.reference_node, f.reference_direction);
        format!("{response}/{reference}")
    };
    match source {
        Some(file) => format!("{file}:{channel}"),
        None => channel,
    }
}

/// [`csv_text`], each column named `FILE:<resp>/<ref>` when `sources` (one
/// file name per record) is given and with its unit (`re[m/s^2/N]`) when
/// `units` gives one; a name met twice gets ` #2`, ` #3`, ...
pub fn csv_text_from(
    records: &[Function58],
    sources: Option<&[String]>,
    units: Option<&[Option<String>]>,
) -> Result<String, String> {
    let first = records.first().ok_or("no record")?;
    let n = first.len();
    for (i, f) in records.iter().enumerate() {
        let same = f.len() == n && (0..n).all(|k| f.abscissa_at(k) == first.abscissa_at(k));
        if !same {
            return Err(format!(
                "selected record {} does not share the abscissa of record 1; CSV needs one abscissa (select channels with --channels)",
                i + 1
            ));
        }
    }
    let abscissa = match (first.abscissa_axis.data_type, &first.abscissa) {
        (17, _) => "time_s",
        (18, _) | (0, Abscissa::Even { .. }) | (0, Abscissa::Uneven(_))
            if first.function_type != 1 =>
        {
            "frequency_hz"
        }
        _ if first.function_type == 1 => "time_s",
        _ => "abscissa",
    };
    let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
    let mut header = vec![abscissa.to_string()];
    let mut seen: Vec<String> = Vec::new();
    for (i, f) in records.iter().enumerate() {
        let base = column_label(f, sources.map(|s| s[i].as_str()));
        let count = seen.iter().filter(|s| **s == base).count();
        seen.push(base.clone());
        let name = match count {
            0 => base,
            c => format!("{base} #{}", c + 1),
        };
        let unit = units
            .and_then(|u| u[i].as_deref())
            .map(|u| format!("[{u}]"))
            .unwrap_or_default();
        if f.ordinate.is_complex() {
            header.push(format!("{name} re{unit}"));
            header.push(format!("{name} im{unit}"));
        } else {
            header.push(format!("{name}{unit}"));
        }
    }
    w.write_record(&header).map_err(|e| e.to_string())?;
    let mut row: Vec<String> = Vec::with_capacity(header.len());
    for k in 0..n {
        row.clear();
        row.push(csv_number(first.abscissa_at(k)));
        for f in records {
            let (re, im) = f.ordinate.at(k);
            row.push(csv_number(re));
            if f.ordinate.is_complex() {
                row.push(csv_number(im));
            }
        }
        w.write_record(&row).map_err(|e| e.to_string())?;
    }
    let bytes = w.into_inner().map_err(|e| e.to_string())?;
    String::from_utf8(bytes).map_err(|e| e.to_string())
}
