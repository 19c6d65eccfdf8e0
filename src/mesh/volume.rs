//! General volume meshes for modal input: nodes plus 8-node hexahedra, 10-node tetrahedra
//! and/or 27-node hexahedra with material ids and named node sets, read from Gmsh MSH 4.1 (`.msh`), legacy VTK
//! ASCII (`.vtk`) or VTK XML (`.vtu`) files; and node selection by a box expression
//! (`x<-1.09, z>=0.2`) for clamping.
//!
//! Node order is VTK's for all kinds (hexahedron type 12, quadratic tetrahedron type 24,
//! triquadratic hexahedron type 29; the Gmsh reader takes hex8 and tet10 only); Gmsh tet10 connectivity is permuted on reading (see [`GMSH_TO_VTK_TET10`]). Lower
//! dimensional cells (vertices, lines, triangles, quads and their quadratic forms) are skipped,
//! as are nodes that no volume element uses (a free node would make K singular).

use std::collections::BTreeMap;

use super::{Mesh, P3};
use crate::{Error, Result};

/// `vtk[k] = gmsh[GMSH_TO_VTK_TET10[k]]` for the 10-node tetrahedron: Gmsh's node 8 is on
/// edge 2-3 and node 9 on edge 1-3 (Gmsh reference manual, "Node ordering"), VTK has them the
/// other way round (1-3, then 2-3).
pub const GMSH_TO_VTK_TET10: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8];

/// One volume element (VTK node order).
#[derive(Clone, Debug, PartialEq)]
pub enum VolumeElement {
    /// Trilinear hexahedron.
    Hex8([usize; 8]),
    /// Quadratic tetrahedron.
    Tet10([usize; 10]),
    /// Linear (constant-strain) tetrahedron; [`VolumeMesh::elevate_linear_tets`] turns it
    /// into a straight-sided tet10.
    Tet4([usize; 4]),
    /// Triquadratic (Lagrange) hexahedron.
    Hex27([usize; 27]),
}

impl VolumeElement {
    /// Node ids.
    pub fn nodes(&self) -> &[usize] {
        match self {
            VolumeElement::Hex8(c) => c,
            VolumeElement::Tet10(c) => c,
            VolumeElement::Tet4(c) => c,
            VolumeElement::Hex27(c) => c,
        }
    }
    /// VTK cell type (12, 24, 10 or 29).
    pub fn vtk_type(&self) -> u8 {
        match self {
            VolumeElement::Hex8(_) => 12,
            VolumeElement::Tet10(_) => 24,
            VolumeElement::Tet4(_) => 10,
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

/// Edges of a tetrahedron in the order of the tet10's mid-edge nodes (VTK type 24).
const TET10_EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]];

impl VolumeMesh {
    /// Elevates every linear tetrahedron to a straight-sided quadratic one (tet10, VTK order):
    /// one new node at the midpoint of each edge, shared by the elements around the edge and
    /// numbered in element order (deterministic); a new node joins a node set when both ends
    /// of its edge are in it. The geometry is unchanged; the element no longer locks in
    /// bending. Returns the number of elements elevated.
    pub fn elevate_linear_tets(&mut self) -> usize {
        let mut midpoints: BTreeMap<(usize, usize), usize> = BTreeMap::new();
        let mut count = 0;
        let nodes = &mut self.nodes;
        for element in self.elements.iter_mut() {
            let VolumeElement::Tet4(corners) = *element else {
                continue;
            };
            let mut conn = [0usize; 10];
            conn[..4].copy_from_slice(&corners);
            for (k, [i, j]) in TET10_EDGES.iter().enumerate() {
                let (a, b) = (corners[*i].min(corners[*j]), corners[*i].max(corners[*j]));
                let id = *midpoints.entry((a, b)).or_insert_with(|| {
                    let (pa, pb) = (nodes[a], nodes[b]);
                    nodes.push([0, 1, 2].map(|d| 0.5 * (pa[d] + pb[d])));
                    nodes.len() - 1
                });
                conn[4 + k] = id;
            }
            *element = VolumeElement::Tet10(conn);
            count += 1;
        }
        for ids in self.node_sets.values_mut() {
            let members: std::collections::HashSet<usize> = ids.iter().copied().collect();
            for (&(a, b), &id) in &midpoints {
                if members.contains(&a) && members.contains(&b) {
                    ids.push(id);
                }
            }
            ids.sort_unstable();
            ids.dedup();
        }
        count
    }

    /// Number of linear tetrahedra.
    pub fn linear_tet_count(&self) -> usize {
        self.elements
            .iter()
            .filter(|e| matches!(e, VolumeElement::Tet4(_)))
            .count()
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
                VolumeElement::Tet4(c) => c.iter_mut().for_each(|k| *k = new_id[*k]),
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
