//! Linear-elastic quadratic 10-node tetrahedron (VTK node order).
//!
//! Node order (VTK `VTK_QUADRATIC_TETRA`, type 24): corners 0-3, then mid-edge nodes on the edges
//! 0-1, 1-2, 0-2, 0-3, 1-3, 2-3. Gmsh (element type 11) orders the last two edges the other way
//! (2-3, then 1-3): [`GMSH_TO_VTK`] converts; the readers apply it.
//!
//! With barycentric coordinates `L_0 = 1 - xi - eta - zeta`, `L_1 = xi`, `L_2 = eta`,
//! `L_3 = zeta`, the shape functions are `N_i = L_i (2 L_i - 1)` at corners and
//! `N_ij = 4 L_i L_j` at the mid-edge nodes.
//! - stiffness `K_e = sum_g B_gᵀ D B_g det J_g w_g` with the 4-point degree-2 rule: exact for a
//!   straight-sided element (B is linear, the integrand quadratic); for curved edges it is the
//!   usual reduced-order choice,
//! - consistent mass `M_e = sum_g rho N_gᵀ N_g det J_g w_g` with the 14-point degree-5 rule
//!   (positive weights; the integrand is quartic for a straight-sided element, so exact),
//! - lumped mass: HRZ (Hinton-Rock-Zienkiewicz) diagonal scaling, `m_ii = M_ii m / sum_j M_jj`.
//!   Row sums are not used: for the tet10 they give negative corner masses (`-m/20` each) and
//!   `m/5` per mid-edge node. HRZ gives every node a positive mass (corners `m/36`, mid-edge
//!   nodes `4m/27` for a straight-sided element: the consistent diagonal `m/70`, `8m/105` scaled
//!   by `35/18`) and conserves the total mass exactly.
//!
//! Degrees of freedom are ordered node-major: `3 a + c` for node `a`, component `c`.

// Index loops mirror the matrix formulas (B, D, J indices); iterator forms would hide them.
#![allow(clippy::needless_range_loop)]

use super::hex8::ElasticMaterial;
use crate::mesh::P3;

/// Number of nodes.
pub const NODES: usize = 10;
/// Number of degrees of freedom.
pub const DOFS: usize = 30;

/// The corner pairs of the mid-edge nodes 4..9 (VTK order).
pub const EDGES: [[usize; 2]; 6] = [[0, 1], [1, 2], [0, 2], [0, 3], [1, 3], [2, 3]];

/// The Gmsh-to-VTK node permutation, defined with the mesh readers.
pub use crate::mesh::volume::GMSH_TO_VTK_TET10 as GMSH_TO_VTK;

/// Element stiffness and mass (30x30, row-major).
#[derive(Clone, Debug)]
pub struct Tet10Matrices {
    /// Stiffness.
    pub k: [[f64; DOFS]; DOFS],
    /// Mass (consistent or HRZ-lumped, as requested).
    pub m: [[f64; DOFS]; DOFS],
    /// Element volume (m³).
    pub volume: f64,
}

/// Reference coordinates of the 10 nodes.
pub const NODE_REFERENCE: [[f64; 3]; 10] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
    [0.5, 0.0, 0.0],
    [0.5, 0.5, 0.0],
    [0.0, 0.5, 0.0],
    [0.0, 0.0, 0.5],
    [0.5, 0.0, 0.5],
    [0.0, 0.5, 0.5],
];

/// Shape functions and their reference derivatives at `xi`.
pub fn shape(xi: [f64; 3]) -> ([f64; 10], [[f64; 3]; 10]) {
    let l = [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]];
    // dL_i / dxi_k
    let dl: [[f64; 3]; 4] = [
        [-1.0, -1.0, -1.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let mut n = [0.0; 10];
    let mut dn = [[0.0; 3]; 10];
    for i in 0..4 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
        for k in 0..3 {
            dn[i][k] = (4.0 * l[i] - 1.0) * dl[i][k];
        }
    }
    for (e, &[i, j]) in EDGES.iter().enumerate() {
        n[4 + e] = 4.0 * l[i] * l[j];
        for k in 0..3 {
            dn[4 + e][k] = 4.0 * (dl[i][k] * l[j] + l[i] * dl[j][k]);
        }
    }
    (n, dn)
}

/// 4-point rule of degree 2 on the reference tetrahedron (volume 1/6): points and weights.
pub fn rule_degree2() -> Vec<([f64; 3], f64)> {
    let a = 0.585_410_196_624_968_5;
    let b = 0.138_196_601_125_010_5;
    let w = 1.0 / 24.0;
    vec![
        ([b, b, b], w),
        ([a, b, b], w),
        ([b, a, b], w),
        ([b, b, a], w),
    ]
}

/// 14-point rule of degree 5 on the reference tetrahedron (positive weights; Walkington 2000,
/// "Quadrature on simplices of arbitrary dimension"); weights sum to 1/6.
pub fn rule_degree5() -> Vec<([f64; 3], f64)> {
    let mut pts = Vec::with_capacity(14);
    for (a, w) in [
        (0.092_735_250_310_891_2, 0.012_248_840_519_393_66),
        (0.310_885_919_263_300_6, 0.018_781_320_953_002_64),
    ] {
        let c = 1.0 - 3.0 * a;
        pts.push(([a, a, a], w));
        pts.push(([c, a, a], w));
        pts.push(([a, c, a], w));
        pts.push(([a, a, c], w));
    }
    let b = 0.045_503_704_125_649_6;
    let c = 0.5 - b;
    let w = 0.007_091_003_462_846_911;
    // barycentric (b, b, c, c) in all 6 arrangements; xi = (L1, L2, L3)
    for bary in [
        [b, b, c, c],
        [b, c, b, c],
        [b, c, c, b],
        [c, b, b, c],
        [c, b, c, b],
        [c, c, b, b],
    ] {
        pts.push(([bary[1], bary[2], bary[3]], w));
    }
    pts
}

/// Physical gradients and det J at `xi`; `None` if det J <= 0 (inverted or degenerate).
fn gradients(x: &[P3; 10], xi: [f64; 3]) -> Option<([f64; 10], [[f64; 3]; 10], f64)> {
    let (n, dn) = shape(xi);
    let (g, det) = super::jacobian::physical_gradients(x, &dn)?;
    Some((n, g, det))
}

/// The 6x30 strain-displacement matrix (Voigt xx, yy, zz, xy, yz, zx; engineering shears).
pub fn b_matrix(g: &[[f64; 3]; 10]) -> [[f64; DOFS]; 6] {
    super::jacobian::b_matrix(g)
}

/// Stiffness and (consistent or HRZ-lumped) mass of one element; `None` for a non-positive
/// Jacobian determinant at an integration point (inverted, degenerate or badly curved element).
pub fn element_matrices(
    x: &[P3; 10],
    mat: &ElasticMaterial,
    lumped: bool,
) -> Option<Tet10Matrices> {
    let d = mat.d_matrix();
    let mut k = [[0.0; DOFS]; DOFS];
    for (xi, w) in rule_degree2() {
        let (_, grad, det) = gradients(x, xi)?;
        let bm = b_matrix(&grad);
        let mut db = [[0.0; DOFS]; 6];
        for i in 0..6 {
            for j in 0..DOFS {
                db[i][j] = (0..6).map(|l| d[i][l] * bm[l][j]).sum::<f64>() * det * w;
            }
        }
        for i in 0..DOFS {
            for j in i..DOFS {
                let mut s = 0.0;
                for l in 0..6 {
                    s += bm[l][i] * db[l][j];
                }
                k[i][j] += s;
            }
        }
    }
    for i in 0..DOFS {
        for j in 0..i {
            k[i][j] = k[j][i];
        }
    }
    let rho = mat.density_kg_per_m3;
    let mut ms = [[0.0; 10]; 10];
    let mut volume = 0.0;
    for (xi, w) in rule_degree5() {
        let (n, _, det) = gradients(x, xi)?;
        volume += det * w;
        for p in 0..10 {
            for q in 0..10 {
                ms[p][q] += rho * n[p] * n[q] * det * w;
            }
        }
    }
    let mut m = [[0.0; DOFS]; DOFS];
    if lumped {
        let diag: f64 = (0..10).map(|p| ms[p][p]).sum();
        let scale = rho * volume / diag;
        for p in 0..10 {
            for c in 0..3 {
                m[3 * p + c][3 * p + c] = ms[p][p] * scale;
            }
        }
    } else {
        for p in 0..10 {
            for q in 0..10 {
                for c in 0..3 {
                    m[3 * p + c][3 * q + c] = ms[p][q];
                }
            }
        }
    }
    Some(Tet10Matrices { k, m, volume })
}

/// Volume of a (possibly curved) tet10 by the degree-5 rule; negative or zero if inverted.
pub fn volume(x: &[P3; 10]) -> f64 {
    super::jacobian::volume_by_rule(x, &rule_degree5(), |xi| shape(xi).1)
}

/// A straight-sided tet10 from its four corners (mid-edge nodes at the edge midpoints).
pub fn straight(corners: [P3; 4]) -> [P3; 10] {
    std::array::from_fn(|k| {
        if k < 4 {
            corners[k]
        } else {
            let [i, j] = EDGES[k - 4];
            [0, 1, 2].map(|d| 0.5 * (corners[i][d] + corners[j][d]))
        }
    })
}
