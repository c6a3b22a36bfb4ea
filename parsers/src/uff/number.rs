//! Fast path for the fixed-format reals of UFF data records.
//!
//! Accepted form (anything else returns `None` and the caller falls back to
//! the general parser, lexical-core): `[+-]D+.D+[(E|e|D|d)[+-]d{1,3}]` or
//! `[+-]D+`, with at most 19 significant digits in total. This covers the
//! Fortran `E13.5` (`-1.23456E-01`), `E20.12`, `D25.16` and 3-digit exponent
//! (`1.23456E+000`) fields that writers produce.
//!
//! Conversion is Clinger's fast path: the digits are accumulated into a `u64`
//! mantissa `m` and a decimal exponent `e`; when `m <= 2^53` and `|e| <= 22`,
//! both `m` and `10^|e|` are exact doubles, so one IEEE multiplication or
//! division gives the correctly rounded result, bit-identical to
//! `str::parse::<f64>` and lexical-core. Other values return `None`.

/// Exact powers of ten as doubles: `10^0 ..= 10^22`.
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Largest mantissa for which `m as f64` is exact.
const MAX_EXACT: u64 = 1 << 53;

/// Parses `field` (no leading blanks) in the fast form; `None` when the field
/// is not in that form or the value needs the general (slow) algorithm.
#[inline(always)]
pub(crate) fn fast_real(field: &[u8]) -> Option<f64> {
    // Signs are data (random in FRFs): handled without branches.
    let n = field.len();
    let first = *field.first()?;
    let negative = first == b'-';
    let mut i = usize::from(negative | (first == b'+'));
    if n - i == 11 {
        if let Some(v) = e13_5(&field[i..]) {
            return Some(f64::from_bits(v.to_bits() | (u64::from(negative) << 63)));
        }
    }
    let mut mantissa: u64 = 0;
    let int_start = i;
    while i < n {
        let d = field[i].wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(d));
        i += 1;
    }
    let int_digits = i - int_start;
    if int_digits == 0 {
        return None;
    }
    let mut frac_digits = 0;
    if i < n && field[i] == b'.' {
        i += 1;
        let frac_start = i;
        while i < n {
            let d = field[i].wrapping_sub(b'0');
            if d > 9 {
                break;
            }
            mantissa = mantissa.wrapping_mul(10).wrapping_add(u64::from(d));
            i += 1;
        }
        frac_digits = i - frac_start;
        if frac_digits == 0 {
            return None;
        }
    }
    // 19 decimal digits always fit a u64 (no wrap above).
    if int_digits + frac_digits > 19 || mantissa > MAX_EXACT {
        return None;
    }
    let mut exponent: i32 = 0;
    if i < n {
        if !matches!(field[i], b'E' | b'e' | b'D' | b'd') {
            return None;
        }
        i += 1;
        let sign = *field.get(i)?;
        let exp_negative = sign == b'-';
        i += usize::from(exp_negative | (sign == b'+'));
        let digits = n - i;
        if !(1..=3).contains(&digits) {
            return None;
        }
        for &b in &field[i..] {
            let d = b.wrapping_sub(b'0');
            if d > 9 {
                return None;
            }
            exponent = exponent * 10 + i32::from(d);
        }
        // exponent - 2 * exponent * negative, without a branch.
        exponent -= 2 * exponent * i32::from(exp_negative);
    }
    let e10 = exponent - frac_digits as i32;
    if !(-22..=22).contains(&e10) {
        return None;
    }
    // One of the two operations is by 10^0 = 1 (exact), the other is the one
    // correctly rounded operation: no branch on the exponent's sign.
    let up = POW10[e10.max(0) as usize];
    let down = POW10[(-e10).max(0) as usize];
    let value = mantissa as f64 * up / down;
    Some(f64::from_bits(
        value.to_bits() | (u64::from(negative) << 63),
    ))
}

/// The `E13.5` shape without its sign, `d.dddddE+dd` (11 bytes): straight-line
/// code, no loops. `None` if `t` has another shape.
#[inline(always)]
fn e13_5(t: &[u8]) -> Option<f64> {
    let t: &[u8; 11] = t.try_into().ok()?;
    let d = |k: usize| u32::from(t[k].wrapping_sub(b'0'));
    let (d0, d1, d2, d3, d4, d5, e1, e2) = (d(0), d(2), d(3), d(4), d(5), d(6), d(9), d(10));
    let digits_ok = (d0 < 10)
        & (d1 < 10)
        & (d2 < 10)
        & (d3 < 10)
        & (d4 < 10)
        & (d5 < 10)
        & (e1 < 10)
        & (e2 < 10);
    let letter_ok = matches!(t[7], b'E' | b'e' | b'D' | b'd');
    let sign_ok = (t[8] == b'-') | (t[8] == b'+');
    if !(digits_ok & letter_ok & sign_ok & (t[1] == b'.')) {
        return None;
    }
    let mantissa = d0 * 100_000 + d1 * 10_000 + d2 * 1000 + d3 * 100 + d4 * 10 + d5;
    let exponent = (e1 * 10 + e2) as i32;
    let e10 = if t[8] == b'-' { -exponent } else { exponent } - 5;
    if !(-22..=22).contains(&e10) {
        return None;
    }
    let up = POW10[e10.max(0) as usize];
    let down = POW10[(-e10).max(0) as usize];
    Some(f64::from(mantissa) * up / down)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// xorshift64*: deterministic test values.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
    }

    /// Fortran `E` format with `digits` after the point and a 2- or 3-digit exponent.
    fn fortran(v: f64, digits: usize, exp_digits: usize, letter: char) -> String {
        let s = format!("{:.*e}", digits, v); // "1.23456e-1"
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let e: i32 = e.parse().unwrap_or(0);
        let sign = if e < 0 { '-' } else { '+' };
        format!("{m}{letter}{sign}{:0w$}", e.abs(), w = exp_digits)
    }

    #[test]
    fn fixed_forms() {
        assert_eq!(fast_real(b"-1.23456E-01"), Some(-0.123456));
        assert_eq!(fast_real(b"1.5E+000"), Some(1.5));
        assert_eq!(fast_real(b"1.5D+01"), Some(15.0));
        assert_eq!(fast_real(b"+2.5"), Some(2.5));
        assert_eq!(fast_real(b"42"), Some(42.0));
        assert_eq!(
            fast_real(b"-0.00000E+00").map(f64::to_bits),
            Some((-0.0f64).to_bits())
        );
        for bad in [
            &b""[..],
            b"-",
            b".5",
            b"1.",
            b"1.0-100",
            b"1.0E",
            b"1.0E+",
            b"1.0E+0001",
            b"1.0 ",
            b"1.0E+01 ",
            b"1.0Q+01",
            b"1e300",
            b"12345678901234567890.0",
            b"nan",
        ] {
            assert_eq!(fast_real(bad), None, "{}", String::from_utf8_lossy(bad));
        }
    }

    /// Random values in the fixed formats: fast path bit-identical to
    /// `str::parse::<f64>` whenever it answers, and it answers for the usual range.
    #[test]
    fn random_values_are_correctly_rounded() {
        let mut rng = Rng(0x1234_5678_9abc_def1);
        let (mut fast, mut total) = (0usize, 0usize);
        let count = if cfg!(debug_assertions) {
            200_000
        } else {
            2_000_000
        };
        for k in 0..count {
            let bits = rng.next();
            // Half: FRF-like magnitudes 1e-12..1e12; half: any finite double.
            let v = if k % 2 == 0 {
                let mant = (bits >> 11) as f64 / (1u64 << 53) as f64 + 0.1;
                let e = (bits % 25) as i32 - 12;
                mant * 10f64.powi(e) * if bits & 1 == 0 { 1.0 } else { -1.0 }
            } else {
                f64::from_bits(bits)
            };
            if !v.is_finite() {
                continue;
            }
            let digits = [5, 12, 16, 17][k % 4];
            let exp_digits = if k % 3 == 0 { 3 } else { 2 };
            let letter = if k % 5 == 0 { 'D' } else { 'E' };
            let s = fortran(v, digits, exp_digits, letter);
            let reference: f64 = s.replace('D', "E").parse().expect("valid");
            total += 1;
            if let Some(x) = fast_real(s.as_bytes()) {
                fast += 1;
                assert_eq!(x.to_bits(), reference.to_bits(), "{s}");
            }
        }
        assert!(fast * 4 > total, "fast path used for {fast} of {total}");
    }

    /// Random strings of the field alphabet: when the fast path answers, the
    /// general path (lexical-core, then Fortran rewriting) gives the same bits.
    #[test]
    fn agrees_with_general_parser() {
        let mut rng = Rng(0x0dd_ba11_cafe_f00d);
        let pick = |rng: &mut Rng, set: &[u8]| set[(rng.next() % set.len() as u64) as usize];
        for _ in 0..300_000 {
            // Grammar-shaped strings: [sign] digits [. digits] [letter [sign] digits],
            // each part possibly empty or too long.
            let mut s = Vec::new();
            let digits = |rng: &mut Rng, s: &mut Vec<u8>, max: u64| {
                for _ in 0..rng.next() % (max + 1) {
                    s.push(pick(rng, b"0123456789"));
                }
            };
            if rng.next() % 2 == 0 {
                s.push(pick(&mut rng, b"+- "));
            }
            digits(&mut rng, &mut s, 3);
            if rng.next() % 4 != 0 {
                s.push(b'.');
            }
            digits(&mut rng, &mut s, 18);
            if rng.next() % 4 != 0 {
                s.push(pick(&mut rng, b"EeDdQ+-"));
                if rng.next() % 2 == 0 {
                    s.push(pick(&mut rng, b"+-"));
                }
                digits(&mut rng, &mut s, 4);
            }
            if let Some(x) = fast_real(&s) {
                let general = super::super::text::parse_real_general(&s);
                assert_eq!(
                    Some(x.to_bits()),
                    general.map(f64::to_bits),
                    "{}",
                    String::from_utf8_lossy(&s)
                );
            }
        }
    }
}
