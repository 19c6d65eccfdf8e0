//! Fixed-column Fortran records: reading fields by column, numbers with `E`, `e`, `D` or no
//! exponent letter, and writing `Ew.d` / `Dw.d` / `Iw` fields.
//!
//! Header records are read by columns (names may contain blanks and integer fields may touch);
//! when a record does not fill its columns (hand-edited files) the whitespace-separated tokens
//! are used instead, if there are exactly as many as fields. Data records are read as
//! whitespace-separated numbers (hand-edited files and writers with other widths), and a line
//! whose tokens are not all numbers is read again by its record's Fortran field widths: a
//! negative `E13.5` value with a 3-digit mantissa exponent, or a writer that fills the field,
//! leaves no blank before its sign (`1.00000E+00-2.00000E+00`, pyuff's `sample_test` files).

use super::block::Context;
use crate::Result;

/// Columns `first..=last` (1-based) of `line`, blank-padded, trimmed.
pub fn column(line: &str, first: usize, last: usize) -> &str {
    let start = (first - 1).min(line.len());
    let end = last.min(line.len());
    line.get(start..end).unwrap_or("").trim()
}

/// A Fortran real: `1.5E+03`, `1.5e3`, `1.5D+03`, or `1.5+003` (no exponent letter).
pub fn parse_real(text: &str) -> Option<f64> {
    let t = text.trim();
    if t.is_empty() {
        return None;
    }
    let normal: String = t
        .chars()
        .map(|c| if c == 'D' || c == 'd' { 'E' } else { c })
        .collect();
    if let Ok(v) = normal.parse::<f64>() {
        return Some(v);
    }
    // Exponent without its letter: a sign after a digit or point starts the exponent.
    let bytes = normal.as_bytes();
    let split = (1..bytes.len()).find(|&i| {
        matches!(bytes[i], b'+' | b'-') && (bytes[i - 1].is_ascii_digit() || bytes[i - 1] == b'.')
    })?;
    format!("{}E{}", &normal[..split], &normal[split..])
        .parse()
        .ok()
}

/// Integer fields of a record by their column widths, or by whitespace tokens when the columns
/// do not parse and the token count equals the field count.
pub fn integers(line: &str, widths: &[usize]) -> Option<Vec<i64>> {
    let mut start = 1;
    let by_columns: Option<Vec<i64>> = widths
        .iter()
        .map(|&w| {
            let field = column(line, start, start + w - 1);
            start += w;
            field.parse().ok()
        })
        .collect();
    by_columns.or_else(|| {
        let tokens: Vec<&str> = line.split_whitespace().collect();
        (tokens.len() == widths.len())
            .then(|| tokens.iter().map(|t| t.parse().ok()).collect())
            .flatten()
    })
}

/// The fields of `line` by the Fortran widths `widths`, repeated from column 1 to the end of
/// the line (`6E13.5`: `[13]`; `2(E13.5,E20.12)`: `[13, 20]`). Blank fields (a partly filled
/// last line) are left out. None when a field is not a number, or the line does not split at
/// a character boundary.
pub fn reals_by_widths(line: &str, widths: &[usize]) -> Option<Vec<f64>> {
    let end = line.trim_end().len();
    let mut values = Vec::new();
    let mut start = 0;
    for &width in widths.iter().cycle() {
        if start >= end || width == 0 {
            break;
        }
        let field = line.get(start..(start + width).min(end))?;
        if !field.trim().is_empty() {
            values.push(parse_real(field)?);
        }
        start += width;
    }
    Some(values)
}

/// Reads `count` reals from `lines` (record `record` of the dataset, spread over as many lines
/// as it takes), each line by whitespace or, where that fails, by the record's Fortran field
/// `widths` (module docs). Returns the values and the lines consumed.
pub fn reals(
    lines: &[String],
    count: usize,
    widths: &[usize],
    ctx: &Context,
    record: usize,
    what: &str,
) -> Result<(Vec<f64>, usize)> {
    // A corrupt count never reserves more than a million values up front.
    let mut values = Vec::with_capacity(count.min(1 << 20));
    let mut used = 0;
    while values.len() < count {
        let Some(line) = lines.get(used) else {
            return Err(ctx.record_error(
                record,
                what,
                format!("{} of {count} values present", values.len()),
            ));
        };
        used += 1;
        let by_tokens: Option<Vec<f64>> = line.split_whitespace().map(parse_real).collect();
        let Some(line_values) = by_tokens.or_else(|| reals_by_widths(line, widths)) else {
            // Name the first token that is no number (by whitespace, as a reader sees it).
            let (k, token) = line
                .split_whitespace()
                .enumerate()
                .find(|(_, t)| parse_real(t).is_none())
                .unwrap_or((0, line.as_str()));
            return Err(ctx.record_error(
                record,
                what,
                format!(
                    "`{token}` (value {}) is not a number, by whitespace or by the record's \
                     field widths {widths:?}",
                    values.len() + k + 1
                ),
            ));
        };
        for value in line_values {
            if values.len() == count {
                return Err(ctx.record_error(
                    record,
                    what,
                    format!("more values on a line than the {count} announced"),
                ));
            }
            values.push(value);
        }
    }
    Ok((values, used))
}

/// A real in Fortran `Ew.d` (or `Dw.d` with `letter` 'D') style with one digit before the point
/// (`1P`), right-justified in `width` columns: `-1.23456E+00`.
pub fn format_real(value: f64, width: usize, decimals: usize, letter: char) -> String {
    let text = format!("{value:.decimals$e}");
    let (mantissa, exponent) = text.split_once('e').unwrap_or((&text, "0"));
    let exponent: i32 = exponent.parse().unwrap_or(0);
    let sign = if exponent < 0 { '-' } else { '+' };
    format!(
        "{:>width$}",
        format!("{mantissa}{letter}{sign}{:02}", exponent.abs())
    )
}

/// An integer right-justified in `width` columns.
pub fn format_int(value: i64, width: usize) -> String {
    format!("{value:>width$}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fortran_reals_in_every_spelling() {
        for (text, value) in [
            ("1.5E+03", 1500.0),
            ("  -2.5e-2", -0.025),
            ("1.0000000000000001D-01", 0.1),
            ("3.0d0", 3.0),
            ("1.23456-100", 1.23456e-100),
            ("-4.5+003", -4500.0),
        ] {
            assert_eq!(parse_real(text), Some(value), "{text}");
        }
        assert_eq!(parse_real(""), None);
        assert_eq!(parse_real("NONE"), None);
    }

    #[test]
    fn written_reals_read_back_and_keep_their_width() {
        for value in [0.0, 1.0, -1.23456e-7, 6.02214076e23, -9.99999e99, 1e-300] {
            let text = format_real(value, 20, 11, 'E');
            assert_eq!(text.len(), 20, "{text}");
            let back = parse_real(&text).unwrap();
            assert!((back - value).abs() <= 1e-11 * value.abs(), "{text}");
        }
        assert_eq!(format_real(-1.234564, 13, 5, 'E'), " -1.23456E+00");
        assert_eq!(format_real(0.1, 25, 16, 'D'), "   1.0000000000000001D-01");
    }

    #[test]
    fn integers_by_columns_or_by_tokens() {
        assert_eq!(
            integers("    4         1    0         0", &[5, 10, 5, 10]),
            Some(vec![4, 1, 0, 0])
        );
        assert_eq!(integers("4 1 0 0", &[5, 10, 5, 10]), Some(vec![4, 1, 0, 0]));
        assert_eq!(integers("4 1 x 0", &[5, 10, 5, 10]), None);
    }
}
