//! Universal File Format (UFF / UNV): reading and writing.
//!
//! CONTRACT (shared with `frfup::testdata` and the CLI): items marked CONTRACT
//! keep their names and meaning; add freely around them.

/// CONTRACT. A whole parsed file.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UffFile {
    pub datasets: Vec<Dataset>,
    /// Non-fatal remarks (skipped unknown datasets, repaired quirks), with line numbers.
    pub notes: Vec<String>,
}

/// CONTRACT. One dataset of a file, in file order.
#[derive(Clone, Debug, PartialEq)]
pub enum Dataset {
    /// 58 and 58b: a function at one node/direction pair.
    Function(Box<Function58>),
    /// Any other dataset; `kind` says which and holds its typed content.
    Other(OtherDataset),
}

/// CONTRACT. Datasets other than 58; variants are added by the UFF parser.
#[derive(Clone, Debug, PartialEq)]
pub struct OtherDataset {
    /// Dataset number (151, 164, 15, ...).
    pub number: u32,
    /// 1-based line of the dataset number in the file.
    pub line: usize,
    /// A one-line human summary (e.g. "164 units: SI, length 1 m, force 1 N").
    pub summary: String,
}

/// CONTRACT. Abscissa of a function record.
#[derive(Clone, Debug, PartialEq)]
pub enum Abscissa {
    Even { start: f64, step: f64 },
    Uneven(Vec<f64>),
}

/// CONTRACT. Ordinate data, in file order.
#[derive(Clone, Debug, PartialEq)]
pub enum Ordinate {
    /// Ordinate type 2 (single) or 4 (double).
    Real(Vec<f64>),
    /// Ordinate type 5 (single) or 6 (double): (re, im) pairs.
    Complex(Vec<(f64, f64)>),
}

/// CONTRACT. Records 8–11 of dataset 58: data characteristics of one axis.
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

/// CONTRACT. Dataset 58 / 58b.
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
    /// CONTRACT. Number of points.
    pub fn len(&self) -> usize {
        match &self.ordinate {
            Ordinate::Real(v) => v.len(),
            Ordinate::Complex(v) => v.len(),
        }
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// CONTRACT. Abscissa value of point i.
    pub fn abscissa_at(&self, i: usize) -> f64 {
        match &self.abscissa {
            Abscissa::Even { start, step } => start + step * i as f64,
            Abscissa::Uneven(x) => x[i],
        }
    }
}

/// CONTRACT. Why a file could not be read. The caller adds the file name.
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

/// CONTRACT. Parse a whole file from its bytes.
pub fn parse(bytes: &[u8]) -> Result<UffFile, UffError> {
    let _ = bytes;
    todo!("UFF helper implements this")
}

/// CONTRACT. Write dataset 58 records (58b where `binary` is true) to `out`.
pub fn write_functions<W: std::io::Write>(out: &mut W, functions: &[Function58]) -> std::io::Result<()> {
    let _ = (out, functions);
    todo!("UFF helper implements this")
}
