//! Dataset 58 (function at nodal DOF), ASCII and 58b binary.
//!
//! Records (after the number line):
//! - 1–5 `80A1`: ID lines 1–4, record 5 often the date.
//! - 6 `2(I5,I10),2(1X,10A1,I10,I4)`: function type, function id, version,
//!   load case, response entity/node/direction, reference entity/node/direction.
//! - 7 `3I10,3E13.5`: ordinate type (2 real single, 4 real double, 5 complex
//!   single, 6 complex double), points, spacing (0 uneven, 1 even),
//!   abscissa minimum, increment, z-axis value.
//! - 8–11 `I10,3I5,2(1X,20A1)`: data type, length/force/temperature unit
//!   exponents, label, units label of abscissa, numerator, denominator, z axis.
//! - 12 data. ASCII: types 2/5 `6E13.5` (uneven: x,y or x,re,im in the same
//!   fields); types 4/6 even `4E20.12`; type 4 uneven `2(E13.5,E20.12)`;
//!   type 6 uneven `E13.5,2E20.12`. 58b: IEEE values in the byte order of the
//!   header; an uneven abscissa has the ordinate's precision (pyuff) or single
//!   precision (UFFFiles.jl), told apart by the byte count.

use super::split::{Binary, Block};
use super::text::{self, Lines};
use super::{Abscissa, AxisCharacteristics, Complex64, Function58, Ordinate, UffError};
use num_complex::Complex;

/// Record 7 of dataset 58.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Record7 {
    pub ordinate_type: i32,
    pub points: usize,
    pub even: bool,
    pub start: f64,
    pub step: f64,
    pub z_axis_value: f64,
}

impl Record7 {
    pub fn is_complex(&self) -> bool {
        matches!(self.ordinate_type, 5 | 6)
    }
    /// Bytes of one stored value: 4 (types 2, 5) or 8 (types 4, 6).
    pub fn value_bytes(&self) -> usize {
        if matches!(self.ordinate_type, 4 | 6) {
            8
        } else {
            4
        }
    }
    /// Stored values per point: ordinate (1 or 2) plus abscissa if uneven.
    fn values_per_point(&self) -> usize {
        usize::from(self.is_complex()) + 1 + usize::from(!self.even)
    }
    /// Fortran field widths of one ASCII data line, cycled across the line.
    fn ascii_widths(&self) -> &'static [usize] {
        match (self.value_bytes(), self.even, self.is_complex()) {
            (4, _, _) => &[13],
            (_, true, _) => &[20],
            (_, false, false) => &[13, 20],
            (_, false, true) => &[13, 20, 20],
        }
    }
}

/// Parses record 7 (`3I10,3E13.5`), by column or by whitespace.
pub(crate) fn record7(line: &[u8]) -> Result<Record7, String> {
    let by_columns = || -> Option<(Vec<i64>, [f64; 3])> {
        let ints = [(0, 10), (10, 20), (20, 30)]
            .iter()
            .map(|&(s, e)| text::parse_int(text::column(line, s, e)))
            .collect::<Option<Vec<i64>>>()?;
        let mut reals = [0.0; 3];
        for (k, (s, e)) in [(30, 43), (43, 56), (56, 69)].into_iter().enumerate() {
            let f = text::column(line, s, e);
            reals[k] = if text::trim(f).is_empty() {
                0.0
            } else {
                text::parse_real(f)?
            };
        }
        Some((ints, reals))
    };
    let by_tokens = || -> Option<(Vec<i64>, [f64; 3])> {
        let toks: Vec<&[u8]> = text::tokens(line).collect();
        if toks.len() < 3 || toks.len() > 6 {
            return None;
        }
        let ints = toks[..3]
            .iter()
            .map(|t| text::parse_int(t))
            .collect::<Option<Vec<i64>>>()?;
        let mut reals = [0.0; 3];
        for (k, t) in toks[3..].iter().enumerate() {
            reals[k] = text::parse_real(t)?;
        }
        Some((ints, reals))
    };
    let Some((ints, reals)) = by_columns().or_else(by_tokens) else {
        return Err(format!(
            "expected ordinate type, points, spacing (3I10) and abscissa minimum, increment, z value (3E13.5), found '{}'",
            text::excerpt(line)
        ));
    };
    let ordinate_type = ints[0];
    if !matches!(ordinate_type, 2 | 4 | 5 | 6) {
        return Err(format!(
            "ordinate type must be 2, 4, 5 or 6, found {ordinate_type}"
        ));
    }
    let points = usize::try_from(ints[1])
        .map_err(|_| format!("number of points must be >= 0, found {}", ints[1]))?;
    let even = match ints[2] {
        0 => false,
        1 => true,
        s => {
            return Err(format!(
                "abscissa spacing must be 0 (uneven) or 1 (even), found {s}"
            ))
        }
    };
    if let Some(v) = reals.iter().find(|v| !v.is_finite()) {
        return Err(format!(
            "abscissa minimum, increment and z value must be finite, found {v}"
        ));
    }
    if even && points > 1 && reals[1].partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) {
        return Err(format!(
            "even abscissa with increment {}: it must be > 0 (the {points} abscissae would not increase)",
            reals[1]
        ));
    }
    Ok(Record7 {
        ordinate_type: ordinate_type as i32,
        points,
        even,
        start: reals[0],
        step: reals[1],
        z_axis_value: reals[2],
    })
}

struct Record6 {
    function_type: i32,
    function_id: i32,
    version: i32,
    load_case: i32,
    response_entity: String,
    response_node: i64,
    response_direction: i32,
    reference_entity: String,
    reference_node: i64,
    reference_direction: i32,
}

fn to_i32(v: i64, what: &str) -> Result<i32, String> {
    i32::try_from(v).map_err(|_| format!("{what} {v} out of range"))
}

/// Parses record 6 (`2(I5,I10),2(1X,10A1,I10,I4)`): by column; by whitespace
/// (10 tokens) when the columns do not hold integers.
fn record6(line: &[u8]) -> Result<Record6, String> {
    let int_columns = [
        (0, 5),
        (5, 15),
        (15, 20),
        (20, 30),
        (41, 51),
        (51, 55),
        (66, 76),
        (76, 80),
    ];
    let by_columns = int_columns
        .iter()
        .map(|&(s, e)| text::parse_int_or_zero(text::column(line, s, e)))
        .collect::<Option<Vec<i64>>>()
        .map(|v| {
            (
                v,
                text::text_field(text::trim(text::column(line, 30, 41))),
                text::text_field(text::trim(text::column(line, 55, 66))),
            )
        });
    let by_tokens = || {
        let toks: Vec<&[u8]> = text::tokens(line).collect();
        if toks.len() != 10 {
            return None;
        }
        let ints = [0, 1, 2, 3, 5, 6, 8, 9]
            .iter()
            .map(|&k| text::parse_int(toks[k]))
            .collect::<Option<Vec<i64>>>()?;
        Some((ints, text::decode(toks[4]), text::decode(toks[7])))
    };
    let Some((i, response_entity, reference_entity)) = by_columns.or_else(by_tokens) else {
        return Err(format!(
            "expected function type, id, version, load case, response entity/node/direction, reference entity/node/direction (2(I5,I10),2(1X,10A1,I10,I4)), found '{}'",
            text::excerpt(line)
        ));
    };
    Ok(Record6 {
        function_type: to_i32(i[0], "function type")?,
        function_id: to_i32(i[1], "function id")?,
        version: to_i32(i[2], "version")?,
        load_case: to_i32(i[3], "load case")?,
        response_entity,
        response_node: i[4],
        response_direction: to_i32(i[5], "response direction")?,
        reference_entity,
        reference_node: i[6],
        reference_direction: to_i32(i[7], "reference direction")?,
    })
}

/// Parses records 8–11 (`I10,3I5,2(1X,20A1)`).
pub(crate) fn axis_record(line: &[u8]) -> Result<AxisCharacteristics, String> {
    let columns = [(0, 10), (10, 15), (15, 20), (20, 25)];
    let by_columns = columns
        .iter()
        .map(|&(s, e)| text::parse_int_or_zero(text::column(line, s, e)))
        .collect::<Option<Vec<i64>>>();
    let (ints, label, units_label) = match by_columns {
        Some(ints) => {
            // Units label: the rest of the line, so multi-byte characters in the
            // label do not cut it.
            let label = text::text_field(text::trim(text::column(line, 26, 46)));
            let units = text::text_field(text::trim(text::column_rest(line, 47)));
            (ints, label, units)
        }
        None => {
            // Whitespace-separated: 4 integers, then label and units label
            // separated by a run of 2+ blanks.
            let toks: Vec<&[u8]> = text::tokens(line).take(4).collect();
            let ints = toks
                .iter()
                .map(|t| text::parse_int(t))
                .collect::<Option<Vec<i64>>>();
            let Some(ints) = ints.filter(|v| v.len() == 4) else {
                return Err(format!(
                    "expected data type and length, force, temperature exponents (I10,3I5) then labels, found '{}'",
                    text::excerpt(line)
                ));
            };
            let after = toks[3].as_ptr() as usize - line.as_ptr() as usize + toks[3].len();
            let rest = text::trim(&line[after..]);
            let cut = rest.windows(2).position(|w| w == b"  ");
            let (label, units) = match cut {
                Some(c) => (&rest[..c], text::trim(&rest[c..])),
                None => (rest, &rest[rest.len()..]),
            };
            (ints, text::text_field(label), text::text_field(units))
        }
    };
    Ok(AxisCharacteristics {
        data_type: to_i32(ints[0], "data type")?,
        length_exponent: to_i32(ints[1], "length exponent")?,
        force_exponent: to_i32(ints[2], "force exponent")?,
        temperature_exponent: to_i32(ints[3], "temperature exponent")?,
        label,
        units_label,
    })
}

/// Error factory for one block.
pub(crate) struct Context<'a> {
    pub block: &'a Block,
}

impl Context<'_> {
    pub fn error(&self, line: Option<usize>, offset: usize, message: String) -> UffError {
        UffError {
            line,
            byte_offset: offset,
            dataset_index: Some(self.block.index),
            dataset_number: Some(self.block.number),
            message,
        }
    }
}

/// Parses a 58 or 58b block; `direct`: its values, when the streaming
/// reader read its data straight into them ([`direct_storage`]).
pub(crate) fn parse(
    bytes: &[u8],
    block: &Block,
    direct: Option<Ordinate>,
    notes: &mut Vec<String>,
) -> Result<Function58, UffError> {
    let cx = Context { block };
    let mut lines = Lines::new(bytes, block.text.clone(), block.line + 1);
    let mut header = Vec::with_capacity(11);
    for k in 0..11 {
        match lines.next() {
            Some(l) => header.push(l),
            None => {
                return Err(cx.error(
                    Some(block.close_line),
                    block.close_offset,
                    format!("dataset 58 ends after {k} of its 11 header records (records 1-11 expected before the data)"),
                ))
            }
        }
    }
    let at = |k: usize, m: String| cx.error(Some(header[k].number), header[k].start, m);
    let id_lines: [String; 5] = std::array::from_fn(|k| text::text_field(header[k].text));
    let r6 = record6(header[5].text).map_err(|m| at(5, format!("record 6: {m}")))?;
    let r7 = match &block.binary {
        Some(b) => b.record7.clone(),
        None => record7(header[6].text).map_err(|m| at(6, format!("record 7: {m}")))?,
    };
    let mut axes = Vec::with_capacity(4);
    for (k, line) in header.iter().enumerate().skip(7) {
        axes.push(axis_record(line.text).map_err(|m| at(k, format!("record {}: {m}", k + 1)))?);
    }
    let [abscissa_axis, numerator_axis, denominator_axis, z_axis]: [AxisCharacteristics; 4] = axes
        .try_into()
        .map_err(|_| at(10, "records 8-11 missing".into()))?;

    let (abscissa, ordinate) = match &block.binary {
        Some(b) => match direct {
            Some(values) => direct_data(values, b, &r7, &cx)?,
            None => binary_data(bytes, b, &r7, &cx)?,
        },
        None => ascii_data(&mut lines, &r7, &cx, notes)?.finish(&r7),
    };
    Ok(Function58 {
        id_lines,
        function_type: r6.function_type,
        function_id: r6.function_id,
        version: r6.version,
        load_case: r6.load_case,
        response_entity: r6.response_entity,
        response_node: r6.response_node,
        response_direction: r6.response_direction,
        reference_entity: r6.reference_entity,
        reference_node: r6.reference_node,
        reference_direction: r6.reference_direction,
        ordinate_type: r7.ordinate_type,
        abscissa,
        z_axis_value: r7.z_axis_value,
        abscissa_axis,
        numerator_axis,
        denominator_axis,
        z_axis,
        ordinate,
        binary: block.binary.is_some(),
    })
}

/// Receives data values in file order and files them as abscissa / ordinate.
struct Sink {
    complex: bool,
    even: bool,
    phase: u8,
    pending: f64,
    x: Vec<f64>,
    real: Vec<f64>,
    pairs: Vec<Complex64>,
}

impl Sink {
    /// `capacity`: points to reserve (bounded by the input size by the caller).
    fn new(r7: &Record7, capacity: usize) -> Self {
        let complex = r7.is_complex();
        Sink {
            complex,
            even: r7.even,
            phase: 0,
            pending: 0.0,
            x: if r7.even {
                Vec::new()
            } else {
                Vec::with_capacity(capacity)
            },
            real: if complex {
                Vec::new()
            } else {
                Vec::with_capacity(capacity)
            },
            pairs: if complex {
                Vec::with_capacity(capacity)
            } else {
                Vec::new()
            },
        }
    }

    #[inline]
    fn push(&mut self, v: f64) {
        if self.even {
            if !self.complex {
                self.real.push(v);
            } else if self.phase == 0 {
                self.pending = v;
                self.phase = 1;
            } else {
                self.pairs.push(Complex64::new(self.pending, v));
                self.phase = 0;
            }
            return;
        }
        match self.phase {
            0 => {
                self.x.push(v);
                self.phase = 1;
            }
            1 if !self.complex => {
                self.real.push(v);
                self.phase = 0;
            }
            1 => {
                self.pending = v;
                self.phase = 2;
            }
            _ => {
                self.pairs.push(Complex64::new(self.pending, v));
                self.phase = 0;
            }
        }
    }

    /// `push` for each value, with the common layouts copied in bulk.
    #[inline]
    fn extend(&mut self, values: &[f64]) {
        if self.even && !self.complex {
            self.real.extend_from_slice(values);
        } else if self.even && self.phase == 0 {
            let (pairs, rest) = values.split_at(values.len() & !1);
            self.pairs.extend_from_slice(bytemuck::cast_slice(pairs));
            for &v in rest {
                self.push(v);
            }
        } else {
            for &v in values {
                self.push(v);
            }
        }
    }

    fn finish(self, r7: &Record7) -> (Abscissa, Ordinate) {
        let abscissa = if r7.even {
            Abscissa::Even {
                start: r7.start,
                step: r7.step,
            }
        } else {
            Abscissa::Uneven(self.x)
        };
        let ordinate = if self.complex {
            Ordinate::Complex(self.pairs)
        } else {
            Ordinate::Real(self.real)
        };
        (abscissa, ordinate)
    }
}

/// Reads the ASCII data lines (record 12) of a 58 block.
fn ascii_data(
    lines: &mut Lines<'_>,
    r7: &Record7,
    cx: &Context<'_>,
    notes: &mut Vec<String>,
) -> Result<Sink, UffError> {
    let expected = r7
        .points
        .checked_mul(r7.values_per_point())
        .ok_or_else(|| {
            cx.error(
                Some(cx.block.line + 7),
                cx.block.start,
                format!("record 7: {} points is too many", r7.points),
            )
        })?;
    // Each value takes at least 2 bytes of text: never reserve more than the text holds.
    let room = (cx.block.text.end - lines.pos.min(cx.block.text.end)) / 2 / r7.values_per_point();
    let mut sink = Sink::new(r7, r7.points.min(room + 1));
    let widths = r7.ascii_widths();
    if let Some(values) = split_values(lines.rest(), widths, expected) {
        sink.extend(&values[0]);
        sink.extend(&values[1]);
        return Ok(sink);
    }
    let mut buf: Vec<f64> = Vec::with_capacity(8);
    let mut count = 0usize;
    let mut padded: Option<(usize, usize)> = None;
    for line in lines.by_ref() {
        buf.clear();
        if !text::reals_fixed(line.text, widths, &mut buf) {
            buf.clear();
            text::reals_tokens(line.text, &mut buf).map_err(|m| {
                cx.error(
                    Some(line.number),
                    line.start,
                    format!("data (record 12): {m}"),
                )
            })?;
        }
        if let Some((k, v)) = text::first_non_finite(&buf) {
            return Err(cx.error(
                Some(line.number),
                line.start,
                format!(
                    "data (record 12): value {} of the line is {v}; expected a finite number",
                    k + 1
                ),
            ));
        }
        let mut take = buf.len();
        if count + buf.len() > expected {
            // Some writers pad the last line with zeros beyond the declared points.
            let room = expected - count;
            if count == expected || buf[room..].iter().any(|&v| v != 0.0) {
                return Err(cx.error(
                    Some(line.number),
                    line.start,
                    format!(
                        "data (record 12): more values than record 7 declares ({} points, {} values)",
                        r7.points, expected
                    ),
                ));
            }
            padded = Some((line.number, buf.len() - room));
            take = room;
        }
        count += take;
        sink.extend(&buf[..take]);
    }
    if let Some((line, extra)) = padded {
        notes.push(format!(
            "line {line}: {extra} zero value(s) after the declared {} points ignored (padding)",
            r7.points
        ));
    }
    if count < expected {
        return Err(cx.error(
            Some(cx.block.close_line),
            cx.block.close_offset,
            format!(
                "data (record 12): record 7 declares {} points ({expected} values) but the dataset holds {count} values",
                r7.points
            ),
        ));
    }
    Ok(sink)
}

/// Data records of at least this many bytes are read by two threads.
const SPLIT_MIN_BYTES: usize = 4 << 20;

/// The values of data lines, or `None` at the first line that is not all
/// finite numbers.
fn line_values(region: &[u8], widths: &[usize]) -> Option<Vec<f64>> {
    let mut out = Vec::with_capacity(region.len() / 12 + 8);
    for line in Lines::new(region, 0..region.len(), 1) {
        let start = out.len();
        if !text::reals_fixed(line.text, widths, &mut out) {
            out.truncate(start);
            text::reals_tokens(line.text, &mut out).ok()?;
        }
    }
    if text::first_non_finite(&out).is_some() {
        return None;
    }
    Some(out)
}

/// A big data record read in two halves (cut at a line break) on two
/// threads. `None` when not worth it, or when the halves do not hold exactly
/// `expected` finite numbers: the caller then reads line by line, which
/// gives the exact error (line number) or padding note.
fn split_values(region: &[u8], widths: &[usize], expected: usize) -> Option<[Vec<f64>; 2]> {
    let parallel = std::thread::available_parallelism().map_or(1, |n| n.get());
    if region.len() < SPLIT_MIN_BYTES || parallel < 2 {
        return None;
    }
    let mid = region.len() / 2;
    let cut = memchr::memchr(b'\n', &region[mid..]).map_or(region.len(), |k| mid + k + 1);
    let (first, second) = region.split_at(cut);
    let (a, b) = std::thread::scope(|scope| {
        let other = scope.spawn(|| line_values(second, widths));
        let a = line_values(first, widths);
        match other.join() {
            Ok(b) => (a, b),
            Err(panic) => std::panic::resume_unwind(panic),
        }
    });
    let (a, b) = (a?, b?);
    (a.len() + b.len() == expected).then_some([a, b])
}

/// One stored binary value: its type, size and byte order.
trait Raw {
    /// The stored type (`f32` or `f64`), kept as is in the record.
    type Value: Copy + Into<f64>;
    const SIZE: usize;
    fn get(c: &[u8]) -> Self::Value;
    /// Real and complex ordinates of this precision.
    fn real(v: Vec<Self::Value>) -> Ordinate;
    fn complex(v: Vec<Complex<Self::Value>>) -> Ordinate;
}

macro_rules! raw {
    ($name:ident, $t:ty, $size:expr, $from:ident, $real:ident, $complex:ident) => {
        struct $name;
        impl Raw for $name {
            type Value = $t;
            const SIZE: usize = $size;
            #[inline(always)]
            fn get(c: &[u8]) -> $t {
                let mut a = [0u8; $size];
                a.copy_from_slice(&c[..$size]);
                <$t>::$from(a)
            }
            fn real(v: Vec<$t>) -> Ordinate {
                Ordinate::$real(v)
            }
            fn complex(v: Vec<Complex<$t>>) -> Ordinate {
                Ordinate::$complex(v)
            }
        }
    };
}
raw!(F32Le, f32, 4, from_le_bytes, RealSingle, ComplexSingle);
raw!(F32Be, f32, 4, from_be_bytes, RealSingle, ComplexSingle);
raw!(F64Le, f64, 8, from_le_bytes, Real, Complex);
raw!(F64Be, f64, 8, from_be_bytes, Real, Complex);

/// Even abscissa: the data are the ordinate values, one after the other.
fn even<R: Raw>(data: &[u8], complex: bool) -> Ordinate {
    if complex {
        R::complex(
            data.chunks_exact(2 * R::SIZE)
                .map(|c| Complex::new(R::get(c), R::get(&c[R::SIZE..])))
                .collect(),
        )
    } else {
        R::real(data.chunks_exact(R::SIZE).map(R::get).collect())
    }
}

/// Uneven abscissa: each point is its abscissa (type `X`, kept as `f64`)
/// followed by its ordinate value(s).
fn uneven<X: Raw, R: Raw>(data: &[u8], complex: bool) -> (Abscissa, Ordinate) {
    let per_point = X::SIZE + R::SIZE * (1 + usize::from(complex));
    let points = data.chunks_exact(per_point);
    let x = points.clone().map(|c| X::get(c).into()).collect();
    let ordinate = if complex {
        R::complex(
            points
                .map(|c| Complex::new(R::get(&c[X::SIZE..]), R::get(&c[X::SIZE + R::SIZE..])))
                .collect(),
        )
    } else {
        R::real(points.map(|c| R::get(&c[X::SIZE..])).collect())
    };
    (Abscissa::Uneven(x), ordinate)
}

/// Abscissa and ordinate of a 58b data block whose values are `R` (and an
/// uneven abscissa `abscissa_bytes` wide: `R`, or `X` when narrower).
fn decode<R: Raw, X: Raw>(
    data: &[u8],
    r7: &Record7,
    abscissa_bytes: usize,
) -> (Abscissa, Ordinate) {
    match (r7.even, r7.is_complex()) {
        (true, c) => (
            Abscissa::Even {
                start: r7.start,
                step: r7.step,
            },
            even::<R>(data, c),
        ),
        (false, c) if abscissa_bytes == R::SIZE => uneven::<R, R>(data, c),
        (false, c) => uneven::<X, R>(data, c),
    }
}

/// Whether every value stored in `data` (all `size` bytes wide, in the given
/// byte order) is finite: its exponent bits are not all ones. Checked on the
/// stored bytes, still in cache from the read, instead of sweeping the
/// decoded values (twice the size, cold): that sweep was 15% of the CPU time
/// of reading a 58b file. Branch-free, so it vectorises; only a block that
/// fails it is scanned for the exact point to report.
fn raw_all_finite(data: &[u8], size: usize, little_endian: bool) -> bool {
    fn any_all_ones<const N: usize, W: Copy + std::ops::BitAnd<Output = W> + PartialEq>(
        data: &[u8],
        mask: W,
        word: impl Fn([u8; N]) -> W,
    ) -> bool {
        let mut bad = false;
        for c in data.chunks_exact(N) {
            let mut a = [0u8; N];
            a.copy_from_slice(c);
            bad |= word(a) & mask == mask;
        }
        bad
    }
    const M32: u32 = 0x7f80_0000;
    const M64: u64 = 0x7ff0_0000_0000_0000;
    !match (size, little_endian) {
        (4, true) => any_all_ones(data, M32, u32::from_le_bytes),
        (4, false) => any_all_ones(data, M32, u32::from_be_bytes),
        (_, true) => any_all_ones(data, M64, u64::from_le_bytes),
        (_, false) => any_all_ones(data, M64, u64::from_be_bytes),
    }
}

/// Reads the binary data of a 58b block: abscissa and ordinate, values of
/// single precision kept as `f32`.
fn binary_data(
    bytes: &[u8],
    b: &Binary,
    r7: &Record7,
    cx: &Context<'_>,
) -> Result<(Abscissa, Ordinate), UffError> {
    let data = &bytes[b.data.clone()];
    let n = r7.points;
    let (abscissa, ordinate) = match (r7.value_bytes(), b.little_endian) {
        (4, true) => decode::<F32Le, F32Le>(data, r7, b.abscissa_bytes),
        (4, false) => decode::<F32Be, F32Be>(data, r7, b.abscissa_bytes),
        (_, true) => decode::<F64Le, F32Le>(data, r7, b.abscissa_bytes),
        (_, false) => decode::<F64Be, F32Be>(data, r7, b.abscissa_bytes),
    };
    if (r7.even || b.abscissa_bytes == r7.value_bytes())
        && raw_all_finite(data, r7.value_bytes(), b.little_endian)
    {
        return Ok((abscissa, ordinate));
    }
    check_finite(abscissa, ordinate, b, n, cx)
}

/// The abscissa and ordinate if all their values are finite; else the
/// error naming the first point that is not (its byte offset in the data).
fn check_finite(
    abscissa: Abscissa,
    ordinate: Ordinate,
    b: &Binary,
    n: usize,
    cx: &Context<'_>,
) -> Result<(Abscissa, Ordinate), UffError> {
    let x: &[f64] = match &abscissa {
        Abscissa::Uneven(x) => x,
        Abscissa::Even { .. } => &[],
    };
    let bad = text::first_non_finite(x)
        .map(|(i, v)| (i, v, "abscissa"))
        .or_else(|| {
            (0..ordinate.len()).find_map(|i| {
                let (re, im) = ordinate.at(i);
                let v = if re.is_finite() { im } else { re };
                (!v.is_finite()).then_some((i, v, "ordinate"))
            })
        });
    if let Some((i, v, what)) = bad {
        let point_bytes = b.data.len() / n.max(1);
        return Err(cx.error(
            None,
            b.data.start + i * point_bytes,
            format!(
                "58b data: {what} of point {} is {v}; expected a finite number",
                i + 1
            ),
        ));
    }
    Ok((abscissa, ordinate))
}

/// The memory of the values of `o` as bytes, in file order (for a complex
/// ordinate: re, im, re, im, ...; `Complex` is `#[repr(C)]`).
fn ordinate_bytes_mut(o: &mut Ordinate) -> &mut [u8] {
    match o {
        Ordinate::Real(v) => bytemuck::cast_slice_mut(v),
        Ordinate::Complex(v) => bytemuck::cast_slice_mut(v),
        Ordinate::RealSingle(v) => bytemuck::cast_slice_mut(v),
        Ordinate::ComplexSingle(v) => bytemuck::cast_slice_mut(v),
    }
}

/// Zeroed values for the data of a 58b block of an even function (record
/// 7), as [`binary_data`] would decode them, and their memory as bytes, of
/// exactly the data's length: the streaming reader reads the data into it.
/// Zeroed (not uninitialised: `Read` may look at its buffer) with
/// `alloc_zeroed`, whose fresh pages need no clearing.
pub(crate) fn direct_storage(r7: &Record7) -> Ordinate {
    let n = r7.points;
    match (r7.value_bytes(), r7.is_complex()) {
        (4, false) => Ordinate::RealSingle(bytemuck::zeroed_vec(n)),
        (4, true) => Ordinate::ComplexSingle(bytemuck::zeroed_vec(n)),
        (_, false) => Ordinate::Real(bytemuck::zeroed_vec(n)),
        (_, true) => Ordinate::Complex(bytemuck::zeroed_vec(n)),
    }
}

/// The bytes of `o` to read 58b data into (see [`direct_storage`]).
pub(crate) fn direct_bytes(o: &mut Ordinate) -> &mut [u8] {
    ordinate_bytes_mut(o)
}

/// The values of a 58b block of an even function whose data were read, as
/// stored, into `ordinate` ([`direct_storage`]): put in the host's byte
/// order and checked as [`binary_data`] does. Same result as
/// [`binary_data`] on the data bytes.
fn direct_data(
    mut ordinate: Ordinate,
    b: &Binary,
    r7: &Record7,
    cx: &Context<'_>,
) -> Result<(Abscissa, Ordinate), UffError> {
    let size = r7.value_bytes();
    let host_le = cfg!(target_endian = "little");
    let bytes = ordinate_bytes_mut(&mut ordinate);
    if bytes.len() != b.data.len() || !r7.even {
        return Err(cx.error(
            None,
            b.data.start,
            "internal error: 58b values do not match their data".into(),
        ));
    }
    if b.little_endian != host_le {
        for c in bytes.chunks_exact_mut(size) {
            c.reverse();
        }
    }
    let finite = raw_all_finite(bytes, size, host_le);
    let abscissa = Abscissa::Even {
        start: r7.start,
        step: r7.step,
    };
    if finite {
        return Ok((abscissa, ordinate));
    }
    check_finite(abscissa, ordinate, b, r7.points, cx)
}

#[cfg(test)]
mod raw_finite_tests {
    use super::raw_all_finite;

    fn bytes32(v: &[f32], le: bool) -> Vec<u8> {
        v.iter()
            .flat_map(|x| if le { x.to_le_bytes() } else { x.to_be_bytes() })
            .collect()
    }

    fn bytes64(v: &[f64], le: bool) -> Vec<u8> {
        v.iter()
            .flat_map(|x| if le { x.to_le_bytes() } else { x.to_be_bytes() })
            .collect()
    }

    /// Finite extremes pass; NaN, +inf and -inf fail at any position, in
    /// both widths and byte orders.
    #[test]
    fn flags_exactly_the_non_finite_values() {
        let f32s = [0.0, -0.0, f32::MAX, f32::MIN, f32::MIN_POSITIVE, 1e-45, 1.5];
        let f64s = [
            0.0,
            -0.0,
            f64::MAX,
            f64::MIN,
            f64::MIN_POSITIVE,
            5e-324,
            1.5,
        ];
        for le in [true, false] {
            assert!(raw_all_finite(&bytes32(&f32s, le), 4, le));
            assert!(raw_all_finite(&bytes64(&f64s, le), 8, le));
            for pos in 0..f32s.len() {
                for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
                    let mut v = f32s;
                    v[pos] = bad;
                    assert!(!raw_all_finite(&bytes32(&v, le), 4, le), "{bad} at {pos}");
                }
                for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                    let mut v = f64s;
                    v[pos] = bad;
                    assert!(!raw_all_finite(&bytes64(&v, le), 8, le), "{bad} at {pos}");
                }
            }
        }
        // The byte order matters: these bytes are finite read big-endian
        // (1.0039214) and NaN read little-endian.
        let b = [0x3f, 0x80, 0x80, 0x7f];
        assert!(f32::from_be_bytes(b).is_finite() && f32::from_le_bytes(b).is_nan());
        assert!(raw_all_finite(&b, 4, false));
        assert!(!raw_all_finite(&b, 4, true));
    }
}
