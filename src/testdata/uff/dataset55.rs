//! Dataset 55, data at nodes: mode shapes and other nodal results (docs/uff-format.md, section 3).
//!
//! Records 1-5 are ID lines; record 6 (6I10) gives the model type, the analysis type (2 normal
//! mode, 3 and 7 complex eigenvalue, ...), the data characteristic (1 scalar, 2 three
//! translations, 3 translations and rotations, ...), the specific data type, the data type
//! (2 real, 5 complex) and the number of values per node; record 7 (8I10) the count of
//! integers and reals that follow and the integers (load case, mode number); record 8 (6E13.5)
//! the reals (normal mode: frequency, modal mass, viscous and hysteretic damping ratios; complex
//! eigenvalue: Re and Im of the eigenvalue, modal A and B). Then per node a label (I10) and its
//! values (6E13.5 per line, complex as Re, Im pairs).

use rustfft::num_complex::Complex;

use super::block::Context;
use super::fields::{integers, reals};
use crate::Result;

/// Values of one node.
#[derive(Clone, Debug, PartialEq)]
pub struct NodalValues {
    /// Node label.
    pub node: i64,
    /// Its values (real data: zero imaginary parts).
    pub values: Vec<Complex<f64>>,
}

/// Analysis type codes of record 6 field 2 that the toolkit names.
pub mod analysis_type {
    /// Normal mode.
    pub const NORMAL_MODE: i64 = 2;
    /// Complex eigenvalue, first order.
    pub const COMPLEX_EIGENVALUE: i64 = 3;
    /// Complex eigenvalue, second order (same records as first order).
    pub const COMPLEX_EIGENVALUE_SECOND_ORDER: i64 = 7;
}

/// A dataset 55.
#[derive(Clone, Debug, PartialEq)]
pub struct NodalData {
    /// Records 1-5.
    pub id_lines: [String; 5],
    /// Model type (1 structural).
    pub model_type: i64,
    /// Analysis type (2 normal mode, 3/7 complex eigenvalue, ...).
    pub analysis_type: i64,
    /// Data characteristic (2: X, Y, Z translations).
    pub data_characteristic: i64,
    /// Specific data type (8 displacement, ...).
    pub specific_data_type: i64,
    /// Whether the values are complex (data type 5).
    pub complex: bool,
    /// Values per node.
    pub values_per_node: usize,
    /// Record 7's integers (normal mode: load case, mode number).
    pub integers: Vec<i64>,
    /// Record 8's reals.
    pub reals: Vec<f64>,
    /// Values per node, in file order.
    pub nodes: Vec<NodalValues>,
}

impl NodalData {
    /// Natural frequency of a mode, Hz: record 8's frequency for a normal mode, `|lambda| / 2 pi`
    /// for a complex eigenvalue.
    pub fn frequency_hz(&self) -> Option<f64> {
        match self.analysis_type {
            analysis_type::NORMAL_MODE => self.reals.first().copied(),
            analysis_type::COMPLEX_EIGENVALUE | analysis_type::COMPLEX_EIGENVALUE_SECOND_ORDER => {
                let (re, im) = (*self.reals.first()?, *self.reals.get(1)?);
                Some(re.hypot(im) / (2.0 * std::f64::consts::PI))
            }
            _ => None,
        }
    }

    /// Viscous damping ratio of a mode: record 8's third real for a normal mode,
    /// `-Re(lambda) / |lambda|` for a complex eigenvalue.
    pub fn damping_ratio(&self) -> Option<f64> {
        match self.analysis_type {
            analysis_type::NORMAL_MODE => self.reals.get(2).copied(),
            analysis_type::COMPLEX_EIGENVALUE | analysis_type::COMPLEX_EIGENVALUE_SECOND_ORDER => {
                let (re, im) = (*self.reals.first()?, *self.reals.get(1)?);
                Some(-re / re.hypot(im))
            }
            _ => None,
        }
    }

    /// Mode number (record 7's second integer for modal analysis types).
    pub fn mode_number(&self) -> Option<i64> {
        self.integers.get(1).copied()
    }
}

/// Parses the records of one dataset 55.
pub fn parse(lines: &[String], ctx: &Context) -> Result<NodalData> {
    if lines.len() < 8 {
        return Err(ctx.error(
            "records",
            format!(
                "{} records; a dataset 55 has 8 before its nodes",
                lines.len()
            ),
        ));
    }
    let id_lines: [String; 5] = std::array::from_fn(|k| lines[k].clone());
    let r6 = integers(&lines[5], &[10; 6]).ok_or_else(|| {
        ctx.record_error(
            6,
            "data description",
            format!(
                "`{}` is not Format(6I10): model type, analysis type, data characteristic, \
                 specific data type, data type, values per node",
                lines[5]
            ),
        )
    })?;
    let complex = match r6[4] {
        2 => false,
        5 => true,
        other => {
            return Err(ctx.record_error(
                6,
                "data type",
                format!("{other}; allowed: 2 (real) or 5 (complex)"),
            ))
        }
    };
    let values_per_node = usize::try_from(r6[5])
        .ok()
        .filter(|n| (1..=1000).contains(n))
        .ok_or_else(|| {
            ctx.record_error(
                6,
                "values per node",
                format!("{}; allowed: 1..=1000", r6[5]),
            )
        })?;

    // Record 7: NINT, NRVAL, then NINT integers, 8 per line.
    let first: Vec<i64> = lines[6]
        .split_whitespace()
        .map(|t| t.parse().ok())
        .collect::<Option<Vec<i64>>>()
        .filter(|t| t.len() >= 2)
        .ok_or_else(|| {
            ctx.record_error(
                7,
                "integers",
                format!(
                    "`{}` is not Format(8I10) starting with the counts of integers and reals",
                    lines[6]
                ),
            )
        })?;
    let (int_count, real_count) = (first[0], first[1]);
    if !(0..=10).contains(&int_count) || !(0..=12).contains(&real_count) {
        return Err(ctx.record_error(
            7,
            "counts",
            format!("{int_count} integers and {real_count} reals; allowed: 0..=10 and 0..=12"),
        ));
    }
    let (int_count, real_count) = (int_count as usize, real_count as usize);
    let mut integer_values: Vec<i64> = first[2..].to_vec();
    let mut next = 7;
    while integer_values.len() < int_count {
        let line = lines
            .get(next)
            .ok_or_else(|| ctx.record_error(7, "integers", "the dataset ends inside record 7"))?;
        next += 1;
        for token in line.split_whitespace() {
            integer_values.push(token.parse().map_err(|_| {
                ctx.record_error(7, "integers", format!("`{token}` is not an integer"))
            })?);
        }
    }
    if integer_values.len() != int_count {
        return Err(ctx.record_error(
            7,
            "integers",
            format!(
                "{} integers for the {int_count} announced",
                integer_values.len()
            ),
        ));
    }
    let (real_values, used) = reals(&lines[next..], real_count, &[13], ctx, 8, "reals")?;
    next += used;

    // Records 9 and 10 per node.
    let per_node = values_per_node * if complex { 2 } else { 1 };
    let mut nodes = Vec::new();
    while next < lines.len() {
        let label_line = lines[next].trim();
        let node: i64 = label_line.parse().map_err(|_| {
            ctx.record_error(
                9,
                "node label",
                format!(
                    "`{label_line}` (record {} of the dataset) is not a node label (I10)",
                    next + 1
                ),
            )
        })?;
        next += 1;
        let (values, used) = reals(
            &lines[next..],
            per_node,
            &[13],
            ctx,
            10,
            &format!("node {node}"),
        )?;
        next += used;
        if let Some(index) = values.iter().position(|v| !v.is_finite()) {
            return Err(ctx.record_error(
                10,
                &format!("node {node}"),
                format!("value {} is not finite", index + 1),
            ));
        }
        let values = if complex {
            values
                .chunks_exact(2)
                .map(|c| Complex::new(c[0], c[1]))
                .collect()
        } else {
            values.iter().map(|&x| Complex::new(x, 0.0)).collect()
        };
        nodes.push(NodalValues { node, values });
    }
    Ok(NodalData {
        id_lines,
        model_type: r6[0],
        analysis_type: r6[1],
        data_characteristic: r6[2],
        specific_data_type: r6[3],
        complex,
        values_per_node,
        integers: integer_values,
        reals: real_values,
        nodes,
    })
}
