//! Linear-elastic 4-node (constant-strain) tetrahedron.
//!
//! With barycentric coordinates `L_a` the shape functions are `N_a = L_a`; their gradients are
//! constant over the element, so the strain is constant and
//! - stiffness `K_e = V Bᵀ D B` (exact),
//! - consistent mass `M_ab = rho V (1 + delta_ab) / 20` per component (exact integral of
//!   `L_a L_b`; Zienkiewicz, Taylor & Zhu, The Finite Element Method, vol. 1, 7th ed., 2013,
//!   ch. 6), lumped `rho V / 4` per node.
//!
//! The element is stiff in bending (constant strain through the thickness): it is offered for
//! meshes people already have, with the quadratic tetrahedron as the default (`squeal modes`
//! elevates linear tetrahedra to straight-sided tet10 unless `--element-order 1`).
//!
//! Degrees of freedom are node-major: `3 a + c` for node `a`, component `c`.

// Index loops mirror the matrix formulas (B, D indices).
#![allow(clippy::needless_range_loop)]

use super::hex8::ElasticMaterial;
use crate::mesh::P3;

/// Degrees of freedom.
pub const DOFS: usize = 12;

/// Element matrices.
pub struct Tet4Matrices {
    /// Stiffness (12 x 12).
    pub k: [[f64; DOFS]; DOFS],
    /// Mass (12 x 12), consistent or lumped.
    pub m: [[f64; DOFS]; DOFS],
    /// Volume (m³).
    pub volume: f64,
}

/// Signed volume `det[x1 - x0, x2 - x0, x3 - x0] / 6` (positive for the VTK corner order).
pub fn volume(x: &[P3; 4]) -> f64 {
    let e = |k: usize| [0, 1, 2].map(|d| x[k][d] - x[0][d]);
    let (a, b, c) = (e(1), e(2), e(3));
    (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0]))
        / 6.0
}

/// Gradients of the four shape functions (constant); `None` for a non-positive volume.
pub fn gradients(x: &[P3; 4]) -> Option<[[f64; 3]; 4]> {
    let v = volume(x);
    if v.is_nan() || v <= 0.0 {
        return None;
    }
    // Rows of J⁻¹ with J = [x1 - x0, x2 - x0, x3 - x0] (columns) are the gradients of L_1..L_3:
    // J⁻¹ = adj(J) / det J, and det J = 6 V.
    let e = |k: usize| [0, 1, 2].map(|d| x[k][d] - x[0][d]);
    let (a, b, c) = (e(1), e(2), e(3));
    let cross = |u: [f64; 3], w: [f64; 3]| {
        [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ]
    };
    let det = 6.0 * v;
    let g1 = cross(b, c).map(|t| t / det);
    let g2 = cross(c, a).map(|t| t / det);
    let g3 = cross(a, b).map(|t| t / det);
    let g0 = [0, 1, 2].map(|d| -(g1[d] + g2[d] + g3[d]));
    Some([g0, g1, g2, g3])
}

/// Stiffness and mass of one element; `None` for an inverted or degenerate element.
pub fn element_matrices(x: &[P3; 4], mat: &ElasticMaterial, lumped: bool) -> Option<Tet4Matrices> {
    let g = gradients(x)?;
    let v = volume(x);
    // B (6 x 12), Voigt xx, yy, zz, xy, yz, zx with engineering shears.
    let b: [[f64; DOFS]; 6] = super::jacobian::b_matrix(&g);
    let d = mat.d_matrix();
    let mut k = [[0.0; DOFS]; DOFS];
    for i in 0..DOFS {
        for j in 0..DOFS {
            let mut s = 0.0;
            for p in 0..6 {
                for q in 0..6 {
                    s += b[p][i] * d[p][q] * b[q][j];
                }
            }
            k[i][j] = s * v;
        }
    }
    let rho = mat.density_kg_per_m3;
    let mut m = [[0.0; DOFS]; DOFS];
    for p in 0..4 {
        for q in 0..4 {
            let value = if lumped {
                if p == q {
                    rho * v / 4.0
                } else {
                    0.0
                }
            } else if p == q {
                rho * v / 10.0
            } else {
                rho * v / 20.0
            };
            for c in 0..3 {
                m[3 * p + c][3 * q + c] = value;
            }
        }
    }
    Some(Tet4Matrices { k, m, volume: v })
}
