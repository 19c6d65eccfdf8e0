//! Linear-elastic 8-node hexahedron (trilinear, VTK node order), full 2x2x2 Gauss integration.
//!
//! With shape functions `N_a(xi, eta, zeta) = (1 + xi xi_a)(1 + eta eta_a)(1 + zeta zeta_a) / 8`,
//! the strain `eps = B u` (Voigt order xx, yy, zz, xy, yz, zx with engineering shears) and the
//! isotropic elasticity matrix `D(E, nu)`:
//! - stiffness  `K_e = sum_g B_gᵀ D B_g det J_g w_g`,
//! - consistent mass `M_e = sum_g rho N_gᵀ N_g det J_g w_g` (3 dofs per node, same scalar block),
//! - lumped mass: the row sums of the consistent mass (all positive for the trilinear hex).
//!
//! Degrees of freedom are ordered node-major: `3 a + c` for node `a`, component `c`.

// Index loops mirror the matrix formulas (B, D, J indices); iterator forms would hide them.
#![allow(clippy::needless_range_loop)]

use crate::mesh::hex::NODE_NATURAL;
use crate::mesh::P3;

/// Isotropic linear-elastic material: the crate's one material type.
pub use crate::material::Material as ElasticMaterial;

/// Element stiffness and mass (24x24, row-major).
#[derive(Clone, Debug)]
pub struct ElementMatrices {
    /// Stiffness.
    pub k: [[f64; 24]; 24],
    /// Mass (consistent or lumped, as requested).
    pub m: [[f64; 24]; 24],
    /// Element volume (m³).
    pub volume: f64,
}

/// Shape functions and their reference derivatives at a point.
pub(crate) fn shape(xi: [f64; 3]) -> ([f64; 8], [[f64; 3]; 8]) {
    let mut n = [0.0; 8];
    let mut dn = [[0.0; 3]; 8];
    for a in 0..8 {
        let p = NODE_NATURAL[a];
        let f = [1.0 + p[0] * xi[0], 1.0 + p[1] * xi[1], 1.0 + p[2] * xi[2]];
        n[a] = 0.125 * f[0] * f[1] * f[2];
        dn[a] = [
            0.125 * p[0] * f[1] * f[2],
            0.125 * f[0] * p[1] * f[2],
            0.125 * f[0] * f[1] * p[2],
        ];
    }
    (n, dn)
}

/// Physical shape-function gradients and det J at a reference point; `None` if det J <= 0.
pub(crate) fn gradients(x: &[P3; 8], xi: [f64; 3]) -> Option<([f64; 8], [[f64; 3]; 8], f64)> {
    let (n, dn) = shape(xi);
    let (g, det) = super::jacobian::physical_gradients(x, &dn)?;
    Some((n, g, det))
}

/// The 6x24 strain-displacement matrix from physical gradients.
pub fn b_matrix(g: &[[f64; 3]; 8]) -> [[f64; 24]; 6] {
    super::jacobian::b_matrix(g)
}

/// Stiffness and (consistent or row-sum lumped) mass of one element; `None` for an element with
/// a non-positive Jacobian determinant at a Gauss point (inverted or degenerate).
pub fn element_matrices(
    x: &[P3; 8],
    mat: &ElasticMaterial,
    lumped: bool,
) -> Option<ElementMatrices> {
    let d = mat.d_matrix();
    let g = 1.0 / 3f64.sqrt();
    let mut k = [[0.0; 24]; 24];
    let mut ms = [[0.0; 8]; 8];
    let mut volume = 0.0;
    for &a in &[-g, g] {
        for &b in &[-g, g] {
            for &c in &[-g, g] {
                let (n, grad, det) = gradients(x, [a, b, c])?;
                volume += det;
                let bm = b_matrix(&grad);
                // DB (6x24)
                let mut db = [[0.0; 24]; 6];
                for i in 0..6 {
                    for j in 0..24 {
                        db[i][j] = (0..6).map(|l| d[i][l] * bm[l][j]).sum::<f64>() * det;
                    }
                }
                for i in 0..24 {
                    for j in i..24 {
                        let mut s = 0.0;
                        for l in 0..6 {
                            s += bm[l][i] * db[l][j];
                        }
                        k[i][j] += s;
                    }
                }
                for p in 0..8 {
                    for q in 0..8 {
                        ms[p][q] += mat.density_kg_per_m3 * n[p] * n[q] * det;
                    }
                }
            }
        }
    }
    for i in 0..24 {
        for j in 0..i {
            k[i][j] = k[j][i];
        }
    }
    let mut m = [[0.0; 24]; 24];
    for p in 0..8 {
        if lumped {
            let row: f64 = ms[p].iter().sum();
            for c in 0..3 {
                m[3 * p + c][3 * p + c] = row;
            }
        } else {
            for q in 0..8 {
                for c in 0..3 {
                    m[3 * p + c][3 * q + c] = ms[p][q];
                }
            }
        }
    }
    Some(ElementMatrices { k, m, volume })
}
