//! Uniformly sampled time series read from a CSV file with a `time_s` column.

use std::path::Path;

use crate::{Error, Result};

/// Name of the time column (seconds).
pub const TIME_COLUMN: &str = "time_s";
/// Allowed relative deviation of each time step from the mean step.
pub const UNIFORM_STEP_TOLERANCE: f64 = 1e-6;

/// One column of a CSV file sampled at a uniform rate.
#[derive(Debug, Clone, PartialEq)]
pub struct TimeSeries {
    /// The column name.
    pub column: String,
    /// Time of the first sample, s.
    pub start_time_s: f64,
    /// `1 / mean time step`, Hz.
    pub sample_rate_hz: f64,
    /// The samples.
    pub values: Vec<f64>,
}

impl TimeSeries {
    /// Reads column `column` of `path`; the sample rate comes from the `time_s` column, whose
    /// steps must all equal their mean within [`UNIFORM_STEP_TOLERANCE`] (relative).
    pub fn from_csv(path: &Path, column: &str) -> Result<Self> {
        let mut series = Self::columns_from_csv(path, &[column])?;
        Ok(series.remove(0))
    }

    /// Reads the columns `columns` of `path` in one pass (as [`TimeSeries::from_csv`] each).
    pub fn columns_from_csv(path: &Path, columns: &[&str]) -> Result<Vec<Self>> {
        crate::table::check_table_file(path)?;
        let source = path.display().to_string();
        let file = std::fs::File::open(path).map_err(|e| {
            Error::input(
                source.clone(),
                "file",
                format!("cannot open: {}", crate::error::io_words(&e)),
            )
        })?;
        let mut reader = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .from_reader(file);
        let headers = reader
            .headers()
            .map_err(|e| {
                Error::input(
                    source.clone(),
                    "header",
                    format!("cannot read the header: {e}"),
                )
            })?
            .clone();
        if headers.iter().all(|h| h.trim().is_empty()) {
            return Err(Error::input(
                source.clone(),
                "header",
                format!(
                    "the file has no header line (is it empty?): need a `{TIME_COLUMN}` column \
                     and the signal's column"
                ),
            ));
        }
        crate::table::check_unique_headers(&source, headers.iter())?;
        let available = column_list(headers.iter());
        let find = |name: &str| {
            headers.iter().position(|h| h == name).ok_or_else(|| {
                Error::input(
                    source.clone(),
                    name,
                    format!("no column named `{name}`; available columns: {available}"),
                )
            })
        };
        let time_index = find(TIME_COLUMN)?;
        let value_indices: Vec<usize> = columns.iter().map(|c| find(c)).collect::<Result<_>>()?;

        let mut times_s = Vec::new();
        let mut values: Vec<Vec<f64>> = vec![Vec::new(); columns.len()];
        for (row, record) in reader.records().enumerate() {
            let line = row + 2; // 1-based, after the header
            let record = record
                .map_err(|e| Error::input(source.clone(), "row", format!("line {line}: {e}")))?;
            let parse = |index: usize, name: &str| -> Result<f64> {
                let text = record.get(index).unwrap_or("");
                text.parse::<f64>()
                    .ok()
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        Error::input(
                            source.clone(),
                            name,
                            format!("line {line}: `{text}` is not a finite number"),
                        )
                    })
            };
            times_s.push(parse(time_index, TIME_COLUMN)?);
            for (k, &index) in value_indices.iter().enumerate() {
                values[k].push(parse(index, columns[k])?);
            }
        }
        let sample_rate_hz = uniform_sample_rate_hz(&times_s)
            .map_err(|message| Error::input(source.clone(), TIME_COLUMN, message))?;
        Ok(columns
            .iter()
            .zip(values)
            .map(|(column, values)| TimeSeries {
                column: column.to_string(),
                start_time_s: times_s[0],
                sample_rate_hz,
                values,
            })
            .collect())
    }

    /// Duration spanned by the samples, s.
    pub fn duration_s(&self) -> f64 {
        (self.values.len().saturating_sub(1)) as f64 / self.sample_rate_hz
    }
}

/// `1 / mean step` of increasing, uniformly spaced times; a message saying why not otherwise.
pub fn uniform_sample_rate_hz(times_s: &[f64]) -> std::result::Result<f64, String> {
    if times_s.len() < 2 {
        return Err(format!(
            "{} samples; need at least 2 to know the sample rate",
            times_s.len()
        ));
    }
    let mean_step_s = (times_s[times_s.len() - 1] - times_s[0]) / (times_s.len() - 1) as f64;
    if mean_step_s.is_nan() || mean_step_s <= 0.0 {
        return Err("times must increase".into());
    }
    for (k, pair) in times_s.windows(2).enumerate() {
        let step_s = pair[1] - pair[0];
        if (step_s - mean_step_s).abs() > UNIFORM_STEP_TOLERANCE * mean_step_s {
            return Err(format!(
                "not uniformly sampled: step {step_s} s between rows {} and {} differs from the mean \
                 step {mean_step_s} s by more than {UNIFORM_STEP_TOLERANCE} (relative)",
                k + 1,
                k + 2
            ));
        }
    }
    Ok(1.0 / mean_step_s)
}

/// Most columns, and most characters of each, that a message lists: a file that is no table
/// (a binary file, one line of megabytes) must not turn the message into megabytes.
const LISTED_COLUMNS: usize = 30;
const LISTED_CHARACTERS: usize = 60;

/// The header's columns for a message: the first [`LISTED_COLUMNS`], each cut to
/// [`LISTED_CHARACTERS`] characters with control characters shown escaped, and how many more.
fn column_list<'a>(headers: impl Iterator<Item = &'a str>) -> String {
    let headers: Vec<&str> = headers.collect();
    let mut listed: Vec<String> = headers
        .iter()
        .take(LISTED_COLUMNS)
        .map(|h| {
            let shown: String = h.chars().flat_map(char::escape_debug).collect();
            if shown.chars().count() > LISTED_CHARACTERS {
                let cut: String = shown.chars().take(LISTED_CHARACTERS).collect();
                format!("{cut}... ({} characters)", h.chars().count())
            } else {
                shown
            }
        })
        .collect();
    if headers.len() > LISTED_COLUMNS {
        listed.push(format!("and {} more", headers.len() - LISTED_COLUMNS));
    }
    listed.join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A header that is no table's (a megabyte of NUL bytes, thousands of columns) is listed
    /// in a message short enough to read.
    #[test]
    fn a_message_lists_a_bounded_part_of_a_huge_header() {
        let nul = "\0".repeat(1 << 20);
        let listed = column_list([nul.as_str(), "time_s"].into_iter());
        assert!(listed.len() < 200, "{} characters", listed.len());
        assert!(listed.contains("(1048576 characters)") && listed.ends_with("time_s"));
        let many: Vec<String> = (0..1000).map(|k| format!("c{k}")).collect();
        let listed = column_list(many.iter().map(String::as_str));
        assert!(listed.starts_with("c0, c1,") && listed.ends_with("c29, and 970 more"));
    }

    fn write_temp(name: &str, text: &str) -> std::path::PathBuf {
        let path =
            std::env::temp_dir().join(format!("squeal-series-{}-{name}", std::process::id()));
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn reads_column_and_sample_rate() {
        let path = write_temp("ok.csv", "time_s,uy_m\n0.0,1\n0.001,2\n0.002,3\n");
        let series = TimeSeries::from_csv(&path, "uy_m").unwrap();
        let _ = std::fs::remove_file(&path);
        assert!((series.sample_rate_hz - 1000.0).abs() < 1e-9);
        assert_eq!(series.values, vec![1.0, 2.0, 3.0]);
    }

    #[test]
    fn missing_column_lists_available_columns() {
        let path = write_temp("cols.csv", "time_s,uy_m,uz_m\n0,1,2\n1,2,3\n");
        let err = TimeSeries::from_csv(&path, "ux_m").unwrap_err();
        let _ = std::fs::remove_file(&path);
        assert_eq!(err.exit_code(), 2);
        let text = err.to_string();
        assert!(
            text.contains("ux_m") && text.contains("time_s, uy_m, uz_m"),
            "{text}"
        );
    }

    #[test]
    fn missing_file_is_an_input_error_naming_the_file() {
        let err = TimeSeries::from_csv(Path::new("/nonexistent/dir/x.csv"), "a").unwrap_err();
        assert_eq!(err.exit_code(), 2);
        assert!(err.to_string().contains("/nonexistent/dir/x.csv"));
    }

    #[test]
    fn non_uniform_time_is_an_input_error() {
        let path = write_temp("nonuni.csv", "time_s,a\n0,1\n1,2\n2.01,3\n3,4\n");
        let err = TimeSeries::from_csv(&path, "a").unwrap_err();
        let _ = std::fs::remove_file(&path);
        assert_eq!(err.exit_code(), 2);
        assert!(err.to_string().contains("not uniformly sampled"), "{err}");
        let path = write_temp("bad.csv", "time_s,a\n0,1\n1,x\n");
        let err = TimeSeries::from_csv(&path, "a").unwrap_err();
        let _ = std::fs::remove_file(&path);
        assert!(err.to_string().contains("line 3"), "{err}");
    }
}
