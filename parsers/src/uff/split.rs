//! Splitting a file into dataset blocks.
//!
//! A dataset is `    -1` (format `I6`), its number (`I6`, `58b` for binary
//! 58), its records, and a closing `    -1`. A 58b dataset has a header line
//! `I6,1A1,I6,I6,I12,I12,I6,I6,I12,I12` (number, `b`, byte order 1=little
//! 2=big, floating point format 2=IEEE, ASCII line count (11), byte count, 4
//! unused) and, after its 11 ASCII lines, exactly `byte count` bytes of data.
//!
//! Line numbers count line breaks in text parts; the binary data of a 58b
//! dataset counts as one line.

use std::ops::Range;

use super::function58::{self, Record7};
use super::text::{self, Line, Lines};
use super::UffError;

/// One dataset found in the file; no content parsed yet beyond what the
/// split needs.
#[derive(Clone, Debug)]
pub(crate) struct Block {
    pub index: usize,
    pub number: u32,
    /// Line and byte offset of the dataset number line.
    pub line: usize,
    pub start: usize,
    /// The ASCII records after the number line: up to the closing `-1` (58b:
    /// the ASCII header lines only).
    pub text: Range<usize>,
    /// Line and offset of the closing `-1`.
    pub close_line: usize,
    pub close_offset: usize,
    pub binary: Option<Binary>,
    /// Remarks made while splitting (repaired quirks).
    pub notes: Vec<String>,
}

/// Where and how the data of a 58b dataset are stored.
#[derive(Clone, Debug)]
pub(crate) struct Binary {
    pub little_endian: bool,
    pub data: Range<usize>,
    /// Bytes of one abscissa value of an uneven function (4 or 8).
    pub abscissa_bytes: usize,
    pub record7: Record7,
}

fn error(
    line: Option<usize>,
    offset: usize,
    index: Option<usize>,
    number: Option<u32>,
    message: String,
) -> UffError {
    UffError {
        line,
        byte_offset: offset,
        dataset_index: index,
        dataset_number: number,
        message,
    }
}

/// Dataset number of a number line (`    58`, `    58b`, `  2411`): number and
/// whether the dataset is binary.
fn dataset_number(text: &[u8]) -> Option<(u32, bool)> {
    let first = text::tokens(text).next()?;
    let (digits, binary) = match first.last() {
        Some(b'b') | Some(b'B') => (&first[..first.len() - 1], true),
        _ => (first, false),
    };
    let number = lexical_core::parse::<u32>(digits).ok()?;
    Some((number, binary))
}

/// Outcome of one [`Splitter::next`] call.
#[derive(Debug)]
pub(crate) enum Step {
    /// The next dataset block.
    Block(Block),
    /// The buffer ends before the next block does: call again with more bytes.
    NeedMore,
    /// No more blocks (the file ended).
    End,
    /// A 58b dataset whose data (`binary.data`, at least `direct_min` bytes
    /// beyond the buffer) the caller reads itself, straight into the values'
    /// memory: from `binary.data.start` on, the buffer's bytes are its data.
    /// The caller then calls [`Splitter::skip_direct`] and continues with a
    /// buffer that starts right after the data; the next step is
    /// [`Step::Closed`] (or an error). Its `close_line` and `close_offset`
    /// are not known yet.
    Direct(Block),
    /// The closing `-1` after the data of the [`Step::Direct`] dataset: its
    /// line and buffer position (in the buffer after the data).
    Closed { line: usize, offset: usize },
}

/// Inner outcome of one block attempt.
enum Attempt {
    Block(Block),
    NeedMore,
    /// The file ends right after a `-1` delimiter.
    EndOfFile,
    Direct(Block, Awaiting),
}

/// A [`Step::Direct`] dataset whose data the caller reads.
#[derive(Debug)]
pub(crate) struct Awaiting {
    /// Its data (their start a file offset once returned).
    section: DataSection,
    /// Bytes of the data (the declared count).
    len: usize,
}

/// Splits a file into dataset blocks, incrementally.
///
/// The caller passes a buffer holding the file from some point on (`eof`
/// true when the buffer reaches the end of the file). Positions in blocks and
/// errors are relative to that buffer; line numbers are absolute. A block is
/// only returned once its last byte (and what decides where it ends, e.g. the
/// `-1` after 58b data) is in the buffer, so results do not depend on how the
/// file is cut into buffers. After [`Step::NeedMore`], call again with the
/// same bytes plus more after them (bytes before [`Splitter::pos`] may be
/// dropped with [`Splitter::consume`]).
/// True for a line holding one unsigned integer of at most 6 digits (blanks
/// around): how a dataset's number line reads (`    58`, `  2414`).
fn looks_like_dataset_number(text: &[u8]) -> bool {
    let start = text.iter().position(|&b| !text::is_blank(b));
    let end = text.iter().rposition(|&b| !text::is_blank(b));
    match (start, end) {
        (Some(a), Some(b)) => b - a < 6 && text[a..=b].iter().all(u8::is_ascii_digit),
        _ => false,
    }
}

/// The note on lines outside any dataset: when the first of them reads like
/// a dataset number, a `-1` delimiter was most likely lost before it (and
/// with it that whole dataset).
fn stray_note((first, count, numbered): (usize, usize, bool)) -> String {
    let mut note = format!("line {first}: {count} line(s) outside any dataset ignored");
    if numbered {
        note.push_str(&format!(
            "; line {first} reads like a dataset number: a '    -1' delimiter seems missing before it, so that dataset was skipped (add the -1 line)"
        ));
    }
    note
}

#[derive(Debug)]
pub(crate) struct Splitter {
    /// Remarks made while splitting (stray lines, repeated delimiters).
    pub notes: Vec<String>,
    /// Buffer position of the first byte not yet split.
    pos: usize,
    /// Line number at `pos`.
    number: usize,
    /// (first line, count, whether the first line reads like a dataset
    /// number) of text outside datasets, not yet reported.
    stray: Option<(usize, usize, bool)>,
    /// File offset of the buffer's first byte (moved by `consume`).
    base: usize,
    /// Blocks returned so far.
    blocks: usize,
    finished: bool,
    /// 58b data of at least this many bytes beyond the buffer are left to
    /// the caller ([`Step::Direct`]); `None`: never.
    pub direct_min: Option<usize>,
    /// The [`Step::Direct`] dataset, until its closing `-1` is found.
    awaiting: Option<Awaiting>,
}

impl Default for Splitter {
    fn default() -> Self {
        Splitter {
            notes: Vec::new(),
            pos: 0,
            number: 1,
            stray: None,
            base: 0,
            blocks: 0,
            finished: false,
            direct_min: None,
            awaiting: None,
        }
    }
}

impl Splitter {
    /// Buffer position of the first byte not yet split.
    pub fn pos(&self) -> usize {
        self.pos
    }

    /// The caller dropped the first `n` (<= `pos`) bytes of its buffer.
    pub fn consume(&mut self, n: usize) {
        let n = n.min(self.pos);
        self.pos -= n;
        self.base += n;
    }

    /// After [`Step::Direct`]: the caller read the data itself, and its next
    /// buffer starts right after them, `n` bytes after the current one's
    /// start.
    pub fn skip_direct(&mut self, n: usize) {
        debug_assert!(self.awaiting.is_some() && n >= self.pos);
        self.base += n;
        self.pos = 0;
    }

    /// After [`Step::Direct`]: the file ended `available` bytes into the
    /// data. The whole-file split's error for that file.
    pub fn direct_truncated(&mut self, available: usize) -> UffError {
        self.finished = true;
        match self.awaiting.take() {
            Some(a) => a.section.error(available),
            None => error(
                None,
                self.base,
                None,
                None,
                "internal error: no 58b data pending".into(),
            ),
        }
    }

    /// The closing `-1` after the data of a [`Step::Direct`] dataset.
    fn closed(&mut self, bytes: &[u8], eof: bool) -> Result<Step, UffError> {
        let Some(a) = self.awaiting.take() else {
            return Ok(Step::NeedMore);
        };
        match closing_after(bytes, self.pos, eof) {
            Err(()) => {
                self.awaiting = Some(a);
                Ok(Step::NeedMore)
            }
            Ok(Some((line_start, after, breaks))) => {
                self.pos = after;
                self.number = a.section.data_line + breaks + 1;
                self.blocks += 1;
                Ok(Step::Closed {
                    line: a.section.data_line + breaks,
                    offset: line_start,
                })
            }
            Ok(None) => {
                // All the declared bytes were read, and no `-1` follows them.
                self.finished = true;
                Err(a.section.error(a.len))
            }
        }
    }

    /// The next block of `bytes[pos..]`; `eof` tells whether `bytes` ends
    /// where the file does. Block positions are relative to `bytes`; error
    /// offsets are file offsets.
    pub fn next(&mut self, bytes: &[u8], eof: bool) -> Result<Step, UffError> {
        if self.finished {
            return Ok(Step::End);
        }
        if self.awaiting.is_some() {
            return self.closed(bytes, eof);
        }
        let mut lines = Lines::partial(bytes, self.pos..bytes.len(), self.number, eof);
        loop {
            let Some(line) = lines.next() else {
                if lines.incomplete {
                    return Ok(Step::NeedMore);
                }
                return self.finish();
            };
            if !text::is_delimiter(line.text) {
                if !text::is_blank_line(line.text) {
                    self.stray = Some(self.stray.map_or(
                        (line.number, 1, looks_like_dataset_number(line.text)),
                        |(l, c, n)| (l, c + 1, n),
                    ));
                }
                self.pos = lines.pos;
                self.number = lines.number;
                continue;
            }
            let (notes, stray) = (self.notes.len(), self.stray);
            match self.block(bytes, &mut lines, line, eof) {
                Ok(Attempt::Block(block)) => {
                    self.pos = lines.pos;
                    self.number = lines.number;
                    self.blocks += 1;
                    return Ok(Step::Block(block));
                }
                Ok(Attempt::NeedMore) => {
                    // Undo the attempt: it is made again with more bytes.
                    self.notes.truncate(notes);
                    self.stray = stray;
                    return Ok(Step::NeedMore);
                }
                Ok(Attempt::EndOfFile) => return self.finish(),
                Ok(Attempt::Direct(block, mut awaiting)) => {
                    self.pos = lines.pos;
                    self.number = lines.number;
                    awaiting.section.data_start += self.base;
                    self.awaiting = Some(awaiting);
                    return Ok(Step::Direct(block));
                }
                Err(mut e) => {
                    self.finished = true;
                    e.byte_offset += self.base;
                    return Err(e);
                }
            }
        }
    }

    fn finish(&mut self) -> Result<Step, UffError> {
        self.finished = true;
        if let Some(stray) = self.stray.take() {
            self.notes.push(stray_note(stray));
        }
        if self.blocks == 0 {
            return Err(error(
                None,
                0,
                None,
                None,
                "no UFF dataset found: expected a '    -1' line followed by a dataset number"
                    .into(),
            ));
        }
        Ok(Step::End)
    }

    /// One dataset starting at the delimiter `line`.
    fn block(
        &mut self,
        bytes: &[u8],
        lines: &mut Lines<'_>,
        line: Line<'_>,
        eof: bool,
    ) -> Result<Attempt, UffError> {
        if let Some(stray) = self.stray.take() {
            self.notes.push(stray_note(stray));
        }
        // Number line; extra `-1` lines in a row are tolerated.
        let mut number_line = lines.next();
        while let Some(l) = number_line.filter(|l| text::is_delimiter(l.text)) {
            self.notes
                .push(format!("line {}: repeated -1 delimiter ignored", l.number));
            number_line = lines.next();
        }
        let index = self.blocks;
        let Some(number_line) = number_line else {
            if lines.incomplete {
                return Ok(Attempt::NeedMore);
            }
            self.notes.push(format!(
                "line {}: file ends after a -1 delimiter",
                line.number
            ));
            return Ok(Attempt::EndOfFile);
        };
        let Some((number, binary)) = dataset_number(number_line.text) else {
            return Err(error(
                Some(number_line.number),
                number_line.start,
                Some(index),
                None,
                format!(
                    "expected a dataset number (format I6) after the -1 delimiter, found '{}'",
                    text::excerpt(number_line.text)
                ),
            ));
        };
        let opening = Opening {
            line: number_line,
            index,
            number,
        };
        if binary {
            let direct_min = self.direct_min;
            return Ok(
                binary_block(bytes, lines, &opening, eof, direct_min)?.unwrap_or(Attempt::NeedMore)
            );
        }
        let block = text_block(lines, &opening)?;
        Ok(block.map_or(Attempt::NeedMore, Attempt::Block))
    }
}

/// The blocks of a whole file and the remarks made while splitting.
#[derive(Debug, Default)]
pub(crate) struct Split {
    pub blocks: Vec<Block>,
    pub notes: Vec<String>,
}

/// Splits the whole file `bytes` into dataset blocks. On an error, the
/// blocks before it are returned with it (the first error in file order may
/// be in one of them).
pub(crate) fn split(bytes: &[u8]) -> (Split, Option<UffError>) {
    let mut splitter = Splitter::default();
    let mut blocks = Vec::new();
    let failure = loop {
        match splitter.next(bytes, true) {
            Ok(Step::Block(b)) => blocks.push(b),
            // With eof, the splitter never needs more bytes; without
            // `direct_min`, it reads every data section itself.
            Ok(Step::End) | Ok(Step::NeedMore) | Ok(Step::Direct(_)) | Ok(Step::Closed { .. }) => {
                break None
            }
            Err(e) => break Some(e),
        }
    };
    (
        Split {
            blocks,
            notes: splitter.notes,
        },
        failure,
    )
}

/// Where a dataset starts: its number line, its index in the file and its
/// number.
struct Opening<'a> {
    line: Line<'a>,
    index: usize,
    number: u32,
}

impl Opening<'_> {
    /// An error of this dataset.
    fn error(&self, line: Option<usize>, offset: usize, message: String) -> UffError {
        error(line, offset, Some(self.index), Some(self.number), message)
    }

    /// An error on its number line.
    fn header_error(&self, message: String) -> UffError {
        self.error(Some(self.line.number), self.line.start, message)
    }
}

/// An ASCII dataset: every line up to the closing `-1`.
/// `Ok(None)`: the buffer ends first.
fn text_block(lines: &mut Lines<'_>, opening: &Opening<'_>) -> Result<Option<Block>, UffError> {
    let Opening {
        line: number_line,
        index,
        number,
    } = *opening;
    let text_start = lines.pos;
    for line in lines.by_ref() {
        if text::is_delimiter(line.text) {
            return Ok(Some(Block {
                index,
                number,
                line: number_line.number,
                start: number_line.start,
                text: text_start..line.start,
                close_line: line.number,
                close_offset: line.start,
                binary: None,
                notes: Vec::new(),
            }));
        }
    }
    if lines.incomplete {
        return Ok(None);
    }
    Err(error(
        Some(lines.number.saturating_sub(1).max(number_line.number)),
        lines.pos,
        Some(index),
        Some(number),
        format!(
            "file ends inside dataset {number} that starts at line {}: expected a closing '    -1' line (truncated file?)",
            number_line.number
        ),
    ))
}

/// Byte counts of the data of a 58b function, most likely first:
/// (bytes, abscissa bytes per point).
fn binary_layouts(r7: &Record7) -> Vec<(Option<usize>, usize)> {
    let value = r7.value_bytes();
    let per_point = if r7.is_complex() { 2 * value } else { value };
    let n = r7.points;
    if r7.even {
        vec![(n.checked_mul(per_point), value)]
    } else if value == 8 {
        // Same precision as the ordinate (pyuff), or single-precision abscissa
        // (UFFFiles.jl and the standard's E13.5 abscissa of ASCII 58).
        vec![
            (n.checked_mul(per_point + 8), 8),
            (n.checked_mul(per_point + 4), 4),
        ]
    } else {
        vec![(n.checked_mul(per_point + 4), 4)]
    }
}

/// Where the closing `-1` after 58b data is: (offset of the `-1` line,
/// position after it, line breaks skipped before it).
type Closing = (usize, usize, usize);

/// After 58b data at `pos`: the closing `-1`, after optional blanks and line
/// breaks. `Err(())`: the buffer ends (not at `eof`) before this is decided.
fn closing_after(bytes: &[u8], pos: usize, eof: bool) -> Result<Option<Closing>, ()> {
    let mut p = pos;
    let mut breaks = 0;
    let mut line_start = pos;
    while p < bytes.len() && matches!(bytes[p], b' ' | b'\t' | b'\r' | b'\n') {
        if bytes[p] == b'\n' {
            breaks += 1;
            line_start = p + 1;
        }
        p += 1;
    }
    let rest = &bytes[p.min(bytes.len())..];
    if !rest.starts_with(b"-1") {
        // "" or "-" at the end of a partial buffer may still become "-1".
        return if !eof && b"-1".starts_with(rest) {
            Err(())
        } else {
            Ok(None)
        };
    }
    p += 2;
    while p < bytes.len() && bytes[p] != b'\n' {
        if !matches!(bytes[p], b' ' | b'\t' | b'\r') {
            return Ok(None);
        }
        p += 1;
    }
    if p >= bytes.len() && !eof {
        return Err(());
    }
    Ok(Some((line_start, (p + 1).min(bytes.len()), breaks)))
}

/// The value of an `Option` that is `None` when more bytes are needed;
/// returns `Ok(None)` (need more) from the enclosing function otherwise.
macro_rules! need {
    ($e:expr) => {
        match $e {
            Some(v) => v,
            None => return Ok(None),
        }
    };
}

/// Largest 58b data section read straight into its values (allocated whole
/// before they arrive); larger ones grow the buffer as they are read, so a
/// header that declares more than the file holds costs no more memory than
/// the file.
const DIRECT_MAX: usize = 64 << 20;

/// The data section of a 58b dataset: where it starts and what the header
/// and record 7 say it holds.
#[derive(Debug)]
struct DataSection {
    index: usize,
    number: u32,
    /// Line of the data, and their start (a buffer offset).
    data_line: usize,
    data_start: usize,
    /// The header's byte count.
    declared: i64,
    record7: Record7,
}

/// Where the data of a 58b dataset end: their length, the abscissa bytes
/// per point, the closing `-1`, and a note when the header's byte count was
/// overruled.
struct Placed {
    len: usize,
    abscissa_bytes: usize,
    close: Closing,
    note: Option<String>,
}

impl DataSection {
    fn error_at_data(&self, message: String) -> UffError {
        error(
            Some(self.data_line),
            self.data_start,
            Some(self.index),
            Some(self.number),
            message,
        )
    }

    /// The record 7 byte counts, as "a or b".
    fn expected(&self) -> String {
        let expected: Vec<String> = binary_layouts(&self.record7)
            .iter()
            .filter_map(|(b, _)| b.map(|b| b.to_string()))
            .collect();
        expected.join(" or ")
    }

    /// The layout (bytes, abscissa bytes) whose byte count is the declared one.
    fn declared_layout(&self) -> Option<(usize, usize)> {
        let declared = usize::try_from(self.declared).ok();
        binary_layouts(&self.record7)
            .into_iter()
            .find_map(|(b, abscissa)| b.filter(|&b| Some(b) == declared).map(|b| (b, abscissa)))
    }

    /// The error when no byte count fits the data: truncated (`available`
    /// bytes follow the data start) or wrong byte count.
    fn error(&self, available: usize) -> UffError {
        let (declared, r7) = (self.declared, &self.record7);
        let declared_ok = usize::try_from(declared).ok();
        let message = if declared_ok.is_some_and(|d| d > available)
            || binary_layouts(r7)
                .iter()
                .all(|(b, _)| b.is_none_or(|b| b > available))
        {
            format!(
                "58b data truncated: header declares {declared} bytes and record 7 ({} points, ordinate type {}) needs {} bytes, but only {available} bytes follow",
                r7.points,
                r7.ordinate_type,
                self.expected()
            )
        } else {
            format!(
                "wrong byte count in 58b: header declares {declared} bytes, record 7 ({} points, ordinate type {}) needs {} bytes, and no closing -1 follows either",
                r7.points,
                r7.ordinate_type,
                self.expected()
            )
        };
        self.error_at_data(message)
    }

    /// The data's length and abscissa bytes when the caller should read them
    /// itself ([`Attempt::Direct`]): an even function (one layout, so the
    /// declared count is the data's length whatever follows; the closing
    /// `-1` is checked after them) extending at least `direct_min` bytes
    /// beyond the buffer.
    fn direct(
        &self,
        available: usize,
        eof: bool,
        direct_min: Option<usize>,
    ) -> Option<(usize, usize)> {
        let (len, abscissa) = self.declared_layout()?;
        let min = direct_min?;
        (self.record7.even
            && !eof
            && len > available
            && len - available >= min
            && len <= DIRECT_MAX)
            .then_some((len, abscissa))
    }

    /// Where the data end in `bytes`: the declared byte count if a `-1`
    /// follows it and record 7 allows it, else the first length record 7
    /// allows that a `-1` follows (with a note). `Ok(None)`: more bytes are
    /// needed to decide.
    fn place(&self, bytes: &[u8], eof: bool) -> Result<Option<Placed>, UffError> {
        let available = bytes.len() - self.data_start;
        let layouts = binary_layouts(&self.record7);
        let declared_ok = usize::try_from(self.declared).ok();
        let closing = |len: usize| closing_after(bytes, self.data_start + len, eof).ok();
        if let Some((len, abscissa_bytes)) = self.declared_layout() {
            if len <= available {
                if let Some(close) = need!(closing(len)) {
                    return Ok(Some(Placed {
                        len,
                        abscissa_bytes,
                        close,
                        note: None,
                    }));
                }
            } else if !eof {
                return Ok(None);
            }
        }
        if !eof {
            // What follows compares lengths with what the file holds: wait for
            // every candidate length to be in the buffer (or for the file end).
            let longest = layouts
                .iter()
                .filter_map(|(b, _)| *b)
                .chain(declared_ok)
                .max()
                .unwrap_or(0);
            if longest > available {
                return Ok(None);
            }
        }
        if let Some(d) = declared_ok.filter(|&d| d <= available) {
            if need!(closing(d)).is_some() {
                // The data hold what the header declares, but not what record 7 needs.
                let r7 = &self.record7;
                return Err(self.error_at_data(format!(
                    "wrong byte count in 58b: header and data hold {} bytes, but record 7 ({} points, ordinate type {}) needs {}",
                    self.declared,
                    r7.points,
                    r7.ordinate_type,
                    self.expected()
                )));
            }
        }
        // Declared byte count inconsistent with record 7 (pyuff writes n*8 for
        // complex data): accept the length record 7 implies if a `-1` follows it.
        for &(len, abscissa_bytes) in &layouts {
            let Some(len) = len.filter(|&l| l <= available) else {
                continue;
            };
            if let Some(close) = need!(closing(len)) {
                let note = format!(
                    "line {}: 58b header declares {} bytes, but record 7 ({} points, ordinate type {}) implies {len}; read {len}",
                    self.data_line, self.declared, self.record7.points, self.record7.ordinate_type
                );
                return Ok(Some(Placed {
                    len,
                    abscissa_bytes,
                    close,
                    note: Some(note),
                }));
            }
        }
        Err(self.error(available))
    }
}

/// The fields of a 58b header line after `58b`: byte order, ASCII line
/// count and byte count (the floating point format must be IEEE).
struct BinaryHeader {
    little_endian: bool,
    ascii_lines: i64,
    declared: i64,
}

fn binary_header(opening: &Opening<'_>) -> Result<BinaryHeader, UffError> {
    let number_line = &opening.line;
    if opening.number != 58 {
        return Err(opening.header_error(format!(
            "binary form 'b' is only defined for dataset 58, found {}b",
            opening.number
        )));
    }
    // Header fields after `58b`, separated by blanks (widths vary between writers).
    let fields: Option<Vec<i64>> = text::tokens(number_line.text)
        .skip(1)
        .take(4)
        .map(text::parse_int)
        .collect();
    let header = match fields {
        Some(f) if f.len() == 4 => f,
        _ => {
            return Err(opening.header_error(format!(
                "58b header (format I6,1A1,I6,I6,I12,I12,...): expected byte order, floating point format, ASCII line count and byte count, found '{}'",
                text::excerpt(number_line.text)
            )))
        }
    };
    let (byte_order, fp_format, ascii_lines, declared) =
        (header[0], header[1], header[2], header[3]);
    let little_endian = match byte_order {
        1 => true,
        2 => false,
        _ => {
            return Err(opening.header_error(format!(
                "58b byte order must be 1 (little-endian) or 2 (big-endian), found {byte_order}"
            )))
        }
    };
    if fp_format != 2 {
        return Err(opening.header_error(format!(
            "58b floating point format must be 2 (IEEE 754), found {fp_format}"
        )));
    }
    if !(11..=1000).contains(&ascii_lines) {
        return Err(opening.header_error(format!(
            "58b ASCII line count must be 11 (records 1-11), found {ascii_lines}"
        )));
    }
    Ok(BinaryHeader {
        little_endian,
        ascii_lines,
        declared,
    })
}

/// The ASCII lines of a 58b dataset (records 1-11): its record 7.
/// `Ok(None)`: the buffer ends first.
fn binary_text(
    lines: &mut Lines<'_>,
    opening: &Opening<'_>,
    ascii_lines: i64,
) -> Result<Option<Record7>, UffError> {
    let mut record7: Option<Record7> = None;
    for k in 0..ascii_lines as usize {
        let Some(line) = lines.next() else {
            if lines.incomplete {
                return Ok(None);
            }
            return Err(opening.error(
                Some(lines.number),
                lines.pos,
                format!(
                    "file ends in the ASCII header of 58b: expected {ascii_lines} lines, found {k}"
                ),
            ));
        };
        if k == 6 {
            record7 = Some(function58::record7(line.text).map_err(|m| {
                opening.error(Some(line.number), line.start, format!("record 7: {m}"))
            })?);
        }
    }
    match record7 {
        Some(r7) => Ok(Some(r7)),
        None => Err(opening.error(
            Some(lines.number),
            lines.pos,
            "58b header has no record 7".into(),
        )),
    }
}

/// A 58b dataset: header fields, ASCII records, then the binary data.
/// `Ok(None)`: the buffer ends (not at `eof`) before the block is decided.
/// With `direct_min`, data of an even function that match the declared
/// byte count and extend at least that far beyond the buffer are left to
/// the caller ([`Attempt::Direct`]).
fn binary_block(
    bytes: &[u8],
    lines: &mut Lines<'_>,
    opening: &Opening<'_>,
    eof: bool,
    direct_min: Option<usize>,
) -> Result<Option<Attempt>, UffError> {
    let header = binary_header(opening)?;
    let text_start = lines.pos;
    let Some(record7) = binary_text(lines, opening, header.ascii_lines)? else {
        return Ok(None);
    };
    let section = DataSection {
        index: opening.index,
        number: opening.number,
        data_line: lines.number,
        data_start: lines.pos,
        declared: header.declared,
        record7,
    };
    let block = |len: usize, abscissa_bytes: usize, close_line, close_offset, notes| Block {
        index: opening.index,
        number: opening.number,
        line: opening.line.number,
        start: opening.line.start,
        text: text_start..section.data_start,
        close_line,
        close_offset,
        binary: Some(Binary {
            little_endian: header.little_endian,
            data: section.data_start..section.data_start + len,
            abscissa_bytes,
            record7: section.record7.clone(),
        }),
        notes,
    };
    let available = bytes.len() - section.data_start;
    if let Some((len, abscissa)) = section.direct(available, eof, direct_min) {
        let block = block(
            len,
            abscissa,
            section.data_line,
            section.data_start + len,
            Vec::new(),
        );
        return Ok(Some(Attempt::Direct(block, Awaiting { section, len })));
    }
    let Some(placed) = section.place(bytes, eof)? else {
        return Ok(None);
    };
    let (close_offset, after, breaks) = placed.close;
    let block = block(
        placed.len,
        placed.abscissa_bytes,
        section.data_line + breaks,
        close_offset,
        placed.note.into_iter().collect(),
    );
    lines.pos = after;
    lines.number = section.data_line + breaks + 1;
    Ok(Some(Attempt::Block(block)))
}
