//! Text helpers for the ASCII parts of a UFF file: lines, lossy decoding,
//! Fortran fixed-column fields and Fortran-style numbers.
//!
//! Field widths follow the Fortran formats of the records (`I10`, `E13.5`,
//! `D25.16`, ...). Writers differ, so numeric records are read by column first
//! and by whitespace when the columns do not hold numbers.

use super::number;

/// One line of a text part, without its line break (`\n`, `\r\n`).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Line<'a> {
    pub text: &'a [u8],
    /// Byte offset of the line start in the file.
    pub start: usize,
    /// 1-based line number.
    pub number: usize,
}

/// Iterates the lines of `bytes[pos..end]`, counting line numbers from `number`.
///
/// In partial mode (`eof` false: more of the file may follow `end`), a last
/// line without its line break is not returned; `incomplete` is set instead.
#[derive(Clone, Debug)]
pub(crate) struct Lines<'a> {
    bytes: &'a [u8],
    pub pos: usize,
    end: usize,
    /// Number of the next line to be returned.
    pub number: usize,
    eof: bool,
    /// Set when `next` stopped at a line that may continue past `end`.
    pub incomplete: bool,
}

impl<'a> Lines<'a> {
    pub fn new(bytes: &'a [u8], range: std::ops::Range<usize>, number: usize) -> Self {
        Self::partial(bytes, range, number, true)
    }

    /// The bytes not yet returned.
    pub fn rest(&self) -> &'a [u8] {
        &self.bytes[self.pos..self.end]
    }

    /// Lines of a buffer that may end before the file does (`eof` false).
    pub fn partial(
        bytes: &'a [u8],
        range: std::ops::Range<usize>,
        number: usize,
        eof: bool,
    ) -> Self {
        let end = range.end.min(bytes.len());
        Lines {
            bytes,
            pos: range.start.min(end),
            end,
            number,
            eof,
            incomplete: false,
        }
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = Line<'a>;

    #[inline]
    fn next(&mut self) -> Option<Line<'a>> {
        if self.pos >= self.end {
            self.incomplete = !self.eof;
            return None;
        }
        let rest = &self.bytes[self.pos..self.end];
        let (text, advance) = match memchr::memchr(b'\n', rest) {
            Some(i) => (&rest[..i], i + 1),
            None if self.eof => (rest, rest.len()),
            None => {
                self.incomplete = true;
                return None;
            }
        };
        let text = text.strip_suffix(b"\r").unwrap_or(text);
        let line = Line {
            text,
            start: self.pos,
            number: self.number,
        };
        self.pos += advance;
        self.number += 1;
        Some(line)
    }
}

#[inline]
pub(crate) fn is_blank(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n' | 0)
}

/// `bytes` without leading and trailing blanks.
#[inline]
pub(crate) fn trim(bytes: &[u8]) -> &[u8] {
    let start = bytes
        .iter()
        .position(|&b| !is_blank(b))
        .unwrap_or(bytes.len());
    let end = bytes
        .iter()
        .rposition(|&b| !is_blank(b))
        .map_or(start, |i| i + 1);
    &bytes[start..end.max(start)]
}

/// `bytes` without trailing blanks.
#[inline]
pub(crate) fn trim_end(bytes: &[u8]) -> &[u8] {
    let end = bytes
        .iter()
        .rposition(|&b| !is_blank(b))
        .map_or(0, |i| i + 1);
    &bytes[..end]
}

/// True for a line holding only blanks.
pub(crate) fn is_blank_line(text: &[u8]) -> bool {
    text.iter().all(|&b| is_blank(b))
}

/// True for a dataset delimiter line: `-1` in format `I6`, any blanks around.
#[inline]
pub(crate) fn is_delimiter(text: &[u8]) -> bool {
    let mut i = 0;
    while i < text.len() && (text[i] == b' ' || text[i] == b'\t') {
        i += 1;
    }
    if text.len() < i + 2 || text[i] != b'-' || text[i + 1] != b'1' {
        return false;
    }
    text[i + 2..].iter().all(|&b| is_blank(b))
}

/// Decodes header text: UTF-8 when valid, otherwise Latin-1 (every byte is a
/// character), so decoding never fails.
pub(crate) fn decode(bytes: &[u8]) -> String {
    match std::str::from_utf8(bytes) {
        Ok(s) => s.to_owned(),
        Err(_) => bytes.iter().map(|&b| b as char).collect(),
    }
}

/// Decoded text field without trailing blanks.
pub(crate) fn text_field(bytes: &[u8]) -> String {
    decode(trim_end(bytes))
}

/// Columns `start..end` of a line (0-based, clamped to the line).
#[inline]
pub(crate) fn column(text: &[u8], start: usize, end: usize) -> &[u8] {
    let end = end.min(text.len());
    &text[start.min(end)..end]
}

/// Columns `start..` of a line.
#[inline]
pub(crate) fn column_rest(text: &[u8], start: usize) -> &[u8] {
    &text[start.min(text.len())..]
}

/// Whitespace-separated tokens of a line.
pub(crate) fn tokens(text: &[u8]) -> impl Iterator<Item = &[u8]> {
    text.split(|&b| is_blank(b)).filter(|t| !t.is_empty())
}

/// An integer field (`I` format); `None` if blank or not an integer.
#[inline]
pub(crate) fn parse_int(field: &[u8]) -> Option<i64> {
    let t = trim(field);
    if t.is_empty() {
        return None;
    }
    let t = t.strip_prefix(b"+").unwrap_or(t);
    lexical_core::parse::<i64>(t).ok()
}

/// An integer field that may be blank (blank reads as 0, as Fortran does).
#[inline]
pub(crate) fn parse_int_or_zero(field: &[u8]) -> Option<i64> {
    if trim(field).is_empty() {
        Some(0)
    } else {
        parse_int(field)
    }
}

/// A real field (`E`, `D` or `F` format); `None` if blank or not a number.
///
/// Accepts `1.0E+00`, 3-digit exponents `1.0E+000`, Fortran `D` exponents
/// `1.0D+00` and exponents without a letter `1.0-100`. Non-finite values are
/// returned as parsed; callers reject them.
#[inline]
pub(crate) fn parse_real(field: &[u8]) -> Option<f64> {
    let t = trim(field);
    if t.is_empty() {
        return None;
    }
    if let Some(v) = number::fast_real(t) {
        return Some(v);
    }
    match lexical_core::parse::<f64>(t) {
        Ok(v) => Some(v),
        Err(_) => parse_fortran_real(t),
    }
}

/// The general path of a data field (leading blanks already skipped):
/// lexical-core, then Fortran exponent rewriting. [`number::fast_real`] must
/// agree with it wherever it answers.
#[cfg(test)]
pub(crate) fn parse_real_general(field: &[u8]) -> Option<f64> {
    match lexical_core::parse::<f64>(field) {
        Ok(v) => Some(v),
        Err(_) => {
            let t = trim(field);
            if t.is_empty() {
                None
            } else {
                parse_fortran_real(t)
            }
        }
    }
}

/// Slow path of [`parse_real`]: rewrites Fortran exponents into `E` form.
#[cold]
fn parse_fortran_real(t: &[u8]) -> Option<f64> {
    const MAX: usize = 64;
    if t.len() >= MAX {
        return None;
    }
    let mut buf = [0u8; MAX + 1];
    let mut n = 0;
    let mut has_exponent = false;
    for (i, &b) in t.iter().enumerate() {
        let b = match b {
            b'D' | b'd' | b'Q' | b'q' => b'E',
            _ => b,
        };
        if b == b'E' || b == b'e' {
            has_exponent = true;
        }
        if (b == b'+' || b == b'-') && i > 0 && !has_exponent {
            let prev = t[i - 1];
            if prev.is_ascii_digit() || prev == b'.' {
                buf[n] = b'E';
                n += 1;
                has_exponent = true;
            }
        }
        buf[n] = b;
        n += 1;
    }
    lexical_core::parse::<f64>(&buf[..n]).ok()
}

/// Parses the integers at `columns` (start, end) of a line; if any is not an
/// integer, parses whitespace tokens instead. Blank columns read as 0.
pub(crate) fn ints_by_columns_or_tokens(
    text: &[u8],
    columns: &[(usize, usize)],
) -> Option<Vec<i64>> {
    let by_column: Option<Vec<i64>> = columns
        .iter()
        .map(|&(s, e)| parse_int_or_zero(column(text, s, e)))
        .collect();
    if let Some(v) = by_column {
        if !trim(text).is_empty() {
            return Some(v);
        }
    }
    let toks: Vec<&[u8]> = tokens(text).collect();
    if toks.is_empty() || toks.len() > columns.len() {
        return None;
    }
    let mut out: Vec<i64> = toks.iter().map(|t| parse_int(t)).collect::<Option<_>>()?;
    out.resize(columns.len(), 0);
    Some(out)
}

/// Parses reals in fields of `width` across a line; whitespace tokens when the
/// columns do not hold numbers. Values are appended to `out`.
pub(crate) fn reals_by_width_or_tokens(
    text: &[u8],
    width: usize,
    out: &mut Vec<f64>,
) -> Result<(), String> {
    let start = out.len();
    if reals_fixed(text, &[width], out) {
        return Ok(());
    }
    out.truncate(start);
    reals_tokens(text, out)
}

/// Reals of a line in fixed fields cycling through `widths`; blank fields are
/// skipped. False (with `out` partly filled) if a field is not a number.
#[inline]
pub(crate) fn reals_fixed(text: &[u8], widths: &[usize], out: &mut Vec<f64>) -> bool {
    let mut len = text.len();
    while len > 0 && matches!(text[len - 1], b' ' | b'\t' | b'\r' | 0) {
        len -= 1;
    }
    let mut pos = 0;
    let mut k = 0;
    while pos < len {
        let w = widths[k];
        k = if k + 1 == widths.len() { 0 } else { k + 1 };
        let end = (pos + w).min(len);
        // Fields are right-aligned: skip the leading blanks only (fast path);
        // 8 at a time, as their count varies with the sign (a branch per
        // blank would be mispredicted).
        let mut start = pos;
        while let Some(word) = text.get(start..start + 8).filter(|_| start + 8 <= end) {
            let mut a = [0u8; 8];
            a.copy_from_slice(word);
            let not_blank = u64::from_le_bytes(a) ^ 0x2020_2020_2020_2020;
            let skip = (not_blank.trailing_zeros() / 8) as usize;
            start += skip;
            if skip < 8 {
                break;
            }
        }
        while start < end && text[start] == b' ' {
            start += 1;
        }
        let field = &text[start..end];
        pos = end;
        if field.is_empty() {
            continue;
        }
        if let Some(v) = number::fast_real(field) {
            out.push(v);
            continue;
        }
        match lexical_core::parse::<f64>(field) {
            Ok(v) => out.push(v),
            Err(_) => {
                let t = trim(field);
                if t.is_empty() {
                    continue;
                }
                match parse_fortran_real(t) {
                    Some(v) => out.push(v),
                    None => return false,
                }
            }
        }
    }
    true
}

/// Reals of a line split at whitespace; the error names the bad token.
pub(crate) fn reals_tokens(text: &[u8], out: &mut Vec<f64>) -> Result<(), String> {
    for t in tokens(text) {
        match parse_real(t) {
            Some(v) => out.push(v),
            None => return Err(format!("expected a number, found '{}'", decode(t))),
        }
    }
    Ok(())
}

/// First non-finite value of `values`, as (index, value).
pub(crate) fn first_non_finite(values: &[f64]) -> Option<(usize, f64)> {
    values
        .iter()
        .position(|v| !v.is_finite())
        .map(|i| (i, values[i]))
}

/// A short, printable excerpt of a line for messages.
pub(crate) fn excerpt(text: &[u8]) -> String {
    let t = trim_end(text);
    let t = &t[..t.len().min(60)];
    decode(t)
        .chars()
        .map(|c| if c.is_control() { '?' } else { c })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fortran_reals() {
        assert_eq!(parse_real(b"  1.5E+00"), Some(1.5));
        assert_eq!(parse_real(b" 1.5E+000"), Some(1.5));
        assert_eq!(parse_real(b"1.5D+01"), Some(15.0));
        assert_eq!(parse_real(b"1.5d-01"), Some(0.15));
        assert_eq!(parse_real(b"1.0-100"), Some(1.0e-100));
        assert_eq!(parse_real(b"-2.5+3"), Some(-2500.0));
        assert_eq!(parse_real(b"+2.5"), Some(2.5));
        assert_eq!(parse_real(b"abc"), None);
        assert_eq!(parse_real(b"1.0 2.0"), None);
        assert_eq!(parse_real(b"   "), None);
    }

    #[test]
    fn run_together_columns() {
        let mut v = Vec::new();
        assert!(reals_fixed(
            b"-1.111111E-01 4.111111E+01 4.111111E+03-3.111111E+03",
            &[13],
            &mut v
        ));
        assert_eq!(v, vec![-0.1111111, 41.11111, 4111.111, -3111.111]);
    }

    #[test]
    fn delimiter() {
        assert!(is_delimiter(b"    -1"));
        assert!(is_delimiter(b"-1   \r"));
        assert!(!is_delimiter(b" -1.00000E+00"));
        assert!(!is_delimiter(b"    -10"));
    }

    #[test]
    fn latin1() {
        assert_eq!(decode(b"m/s\xb2"), "m/s²");
        assert_eq!(decode("m/s²".as_bytes()), "m/s²");
    }
}
