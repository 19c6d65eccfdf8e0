//! General volume meshes for modal input: nodes plus 8-node hexahedra, 10-node tetrahedra
//! and/or 27-node hexahedra with material ids and named node sets, read from Gmsh MSH 4.1 (`.msh`), legacy VTK
//! ASCII (`.vtk`) or VTK XML (`.vtu`) files; and node selection by a box expression
//! (`x<-1.09, z>=0.2`) for clamping.
//!
//! Node order is VTK's for all kinds (hexahedron type 12, quadratic tetrahedron type 24,
//! triquadratic hexahedron type 29; the Gmsh reader takes hex8 and tet10 only); Gmsh tet10 connectivity is permuted on reading (see [`crate::fem::tet10::GMSH_TO_VTK`]). Lower
//! dimensional cells (vertices, lines, triangles, quads and their quadratic forms) are skipped,
//! as are nodes that no volume element uses (a free node would make K singular).

use std::collections::BTreeMap;
use std::path::Path;

use super::vtu::VtuContents;
use super::{Mesh, P3};
use crate::fem::{hex27, tet10};
use crate::{Error, Result};

/// One volume element (VTK node order).
#[derive(Clone, Debug, PartialEq)]
pub enum VolumeElement {
    /// Trilinear hexahedron.
    Hex8([usize; 8]),
    /// Quadratic tetrahedron.
    Tet10([usize; 10]),
    /// Triquadratic (Lagrange) hexahedron.
    Hex27([usize; 27]),
}

impl VolumeElement {
    /// Node ids.
    pub fn nodes(&self) -> &[usize] {
        match self {
            VolumeElement::Hex8(c) => c,
            VolumeElement::Tet10(c) => c,
            VolumeElement::Hex27(c) => c,
        }
    }
    /// VTK cell type (12, 24 or 29).
    pub fn vtk_type(&self) -> u8 {
        match self {
            VolumeElement::Hex8(_) => 12,
            VolumeElement::Tet10(_) => 24,
            VolumeElement::Hex27(_) => 29,
        }
    }
}

/// A mixed hex8 / tet10 / hex27 mesh.
#[derive(Clone, Debug, Default)]
pub struct VolumeMesh {
    /// Node coordinates (m).
    pub nodes: Vec<P3>,
    /// Elements.
    pub elements: Vec<VolumeElement>,
    /// Material id per element.
    pub material: Vec<u32>,
    /// Named node sets (sorted, unique node ids).
    pub node_sets: BTreeMap<String, Vec<usize>>,
}

impl From<&Mesh> for VolumeMesh {
    fn from(mesh: &Mesh) -> Self {
        VolumeMesh {
            nodes: mesh.nodes.clone(),
            elements: mesh
                .elements
                .iter()
                .map(|&c| VolumeElement::Hex8(c))
                .collect(),
            material: mesh.material.clone(),
            node_sets: mesh.node_sets.clone(),
        }
    }
}

impl VolumeMesh {
    /// Element volume (m³).
    pub fn element_volume(&self, e: usize) -> f64 {
        match &self.elements[e] {
            VolumeElement::Hex8(c) => super::hex::volume(&c.map(|n| self.nodes[n])),
            VolumeElement::Tet10(c) => tet10::volume(&c.map(|n| self.nodes[n])),
            VolumeElement::Hex27(c) => hex27::volume(&c.map(|n| self.nodes[n])),
        }
    }

    /// Total volume (m³).
    pub fn volume(&self) -> f64 {
        (0..self.elements.len())
            .map(|e| self.element_volume(e))
            .sum()
    }

    /// Nodal weights for mode classification: each element's volume shared equally by its
    /// nodes.
    pub fn nodal_weights(&self) -> Vec<f64> {
        let mut w = vec![0.0; self.nodes.len()];
        for (e, el) in self.elements.iter().enumerate() {
            let v = self.element_volume(e).abs() / el.nodes().len() as f64;
            for &n in el.nodes() {
                w[n] += v;
            }
        }
        w
    }

    /// Volume centroid (m), from the nodal weights.
    pub fn centroid(&self) -> P3 {
        let w = self.nodal_weights();
        let total: f64 = w.iter().sum::<f64>().max(1e-300);
        [0, 1, 2].map(|d| {
            self.nodes
                .iter()
                .zip(&w)
                .map(|(p, w)| p[d] * w)
                .sum::<f64>()
                / total
        })
    }

    /// Axis-aligned bounding box (min, max).
    pub fn bounds(&self) -> (P3, P3) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for p in &self.nodes {
            for d in 0..3 {
                lo[d] = lo[d].min(p[d]);
                hi[d] = hi[d].max(p[d]);
            }
        }
        (lo, hi)
    }

    /// Insert (or replace) a node set.
    pub fn set_node_set(&mut self, name: &str, mut ids: Vec<usize>) {
        ids.sort_unstable();
        ids.dedup();
        self.node_sets.insert(name.to_string(), ids);
    }

    /// Checks that every element index is a node, coordinates are finite and there is at least
    /// one element; then drops the nodes no element uses (renumbering the rest, node sets
    /// included).
    pub fn validate_and_compact(&mut self, source: &str) -> Result<()> {
        if self.elements.is_empty() {
            return Err(Error::input(
                source,
                "cells",
                "no volume elements (8-node hexahedra or 10-node tetrahedra) in the file",
            ));
        }
        if self.material.len() != self.elements.len() {
            return Err(Error::input(
                source,
                "cells",
                format!(
                    "{} material ids for {} elements",
                    self.material.len(),
                    self.elements.len()
                ),
            ));
        }
        let n = self.nodes.len();
        for (i, p) in self.nodes.iter().enumerate() {
            if !p.iter().all(|c| c.is_finite()) {
                return Err(Error::input(
                    source,
                    "points",
                    format!("point {i} has a non-finite coordinate {p:?}"),
                ));
            }
        }
        let mut used = vec![false; n];
        for (e, el) in self.elements.iter().enumerate() {
            for &k in el.nodes() {
                if k >= n {
                    return Err(Error::input(
                        source,
                        "cells",
                        format!("element {e} refers to point {k}, but there are only {n} points (0-based indices 0..{})", n.saturating_sub(1)),
                    ));
                }
                used[k] = true;
            }
        }
        if used.iter().all(|&u| u) {
            return Ok(());
        }
        let mut new_id = vec![usize::MAX; n];
        let mut nodes = Vec::new();
        for i in 0..n {
            if used[i] {
                new_id[i] = nodes.len();
                nodes.push(self.nodes[i]);
            }
        }
        self.nodes = nodes;
        for el in &mut self.elements {
            match el {
                VolumeElement::Hex8(c) => c.iter_mut().for_each(|k| *k = new_id[*k]),
                VolumeElement::Tet10(c) => c.iter_mut().for_each(|k| *k = new_id[*k]),
                VolumeElement::Hex27(c) => c.iter_mut().for_each(|k| *k = new_id[*k]),
            }
        }
        for ids in self.node_sets.values_mut() {
            *ids = ids
                .iter()
                .filter(|&&k| k < n && used[k])
                .map(|&k| new_id[k])
                .collect();
        }
        Ok(())
    }
}

/// Read a volume mesh: `.msh` (Gmsh 4.1 ASCII; material id = volume entity tag), `.vtk` (legacy
/// ASCII unstructured grid) or `.vtu` (VTK XML, ASCII or inline binary arrays). VTK material ids
/// come from the cell array `material`, `gmsh:physical`, `CellEntityIds` or `MaterialIds` (the
/// first present), else 1.
pub fn read(path: &Path) -> Result<VolumeMesh> {
    let name = path.display().to_string();
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let mut mesh = match ext.as_str() {
        "msh" => {
            let c = super::gmsh::read(path)?;
            let mut m = VolumeMesh {
                nodes: c.nodes,
                ..Default::default()
            };
            for (conn, entity) in c.hexahedra {
                m.elements.push(VolumeElement::Hex8(conn));
                m.material.push(entity.max(0) as u32);
            }
            for (conn, entity) in c.tetrahedra10 {
                let vtk = tet10::GMSH_TO_VTK.map(|k| conn[k]);
                m.elements.push(VolumeElement::Tet10(vtk));
                m.material.push(entity.max(0) as u32);
            }
            m
        }
        "vtk" => from_vtk_contents(&name, super::vtk_legacy::read(path)?)?,
        "vtu" => from_vtk_contents(&name, super::vtu::read(path)?)?,
        _ => {
            return Err(Error::input(
                &name,
                "--mesh",
                format!("unknown mesh file extension `.{ext}`: expected .msh (Gmsh 4.1 ASCII), .vtk (legacy VTK ASCII) or .vtu (VTK XML)"),
            ))
        }
    };
    mesh.validate_and_compact(&name)?;
    Ok(mesh)
}

/// VTK cell types that are not volume elements and are skipped (vertex, poly-vertex, line,
/// poly-line, triangle, triangle strip, polygon, pixel, quad, and their quadratic forms).
const SKIPPED_VTK_TYPES: [u8; 13] = [1, 2, 3, 4, 5, 6, 7, 8, 9, 21, 22, 23, 28];

/// Convert VTK cells (types 12, 24 and 29) into a volume mesh; other volume cell types are errors.
pub fn from_vtk_contents(source: &str, c: VtuContents) -> Result<VolumeMesh> {
    let ids = ["material", "gmsh:physical", "CellEntityIds", "MaterialIds"]
        .iter()
        .find_map(|k| c.cell_data.get(*k).map(|v| (*k, v)));
    if let Some((key, v)) = ids {
        if v.len() != c.cells.len() {
            return Err(Error::input(
                source,
                format!("cell data `{key}`"),
                format!("{} values for {} cells", v.len(), c.cells.len()),
            ));
        }
    }
    let mut m = VolumeMesh {
        nodes: c.points,
        ..Default::default()
    };
    for (i, (cell, &ty)) in c.cells.iter().zip(&c.cell_types).enumerate() {
        let material = match ids {
            Some((key, v)) => {
                let x = v[i];
                if !(x.is_finite() && x >= 0.0 && x.fract() == 0.0 && x <= u32::MAX as f64) {
                    return Err(Error::input(
                        source,
                        format!("cell data `{key}`"),
                        format!("cell {i}: material id {x} is not a non-negative integer"),
                    ));
                }
                x as u32
            }
            None => 1,
        };
        let wrong_count = |n: usize| {
            Error::input(
                source,
                "cells",
                format!(
                    "cell {i} of type {ty} has {} nodes, expected {n}",
                    cell.len()
                ),
            )
        };
        match ty {
            12 => {
                let conn: [usize; 8] = cell.as_slice().try_into().map_err(|_| wrong_count(8))?;
                m.elements.push(VolumeElement::Hex8(conn));
                m.material.push(material);
            }
            24 => {
                let conn: [usize; 10] =
                    cell.as_slice().try_into().map_err(|_| wrong_count(10))?;
                m.elements.push(VolumeElement::Tet10(conn));
                m.material.push(material);
            }
            29 => {
                let conn: [usize; 27] =
                    cell.as_slice().try_into().map_err(|_| wrong_count(27))?;
                m.elements.push(VolumeElement::Hex27(conn));
                m.material.push(material);
            }
            10 => {
                return Err(Error::input(
                    source,
                    "cells",
                    format!("cell {i} is a linear tetrahedron (VTK type 10): not supported (too stiff for modal analysis); use quadratic tetrahedra (type 24, e.g. Gmsh -order 2) or hexahedra (type 12)"),
                ))
            }
            t if SKIPPED_VTK_TYPES.contains(&t) => {}
            t => {
                return Err(Error::input(
                    source,
                    "cells",
                    format!("cell {i} has VTK cell type {t}, which is not supported: volume cells must be hexahedra (12), quadratic tetrahedra (24) or triquadratic hexahedra (29)"),
                ))
            }
        }
    }
    Ok(m)
}

/// The coordinate a box condition tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoxCoordinate {
    /// x (m).
    X,
    /// y (m), the wheel axis.
    Y,
    /// z (m).
    Z,
    /// Distance from the y axis, `sqrt(x² + z²)` (m).
    R,
}

/// A comparison.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BoxComparison {
    /// `<`
    Less,
    /// `<=`
    LessEqual,
    /// `>`
    Greater,
    /// `>=`
    GreaterEqual,
}

/// One condition of a box expression, e.g. `x<-1.09`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BoxCondition {
    /// Coordinate.
    pub coordinate: BoxCoordinate,
    /// Comparison.
    pub comparison: BoxComparison,
    /// Value (m).
    pub value: f64,
}

/// The allowed form of a box expression, for error messages.
pub const BOX_EXPRESSION_FORM: &str = "one or more conditions `<coordinate><op><value>` joined by `,` or `&`, coordinate x, y, z (m) or r = sqrt(x² + z²) (distance from the y axis, m), op <, <=, > or >=, e.g. \"x<-1.09\" or \"y>=0.2, r<0.1\"";

/// Parse a box expression like `x<-1.09` or `y>=0.2 & r<0.1`; the error text says what is
/// wrong (the caller adds the option name).
pub fn parse_box_expression(text: &str) -> std::result::Result<Vec<BoxCondition>, String> {
    let mut out = Vec::new();
    for part in text.split([',', '&']) {
        let p: String = part.chars().filter(|c| !c.is_whitespace()).collect();
        if p.is_empty() {
            if text.contains("&&") && part.trim().is_empty() && !out.is_empty() {
                continue; // `a && b`
            }
            return Err(format!("empty condition in `{text}`"));
        }
        let mut chars = p.chars();
        let coordinate = match chars.next().map(|c| c.to_ascii_lowercase()) {
            Some('x') => BoxCoordinate::X,
            Some('y') => BoxCoordinate::Y,
            Some('z') => BoxCoordinate::Z,
            Some('r') => BoxCoordinate::R,
            _ => return Err(format!("`{p}` does not start with x, y, z or r")),
        };
        let rest = chars.as_str();
        let (comparison, value) = if let Some(v) = rest.strip_prefix("<=") {
            (BoxComparison::LessEqual, v)
        } else if let Some(v) = rest.strip_prefix(">=") {
            (BoxComparison::GreaterEqual, v)
        } else if let Some(v) = rest.strip_prefix('<') {
            (BoxComparison::Less, v)
        } else if let Some(v) = rest.strip_prefix('>') {
            (BoxComparison::Greater, v)
        } else {
            return Err(format!("`{p}` has no comparison <, <=, > or >="));
        };
        let value: f64 = value
            .parse()
            .ok()
            .filter(|v: &f64| v.is_finite())
            .ok_or_else(|| format!("`{value}` in `{p}` is not a finite number (metres)"))?;
        out.push(BoxCondition {
            coordinate,
            comparison,
            value,
        });
    }
    Ok(out)
}

/// Whether `p` satisfies every condition.
pub fn box_contains(conditions: &[BoxCondition], p: &P3) -> bool {
    conditions.iter().all(|c| {
        let v = match c.coordinate {
            BoxCoordinate::X => p[0],
            BoxCoordinate::Y => p[1],
            BoxCoordinate::Z => p[2],
            BoxCoordinate::R => p[0].hypot(p[2]),
        };
        match c.comparison {
            BoxComparison::Less => v < c.value,
            BoxComparison::LessEqual => v <= c.value,
            BoxComparison::Greater => v > c.value,
            BoxComparison::GreaterEqual => v >= c.value,
        }
    })
}

/// Nodes satisfying every condition.
pub fn select_nodes(nodes: &[P3], conditions: &[BoxCondition]) -> Vec<usize> {
    (0..nodes.len())
        .filter(|&i| box_contains(conditions, &nodes[i]))
        .collect()
}
