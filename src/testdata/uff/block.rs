//! Splitting a universal file into its datasets.
//!
//! A block is a line `    -1`, a line with the dataset number in columns 1-6, the records,
//! and a closing `    -1` line. Lines end with LF or CR LF. ASCII blocks end at their closing
//! line. A binary 58 block ("58b" in columns 1-7) carries raw bytes after its ASCII records
//! (which may contain LF, CR or even `    -1`), so it is cut by its byte count, never by lines.
//!
//! The 58b byte count (header field 6) is checked against the count record 7 implies
//! (values x 4 or 8 bytes). pyuff 2.5.8 writes `points x 8` whatever the ordinate type (half the
//! true size for complex data), so when the two disagree the length that is followed by the
//! closing `    -1` line wins, and neither is accepted otherwise.

use crate::{Error, Result};

/// One dataset of a file.
#[derive(Clone, Debug, PartialEq)]
pub struct Block {
    /// Dataset number (58, 55, 15, 2411, 164, ...).
    pub number: u32,
    /// 1-based line number of the dataset-number line.
    pub first_line: usize,
    /// The ASCII records (line ends and trailing blanks removed).
    pub lines: Vec<String>,
    /// The binary part of a 58b block.
    pub binary: Option<BinaryData>,
}

/// The raw data of a binary block and how to decode it.
#[derive(Clone, Debug, PartialEq)]
pub struct BinaryData {
    /// Header field 3: 1 little endian, 2 big endian.
    pub byte_order: u32,
    /// Header field 4: 2 IEEE 754 (the only format read).
    pub float_format: u32,
    /// The data bytes.
    pub bytes: Vec<u8>,
}

/// Where a record sits, for error messages.
pub struct Context<'a> {
    /// File name.
    pub file: &'a str,
    /// Dataset number.
    pub dataset: u32,
    /// 1-based line of the dataset-number line.
    pub first_line: usize,
}

impl Context<'_> {
    /// An input error naming the file, this dataset and `field`.
    pub fn error(&self, field: &str, message: impl Into<String>) -> Error {
        Error::input(
            self.file,
            format!(
                "dataset {} (line {}), {field}",
                self.dataset, self.first_line
            ),
            message,
        )
    }

    /// An error about record `record` (1-based record number of the dataset).
    pub fn record_error(&self, record: usize, field: &str, message: impl Into<String>) -> Error {
        self.error(&format!("record {record}, {field}"), message)
    }
}

/// A cursor over the lines of a byte buffer.
struct Lines<'a> {
    bytes: &'a [u8],
    position: usize,
    line_number: usize,
}

impl<'a> Lines<'a> {
    /// The next line without its line end (LF or CR LF), or None at the end.
    fn next_line(&mut self) -> Option<&'a [u8]> {
        if self.position >= self.bytes.len() {
            return None;
        }
        let rest = &self.bytes[self.position..];
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        self.position += (end + 1).min(rest.len());
        self.line_number += 1;
        let mut line = &rest[..end];
        if line.last() == Some(&b'\r') {
            line = &line[..line.len() - 1];
        }
        Some(line)
    }
}

fn text(line: &[u8]) -> String {
    String::from_utf8_lossy(line).trim_end().to_string()
}

fn is_delimiter(line: &[u8]) -> bool {
    text(line).trim() == "-1"
}

/// Numbers of data bytes record 7 of a dataset 58 implies: `NVAL x values per point x size`
/// (docs/uff-format.md, dataset 58 record 12). Uneven spacing stores an abscissa per point, single
/// precision by the document but the ordinate's size in pyuff's files: both are candidates.
/// Empty when record 7 cannot be read.
pub fn expected_binary_bytes(record7: &str) -> Vec<usize> {
    let fields: Vec<i64> = record7
        .split_whitespace()
        .take(3)
        .map_while(|t| t.parse().ok())
        .collect();
    let [ordinate_type, count, spacing] = fields[..] else {
        return Vec::new();
    };
    let Ok(count) = usize::try_from(count) else {
        return Vec::new();
    };
    let (size, ordinate_values) = match ordinate_type {
        2 => (4, 1),
        4 => (8, 1),
        5 => (4, 2),
        6 => (8, 2),
        _ => return Vec::new(),
    };
    let per_point = if spacing == 0 {
        vec![ordinate_values * size + size, ordinate_values * size + 4]
    } else {
        vec![ordinate_values * size]
    };
    per_point
        .into_iter()
        .filter_map(|bytes| count.checked_mul(bytes))
        .collect()
}

/// Splits `bytes` into blocks; `name` is the file name for errors.
pub fn split_blocks(bytes: &[u8], name: &str) -> Result<Vec<Block>> {
    let mut lines = Lines {
        bytes,
        position: 0,
        line_number: 0,
    };
    let mut blocks = Vec::new();
    while let Some(line) = lines.next_line() {
        if text(line).is_empty() {
            continue;
        }
        if !is_delimiter(line) {
            return Err(Error::input(
                name,
                format!("line {}", lines.line_number),
                format!(
                    "`{}` outside a dataset: a dataset starts with a `    -1` line",
                    clip(&text(line))
                ),
            ));
        }
        let Some(number_line) = lines.next_line() else {
            return Err(Error::input(
                name,
                format!("line {}", lines.line_number),
                "file ends after a `    -1` line: the dataset number is missing",
            ));
        };
        let first_line = lines.line_number;
        let number_text = text(number_line);
        let (digits, rest) = number_text.split_at(number_text.len().min(6));
        let number: u32 = digits.trim().parse().map_err(|_| {
            Error::input(
                name,
                format!("line {first_line}"),
                format!(
                    "`{}` is not a dataset number (an integer in columns 1-6)",
                    clip(&number_text)
                ),
            )
        })?;
        let binary = rest.starts_with(['b', 'B']);
        let ctx = Context {
            file: name,
            dataset: number,
            first_line,
        };
        if binary {
            blocks.push(binary_block(&mut lines, rest, &ctx)?);
            continue;
        }
        let mut records = Vec::new();
        loop {
            match lines.next_line() {
                Some(l) if is_delimiter(l) => break,
                Some(l) => records.push(text(l)),
                None => {
                    return Err(ctx.error(
                        "end",
                        "the file ends inside this dataset: a dataset must end with a `    -1` \
                         line",
                    ))
                }
            }
        }
        blocks.push(Block {
            number,
            first_line,
            lines: records,
            binary: None,
        });
    }
    Ok(blocks)
}

/// The rest of a 58b block after its dataset-number line (module documentation).
fn binary_block(lines: &mut Lines, header: &str, ctx: &Context) -> Result<Block> {
    let fields: Vec<Option<u64>> = header[1..]
        .split_whitespace()
        .map(|t| t.parse().ok())
        .collect();
    let field = |k: usize, what: &str| -> Result<u64> {
        fields.get(k).copied().flatten().ok_or_else(|| {
            ctx.error(
                "binary header",
                format!("field {} ({what}) is missing or not an integer", k + 3),
            )
        })
    };
    let byte_order = field(0, "byte order")? as u32;
    let float_format = field(1, "floating-point format")? as u32;
    let ascii_lines = field(2, "number of ASCII lines")? as usize;
    let declared_bytes = field(3, "number of binary bytes")? as usize;
    if !(byte_order == 1 || byte_order == 2) {
        return Err(ctx.error(
            "binary header, byte order",
            format!("{byte_order}; allowed: 1 (little endian) or 2 (big endian)"),
        ));
    }
    if float_format != 2 {
        return Err(ctx.error(
            "binary header, floating-point format",
            format!("{float_format}; only 2 (IEEE 754) is read"),
        ));
    }
    if !(7..=100).contains(&ascii_lines) {
        return Err(ctx.error(
            "binary header, number of ASCII lines",
            format!("{ascii_lines}; a binary 58 has 11 (allowed 7..=100)"),
        ));
    }
    let mut records = Vec::with_capacity(ascii_lines);
    for _ in 0..ascii_lines {
        let line = lines.next_line().ok_or_else(|| {
            ctx.error(
                "records",
                "the file ends inside the ASCII records of a binary dataset",
            )
        })?;
        records.push(text(line));
    }
    let start = lines.position;
    let remaining = lines.bytes.len() - start;
    // The length followed by the closing line wins (module documentation).
    let closes_at = |length: usize| -> Option<usize> {
        if length > remaining {
            return None;
        }
        let mut after = start + length;
        while after < lines.bytes.len() && matches!(lines.bytes[after], b'\r' | b'\n') {
            after += 1;
        }
        let rest = &lines.bytes[after..];
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        is_delimiter(&rest[..end]).then_some(after)
    };
    let expected = expected_binary_bytes(&records[6]);
    let mut candidates = vec![declared_bytes];
    candidates.extend(expected.iter().filter(|&&e| e != declared_bytes));
    let Some((length, after)) = candidates
        .iter()
        .find_map(|&length| closes_at(length).map(|after| (length, after)))
    else {
        return Err(ctx.error(
            "binary data",
            format!(
                "neither the declared {declared_bytes} bytes nor the {expected:?} bytes record 7 \
                 implies are followed by the closing `    -1` line ({remaining} bytes left in \
                 the file)"
            ),
        ));
    };
    let bytes = lines.bytes[start..start + length].to_vec();
    lines.position = after;
    // Count the lines the binary part spanned, so later line numbers stay right.
    lines.line_number += lines.bytes[start..after]
        .iter()
        .filter(|&&b| b == b'\n')
        .count();
    let closing = lines.next_line();
    debug_assert!(closing.is_some_and(is_delimiter));
    Ok(Block {
        number: ctx.dataset,
        first_line: ctx.first_line,
        lines: records,
        binary: Some(BinaryData {
            byte_order,
            float_format,
            bytes,
        }),
    })
}

/// A line cut to 40 characters for an error message.
fn clip(line: &str) -> String {
    if line.chars().count() > 40 {
        format!("{}...", line.chars().take(40).collect::<String>())
    } else {
        line.to_string()
    }
}
