//! Hammer-test reference data and its comparison with FE modes.
//!
//! File format (`data/hammer/*.csv`), one measured mode per row, header required:
//! ```text
//! family,nodal_circles,nodal_diameters,frequency_hz,damping_ratio,source
//! axial,0,3,1035.0,0.0004,"synthetic: not a measurement"
//! ```
//! - `family`: axial, radial or circumferential;
//! - `nodal_circles`, `nodal_diameters`: non-negative integers (label (nodal circles, nodal
//!   diameters) as in the paper);
//! - `frequency_hz`: > 0; `damping_ratio`: optional (empty), in [0, 1);
//! - `source`: where the number comes from (a publication, a test report; "synthetic" for
//!   made-up data). The toolkit ships no invented measured data.

use std::path::Path;

use serde::Serialize;

use crate::modal::mode::{ModeFamily, ModeRef};
use crate::{Error, Result};

/// One measured mode.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct MeasuredMode {
    /// Family.
    pub family: ModeFamily,
    /// Nodal circles.
    pub nodal_circles: u32,
    /// Nodal diameters.
    pub nodal_diameters: u32,
    /// Natural frequency (Hz).
    pub frequency_hz: f64,
    /// Modal damping ratio, if measured.
    pub damping_ratio: Option<f64>,
    /// Source of the number.
    pub source: String,
}

const COLUMNS: [&str; 6] = [
    "family",
    "nodal_circles",
    "nodal_diameters",
    "frequency_hz",
    "damping_ratio",
    "source",
];

/// Read and validate a hammer-test CSV; errors name the file, line and column.
pub fn read_hammer_csv(path: &Path) -> Result<Vec<MeasuredMode>> {
    let name = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .flexible(true)
        .from_reader(file);
    let headers: Vec<String> = reader
        .headers()
        .map_err(|e| Error::input(&name, "line 1", format!("cannot read the header: {e}")))?
        .iter()
        .map(str::to_string)
        .collect();
    if headers != COLUMNS {
        return Err(Error::input(
            &name,
            "line 1",
            format!(
                "header must be `{}`, got `{}`",
                COLUMNS.join(","),
                headers.join(",")
            ),
        ));
    }
    let mut out = Vec::new();
    for (k, record) in reader.records().enumerate() {
        let line = k + 2;
        let rec = record.map_err(|e| Error::input(&name, format!("line {line}"), e.to_string()))?;
        let cell = |c: usize| rec.get(c).unwrap_or("").to_string();
        let field = |c: usize| format!("line {line}, column {} ({})", c + 1, COLUMNS[c]);
        if rec.len() != COLUMNS.len() {
            return Err(Error::input(
                &name,
                format!("line {line}"),
                format!("expected {} columns, got {}", COLUMNS.len(), rec.len()),
            ));
        }
        let family = match cell(0).to_ascii_lowercase().as_str() {
            "axial" => ModeFamily::Axial,
            "radial" => ModeFamily::Radial,
            "circumferential" => ModeFamily::Circumferential,
            other => {
                return Err(Error::input(
                    &name,
                    field(0),
                    format!("unknown family `{other}`; allowed: axial, radial, circumferential"),
                ))
            }
        };
        let count = |c: usize| -> Result<u32> {
            cell(c).parse::<u32>().map_err(|_| {
                Error::input(
                    &name,
                    field(c),
                    format!("`{}` is not a non-negative integer", cell(c)),
                )
            })
        };
        let nodal_circles = count(1)?;
        let nodal_diameters = count(2)?;
        let frequency_hz = cell(3)
            .parse::<f64>()
            .ok()
            .filter(|f| f.is_finite() && *f > 0.0)
            .ok_or_else(|| {
                Error::input(
                    &name,
                    field(3),
                    format!("`{}` is not a frequency > 0 Hz", cell(3)),
                )
            })?;
        let damping_ratio = if cell(4).is_empty() {
            None
        } else {
            Some(
                cell(4)
                    .parse::<f64>()
                    .ok()
                    .filter(|d| (0.0..1.0).contains(d))
                    .ok_or_else(|| {
                        Error::input(
                            &name,
                            field(4),
                            format!("`{}` is not a damping ratio in [0, 1)", cell(4)),
                        )
                    })?,
            )
        };
        let source = cell(5);
        if source.is_empty() {
            return Err(Error::input(
                &name,
                field(5),
                "every row needs a source (a citation, or `synthetic`)",
            ));
        }
        out.push(MeasuredMode {
            family,
            nodal_circles,
            nodal_diameters,
            frequency_hz,
            damping_ratio,
            source,
        });
    }
    if out.is_empty() {
        return Err(Error::input(&name, "rows", "no measured modes"));
    }
    Ok(out)
}

/// One pair of a measured mode and the FE mode with the same family and indices.
#[derive(Clone, Debug, Serialize)]
pub struct ModePair {
    /// Measured.
    pub measured: MeasuredMode,
    /// FE frequency (Hz).
    pub fe_frequency_hz: f64,
    /// (FE - measured) / measured, per cent.
    pub error_percent: f64,
}

/// Comparison of measured and FE modes.
#[derive(Clone, Debug, Serialize)]
pub struct HammerComparison {
    /// Matched pairs.
    pub pairs: Vec<ModePair>,
    /// Measured modes with no FE mode of the same family and indices.
    pub unmatched_measured: Vec<MeasuredMode>,
    /// FE modes (non-rigid, up to the highest measured frequency x 1.2) with no measured partner.
    pub unmatched_fe: Vec<ModeRef>,
}

/// Pair each measured mode with the FE mode of the same family, nodal circles and nodal
/// diameters (the lowest-frequency one if the FE list repeats a label, e.g. sin/cos members).
pub fn compare(measured: &[MeasuredMode], fe: &[ModeRef]) -> HammerComparison {
    let mut used = vec![false; fe.len()];
    let mut pairs = Vec::new();
    let mut unmatched_measured = Vec::new();
    for m in measured {
        let best = fe
            .iter()
            .enumerate()
            .filter(|(_, f)| {
                f.family == m.family
                    && f.nodal_circles == m.nodal_circles
                    && f.nodal_diameters == m.nodal_diameters
            })
            .min_by(|a, b| a.1.frequency_hz.total_cmp(&b.1.frequency_hz));
        match best {
            Some((k, f)) => {
                used[k] = true;
                pairs.push(ModePair {
                    measured: m.clone(),
                    fe_frequency_hz: f.frequency_hz,
                    error_percent: 100.0 * (f.frequency_hz - m.frequency_hz) / m.frequency_hz,
                });
            }
            None => unmatched_measured.push(m.clone()),
        }
    }
    // Labels already matched (other members of a repeated pair) are not "unmatched".
    let matched_labels: Vec<(ModeFamily, u32, u32)> = pairs
        .iter()
        .map(|p| {
            (
                p.measured.family,
                p.measured.nodal_circles,
                p.measured.nodal_diameters,
            )
        })
        .collect();
    let f_limit = 1.2 * measured.iter().map(|m| m.frequency_hz).fold(0.0, f64::max);
    let unmatched_fe = fe
        .iter()
        .enumerate()
        .filter(|(k, f)| {
            !used[*k]
                && f.family != ModeFamily::Rigid
                && f.frequency_hz <= f_limit
                && !matched_labels.contains(&(f.family, f.nodal_circles, f.nodal_diameters))
        })
        .map(|(_, f)| f.clone())
        .collect();
    HammerComparison {
        pairs,
        unmatched_measured,
        unmatched_fe,
    }
}

impl HammerComparison {
    /// Markdown table.
    pub fn to_markdown(&self) -> String {
        let mut s = String::from("| family | mode (nodal circles, nodal diameters) | measured (Hz) | FE (Hz) | error (%) | source |\n|---|---|---|---|---|---|\n");
        for p in &self.pairs {
            s.push_str(&format!(
                "| {:?} | ({},{}) | {:.1} | {:.1} | {:+.2} | {} |\n",
                p.measured.family,
                p.measured.nodal_circles,
                p.measured.nodal_diameters,
                p.measured.frequency_hz,
                p.fe_frequency_hz,
                p.error_percent,
                p.measured.source
            ));
        }
        if !self.unmatched_measured.is_empty() {
            s.push_str("\nMeasured modes with no FE partner: ");
            s.push_str(
                &self
                    .unmatched_measured
                    .iter()
                    .map(|m| {
                        format!(
                            "{:?} ({},{}) {:.1} Hz",
                            m.family, m.nodal_circles, m.nodal_diameters, m.frequency_hz
                        )
                    })
                    .collect::<Vec<_>>()
                    .join("; "),
            );
            s.push('\n');
        }
        if !self.unmatched_fe.is_empty() {
            s.push_str("\nFE modes with no measured partner: ");
            s.push_str(
                &self
                    .unmatched_fe
                    .iter()
                    .map(|m| format!("{:?} {} {:.1} Hz", m.family, m.label(), m.frequency_hz))
                    .collect::<Vec<_>>()
                    .join("; "),
            );
            s.push('\n');
        }
        s
    }
    /// CSV text.
    pub fn to_csv(&self) -> String {
        let mut s = String::from(
            "family,nodal_circles,nodal_diameters,measured_hz,fe_hz,error_percent,source\n",
        );
        for p in &self.pairs {
            s.push_str(&format!(
                "{:?},{},{},{},{},{},\"{}\"\n",
                p.measured.family,
                p.measured.nodal_circles,
                p.measured.nodal_diameters,
                p.measured.frequency_hz,
                p.fe_frequency_hz,
                p.error_percent,
                p.measured.source.replace('"', "'")
            ));
        }
        s
    }
}
