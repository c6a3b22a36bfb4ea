//! Universal File Format (UFF / UNV): reading and writing.
//!
//! Used by `frfup::testdata` and the command line.
//!
//! Reading: [`parse`] splits the file into dataset blocks (`split`), then
//! parses the blocks on up to `available_parallelism` threads; the result and
//! the first error (in file order) do not depend on the threading.
//! [`parse_reader`] / [`parse_file`] stream (`stream`): bounded chunks cut at
//! dataset boundaries, parsed by workers while reading goes on, text dropped
//! once parsed; same result as [`parse`]. Data fields in the usual fixed
//! formats take an exact fast path (`number`). Datasets
//! read: 58/58b (`function58`), 151, 164 (`units`), 15, 2411, 18, 2420, 82
//! (`geometry`), 55, 1858 (`other`); 2412, 2414 and unknown numbers are kept
//! as [`OtherKind::Skipped`] with a note. Writing: [`write_functions`]
//! (`write`); 55, 15 and 82 (`write_nodal`).

mod function58;
pub mod geometry;
mod number;
pub mod other;
mod split;
mod stream;
mod text;
pub mod units;
pub mod write;
pub mod write_nodal;

pub use geometry::{CoordinateSystem, CsDefinition, Node, Part, TraceLine};
pub use other::{Header151, NodalData55, NodeValues, OtherKind};
pub use units::{
    abscissa_si_factor, ordinate_si_factor, units_label_si_factor, UnitSystem, Units164,
};
pub use write::{write_function, write_functions_with, ByteOrder, WriteOptions};
pub use write_nodal::{write_nodal_data, write_nodes15, write_trace_line82};

/// The complex values of [`Ordinate::Complex`] and [`Ordinate::ComplexSingle`].
pub use num_complex::{Complex32, Complex64};

/// A whole parsed file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UffFile {
    pub datasets: Vec<Dataset>,
    /// Non-fatal remarks (skipped unknown datasets, repaired quirks), with line numbers.
    pub notes: Vec<String>,
}

/// One dataset of a file, in file order.
#[derive(Clone, Debug, PartialEq)]
pub enum Dataset {
    /// 58 and 58b: a function at one node/direction pair.
    Function(Box<Function58>),
    /// Any other dataset; `kind` says which and holds its typed content.
    Other(OtherDataset),
}

/// Datasets other than 58; variants are added by the UFF parser.
#[derive(Clone, Debug, PartialEq)]
pub struct OtherDataset {
    /// Dataset number (151, 164, 15, ...).
    pub number: u32,
    /// 1-based line of the dataset number in the file.
    pub line: usize,
    /// A one-line human summary (e.g. "164 units: SI, length 1 m, force 1 N").
    pub summary: String,
    /// The parsed content.
    pub kind: OtherKind,
}

/// Abscissa of a function record.
#[derive(Clone, Debug, PartialEq)]
pub enum Abscissa {
    Even { start: f64, step: f64 },
    Uneven(Vec<f64>),
}

/// Ordinate data, in file order.
///
/// Single-precision values read from 58b are kept as `f32`, exactly as the
/// file stores them (half the memory of widening them); everything else
/// (ASCII text, double-precision data, values computed by programs) is
/// `f64`. [`Ordinate::at`] reads any variant as `f64`.
#[derive(Clone, Debug, PartialEq)]
pub enum Ordinate {
    /// Ordinate type 2 (single) or 4 (double).
    Real(Vec<f64>),
    /// Ordinate type 5 (single) or 6 (double): (re, im) pairs.
    Complex(Vec<Complex64>),
    /// Ordinate type 2 from 58b binary: the stored single-precision values.
    RealSingle(Vec<f32>),
    /// Ordinate type 5 from 58b binary: the stored single-precision pairs.
    ComplexSingle(Vec<Complex32>),
}

impl Ordinate {
    /// Number of points.
    pub fn len(&self) -> usize {
        match self {
            Ordinate::Real(v) => v.len(),
            Ordinate::Complex(v) => v.len(),
            Ordinate::RealSingle(v) => v.len(),
            Ordinate::ComplexSingle(v) => v.len(),
        }
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Whether the points are (re, im) pairs.
    pub fn is_complex(&self) -> bool {
        matches!(self, Ordinate::Complex(_) | Ordinate::ComplexSingle(_))
    }
    /// Point `i` as (re, im) in double precision (im = 0 for real data).
    /// Panics if `i >= self.len()`.
    #[inline]
    pub fn at(&self, i: usize) -> (f64, f64) {
        match self {
            Ordinate::Real(v) => (v[i], 0.0),
            Ordinate::Complex(v) => (v[i].re, v[i].im),
            Ordinate::RealSingle(v) => (f64::from(v[i]), 0.0),
            Ordinate::ComplexSingle(v) => (f64::from(v[i].re), f64::from(v[i].im)),
        }
    }
    /// Bytes the values occupy in memory.
    pub fn value_bytes(&self) -> usize {
        match self {
            Ordinate::Real(v) => v.len() * 8,
            Ordinate::Complex(v) => v.len() * 16,
            Ordinate::RealSingle(v) => v.len() * 4,
            Ordinate::ComplexSingle(v) => v.len() * 8,
        }
    }
}

/// Records 8–11 of dataset 58: data characteristics of one axis.
#[derive(Clone, Debug, PartialEq, Default)]
pub struct AxisCharacteristics {
    /// Specific data type (0 unknown, 1 general, 2 stress, 3 strain, 5 temperature,
    /// 6 heat flux, 8 displacement, 9 reaction force, 11 velocity, 12 acceleration,
    /// 13 excitation force, 15 pressure, 16 mass, 17 time, 18 frequency, 19 rpm, ...).
    pub data_type: i32,
    pub length_exponent: i32,
    pub force_exponent: i32,
    pub temperature_exponent: i32,
    pub label: String,
    pub units_label: String,
}

/// Dataset 58 / 58b.
#[derive(Clone, Debug, PartialEq)]
pub struct Function58 {
    /// Records 1–5: free text (id line 1..4, record 5 date/time ...).
    pub id_lines: [String; 5],
    /// Record 6.
    pub function_type: i32,
    pub function_id: i32,
    pub version: i32,
    pub load_case: i32,
    pub response_entity: String,
    pub response_node: i64,
    pub response_direction: i32,
    pub reference_entity: String,
    pub reference_node: i64,
    pub reference_direction: i32,
    /// Record 7: 2, 4, 5 or 6.
    pub ordinate_type: i32,
    pub abscissa: Abscissa,
    pub z_axis_value: f64,
    /// Records 8, 9, 10, 11: abscissa, ordinate numerator, ordinate denominator, z axis.
    pub abscissa_axis: AxisCharacteristics,
    pub numerator_axis: AxisCharacteristics,
    pub denominator_axis: AxisCharacteristics,
    pub z_axis: AxisCharacteristics,
    pub ordinate: Ordinate,
    /// True if read from (or to be written as) 58b binary.
    pub binary: bool,
}

impl Function58 {
    /// Number of points.
    pub fn len(&self) -> usize {
        self.ordinate.len()
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Abscissa value of point i.
    pub fn abscissa_at(&self, i: usize) -> f64 {
        match &self.abscissa {
            Abscissa::Even { start, step } => start + step * i as f64,
            Abscissa::Uneven(x) => x[i],
        }
    }
}

/// Why a file could not be read. The caller adds the file name.
#[derive(Clone, Debug, PartialEq)]
pub struct UffError {
    /// 1-based line, where the problem is in a text part.
    pub line: Option<usize>,
    /// Byte offset from the start of the file.
    pub byte_offset: usize,
    /// 0-based index of the dataset in the file, and its number, if known.
    pub dataset_index: Option<usize>,
    pub dataset_number: Option<u32>,
    /// What was expected and what was found, in plain words.
    pub message: String,
}

impl std::fmt::Display for UffError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            Some(line) => write!(f, "line {line} (byte {})", self.byte_offset)?,
            None => write!(f, "byte {}", self.byte_offset)?,
        }
        if let (Some(i), Some(n)) = (self.dataset_index, self.dataset_number) {
            write!(f, ", dataset #{} (type {n})", i + 1)?;
        }
        write!(f, ": {}", self.message)
    }
}

impl std::error::Error for UffError {}

/// Files smaller than this are parsed on one thread.
const PARALLEL_MIN_BYTES: usize = 1 << 20;

/// One parsed block: the dataset and the notes made while parsing it.
pub(crate) type BlockResult = Result<(Dataset, Vec<String>), UffError>;

/// Parses one block of `bytes`; `direct`: the values of a 58b block whose
/// data the streaming reader read straight into them (`stream`).
pub(crate) fn parse_block(
    bytes: &[u8],
    block: &split::Block,
    direct: Option<Ordinate>,
) -> BlockResult {
    let mut notes = block.notes.clone();
    let dataset = if block.number == 58 {
        Dataset::Function(Box::new(function58::parse(
            bytes, block, direct, &mut notes,
        )?))
    } else {
        Dataset::Other(other::parse(bytes, block, &mut notes)?)
    };
    Ok((dataset, notes))
}

/// Parses the blocks, in parallel when worth it; results in block order.
fn parse_blocks(bytes: &[u8], blocks: &[split::Block]) -> Vec<Option<BlockResult>> {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let threads = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, 16)
        .min(blocks.len());
    if threads <= 1 || bytes.len() < PARALLEL_MIN_BYTES {
        let mut out = Vec::with_capacity(blocks.len());
        for b in blocks {
            let r = parse_block(bytes, b, None);
            let failed = r.is_err();
            out.push(Some(r));
            if failed {
                break;
            }
        }
        return out;
    }
    let next = AtomicUsize::new(0);
    let first_error = AtomicUsize::new(usize::MAX);
    let mut slots: Vec<Option<BlockResult>> = (0..blocks.len()).map(|_| None).collect();
    std::thread::scope(|scope| {
        let workers: Vec<_> = (0..threads)
            .map(|_| {
                scope.spawn(|| {
                    let mut done = Vec::new();
                    loop {
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        // Blocks after an error are not needed: the first error in
                        // file order is reported, and every block before it is parsed.
                        if i >= blocks.len() || i > first_error.load(Ordering::Relaxed) {
                            break;
                        }
                        let r = parse_block(bytes, &blocks[i], None);
                        if r.is_err() {
                            first_error.fetch_min(i, Ordering::Relaxed);
                        }
                        done.push((i, r));
                    }
                    done
                })
            })
            .collect();
        for w in workers {
            match w.join() {
                Ok(done) => {
                    for (i, r) in done {
                        slots[i] = Some(r);
                    }
                }
                Err(panic) => std::panic::resume_unwind(panic),
            }
        }
    });
    slots
}

/// Parse a whole file from its bytes.
///
/// Never panics; a malformed file gives an [`UffError`] naming the line (or
/// byte offset), dataset index and number, and what was expected: the first
/// error in file order. Line numbers count line breaks of text parts (58b
/// binary data count as one line). Same result as [`parse_reader`].
pub fn parse(bytes: &[u8]) -> Result<UffFile, UffError> {
    let (split, failure) = split::split(bytes);
    let results = parse_blocks(bytes, &split.blocks);
    let mut file = UffFile {
        datasets: Vec::with_capacity(split.blocks.len()),
        notes: split.notes,
    };
    for (block, r) in split.blocks.iter().zip(results) {
        let Some(r) = r else {
            return Err(UffError {
                line: Some(block.line),
                byte_offset: block.start,
                dataset_index: Some(block.index),
                dataset_number: Some(block.number),
                message: "dataset not parsed".into(),
            });
        };
        let (dataset, notes) = r?;
        file.datasets.push(dataset);
        file.notes.extend(notes);
    }
    match failure {
        Some(e) => Err(e),
        None => Ok(file),
    }
}

/// Parse a file from a reader, streaming: the file is read in 256 KiB chunks
/// (58b data straight into their values), cut at dataset boundaries, and
/// finished datasets are parsed on worker threads (one per core) while
/// reading goes on; their text is dropped once parsed,
/// so memory stays near the size of the decoded data. Gives the same result
/// (and the same first error, with file line numbers and byte offsets) as
/// [`parse`] on the whole file. A read error is reported as an [`UffError`]
/// whose message starts with `read error:`.
pub fn parse_reader<R: std::io::Read>(reader: R) -> Result<UffFile, UffError> {
    stream::parse_reader_with(reader, stream::CHUNK, stream::default_threads())
}

/// [`parse_reader`] with a chosen chunk size (bytes, at least 1) and worker
/// count (1: no threads). For tests and benchmarks; results do not depend on
/// either.
#[doc(hidden)]
pub fn parse_reader_with<R: std::io::Read>(
    reader: R,
    chunk_bytes: usize,
    threads: usize,
) -> Result<UffFile, UffError> {
    stream::parse_reader_with(reader, chunk_bytes, threads)
}

/// Open and [`parse_reader`] a file. An error opening it is an
/// `std::io::Error`; the caller adds the file name to either error.
pub fn parse_file(
    path: impl AsRef<std::path::Path>,
) -> Result<Result<UffFile, UffError>, std::io::Error> {
    let file = std::fs::File::open(path)?;
    Ok(parse_reader(file))
}

/// Write dataset 58 records (58b where `binary` is true) to `out`.
/// 58b data are little-endian; see [`write_functions_with`] for options.
/// Non-finite values, or values that do not fit their Fortran fields, give an
/// `InvalidInput` error.
pub fn write_functions<W: std::io::Write>(
    out: &mut W,
    functions: &[Function58],
) -> std::io::Result<()> {
    write_functions_with(out, functions, &WriteOptions::default())
}
