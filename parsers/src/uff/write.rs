//! Writing dataset 58 (ASCII) and 58b (binary).
//!
//! Layout as read by [`super::parse`] and pyuff: records 1–11 as in
//! [`super::function58`], data in `6E13.5` (types 2, 5), `4E20.12` (types 4, 6
//! even), `2(E13.5,E20.12)` (type 4 uneven), `E13.5,2E20.12` (type 6 uneven).
//! Record 7's minimum and increment use `E13.5` columns with as many digits as
//! fit. 58b data follow the 11 ASCII lines directly, an uneven abscissa in the
//! ordinate's precision (pyuff's layout), then `    -1` right after the data.
//! Lines end with LF; output bytes depend only on the input.

use std::fmt::Write as _;
use std::io::{self, Write};

use super::{Abscissa, AxisCharacteristics, Function58};

/// Byte order of 58b data.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum ByteOrder {
    /// Header code 1.
    #[default]
    Little,
    /// Header code 2.
    Big,
}

/// Options of [`write_functions_with`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct WriteOptions {
    pub byte_order: ByteOrder,
}

pub(crate) fn invalid(message: String) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidInput, message)
}

/// `x` in Fortran E form with `decimals` mantissa decimals and a signed
/// exponent of at least 2 digits: `-1.23457e-04`, `1.00000e+100`.
pub(crate) fn fortran_e(out: &mut String, x: f64, decimals: usize) {
    let s = format!("{x:.decimals$e}");
    let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let sign = if exponent < 0 { '-' } else { '+' };
    let _ = write!(out, "{mantissa}e{sign}{:02}", exponent.unsigned_abs());
}

/// `x` right-aligned in `width` columns with `decimals` decimals.
pub(crate) fn field_e(out: &mut String, x: f64, width: usize, decimals: usize) {
    let mut s = String::with_capacity(24);
    fortran_e(&mut s, x, decimals);
    for _ in s.len()..width {
        out.push(' ');
    }
    out.push_str(&s);
}

/// `x` in `width` columns with as many decimals as fit after one blank.
fn field_e_fit(out: &mut String, x: f64, width: usize) {
    let mut best = String::new();
    for decimals in (1..=12).rev() {
        best.clear();
        fortran_e(&mut best, x, decimals);
        if best.len() < width {
            break;
        }
    }
    for _ in best.len()..width {
        out.push(' ');
    }
    out.push_str(&best);
}

/// Text cut to at most `max` bytes on a character boundary.
pub(crate) fn cut(s: &str, max: usize) -> &str {
    let mut end = s.len().min(max);
    while !s.is_char_boundary(end) {
        end -= 1;
    }
    &s[..end]
}

/// An integer checked against its Fortran field width.
pub(crate) fn int_field(out: &mut String, v: i64, width: usize, what: &str) -> io::Result<()> {
    let s = v.to_string();
    if s.len() > width {
        return Err(invalid(format!(
            "{what} {v} does not fit in {width} columns"
        )));
    }
    let _ = write!(out, "{s:>width$}");
    Ok(())
}

fn axis_record(out: &mut String, a: &AxisCharacteristics, which: &str) -> io::Result<()> {
    int_field(out, a.data_type.into(), 10, &format!("{which} data type"))?;
    int_field(
        out,
        a.length_exponent.into(),
        5,
        &format!("{which} length exponent"),
    )?;
    int_field(
        out,
        a.force_exponent.into(),
        5,
        &format!("{which} force exponent"),
    )?;
    int_field(
        out,
        a.temperature_exponent.into(),
        5,
        &format!("{which} temperature exponent"),
    )?;
    let label = if a.label.is_empty() {
        "NONE"
    } else {
        cut(&a.label, 20)
    };
    let units = if a.units_label.is_empty() {
        "NONE"
    } else {
        cut(&a.units_label, 20)
    };
    let _ = writeln!(out, " {label:<20} {units:<20}");
    Ok(())
}

/// Checks that the ordinate type, ordinate and abscissa agree and are finite.
fn check(f: &Function58) -> io::Result<()> {
    let n = f.len();
    match (f.ordinate.is_complex(), f.ordinate_type) {
        (false, 2 | 4) | (true, 5 | 6) => {}
        (false, t) => {
            return Err(invalid(format!(
                "real ordinate needs ordinate type 2 or 4, not {t}"
            )))
        }
        (true, t) => {
            return Err(invalid(format!(
                "complex ordinate needs ordinate type 5 or 6, not {t}"
            )))
        }
    }
    let finite = (0..n).all(|i| {
        let (re, im) = f.ordinate.at(i);
        re.is_finite() && im.is_finite()
    });
    if !finite {
        return Err(invalid(
            "ordinate holds a non-finite value (NaN or infinity)".into(),
        ));
    }
    match &f.abscissa {
        Abscissa::Even { start, step } if !start.is_finite() || !step.is_finite() => {
            return Err(invalid("abscissa start and step must be finite".into()))
        }
        Abscissa::Uneven(x) if x.len() != n => {
            return Err(invalid(format!(
                "uneven abscissa has {} values for {n} points",
                x.len()
            )))
        }
        Abscissa::Uneven(x) if x.iter().any(|v| !v.is_finite()) => {
            return Err(invalid("abscissa holds a non-finite value".into()))
        }
        _ => {}
    }
    if !f.z_axis_value.is_finite() {
        return Err(invalid("z axis value must be finite".into()));
    }
    Ok(())
}

/// Records 1–11 (after the number line).
fn header(out: &mut String, f: &Function58) -> io::Result<()> {
    for id in &f.id_lines {
        let id = if id.is_empty() { "NONE" } else { cut(id, 80) };
        let _ = writeln!(out, "{id}");
    }
    int_field(out, f.function_type.into(), 5, "function type")?;
    int_field(out, f.function_id.into(), 10, "function id")?;
    int_field(out, f.version.into(), 5, "version")?;
    int_field(out, f.load_case.into(), 10, "load case")?;
    let entity = |e: &str| {
        if e.is_empty() {
            "NONE".to_owned()
        } else {
            cut(e, 10).to_owned()
        }
    };
    let _ = write!(out, " {:<10}", entity(&f.response_entity));
    int_field(out, f.response_node, 10, "response node")?;
    int_field(out, f.response_direction.into(), 4, "response direction")?;
    let _ = write!(out, " {:<10}", entity(&f.reference_entity));
    int_field(out, f.reference_node, 10, "reference node")?;
    int_field(out, f.reference_direction.into(), 4, "reference direction")?;
    out.push('\n');
    let (even, start, step) = match f.abscissa {
        Abscissa::Even { start, step } => (1, start, step),
        Abscissa::Uneven(_) => (0, 0.0, 0.0),
    };
    int_field(out, f.ordinate_type.into(), 10, "ordinate type")?;
    int_field(out, f.len() as i64, 10, "number of points")?;
    int_field(out, even, 10, "abscissa spacing")?;
    field_e_fit(out, start, 13);
    field_e_fit(out, step, 13);
    field_e_fit(out, f.z_axis_value, 13);
    out.push('\n');
    axis_record(out, &f.abscissa_axis, "abscissa")?;
    axis_record(out, &f.numerator_axis, "numerator")?;
    axis_record(out, &f.denominator_axis, "denominator")?;
    axis_record(out, &f.z_axis, "z axis")?;
    Ok(())
}

/// Calls `each` with the stored values in file order: ordinate (re, im), with
/// the abscissa before each point when uneven.
fn for_each_value(f: &Function58, mut each: impl FnMut(f64)) {
    let x = match &f.abscissa {
        Abscissa::Uneven(x) => Some(x),
        Abscissa::Even { .. } => None,
    };
    let complex = f.ordinate.is_complex();
    for i in 0..f.len() {
        if let Some(x) = x {
            each(x[i]);
        }
        let (re, im) = f.ordinate.at(i);
        each(re);
        if complex {
            each(im);
        }
    }
}

fn ascii_data<W: Write>(out: &mut W, f: &Function58, buf: &mut String) -> io::Result<()> {
    let even = matches!(f.abscissa, Abscissa::Even { .. });
    // (width, decimals) of the fields of one line.
    let line: &[(usize, usize)] = match (f.ordinate_type, even) {
        (2 | 5, _) => &[(13, 5); 6],
        (_, true) => &[(20, 12); 4],
        (4, false) => &[(13, 5), (20, 12), (13, 5), (20, 12)],
        _ => &[(13, 5), (20, 12), (20, 12)],
    };
    let mut k = 0;
    for_each_value(f, |v| {
        let (w, d) = line[k];
        field_e(buf, v, w, d);
        k += 1;
        if k == line.len() {
            buf.push('\n');
            k = 0;
        }
    });
    if k != 0 {
        buf.push('\n');
    }
    out.write_all(buf.as_bytes())
}

fn binary_data<W: Write>(out: &mut W, f: &Function58, order: ByteOrder) -> io::Result<()> {
    let single = matches!(f.ordinate_type, 2 | 5);
    let mut bytes = Vec::with_capacity(binary_len(f));
    let mut too_big = None;
    for_each_value(f, |v| {
        if single {
            let s = v as f32;
            if s.is_infinite() {
                too_big = Some(v);
            }
            bytes.extend_from_slice(&match order {
                ByteOrder::Little => s.to_le_bytes(),
                ByteOrder::Big => s.to_be_bytes(),
            });
        } else {
            bytes.extend_from_slice(&match order {
                ByteOrder::Little => v.to_le_bytes(),
                ByteOrder::Big => v.to_be_bytes(),
            });
        }
    });
    if let Some(v) = too_big {
        return Err(invalid(format!(
            "value {v} does not fit single precision (ordinate type {})",
            f.ordinate_type
        )));
    }
    out.write_all(&bytes)
}

/// Bytes of the 58b data of `f`.
fn binary_len(f: &Function58) -> usize {
    let value = if matches!(f.ordinate_type, 2 | 5) {
        4
    } else {
        8
    };
    let per_point = 1
        + usize::from(f.ordinate.is_complex())
        + usize::from(matches!(f.abscissa, Abscissa::Uneven(_)));
    f.len() * per_point * value
}

/// Writes one function as dataset 58 or 58b.
pub fn write_function<W: Write>(
    out: &mut W,
    f: &Function58,
    options: &WriteOptions,
) -> io::Result<()> {
    check(f)?;
    let mut buf = String::with_capacity(1024 + f.len() * 28);
    buf.push_str("    -1\n");
    if f.binary {
        let order = match options.byte_order {
            ByteOrder::Little => 1,
            ByteOrder::Big => 2,
        };
        let _ = writeln!(
            buf,
            "    58b{order:>6}{:>6}{:>12}{:>12}{:>6}{:>6}{:>12}{:>12}",
            2,
            11,
            binary_len(f),
            0,
            0,
            0,
            0
        );
    } else {
        buf.push_str("    58\n");
    }
    header(&mut buf, f)?;
    if f.binary {
        out.write_all(buf.as_bytes())?;
        binary_data(out, f, options.byte_order)?;
        out.write_all(b"    -1\n")
    } else {
        ascii_data(out, f, &mut buf)?;
        out.write_all(b"    -1\n")
    }
}

/// Writes functions as dataset 58 / 58b (by their `binary` flag) with `options`.
pub fn write_functions_with<W: Write>(
    out: &mut W,
    functions: &[Function58],
    options: &WriteOptions,
) -> io::Result<()> {
    for f in functions {
        write_function(out, f, options)?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fortran_fields() {
        let mut s = String::new();
        field_e(&mut s, -1.733310054988e-4, 20, 12);
        field_e(&mut s, 1.5e100, 13, 5);
        field_e(&mut s, 0.0, 13, 5);
        assert_eq!(s, " -1.733310054988e-04 1.50000e+100  0.00000e+00");
        let mut s = String::new();
        field_e_fit(&mut s, 0.1953125, 13);
        field_e_fit(&mut s, -0.1953125, 13);
        assert_eq!(s, " 1.953125e-01 -1.95312e-01");
    }
}
