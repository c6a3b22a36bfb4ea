//! Read a UFF file (the one read path of every command) and gather its
//! dataset 58 FRF records into [`MeasuredFrfs`].

use std::io::Read;
use std::path::{Path, PathBuf};

use faer::c64;
use frfup_parsers::uff::units::{ordinate_si_factor, units_label_si_factor, Units164};
use frfup_parsers::uff::{Dataset, Function58, OtherDataset, OtherKind, UffError, UffFile};

use super::{Channel, FrfKind, MeasuredFrfs};

/// UFF function type of a frequency response function (record 6).
pub const FUNCTION_TYPE_FRF: i32 = 4;

/// Why test data could not be read.
#[derive(Debug)]
pub enum TestDataError {
    /// The file could not be opened or read.
    Io {
        path: PathBuf,
        source: std::io::Error,
    },
    /// The file is not valid UFF.
    Uff { path: PathBuf, source: UffError },
    /// The file holds no usable FRF record.
    NoFrfs { path: PathBuf, detail: String },
    /// Records disagree (frequency axis, kind) or cannot be interpreted.
    Inconsistent { path: PathBuf, detail: String },
}

impl std::fmt::Display for TestDataError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            // The message names the file (`fsio::open_input`, `parse_uff`).
            TestDataError::Io { source, .. } => write!(f, "{source}"),
            TestDataError::Uff { path, source } => write!(f, "{}: {source}", path.display()),
            TestDataError::NoFrfs { path, detail }
            | TestDataError::Inconsistent { path, detail } => {
                write!(f, "{}: {detail}", path.display())
            }
        }
    }
}

impl std::error::Error for TestDataError {}

/// Test data and what was noticed while reading them: the parser's notes
/// (lines outside datasets, 58b byte counts ...) and the loader's (records
/// that are not FRFs, channels measured twice, several references, values no
/// FRF has). Nothing that was skipped or doubtful goes unsaid.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadedTest {
    pub frfs: MeasuredFrfs,
    pub notes: Vec<String>,
}

/// Read a UFF file and gather its FRF records (the notes are dropped: see
/// [`load_with_notes`]).
pub fn load(path: &Path) -> Result<MeasuredFrfs, TestDataError> {
    load_with_notes(path).map(|l| l.frfs)
}

/// Read a UFF file and gather its FRF records, with what was noticed.
pub fn load_with_notes(path: &Path) -> Result<LoadedTest, TestDataError> {
    let (reader, _len) = open_uff(path)?;
    let file = parse_uff(path, reader)?;
    from_uff_with_notes(&file, path)
}

/// Open a UFF file for [`parse_uff`]: directories and devices are refused, a
/// pipe is read to a bound (`fsio::open_input`). Returns the reader and the
/// file's length in bytes (0 for a pipe).
pub fn open_uff(path: &Path) -> Result<(crate::fsio::Bounded<std::fs::File>, u64), TestDataError> {
    crate::fsio::open_input(path).map_err(|message| TestDataError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::other(message),
    })
}

/// Parse the UFF file `path` from `reader`, streaming
/// ([`frfup_parsers::uff::parse_reader`]: read in chunks, datasets parsed on
/// worker threads while reading goes on, memory near the decoded data).
/// A read error is reported as the file's `cannot read: ...`, as for any
/// input; errors name the file.
pub fn parse_uff(path: &Path, reader: impl Read) -> Result<UffFile, TestDataError> {
    let mut reader = Watched {
        inner: reader,
        error: None,
    };
    frfup_parsers::uff::parse_reader(&mut reader).map_err(|source| match reader.error.take() {
        Some(e) => TestDataError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::other(format!("{}: cannot read: {e}", path.display())),
        },
        None => TestDataError::Uff {
            path: path.to_path_buf(),
            source,
        },
    })
}

/// A reader that keeps the words of the first error it returned (the parser
/// reports it as a parse error at a byte offset).
struct Watched<R> {
    inner: R,
    error: Option<String>,
}

impl<R: Read> Read for Watched<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let r = self.inner.read(buf);
        if let Err(e) = &r {
            if self.error.is_none() && e.kind() != std::io::ErrorKind::Interrupted {
                self.error = Some(e.to_string());
            }
        }
        r
    }
}

/// The FRF kind of a record, from the response's specific data type (record 9),
/// or failing that from its units label.
pub fn record_kind(f: &Function58) -> Option<FrfKind> {
    if let Some(kind) = FrfKind::from_uff_data_type(f.numerator_axis.data_type) {
        return Some(kind);
    }
    let label = format!("{} {}", f.numerator_axis.units_label, f.id_lines[0]).to_lowercase();
    let label = label.replace(' ', "");
    if label.contains("s^2")
        || label.contains("s²")
        || label.contains("s2")
        || label.contains("accel")
        || label.contains("(g)")
        || label.starts_with("g/")
        || label == "g"
    {
        Some(FrfKind::Accelerance)
    } else if label.contains("m/s") || label.contains("mobil") || label.contains("veloc") {
        Some(FrfKind::Mobility)
    } else if label.contains("recept") || label.contains("displ") {
        Some(FrfKind::Receptance)
    } else {
        None
    }
}

/// The factor that takes the ordinate of `f` to SI: the unit exponents of
/// records 9–10 under the file's dataset 164 units, times standard gravity for
/// a numerator labelled in g (e.g. `g/N`).
pub fn si_factor(f: &Function58, units: &Units164) -> f64 {
    let g = units_label_si_factor(&f.numerator_axis.units_label).unwrap_or(1.0);
    ordinate_si_factor(f, units) * g
}

/// Gather the FRF records (function type 4) of `file` into channels on a
/// common frequency axis. `path` only names the file in errors.
pub fn from_uff(file: &UffFile, path: &Path) -> Result<MeasuredFrfs, TestDataError> {
    from_uff_with_notes(file, path).map(|l| l.frfs)
}

/// [`from_uff`], with the parser's notes and the loader's own.
pub fn from_uff_with_notes(file: &UffFile, path: &Path) -> Result<LoadedTest, TestDataError> {
    let frfs = gather(file, path)?;
    let mut notes = file.notes.clone();
    notes.extend(super::checks::notes(file, &frfs));
    Ok(LoadedTest { frfs, notes })
}

fn gather(file: &UffFile, path: &Path) -> Result<MeasuredFrfs, TestDataError> {
    // Dataset 164 sets the units of the datasets that follow it.
    let mut units = Units164::si();
    let mut records: Vec<(usize, &Function58, f64)> = Vec::new();
    for (i, d) in file.datasets.iter().enumerate() {
        match d {
            Dataset::Other(OtherDataset {
                kind: OtherKind::Units(u),
                ..
            }) => units = u.clone(),
            Dataset::Function(f) if f.function_type == FUNCTION_TYPE_FRF => {
                records.push((i, f.as_ref(), si_factor(f, &units)));
            }
            _ => {}
        }
    }
    let inconsistent = |detail: String| TestDataError::Inconsistent {
        path: path.to_path_buf(),
        detail,
    };
    let Some(&(first_index, first, _)) = records.first() else {
        let n58 = file
            .datasets
            .iter()
            .filter(|d| matches!(d, Dataset::Function(_)))
            .count();
        return Err(TestDataError::NoFrfs {
            path: path.to_path_buf(),
            detail: format!(
                "no FRF record (dataset 58 with function type 4) among {} dataset(s) ({n58} of type 58)",
                file.datasets.len()
            ),
        });
    };
    let kind = record_kind(first).ok_or_else(|| {
        inconsistent(format!(
            "dataset #{}: cannot tell whether the FRF is receptance, mobility or accelerance \
             (record 9 specific data type {} is not 8, 11 or 12, and the units label {:?} does not say)",
            first_index + 1,
            first.numerator_axis.data_type,
            first.numerator_axis.units_label
        ))
    })?;
    let n = first.len();
    let frequencies_hz: Vec<f64> = (0..n).map(|i| first.abscissa_at(i)).collect();
    let scale = frequencies_hz
        .iter()
        .fold(0.0f64, |a, &b| a.max(b.abs()))
        .max(1e-300);
    let mut channels = Vec::with_capacity(records.len());
    for &(index, f, factor) in &records {
        if f.len() != n {
            return Err(inconsistent(format!(
                "dataset #{} has {} frequency lines, dataset #{} has {n}: all FRFs must share one frequency axis",
                index + 1,
                f.len(),
                first_index + 1
            )));
        }
        if let Some(line) =
            (0..n).find(|&i| (f.abscissa_at(i) - frequencies_hz[i]).abs() > 1e-9 * scale)
        {
            return Err(inconsistent(format!(
                "dataset #{} line {} is at {} Hz, dataset #{} at {} Hz: all FRFs must share one frequency axis",
                index + 1,
                line + 1,
                f.abscissa_at(line),
                first_index + 1,
                frequencies_hz[line]
            )));
        }
        let this_kind = record_kind(f).unwrap_or(kind);
        if this_kind != kind {
            return Err(inconsistent(format!(
                "dataset #{} is {}, dataset #{} is {}: convert them to one kind first",
                index + 1,
                this_kind.name(),
                first_index + 1,
                kind.name()
            )));
        }
        let values = (0..f.len())
            .map(|i| {
                let (re, im) = f.ordinate.at(i);
                c64::new(re * factor, im * factor)
            })
            .collect();
        let (response_node, response_direction) =
            super::checks::record_dof(&f.response_entity, f.response_node, f.response_direction);
        let (reference_node, reference_direction) =
            super::checks::record_dof(&f.reference_entity, f.reference_node, f.reference_direction);
        channels.push(Channel {
            response_node,
            response_direction,
            reference_node,
            reference_direction,
            values,
        });
    }
    Ok(MeasuredFrfs {
        frequencies_hz,
        kind,
        channels,
    })
}
