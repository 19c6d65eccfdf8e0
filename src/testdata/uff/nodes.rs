//! Node coordinates: dataset 15 (one record per node, Format(4I10,1P3E13.5)) and dataset 2411
//! (two records per node, 4I10 then 1P3D25.16) (docs/uff-format.md, sections 4 and 5).

use super::block::Context;
use super::fields::{integers, parse_real};
use crate::Result;

/// A node of a test geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct Node {
    /// Label.
    pub label: i64,
    /// Definition (15) or export (2411) coordinate system number.
    pub coordinate_system: i64,
    /// Displacement coordinate system number.
    pub displacement_system: i64,
    /// Colour.
    pub color: i64,
    /// X, Y, Z in the file's length unit (dataset 164).
    pub position: [f64; 3],
}

fn position(tokens: &[&str]) -> Option<[f64; 3]> {
    let p = [
        parse_real(tokens.first()?)?,
        parse_real(tokens.get(1)?)?,
        parse_real(tokens.get(2)?)?,
    ];
    p.iter().all(|c| c.is_finite()).then_some(p)
}

/// Dataset 15: one line per node, label, two coordinate systems, colour, X, Y, Z.
pub fn parse_15(lines: &[String], ctx: &Context) -> Result<Vec<Node>> {
    lines
        .iter()
        .enumerate()
        .map(|(k, line)| {
            let t: Vec<&str> = line.split_whitespace().collect();
            let node = || -> Option<Node> {
                let ints: Vec<i64> = t
                    .iter()
                    .take(4)
                    .map(|x| x.parse().ok())
                    .collect::<Option<_>>()?;
                (t.len() == 7).then_some(())?;
                Some(Node {
                    label: ints[0],
                    coordinate_system: ints[1],
                    displacement_system: ints[2],
                    color: ints[3],
                    position: position(&t[4..])?,
                })
            };
            node().ok_or_else(|| {
                ctx.record_error(
                    k + 1,
                    "node",
                    format!(
                        "`{line}` is not Format(4I10,1P3E13.5): label, coordinate systems, \
                         colour, X, Y, Z"
                    ),
                )
            })
        })
        .collect()
}

/// Dataset 2411: per node a 4I10 line (label, export and displacement coordinate systems,
/// colour) and a 3D25.16 line (X, Y, Z).
pub fn parse_2411(lines: &[String], ctx: &Context) -> Result<Vec<Node>> {
    if !lines.len().is_multiple_of(2) {
        return Err(ctx.error(
            "records",
            format!(
                "{} records; dataset 2411 has two per node (label line, coordinate line)",
                lines.len()
            ),
        ));
    }
    lines
        .chunks_exact(2)
        .enumerate()
        .map(|(k, pair)| {
            let ints = integers(&pair[0], &[10, 10, 10, 10]).ok_or_else(|| {
                ctx.record_error(
                    2 * k + 1,
                    "node",
                    format!(
                        "`{}` is not Format(4I10): label, coordinate systems, colour",
                        pair[0]
                    ),
                )
            })?;
            let t: Vec<&str> = pair[1].split_whitespace().collect();
            let xyz = (t.len() == 3)
                .then(|| position(&t))
                .flatten()
                .ok_or_else(|| {
                    ctx.record_error(
                        2 * k + 2,
                        &format!("node {}", ints[0]),
                        format!("`{}` is not Format(1P3D25.16): X, Y, Z", pair[1]),
                    )
                })?;
            Ok(Node {
                label: ints[0],
                coordinate_system: ints[1],
                displacement_system: ints[2],
                color: ints[3],
                position: xyz,
            })
        })
        .collect()
}
