//! Linear-elastic triquadratic 27-node hexahedron (Lagrange, VTK node order).
//!
//! Node order (VTK `VTK_TRIQUADRATIC_HEXAHEDRON`, type 29): the 8 corners as the hex8, the 12
//! mid-edge nodes on the edges 0-1, 1-2, 2-3, 3-0, 4-5, 5-6, 6-7, 7-4, 0-4, 1-5, 2-6, 3-7, the
//! 6 mid-face nodes of the faces xi = -1, xi = +1, eta = -1, eta = +1, zeta = -1, zeta = +1, and
//! the centre ([`NODE_REFERENCE`] lists the reference coordinates).
//!
//! Shape functions are tensor products `N_a = L_i(xi) L_j(eta) L_k(zeta)` of the 1D quadratic
//! Lagrange polynomials `L_-1 = s (s - 1) / 2`, `L_0 = 1 - s²`, `L_+1 = s (s + 1) / 2`.
//! - stiffness `K_e = sum_g B_gᵀ D B_g det J_g w_g` with the 3x3x3 Gauss rule (full
//!   integration: exact for a straight-sided parallelepiped, where the integrand is of degree 4
//!   per direction; no spurious zero-energy modes),
//! - consistent mass `M_e = sum_g rho N_gᵀ N_g det J_g w_g` with the 3x3x3 rule (degree 4 per
//!   direction against the integrand's 4 on a parallelepiped: exact there),
//! - lumped mass: row sums `m_aa = rho ∫ N_a dV`. For this element they are all positive (the
//!   1D weights are 1/3, 4/3, 1/3 of the half length), unlike the serendipity hex20's.
//!
//! Its use here: the axisymmetric solver's Q9 cross-section revolved into quadratic sectors
//! ([`crate::modal::axisym::revolve`]) gives a 3D mesh with *the same cross-section discretisation*
//! as the harmonic solver, so the two differ only by the circumferential interpolation.
//!
//! Degrees of freedom are ordered node-major: `3 a + c` for node `a`, component `c`.

// Index loops mirror the matrix formulas (B, D, J indices); iterator forms would hide them.
#![allow(clippy::needless_range_loop)]

use super::hex8::ElasticMaterial;
use crate::mesh::P3;

/// Number of nodes.
pub const NODES: usize = 27;
/// Number of degrees of freedom.
pub const DOFS: usize = 81;

/// Reference coordinates (xi, eta, zeta) of the 27 nodes, VTK order.
pub const NODE_REFERENCE: [[f64; 3]; 27] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
    [0.0, -1.0, -1.0],
    [1.0, 0.0, -1.0],
    [0.0, 1.0, -1.0],
    [-1.0, 0.0, -1.0],
    [0.0, -1.0, 1.0],
    [1.0, 0.0, 1.0],
    [0.0, 1.0, 1.0],
    [-1.0, 0.0, 1.0],
    [-1.0, -1.0, 0.0],
    [1.0, -1.0, 0.0],
    [1.0, 1.0, 0.0],
    [-1.0, 1.0, 0.0],
    [-1.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, -1.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, -1.0],
    [0.0, 0.0, 1.0],
    [0.0, 0.0, 0.0],
];

/// The node of the element at reference position `(xi, eta, zeta)`, each in {-1, 0, 1}.
pub fn node_at(xi: i32, eta: i32, zeta: i32) -> usize {
    NODE_REFERENCE
        .iter()
        .position(|p| p[0] as i32 == xi && p[1] as i32 == eta && p[2] as i32 == zeta)
        .expect("reference coordinates are in {-1, 0, 1}")
}

/// 1D quadratic Lagrange polynomial through -1, 0, 1 that is 1 at `node` (in {-1, 0, 1}), and
/// its derivative, at `s`.
fn lagrange(node: f64, s: f64) -> (f64, f64) {
    if node < -0.5 {
        (0.5 * s * (s - 1.0), s - 0.5)
    } else if node > 0.5 {
        (0.5 * s * (s + 1.0), s + 0.5)
    } else {
        (1.0 - s * s, -2.0 * s)
    }
}

/// Shape functions and their reference derivatives at `xi`.
pub fn shape(xi: [f64; 3]) -> ([f64; 27], [[f64; 3]; 27]) {
    let mut n = [0.0; 27];
    let mut dn = [[0.0; 3]; 27];
    for a in 0..27 {
        let p = NODE_REFERENCE[a];
        let (lx, dx) = lagrange(p[0], xi[0]);
        let (ly, dy) = lagrange(p[1], xi[1]);
        let (lz, dz) = lagrange(p[2], xi[2]);
        n[a] = lx * ly * lz;
        dn[a] = [dx * ly * lz, lx * dy * lz, lx * ly * dz];
    }
    (n, dn)
}

/// The 3x3x3 Gauss rule on [-1, 1]³: points and weights (weights sum to 8).
pub fn gauss_3x3x3() -> Vec<([f64; 3], f64)> {
    let g = (0.6f64).sqrt();
    let pts = [(-g, 5.0 / 9.0), (0.0, 8.0 / 9.0), (g, 5.0 / 9.0)];
    let mut rule = Vec::with_capacity(27);
    for &(x, wx) in &pts {
        for &(y, wy) in &pts {
            for &(z, wz) in &pts {
                rule.push(([x, y, z], wx * wy * wz));
            }
        }
    }
    rule
}

/// Element stiffness and mass (81x81, row-major, flattened).
#[derive(Clone, Debug)]
pub struct Hex27Matrices {
    /// Stiffness, `k[i * DOFS + j]`.
    pub k: Vec<f64>,
    /// Mass (consistent or row-sum lumped, as requested), `m[i * DOFS + j]`.
    pub m: Vec<f64>,
    /// Element volume (m³).
    pub volume: f64,
}

/// Stiffness and (consistent or row-sum lumped) mass of one element; `None` for a non-positive
/// Jacobian determinant at an integration point (inverted or degenerate element). A face
/// collapsed onto a line (an element of a revolved section touching the axis) is allowed: its
/// Jacobian vanishes only on that face, never at a Gauss point.
pub fn element_matrices(
    x: &[P3; 27],
    mat: &ElasticMaterial,
    lumped: bool,
) -> Option<Hex27Matrices> {
    let d = mat.d_matrix();
    let rho = mat.density_kg_per_m3;
    let mut k = vec![0.0; DOFS * DOFS];
    let mut ms = [[0.0; 27]; 27];
    let mut volume = 0.0;
    for (xi, w) in gauss_3x3x3() {
        let (n, dn) = shape(xi);
        let (g, det) = super::jacobian::physical_gradients(x, &dn)?;
        let dv = det * w;
        volume += dv;
        // K += Bᵀ D B dV, node block by node block: B_a is the 6x3 strain operator of node a.
        for a in 0..27 {
            let ba = strain_operator(&g[a]);
            // (D B_a) dV, 6x3
            let mut dba = [[0.0; 3]; 6];
            for i in 0..6 {
                for c in 0..3 {
                    dba[i][c] = (0..6).map(|l| d[i][l] * ba[l][c]).sum::<f64>() * dv;
                }
            }
            for b in a..27 {
                let bb = strain_operator(&g[b]);
                for r in 0..3 {
                    for c in 0..3 {
                        // (B_b)ᵀ (D B_a): row dof 3b + r, column dof 3a + c
                        let s: f64 = (0..6).map(|l| bb[l][r] * dba[l][c]).sum();
                        k[(3 * b + r) * DOFS + 3 * a + c] += s;
                    }
                }
            }
        }
        for p in 0..27 {
            for q in 0..27 {
                ms[p][q] += rho * n[p] * n[q] * dv;
            }
        }
    }
    // The loop filled the blocks with b >= a; mirror them.
    for i in 0..DOFS {
        for j in (i + 1)..DOFS {
            if i / 3 == j / 3 {
                // diagonal node block: filled completely (b == a)
                continue;
            }
            k[i * DOFS + j] = k[j * DOFS + i];
        }
    }
    let mut m = vec![0.0; DOFS * DOFS];
    for p in 0..27 {
        if lumped {
            let row: f64 = ms[p].iter().sum();
            for c in 0..3 {
                m[(3 * p + c) * DOFS + 3 * p + c] = row;
            }
        } else {
            for q in 0..27 {
                for c in 0..3 {
                    m[(3 * p + c) * DOFS + 3 * q + c] = ms[p][q];
                }
            }
        }
    }
    Some(Hex27Matrices { k, m, volume })
}

/// The 6x3 block of the strain-displacement matrix for one node with physical gradient `g`
/// (Voigt xx, yy, zz, xy, yz, zx; engineering shears), as in the other solid elements.
fn strain_operator(g: &[f64; 3]) -> [[f64; 3]; 6] {
    [
        [g[0], 0.0, 0.0],
        [0.0, g[1], 0.0],
        [0.0, 0.0, g[2]],
        [g[1], g[0], 0.0],
        [0.0, g[2], g[1]],
        [g[2], 0.0, g[0]],
    ]
}

/// Volume by the 3x3x3 rule (negative or zero if inverted; a collapsed face still gives a
/// positive volume).
pub fn volume(x: &[P3; 27]) -> f64 {
    super::jacobian::volume_by_rule(x, &gauss_3x3x3(), |xi| shape(xi).1)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A distorted but valid element: the reference cube scaled, sheared and with curved
    /// mid-nodes (an affine map plus a small quadratic bump).
    fn distorted() -> [P3; 27] {
        NODE_REFERENCE.map(|p| {
            let bump = 0.03 * (1.0 - p[0] * p[0]) * (1.0 - p[1] * p[1]);
            [
                0.1 * p[0] + 0.02 * p[1] + bump,
                0.07 * p[1] + 0.01 * p[2],
                0.05 * p[2] + 0.01 * p[0] + 0.5 * bump,
            ]
        })
    }

    #[test]
    fn shape_functions_interpolate_and_partition_unity() {
        for (a, p) in NODE_REFERENCE.iter().enumerate() {
            let (n, _) = shape(*p);
            for (b, v) in n.iter().enumerate() {
                let want = if a == b { 1.0 } else { 0.0 };
                assert!((v - want).abs() < 1e-14, "N_{b} at node {a} = {v}");
            }
        }
        let (n, dn) = shape([0.3, -0.7, 0.45]);
        assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
        for k in 0..3 {
            assert!(dn.iter().map(|d| d[k]).sum::<f64>().abs() < 1e-13);
        }
        assert_eq!(node_at(0, 0, 0), 26);
        assert_eq!(node_at(1, 1, -1), 2);
    }

    #[test]
    fn rigid_motions_are_zero_energy_and_mass_is_exact() {
        let x = distorted();
        let mat = ElasticMaterial::steel();
        let em = element_matrices(&x, &mat, false).expect("valid element");
        // Rigid translations and infinitesimal rotations give K u = 0 (to rounding against the
        // stiffness scale E h ~ 2e10).
        let scale = em.k.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let rigid: [fn(&P3) -> P3; 6] = [
            |_| [1.0, 0.0, 0.0],
            |_| [0.0, 1.0, 0.0],
            |_| [0.0, 0.0, 1.0],
            |p| [-p[1], p[0], 0.0],
            |p| [0.0, -p[2], p[1]],
            |p| [p[2], 0.0, -p[0]],
        ];
        for f in &rigid {
            let u: Vec<f64> = x.iter().flat_map(f).collect();
            for i in 0..DOFS {
                let f_i: f64 = (0..DOFS).map(|j| em.k[i * DOFS + j] * u[j]).sum();
                assert!(f_i.abs() < 1e-10 * scale, "K u = {f_i} at dof {i}");
            }
        }
        // Symmetry.
        for i in 0..DOFS {
            for j in 0..DOFS {
                let (a, b) = (em.k[i * DOFS + j], em.k[j * DOFS + i]);
                assert!((a - b).abs() <= 1e-12 * scale, "K not symmetric at {i},{j}");
            }
        }
        // Mass: uᵀ M u for a unit translation is rho V, for consistent and lumped mass alike.
        let lumped = element_matrices(&x, &mat, true).unwrap();
        let v = volume(&x);
        assert!((v - em.volume).abs() < 1e-15);
        for m in [&em.m, &lumped.m] {
            let u: Vec<f64> = (0..27).flat_map(|_| [1.0, 0.0, 0.0]).collect();
            let total: f64 = (0..DOFS)
                .flat_map(|i| (0..DOFS).map(move |j| (i, j)))
                .map(|(i, j)| u[i] * m[i * DOFS + j] * u[j])
                .sum();
            let want = mat.density_kg_per_m3 * v;
            assert!((total - want).abs() < 1e-12 * want, "{total} vs {want}");
        }
        assert!((0..DOFS).all(|i| lumped.m[i * DOFS + i] > 0.0));
    }

    /// Patch-test-like check: a linear displacement field u = A x gives element forces equal to
    /// the boundary tractions of the uniform stress D eps, i.e. uᵀ K u = V epsᵀ D eps (the strain
    /// energy of a uniform strain, which the element reproduces exactly).
    #[test]
    fn uniform_strain_energy_is_exact() {
        let x = distorted();
        let mat = ElasticMaterial::steel();
        let em = element_matrices(&x, &mat, false).unwrap();
        let a = [
            [1e-3, 2e-4, -3e-4],
            [5e-4, -2e-3, 1e-4],
            [0.0, 7e-4, 1.5e-3],
        ];
        let u: Vec<f64> = x
            .iter()
            .flat_map(|p| [0, 1, 2].map(|r| (0..3).map(|c| a[r][c] * p[c]).sum::<f64>()))
            .collect();
        let ku: Vec<f64> = (0..DOFS)
            .map(|i| (0..DOFS).map(|j| em.k[i * DOFS + j] * u[j]).sum())
            .collect();
        let energy: f64 = u.iter().zip(&ku).map(|(a, b)| a * b).sum();
        let eps = [
            a[0][0],
            a[1][1],
            a[2][2],
            a[0][1] + a[1][0],
            a[1][2] + a[2][1],
            a[2][0] + a[0][2],
        ];
        let d = mat.d_matrix();
        let mut want = 0.0;
        for i in 0..6 {
            for j in 0..6 {
                want += eps[i] * d[i][j] * eps[j];
            }
        }
        want *= em.volume;
        // The isoparametric element reproduces a linear field exactly, so B u = eps at every
        // Gauss point and the sum is eps^T D eps times the rule's volume: equal to rounding.
        assert!((energy - want).abs() < 1e-10 * want, "{energy} vs {want}");
    }

    #[test]
    fn inverted_element_is_refused() {
        let mut x = distorted();
        for p in &mut x {
            p[2] = -p[2];
        }
        assert!(element_matrices(&x, &ElasticMaterial::steel(), false).is_none());
        assert!(volume(&x) < 0.0);
    }
}
