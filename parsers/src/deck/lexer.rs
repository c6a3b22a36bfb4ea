//! Tokens of one deck line and the nom parsers for the value syntax:
//! numbers (`1e-4`, `1.5E+03`, `2.0D+03`), IDs, ID ranges (`1-3,7,9-12`).

use nom::branch::alt;
use nom::bytes::complete::take_till1;
use nom::character::complete::{char, digit0, digit1, one_of, space0};
use nom::combinator::{all_consuming, map_res, opt, recognize};
use nom::multi::{many0, separated_list1};
use nom::{IResult, Parser};

use super::{DeckError, Pos};

/// A token of a line: its text and 1-based position.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Token<'a> {
    pub text: &'a str,
    pub pos: Pos,
}

impl<'a> Token<'a> {
    /// The position of byte offset `offset` inside this token.
    pub fn pos_at(&self, offset: usize) -> Pos {
        let chars = self.text[..offset.min(self.text.len())].chars().count() as u32;
        Pos::new(self.pos.line, self.pos.column + chars)
    }
}

fn is_blank(c: char) -> bool {
    c == ' ' || c == '\t'
}

/// The line without its comment (`#` to the end of the line) and trailing `\r`.
pub(crate) fn strip_comment(line: &str) -> &str {
    let line = line.strip_suffix('\r').unwrap_or(line);
    match line.find('#') {
        Some(i) => &line[..i],
        None => line,
    }
}

fn tokens_raw(input: &str) -> IResult<&str, Vec<&str>> {
    let (rest, toks) = many0((space0, take_till1(is_blank)).map(|(_, t)| t)).parse(input)?;
    let (rest, _) = space0(rest)?;
    Ok((rest, toks))
}

/// Split a (comment-stripped) line into tokens separated by spaces or tabs.
pub(crate) fn tokenize(line: &str, line_no: u32) -> Vec<Token<'_>> {
    // `tokens_raw` cannot fail on any input: `many0` stops at the end.
    let toks = tokens_raw(line).map(|(_, t)| t).unwrap_or_default();
    toks.into_iter()
        .map(|text| {
            let offset = text.as_ptr() as usize - line.as_ptr() as usize;
            let column = line[..offset].chars().count() as u32 + 1;
            Token {
                text,
                pos: Pos::new(line_no, column),
            }
        })
        .collect()
}

/// Recognise a decimal number with an optional `e`/`E`/`D`/`d` exponent.
fn number_text(input: &str) -> IResult<&str, &str> {
    recognize((
        opt(one_of("+-")),
        alt((
            recognize((digit1, opt((char('.'), digit0)))),
            recognize((char('.'), digit1)),
        )),
        opt((one_of("eEdD"), opt(one_of("+-")), digit1)),
    ))
    .parse(input)
}

/// A finite floating-point number occupying the whole of `text`.
pub(crate) fn number(text: &str) -> Option<f64> {
    // The grammar check must consume all of `text`; the value is then read from
    // `text` itself (nom 8's `recognize` over this tuple returned a truncated
    // slice such as "0." for "0.001").
    all_consuming(number_text).parse(text).ok()?;
    let v: f64 = text.replace(['d', 'D'], "e").parse().ok()?;
    v.is_finite().then_some(v)
}

/// A number token, or an error naming what was expected.
pub(crate) fn number_at(text: &str, pos: Pos, what: &str) -> Result<f64, DeckError> {
    number(text)
        .ok_or_else(|| DeckError::new(pos, format!("expected a number for {what}, found `{text}`")))
}

fn id_value(input: &str) -> IResult<&str, u32> {
    map_res(digit1, |s: &str| s.parse::<u32>()).parse(input)
}

/// A positive integer ID occupying the whole of `text`.
pub(crate) fn id(text: &str) -> Option<u32> {
    let (_, v) = all_consuming(id_value).parse(text).ok()?;
    (v > 0).then_some(v)
}

/// An ID token, or an error naming what was expected.
pub(crate) fn id_at(tok: &Token<'_>, what: &str) -> Result<u32, DeckError> {
    id(tok.text).ok_or_else(|| {
        DeckError::new(
            tok.pos,
            format!(
                "expected {what} (a positive integer ID), found `{}`",
                tok.text
            ),
        )
    })
}

type RawRange<'a> = (&'a str, u32, Option<u32>);

fn id_range(input: &str) -> IResult<&str, RawRange<'_>> {
    let start = input;
    let (rest, (a, b)) = (id_value, opt((char('-'), id_value).map(|(_, b)| b))).parse(input)?;
    Ok((rest, (start, a, b)))
}

/// An ID list such as `1-3,7,9-12`: (first, last, byte offset in `text`).
pub(crate) fn id_list(tok: &Token<'_>) -> Result<Vec<(u32, u32, Pos)>, DeckError> {
    let text = tok.text;
    let parsed = all_consuming(separated_list1(char(','), id_range)).parse(text);
    let ranges = match parsed {
        Ok((_, r)) => r,
        Err(_) => {
            return Err(DeckError::new(
                tok.pos,
                format!("expected an ID list such as `1-3,7,9-12`, found `{text}`"),
            ))
        }
    };
    let mut out = Vec::with_capacity(ranges.len());
    for (start, a, b) in ranges {
        let offset = start.as_ptr() as usize - text.as_ptr() as usize;
        let pos = tok.pos_at(offset);
        let b = b.unwrap_or(a);
        if a == 0 || b == 0 {
            return Err(DeckError::new(pos, "IDs are positive integers; found 0"));
        }
        if b < a {
            return Err(DeckError::new(
                pos,
                format!("empty ID range {a}-{b}: the first ID must not exceed the last"),
            ));
        }
        out.push((a, b, pos));
    }
    Ok(out)
}

/// A name (material, section, parameter): a token without `=` or `,`.
pub(crate) fn name_at(tok: &Token<'_>, what: &str) -> Result<String, DeckError> {
    if tok.text.contains(['=', ',']) {
        return Err(DeckError::new(
            tok.pos,
            format!(
                "expected {what} (a name without `=` or `,`), found `{}`",
                tok.text
            ),
        ));
    }
    Ok(tok.text.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers() {
        assert_eq!(number("1e-4"), Some(1e-4));
        assert_eq!(number("1.5E+03"), Some(1500.0));
        assert_eq!(number("2.0D+03"), Some(2000.0));
        assert_eq!(number("-.5"), Some(-0.5));
        assert_eq!(number("7."), Some(7.0));
        assert_eq!(number("0.001"), Some(0.001));
        assert_eq!(number("0.0075"), Some(0.0075));
        assert_eq!(number("-12.5e-3"), Some(-0.0125));
        assert_eq!(number("+3"), Some(3.0));
        assert_eq!(number("1e999"), None);
        assert_eq!(number("1e"), None);
        assert_eq!(number("abc"), None);
        assert_eq!(number("1.2.3"), None);
        assert_eq!(number("nan"), None);
    }

    #[test]
    fn tokens_and_columns() {
        let t = tokenize("  node\t 12  0 1", 3);
        let cols: Vec<_> = t.iter().map(|t| (t.text, t.pos.column)).collect();
        assert_eq!(cols, vec![("node", 3), ("12", 9), ("0", 13), ("1", 15)]);
    }

    #[test]
    fn ranges() {
        let tok = Token {
            text: "1-3,7,9-12",
            pos: Pos::new(1, 10),
        };
        let r = id_list(&tok).unwrap();
        let r: Vec<_> = r.iter().map(|(a, b, p)| (*a, *b, p.column)).collect();
        assert_eq!(r, vec![(1, 3, 10), (7, 7, 14), (9, 12, 16)]);
        let bad = Token {
            text: "1-3,",
            pos: Pos::new(1, 1),
        };
        assert!(id_list(&bad).is_err());
    }
}
