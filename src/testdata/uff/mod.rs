//! Universal File Format (UFF, also UNV) reading and writing: the files every modal test
//! system (Simcenter Testlab, B&K, m+p, Dewesoft) exports, and pyuff / sdypy-EMA read.
//!
//! A file is a sequence of blocks `    -1` / dataset number / records / `    -1` (docs/uff-format.md has
//! every record of every dataset handled here, with its Fortran format). Datasets read:
//! - [`dataset58`]: a function at nodal DOF (FRF, time response, spectrum...), ASCII in all eight
//!   real/complex x single/double x even/uneven layouts, and the binary form "58b";
//! - [`dataset55`]: data at nodes (mode shapes, real or complex);
//! - [`nodes`]: node coordinates, datasets 15 (single precision) and 2411 (double);
//! - [`units`]: dataset 164, the factors that convert the file's units to SI.
//!
//! Other datasets are skipped and listed in [`UffFile::skipped_datasets`]. One concept per
//! file: [`block`] splits a file into datasets (binary-safe), [`fields`] reads fixed-column
//! Fortran records, [`write`] writes our own files in the same layouts.

pub mod block;
pub mod dataset55;
pub mod dataset58;
pub mod fields;
pub mod nodes;
pub mod units;
pub mod write;

use std::path::Path;

pub use dataset55::{NodalData, NodalValues};
pub use dataset58::{Abscissa, AxisInfo, Dof, Function, FunctionValues, OrdinatePrecision};
pub use nodes::Node;
pub use units::Units;

use crate::{Error, Result};

/// The datasets of one universal file, in file order within each kind.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct UffFile {
    /// Dataset 164, when present (applies to the whole file).
    pub units: Option<Units>,
    /// Datasets 15 and 2411, in the file's units.
    pub nodes: Vec<Node>,
    /// Datasets 58 and 58b.
    pub functions: Vec<Function>,
    /// Datasets 55.
    pub nodal_data: Vec<NodalData>,
    /// Numbers of the datasets that were skipped (not read by this toolkit).
    pub skipped_datasets: Vec<u32>,
}

impl UffFile {
    /// Length factor of dataset 164 (SI length = file length / factor); 1 without units.
    pub fn length_factor(&self) -> f64 {
        self.units.as_ref().map_or(1.0, |u| u.length_factor)
    }

    /// Coordinates of node `label` in metres (dataset 164's length factor applied), if present.
    pub fn node_position_m(&self, label: i64) -> Option<[f64; 3]> {
        let factor = self.length_factor();
        self.nodes
            .iter()
            .find(|n| n.label == label)
            .map(|n| n.position.map(|c| c / factor))
    }
}

/// Reads a universal file; errors name the file, the dataset (its number and line) and the
/// record and field at fault.
pub fn read_uff(path: &Path) -> Result<UffFile> {
    let bytes = std::fs::read(path).map_err(|e| Error::reading(path, e))?;
    parse_uff(&bytes, &path.display().to_string())
}

/// Parses the bytes of a universal file; `name` is used in error messages.
pub fn parse_uff(bytes: &[u8], name: &str) -> Result<UffFile> {
    let blocks = block::split_blocks(bytes, name)?;
    if blocks.is_empty() {
        return Err(Error::input(
            name,
            "datasets",
            "no dataset found: a universal file is a sequence of blocks that start and end \
             with a `    -1` line",
        ));
    }
    let mut file = UffFile::default();
    for b in &blocks {
        let ctx = block::Context {
            file: name,
            dataset: b.number,
            first_line: b.first_line,
        };
        match (b.number, &b.binary) {
            (58, _) => file.functions.push(dataset58::parse(b, &ctx)?),
            (55, None) => file.nodal_data.push(dataset55::parse(&b.lines, &ctx)?),
            (15, None) => file.nodes.extend(nodes::parse_15(&b.lines, &ctx)?),
            (2411, None) => file.nodes.extend(nodes::parse_2411(&b.lines, &ctx)?),
            (164, None) => {
                if file.units.is_some() {
                    return Err(ctx.error(
                        "dataset 164",
                        "a second units dataset; a file has one system of units",
                    ));
                }
                file.units = Some(units::parse(&b.lines, &ctx)?)
            }
            (number, _) => file.skipped_datasets.push(number),
        }
    }
    Ok(file)
}
