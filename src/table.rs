//! Numeric CSV tables with a `time_s` column, as the run directory holds them
//! (`histories.csv`, `contact_forces.csv`, `energy.csv`): the one reader the simulation's
//! statistics, the analyses and the report share.

use std::path::Path;

use crate::{Error, Result};

/// Largest input table read (bytes): a CSV row of a run is at least a few bytes per value,
/// and the values (8 bytes each) and the reader's buffers take about as much memory as the
/// text; 4 GiB keeps a table within this project's 24 GB machines with room to analyse it.
pub const MAX_TABLE_BYTES: u64 = 4 << 30;

/// Checks that `path` names a regular file of at most [`MAX_TABLE_BYTES`] before it is read:
/// a device (`/dev/zero`), a pipe or a folder would be read without end or fail obscurely.
pub fn check_table_file(path: &Path) -> Result<()> {
    let name = path.display().to_string();
    let meta = std::fs::metadata(path).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            Error::input(&name, "file", "does not exist (check the path)")
        } else {
            Error::io(path, e)
        }
    })?;
    if !meta.is_file() {
        return Err(Error::input(
            &name,
            "file",
            "is not a regular file (a folder, device or pipe): expected a CSV file",
        ));
    }
    if meta.len() > MAX_TABLE_BYTES {
        return Err(Error::input(
            &name,
            "file",
            format!(
                "is {:.1} GiB: at most {} GiB is read (split the record or thin it)",
                meta.len() as f64 / (1u64 << 30) as f64,
                MAX_TABLE_BYTES >> 30
            ),
        ));
    }
    Ok(())
}

/// Columns of a CSV file with a `time_s` column.
#[derive(Clone, Debug)]
pub struct Table {
    /// Column names (including `time_s`).
    pub headers: Vec<String>,
    /// Columns.
    pub columns: Vec<Vec<f64>>,
}

/// Refuses a header that names a column twice: a reader takes the first of the two, silently
/// (issue 53, item 11). `source` names the file.
pub fn check_unique_headers<'a>(
    source: &str,
    headers: impl Iterator<Item = &'a str>,
) -> Result<()> {
    let mut seen: Vec<&str> = Vec::new();
    for (k, h) in headers.enumerate() {
        if let Some(first) = seen.iter().position(|s| *s == h) {
            return Err(Error::input(
                source,
                "header",
                format!(
                    "column `{h}` appears twice (columns {} and {}): each name must appear once",
                    first + 1,
                    k + 1
                ),
            ));
        }
        seen.push(h);
    }
    Ok(())
}

impl Table {
    /// Read a numeric CSV file with a `time_s` column.
    pub fn read(path: &Path) -> Result<Table> {
        let table = Table::read_numeric(path)?;
        if !table.headers.iter().any(|h| h == "time_s") {
            return Err(Error::input(
                path.display().to_string(),
                "time_s",
                format!("no `time_s` column; columns: {}", table.headers.join(", ")),
            ));
        }
        Ok(table)
    }

    /// Read a numeric CSV file (any columns; each name once).
    pub fn read_numeric(path: &Path) -> Result<Table> {
        check_table_file(path)?;
        let name = path.display().to_string();
        let file = std::fs::File::open(path).map_err(|e| Error::reading(path, e))?;
        let mut reader = csv::ReaderBuilder::new()
            .trim(csv::Trim::All)
            .from_reader(file);
        let headers: Vec<String> = reader
            .headers()
            .map_err(|e| Error::input(&name, "header", e.to_string()))?
            .iter()
            .map(str::to_string)
            .collect();
        check_unique_headers(&name, headers.iter().map(String::as_str))?;
        let mut columns = vec![Vec::new(); headers.len()];
        for (line, rec) in reader.records().enumerate() {
            let rec =
                rec.map_err(|e| Error::input(&name, format!("line {}", line + 2), e.to_string()))?;
            for (k, field) in rec.iter().enumerate().take(headers.len()) {
                let v = field.parse::<f64>().map_err(|_| {
                    Error::input(
                        &name,
                        format!("line {}, column `{}`", line + 2, headers[k]),
                        format!("`{field}` is not a number"),
                    )
                })?;
                columns[k].push(v);
            }
        }
        Ok(Table { headers, columns })
    }
    /// Column by name.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.headers
            .iter()
            .position(|h| h == name)
            .map(|k| self.columns[k].as_slice())
    }
    /// First column whose name starts with `prefix`.
    pub fn column_starting(&self, prefix: &str) -> Option<(&str, &[f64])> {
        self.headers
            .iter()
            .position(|h| h.starts_with(prefix))
            .map(|k| (self.headers[k].as_str(), self.columns[k].as_slice()))
    }
}

/// `column` at `time_s` (samples at times `t`, ascending): linear between the samples around
/// it, the end values outside.
pub fn interpolate(t: &[f64], column: &[f64], time_s: f64) -> f64 {
    let k = t.partition_point(|&x| x <= time_s);
    if k == 0 {
        return column[0];
    }
    if k >= t.len() {
        return column[t.len() - 1];
    }
    let w = (time_s - t[k - 1]) / (t[k] - t[k - 1]);
    column[k - 1] + w * (column[k] - column[k - 1])
}
