//! The contents of a VTK file, whatever its format (legacy ASCII or XML): points, cells of any
//! type as node lists, and named arrays; what the readers of [`super::vtu`] and
//! [`super::vtk_legacy`] return.

/// What the VTK readers return: points, cells (any VTK cell type, as node lists), cell types and the
/// named arrays (as f64) found in the file.
#[derive(Debug, Default)]
pub struct VtuContents {
    /// Points.
    pub points: Vec<[f64; 3]>,
    /// Cell connectivity.
    pub cells: Vec<Vec<usize>>,
    /// VTK cell type per cell.
    pub cell_types: Vec<u8>,
    /// Point arrays by name (flattened components).
    pub point_data: std::collections::BTreeMap<String, Vec<f64>>,
    /// Cell arrays by name.
    pub cell_data: std::collections::BTreeMap<String, Vec<f64>>,
}
