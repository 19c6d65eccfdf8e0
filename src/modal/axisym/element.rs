//! Q9 ring element for one Fourier harmonic n of a body of revolution.
//!
//! Displacements in cylindrical coordinates (r, theta, z), z the axis (Zienkiewicz & Taylor,
//! The Finite Element Method, vol. 1, ch. "Axisymmetric stress analysis", non-symmetric loads):
//!
//! ```text
//! u_r = U_r(r,z) cos(n theta),  u_theta = U_t(r,z) sin(n theta),  u_z = U_z(r,z) cos(n theta)
//! ```
//!
//! (the companion family with cos and sin swapped has the same K and M with n -> -n, hence the
//! same frequencies). The 3D small strains in cylindrical coordinates,
//!
//! ```text
//! e_rr = du_r/dr,   e_tt = (u_r + du_t/dtheta)/r,   e_zz = du_z/dz,
//! g_rz = du_r/dz + du_z/dr,
//! g_rt = (1/r) du_r/dtheta + du_t/dr - u_t/r,   g_tz = du_t/dz + (1/r) du_z/dtheta,
//! ```
//!
//! give with the ansatz above (cos factors on the first four, sin on the last two)
//!
//! ```text
//! e_rr = U_r,r   e_tt = (U_r + n U_t)/r   e_zz = U_z,z   g_rz = U_r,z + U_z,r
//! g_rt = -n U_r/r + U_t,r - U_t/r          g_tz = U_t,z - n U_z/r
//! ```
//!
//! The strain energy and kinetic energy integrate over theta to a factor c_n = 2 pi (n = 0) or
//! pi (n >= 1) times the section integrals
//!
//! ```text
//! K = c_n \int B^T D B r dA,     M = c_n rho \int N^T N r dA,
//! ```
//!
//! with D the isotropic elasticity matrix in the order (rr, tt, zz, rz, rt, tz). For n = 0 the
//! same B covers both the axisymmetric (U_r, U_z) and the torsional (U_t) motions, which
//! decouple. The 1/r terms are smooth inside an element not touching the axis; 3 x 3 Gauss
//! points (exact for the polynomial part of a rectangular Q9, degree 5 per direction) keep the
//! rational part accurate, and no Gauss point ever lies on the axis.

// Index loops mirror the matrix formulas (B^T D B, N^T N) term by term.
#![allow(clippy::needless_range_loop)]

/// A 27 x 27 element matrix (9 nodes x (U_r, U_t, U_z)).
pub type ElementMatrix = [[f64; 27]; 27];

/// Isotropic linear elastic material: the crate's one material type (its `d_matrix` in the
/// strain order rr, tt, zz, rz, rt, tz: three normal strains, then three engineering shears).
pub use crate::material::Material;

/// 3-point Gauss-Legendre rule on [-1, 1]: points and weights.
const GAUSS3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// Parent coordinates of the Q9 nodes (corners, mid-sides, centre).
const NODE_XI: [[f64; 2]; 9] = [
    [-1.0, -1.0],
    [1.0, -1.0],
    [1.0, 1.0],
    [-1.0, 1.0],
    [0.0, -1.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [-1.0, 0.0],
    [0.0, 0.0],
];

/// 1D quadratic Lagrange polynomial through -1, 0, 1 that is 1 at `node` and its derivative.
fn lagrange(node: f64, t: f64) -> (f64, f64) {
    if node < -0.5 {
        (0.5 * t * (t - 1.0), t - 0.5)
    } else if node > 0.5 {
        (0.5 * t * (t + 1.0), t + 0.5)
    } else {
        (1.0 - t * t, -2.0 * t)
    }
}

/// Q9 shape functions and their parent derivatives at (xi, eta).
pub fn shape(xi: f64, eta: f64) -> ([f64; 9], [[f64; 2]; 9]) {
    let mut n = [0.0; 9];
    let mut dn = [[0.0; 2]; 9];
    for k in 0..9 {
        let (a, da) = lagrange(NODE_XI[k][0], xi);
        let (b, db) = lagrange(NODE_XI[k][1], eta);
        n[k] = a * b;
        dn[k] = [da * b, a * db];
    }
    (n, dn)
}

/// Element stiffness and consistent mass (27 x 27, dof order node-major, (U_r, U_t, U_z) per
/// node) of harmonic `n`. `xy[k] = [r, z]` of node k (m). Returns None for an element whose
/// Jacobian is not positive-definite in sign at some Gauss point (degenerate or folded).
pub fn element_matrices(
    xy: &[[f64; 2]; 9],
    harmonic: u32,
    mat: &Material,
) -> Option<(ElementMatrix, ElementMatrix)> {
    let d = mat.d_matrix();
    let nf = harmonic as f64;
    let c_n = if harmonic == 0 {
        std::f64::consts::TAU
    } else {
        std::f64::consts::PI
    };
    let mut ke = [[0.0; 27]; 27];
    let mut me = [[0.0; 27]; 27];
    let mut sign = 0.0f64;
    for &(xi, wx) in &GAUSS3 {
        for &(eta, wy) in &GAUSS3 {
            let (nn, dn) = shape(xi, eta);
            let mut j = [[0.0; 2]; 2];
            let mut r = 0.0;
            for k in 0..9 {
                for a in 0..2 {
                    j[a][0] += dn[k][0] * xy[k][a];
                    j[a][1] += dn[k][1] * xy[k][a];
                }
                r += nn[k] * xy[k][0];
            }
            // j[a][b] = d x_a / d xi_b, x_0 = r, x_1 = z.
            let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
            if det == 0.0 || (sign != 0.0 && det.signum() != sign) || r <= 0.0 {
                return None;
            }
            sign = det.signum();
            let inv = [
                [j[1][1] / det, -j[0][1] / det],
                [-j[1][0] / det, j[0][0] / det],
            ];
            // dN/dr = dN/dxi * dxi/dr + dN/deta * deta/dr; inv[b][a] = d xi_b / d x_a.
            let mut dr = [0.0; 9];
            let mut dz = [0.0; 9];
            for k in 0..9 {
                dr[k] = dn[k][0] * inv[0][0] + dn[k][1] * inv[1][0];
                dz[k] = dn[k][0] * inv[0][1] + dn[k][1] * inv[1][1];
            }
            let w = c_n * wx * wy * det.abs() * r;
            // B (6 x 27).
            let mut b = [[0.0; 27]; 6];
            for k in 0..9 {
                let (c_r, c_t, c_z) = (3 * k, 3 * k + 1, 3 * k + 2);
                let n_r = nn[k] / r;
                b[0][c_r] = dr[k];
                b[1][c_r] = n_r;
                b[1][c_t] = nf * n_r;
                b[2][c_z] = dz[k];
                b[3][c_r] = dz[k];
                b[3][c_z] = dr[k];
                b[4][c_r] = -nf * n_r;
                b[4][c_t] = dr[k] - n_r;
                b[5][c_t] = dz[k];
                b[5][c_z] = -nf * n_r;
            }
            // DB (6 x 27).
            let mut db = [[0.0; 27]; 6];
            for i in 0..6 {
                for c in 0..27 {
                    let mut s = 0.0;
                    for l in 0..6 {
                        s += d[i][l] * b[l][c];
                    }
                    db[i][c] = s;
                }
            }
            for a in 0..27 {
                for c in a..27 {
                    let mut s = 0.0;
                    for i in 0..6 {
                        s += b[i][a] * db[i][c];
                    }
                    ke[a][c] += w * s;
                }
            }
            let wm = w * mat.density_kg_per_m3;
            for p in 0..9 {
                for q in p..9 {
                    let m = wm * nn[p] * nn[q];
                    for comp in 0..3 {
                        me[3 * p + comp][3 * q + comp] += m;
                    }
                }
            }
        }
    }
    for a in 0..27 {
        for c in 0..a {
            ke[a][c] = ke[c][a];
        }
    }
    // Mass: the loop filled (3p+comp, 3q+comp) for p <= q; mirror.
    for a in 0..27 {
        for c in 0..27 {
            if a / 3 > c / 3 {
                me[a][c] = me[c][a];
            }
        }
    }
    Some((ke, me))
}
