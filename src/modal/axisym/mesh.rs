//! Nine-node (Q9, Lagrangian) quadrilateral meshes of a body-of-revolution cross-section in
//! (r, z) metres: z is the axis of revolution (the wheel's lateral coordinate S = y), r the
//! radius.
//!
//! Built either from a linear [`SectionMesh`] (the wheel section of `mesh::wheel`, in (S, r) mm)
//! by adding a node at the middle of every (straight) edge and at the centre of every quad, or
//! directly by the structured rectangle mesher [`Q9Mesh::rectangle`] used by the tests (annular
//! or solid discs, ring sections).

use std::collections::HashMap;

use crate::mesh::section::SectionMesh;

/// A Q9 mesh of a cross-section.
#[derive(Clone, Debug, Default)]
pub struct Q9Mesh {
    /// Node coordinates `[r, z]` (m), r >= 0.
    pub nodes: Vec<[f64; 2]>,
    /// Elements: corners 0..4 (counter-clockwise in the parent square), mid-side nodes 4..8 on
    /// the edges (0,1), (1,2), (2,3), (3,0), centre node 8.
    pub elements: Vec<[usize; 9]>,
    /// Part id per element (material / region, e.g. `mesh::material::AXLE`).
    pub part: Vec<u32>,
}

impl Q9Mesh {
    /// Upgrade a linear quad section mesh in (S, r) millimetres to Q9 in (r, z) metres
    /// (z = S). Quads whose part is in `drop_parts` are left out; nodes no kept quad uses are
    /// removed.
    pub fn from_section(section: &SectionMesh, drop_parts: &[u32]) -> Q9Mesh {
        let mut mesh = Q9Mesh::default();
        let mut corner_id: HashMap<usize, usize> = HashMap::new();
        let mut edge_id: HashMap<(usize, usize), usize> = HashMap::new();
        let to_rz = |p: [f64; 2]| [p[1] * 1e-3, p[0] * 1e-3];
        for (q, quad) in section.quads.iter().enumerate() {
            let part = section.quad_part[q];
            if drop_parts.contains(&part) {
                continue;
            }
            let mut e = [0usize; 9];
            for k in 0..4 {
                let id = *corner_id.entry(quad[k]).or_insert_with(|| {
                    mesh.nodes.push(to_rz(section.nodes[quad[k]]));
                    mesh.nodes.len() - 1
                });
                e[k] = id;
            }
            for k in 0..4 {
                let (a, b) = (quad[k], quad[(k + 1) % 4]);
                let key = (a.min(b), a.max(b));
                let id = *edge_id.entry(key).or_insert_with(|| {
                    let (pa, pb) = (section.nodes[a], section.nodes[b]);
                    mesh.nodes
                        .push(to_rz([0.5 * (pa[0] + pb[0]), 0.5 * (pa[1] + pb[1])]));
                    mesh.nodes.len() - 1
                });
                e[4 + k] = id;
            }
            let c = quad.iter().fold([0.0, 0.0], |acc, &i| {
                let p = section.nodes[i];
                [acc[0] + 0.25 * p[0], acc[1] + 0.25 * p[1]]
            });
            mesh.nodes.push(to_rz(c));
            e[8] = mesh.nodes.len() - 1;
            mesh.elements.push(e);
            mesh.part.push(part);
        }
        mesh
    }

    /// Structured mesh of the rectangle r in [r0, r1], z in [z0, z1] (m) with `nr` x `nz`
    /// elements (part 1). r0 = 0 gives a solid disc (nodes on the axis).
    pub fn rectangle(r0: f64, r1: f64, z0: f64, z1: f64, nr: usize, nz: usize) -> Q9Mesh {
        let (nr, nz) = (nr.max(1), nz.max(1));
        let (cols, rows) = (2 * nr + 1, 2 * nz + 1);
        let nodes: Vec<[f64; 2]> = (0..rows)
            .flat_map(|j| {
                (0..cols).map(move |i| {
                    [
                        r0 + (r1 - r0) * i as f64 / (cols - 1) as f64,
                        z0 + (z1 - z0) * j as f64 / (rows - 1) as f64,
                    ]
                })
            })
            .collect();
        let id = |i: usize, j: usize| j * cols + i;
        let mut elements = Vec::with_capacity(nr * nz);
        for ej in 0..nz {
            for ei in 0..nr {
                let (i, j) = (2 * ei, 2 * ej);
                elements.push([
                    id(i, j),
                    id(i + 2, j),
                    id(i + 2, j + 2),
                    id(i, j + 2),
                    id(i + 1, j),
                    id(i + 2, j + 1),
                    id(i + 1, j + 2),
                    id(i, j + 1),
                    id(i + 1, j + 1),
                ]);
            }
        }
        let part = vec![1; elements.len()];
        Q9Mesh {
            nodes,
            elements,
            part,
        }
    }

    /// Number of nodes.
    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Nodes on the axis (r below `1e-9` times the largest radius).
    pub fn axis_nodes(&self) -> Vec<bool> {
        let r_max = self.nodes.iter().fold(0.0f64, |m, p| m.max(p[0]));
        self.nodes.iter().map(|p| p[0] <= 1e-9 * r_max).collect()
    }

    /// Nodes within `tol_m` of the line z = `z_m`.
    pub fn nodes_at_z(&self, z_m: f64, tol_m: f64) -> Vec<usize> {
        (0..self.nodes.len())
            .filter(|&i| (self.nodes[i][1] - z_m).abs() <= tol_m)
            .collect()
    }

    /// Nodes within `tol_m` of the cylinder r = `r_m`, with z in `[z_lo, z_hi]`.
    pub fn nodes_at_r(&self, r_m: f64, z_lo: f64, z_hi: f64, tol_m: f64) -> Vec<usize> {
        (0..self.nodes.len())
            .filter(|&i| {
                let p = self.nodes[i];
                (p[0] - r_m).abs() <= tol_m && p[1] >= z_lo - tol_m && p[1] <= z_hi + tol_m
            })
            .collect()
    }
}
