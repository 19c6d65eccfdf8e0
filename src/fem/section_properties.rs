//! Properties of a beam cross-section from a plane quad mesh: area, centroid, second moments,
//! and by a finite-element solve of Saint-Venant's warping function the torsion constant, the
//! shear centre and the warping constant.
//!
//! Saint-Venant torsion (Timoshenko & Goodier, Theory of Elasticity, 1970, ch. 10): a twist
//! rate `theta'` about the origin displaces the section by `u_x = theta' omega(y, z)`,
//! `u_y = -theta' x z`, `u_z = theta' x y`. Equilibrium and free lateral surfaces give
//!
//! ```text
//! laplacian(omega) = 0 in the section,   d omega / dn = z n_y - y n_z on its outline,
//! ```
//!
//! whose weak form is `int grad(omega) . grad(v) dA = int (z dv/dy - y dv/dz) dA` for every v
//! (the boundary term is the divergence of `v (z, -y)`, a field without divergence). With
//! bilinear quads (2 x 2 Gauss points) and one node held at zero (omega is fixed only up to a
//! constant) the system is symmetric positive definite (faer's sparse Cholesky). Then
//!
//! * torsion constant `J = int (y^2 + z^2 + y omega_z - z omega_y) dA
//!   = I_p - int |grad omega|^2 dA`: the discrete warping is too stiff, so the computed J
//!   converges to the exact one from above, at O(h^2);
//! * shear centre `(y_s, z_s)`: the warping function about S is
//!   `omega_S = omega - z_s y + y_s z + c`; S is the point whose warping is orthogonal to the
//!   bending modes, `int omega_S y dA = int omega_S z dA = 0` with centroidal y, z (Trefftz's
//!   definition; Pilkey, Analysis and Design of Elastic Beams, 2002, section 6.4), a 2 x 2
//!   system in the second moments;
//! * warping constant `I_w = int omega_S^2 dA` with `c` such that `int omega_S dA = 0`
//!   (Vlasov's sectorial moment of inertia).
//!
//! Lengths are in the mesh's unit (the moments in its powers).

// Index loops mirror the element formulas term by term; `!(x > 0.0)` also rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

use faer::linalg::solvers::Solve;
use faer::sparse::{SparseColMat, Triplet};
use faer::{Mat, Side};
use serde::Serialize;

use crate::geometry::curve2d::P2;
use crate::mesh::section::SectionMesh;
use crate::{Error, Result};

/// The properties, in the mesh's length unit and its powers.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct SectionProperties {
    /// Area.
    pub area: f64,
    /// Centroid (y, z).
    pub centroid: P2,
    /// `int (z - z_c)^2 dA`: bending about the y axis (vertical bending of a rail).
    pub second_moment_yy: f64,
    /// `int (y - y_c)^2 dA`: bending about the z axis (lateral bending of a rail).
    pub second_moment_zz: f64,
    /// `int (y - y_c)(z - z_c) dA`.
    pub product_moment_yz: f64,
    /// Saint-Venant torsion constant J.
    pub torsion_constant: f64,
    /// Shear centre (y, z).
    pub shear_centre: P2,
    /// Warping constant `I_w` about the shear centre.
    pub warping_constant: f64,
}

impl SectionProperties {}

/// Bilinear shape functions and their derivatives at (xi, eta), nodes counter-clockwise from
/// (-1, -1).
fn bilinear(xi: f64, eta: f64) -> ([f64; 4], [[f64; 2]; 4]) {
    let s = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)];
    let mut n = [0.0; 4];
    let mut d = [[0.0; 2]; 4];
    for (i, &(a, b)) in s.iter().enumerate() {
        n[i] = 0.25 * (1.0 + a * xi) * (1.0 + b * eta);
        d[i] = [0.25 * a * (1.0 + b * eta), 0.25 * b * (1.0 + a * xi)];
    }
    (n, d)
}

/// One Gauss point of a quad: shape values, physical gradients, position, weight times |J|.
struct QuadPoint {
    n: [f64; 4],
    grad: [[f64; 2]; 4],
    p: P2,
    w: f64,
}

/// The 2 x 2 Gauss points of quad `q` (exact for the bilinear stiffness of a parallelogram and
/// for the second moments of one); an error for a folded or inverted quad.
fn quad_points(mesh: &SectionMesh, q: usize) -> Result<[QuadPoint; 4]> {
    let g = 1.0 / 3f64.sqrt();
    let x: [P2; 4] = mesh.quads[q].map(|i| mesh.nodes[i]);
    let pts = [(-g, -g), (g, -g), (g, g), (-g, g)];
    let mut out: [QuadPoint; 4] = std::array::from_fn(|_| QuadPoint {
        n: [0.0; 4],
        grad: [[0.0; 2]; 4],
        p: [0.0; 2],
        w: 0.0,
    });
    for (k, &(xi, eta)) in pts.iter().enumerate() {
        let (n, d) = bilinear(xi, eta);
        let mut jac = [[0.0; 2]; 2];
        let mut p = [0.0; 2];
        for i in 0..4 {
            for r in 0..2 {
                p[r] += n[i] * x[i][r];
                for c in 0..2 {
                    jac[r][c] += d[i][c] * x[i][r];
                }
            }
        }
        // jac[r][c] = d x_r / d xi_c.
        let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
        if !(det > 0.0) {
            return Err(Error::Numerical(format!(
                "section properties: quad {q} is inverted or degenerate (Jacobian {det:e})"
            )));
        }
        let mut grad = [[0.0; 2]; 4];
        for i in 0..4 {
            // grad N = J^-T dN/dxi.
            grad[i] = [
                (jac[1][1] * d[i][0] - jac[1][0] * d[i][1]) / det,
                (-jac[0][1] * d[i][0] + jac[0][0] * d[i][1]) / det,
            ];
        }
        out[k] = QuadPoint { n, grad, p, w: det };
    }
    Ok(out)
}

/// All properties of the section meshed by `mesh` (every quad counts; parts are not told
/// apart).
pub fn section_properties(mesh: &SectionMesh) -> Result<SectionProperties> {
    if mesh.quads.is_empty() {
        return Err(Error::Numerical("section properties: no quads".into()));
    }
    let points: Vec<[QuadPoint; 4]> = (0..mesh.quads.len())
        .map(|q| quad_points(mesh, q))
        .collect::<Result<_>>()?;
    // Area and centroid, then centroidal moments.
    let (mut area, mut sy, mut sz) = (0.0, 0.0, 0.0);
    for qp in points.iter().flatten() {
        area += qp.w;
        sy += qp.w * qp.p[0];
        sz += qp.w * qp.p[1];
    }
    let centroid = [sy / area, sz / area];
    let local = |p: P2| [p[0] - centroid[0], p[1] - centroid[1]];
    let (mut iyy, mut izz, mut iyz) = (0.0, 0.0, 0.0);
    for qp in points.iter().flatten() {
        let [y, z] = local(qp.p);
        iyy += qp.w * z * z;
        izz += qp.w * y * y;
        iyz += qp.w * y * z;
    }
    // Warping about the centroid: K omega = f, node 0 held at zero.
    let n = mesh.nodes.len();
    let held = mesh.quads[0][0];
    let index = |i: usize| -> Option<usize> {
        match i.cmp(&held) {
            std::cmp::Ordering::Less => Some(i),
            std::cmp::Ordering::Equal => None,
            std::cmp::Ordering::Greater => Some(i - 1),
        }
    };
    let mut triplets = Vec::with_capacity(16 * mesh.quads.len());
    let mut rhs = Mat::<f64>::zeros(n - 1, 1);
    for (q, pts) in points.iter().enumerate() {
        let nodes = mesh.quads[q];
        for qp in pts {
            let [y, z] = local(qp.p);
            for a in 0..4 {
                let Some(ra) = index(nodes[a]) else { continue };
                rhs[(ra, 0)] += qp.w * (z * qp.grad[a][0] - y * qp.grad[a][1]);
                for b in 0..4 {
                    let Some(rb) = index(nodes[b]) else { continue };
                    let k = qp.w * (qp.grad[a][0] * qp.grad[b][0] + qp.grad[a][1] * qp.grad[b][1]);
                    triplets.push(Triplet::new(ra, rb, k));
                }
            }
        }
    }
    let k = SparseColMat::<usize, f64>::try_new_from_triplets(n - 1, n - 1, &triplets)
        .map_err(|e| Error::Numerical(format!("section properties: assembly: {e:?}")))?;
    let llt = k.sp_cholesky(Side::Lower).map_err(|e| {
        Error::Numerical(format!(
            "section properties: the warping system is not positive definite ({e:?}): is \
             the mesh connected?"
        ))
    })?;
    let solution = llt.solve(&rhs);
    let omega: Vec<f64> = (0..n)
        .map(|i| index(i).map_or(0.0, |r| solution[(r, 0)]))
        .collect();
    // J, the warping's first moments and mean.
    let (mut energy, mut qy, mut qz, mut mean) = (0.0, 0.0, 0.0, 0.0);
    for (q, pts) in points.iter().enumerate() {
        let nodes = mesh.quads[q];
        for qp in pts {
            let [y, z] = local(qp.p);
            let (mut w, mut gy, mut gz) = (0.0, 0.0, 0.0);
            for a in 0..4 {
                let o = omega[nodes[a]];
                w += qp.n[a] * o;
                gy += qp.grad[a][0] * o;
                gz += qp.grad[a][1] * o;
            }
            energy += qp.w * (gy * gy + gz * gz);
            qy += qp.w * w * y;
            qz += qp.w * w * z;
            mean += qp.w * w;
        }
    }
    mean /= area;
    let torsion_constant = iyy + izz - energy;
    // int omega y - z_s Izz + y_s Iyz = 0 and int omega z - z_s Iyz + y_s Iyy = 0.
    let det = izz * iyy - iyz * iyz;
    let z_s = (qy * iyy - qz * iyz) / det;
    let y_s = (z_s * iyz - qz) / iyy;
    // omega_S = omega - z_s y + y_s z - mean (centroidal y, z have zero mean).
    let mut warping_constant = 0.0;
    for (q, pts) in points.iter().enumerate() {
        let nodes = mesh.quads[q];
        for qp in pts {
            let [y, z] = local(qp.p);
            let w: f64 = (0..4).map(|a| qp.n[a] * omega[nodes[a]]).sum();
            let ws = w - z_s * y + y_s * z - mean;
            warping_constant += qp.w * ws * ws;
        }
    }
    Ok(SectionProperties {
        area,
        centroid,
        second_moment_yy: iyy,
        second_moment_zz: izz,
        product_moment_yz: iyz,
        torsion_constant,
        shear_centre: [centroid[0] + y_s, centroid[1] + z_s],
        warping_constant,
    })
}

/// Saint-Venant torsion constant of an `a` x `b` rectangle (`a >= b`) by its series
/// (Timoshenko & Goodier 1970, section 109): `J = a b^3 / 3 (1 - 192 b / (pi^5 a)
/// sum_{n odd} tanh(n pi a / 2b) / n^5)`, summed until the terms vanish in f64.
pub fn rectangle_torsion_constant(a: f64, b: f64) -> f64 {
    let (a, b) = if a >= b { (a, b) } else { (b, a) };
    let mut sum = 0.0;
    let mut n = 1.0f64;
    while n < 200.0 {
        sum += (n * std::f64::consts::PI * a / (2.0 * b)).tanh() / n.powi(5);
        n += 2.0;
    }
    a * b.powi(3) / 3.0 * (1.0 - 192.0 * b / (std::f64::consts::PI.powi(5) * a) * sum)
}
