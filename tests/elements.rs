//! Every solid element of the modal solvers against the same four element-level checks, on a
//! distorted (non-rectangular) element:
//! - **symmetry**: K = K^T;
//! - **rigid modes**: K r = 0 for the three translations and three (infinitesimal) rotations,
//!   and exactly six zero eigenvalues (no spurious zero-energy mode);
//! - **patch test** (consistency): for a linear displacement field u = A x the element stores
//!   exactly the energy of its constant strain, u^T K u = V e^T D e (Voigt, engineering shears);
//! - **mass**: the consistent and the lumped mass each carry rho V in every direction, and the
//!   lumped one is diagonal.
//!
//! Elements: the trilinear hexahedron, the hexahedron with incompatible modes (Wilson-Taylor),
//! the quadratic and the linear tetrahedron and the triquadratic hexahedron. The geometry is a trilinear
//! distortion of a box (non-parallel faces; for the quadratic elements their mid-side and
//! centre nodes placed on the same trilinear map), which every element's quadrature
//! integrates exactly for constant strain, so the checks hold to rounding.

use squeal::fem::hex8::ElasticMaterial;
use squeal::fem::{hex27, hex8, hex8_incompatible, tet10, tet4};

/// An element under test: its name, dofs, K and M (row-major), volume, node coordinates.
struct ElementCase {
    name: &'static str,
    x: Vec<[f64; 3]>,
    k: Vec<f64>,
    m_consistent: Vec<f64>,
    m_lumped: Vec<f64>,
    volume: f64,
}

impl ElementCase {
    fn dofs(&self) -> usize {
        3 * self.x.len()
    }
}

const MATERIAL: ElasticMaterial = ElasticMaterial {
    youngs_modulus_pa: 210e9,
    poisson_ratio: 0.3,
    density_kg_per_m3: 7850.0,
};

/// A trilinear map of the reference cube [-1, 1]^3 onto a distorted brick (about 0.1 x 0.07 x
/// 0.05 m, no two faces parallel).
fn trilinear(p: [f64; 3]) -> [f64; 3] {
    let (a, b, c) = (p[0], p[1], p[2]);
    [
        0.05 * a + 0.006 * b + 0.004 * a * b + 0.003 * a * c,
        0.035 * b + 0.005 * c - 0.004 * a * b + 0.002 * b * c,
        0.025 * c + 0.003 * a + 0.003 * a * c - 0.002 * a * b * c,
    ]
}

/// The corners of the reference cube in VTK order.
const CUBE: [[f64; 3]; 8] = squeal::mesh::hex::NODE_NATURAL;

fn flatten<const N: usize>(m: &[[f64; N]; N]) -> Vec<f64> {
    m.iter().flat_map(|row| row.iter().copied()).collect()
}

fn cases() -> Vec<ElementCase> {
    let mut out = Vec::new();
    let x8: [[f64; 3]; 8] = CUBE.map(trilinear);
    for (name, f) in [
        (
            "hex8",
            hex8::element_matrices as fn(&[[f64; 3]; 8], &ElasticMaterial, bool) -> _,
        ),
        ("hex8 incompatible", hex8_incompatible::element_matrices),
    ] {
        let c = f(&x8, &MATERIAL, false).expect("valid");
        let l = f(&x8, &MATERIAL, true).expect("valid");
        out.push(ElementCase {
            name,
            x: x8.to_vec(),
            k: flatten(&c.k),
            m_consistent: flatten(&c.m),
            m_lumped: flatten(&l.m),
            volume: c.volume,
        });
    }
    // Tet10: one tetrahedron of the distorted brick's corners (0, 1, 3, 4), straight-sided
    // (its mid-edge nodes at the edge midpoints): the map is affine, as the degree-2 rule needs.
    let corners = [x8[0], x8[1], x8[3], x8[4]];
    let x10 = tet10::straight(corners);
    let c = tet10::element_matrices(&x10, &MATERIAL, false).expect("valid");
    let l = tet10::element_matrices(&x10, &MATERIAL, true).expect("valid");
    out.push(ElementCase {
        name: "tet10",
        x: x10.to_vec(),
        k: flatten(&c.k),
        m_consistent: flatten(&c.m),
        m_lumped: flatten(&l.m),
        volume: tet10::volume(&x10),
    });
    // Tet4: the same four corners, linear.
    let c = tet4::element_matrices(&corners, &MATERIAL, false).expect("valid");
    let l = tet4::element_matrices(&corners, &MATERIAL, true).expect("valid");
    out.push(ElementCase {
        name: "tet4",
        x: corners.to_vec(),
        k: flatten(&c.k),
        m_consistent: flatten(&c.m),
        m_lumped: flatten(&l.m),
        volume: tet4::volume(&corners),
    });
    // Hex27: every node on the same trilinear map.
    let x27: [[f64; 3]; 27] = hex27::NODE_REFERENCE.map(trilinear);
    let c = hex27::element_matrices(&x27, &MATERIAL, false).expect("valid");
    let l = hex27::element_matrices(&x27, &MATERIAL, true).expect("valid");
    out.push(ElementCase {
        name: "hex27",
        x: x27.to_vec(),
        k: c.k,
        m_consistent: c.m,
        m_lumped: l.m,
        volume: c.volume,
    });
    out
}

fn mat_vec(k: &[f64], n: usize, v: &[f64]) -> Vec<f64> {
    (0..n)
        .map(|i| (0..n).map(|j| k[i * n + j] * v[j]).sum())
        .collect()
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// K = K^T to 1e-12 of the largest entry (both sides are sums of the same products).
#[test]
fn every_element_stiffness_is_symmetric() {
    for e in cases() {
        let n = e.dofs();
        let scale = e.k.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for i in 0..n {
            for j in 0..i {
                assert!(
                    (e.k[i * n + j] - e.k[j * n + i]).abs() <= 1e-12 * scale,
                    "{}: K[{i}][{j}]",
                    e.name
                );
            }
        }
    }
}

/// Six rigid motions store no force: ||K r|| <= 1e-9 ||K|| ||r|| (rounding of sums over 24-81
/// dofs of entries of order E V^(1/3)).
#[test]
fn every_element_has_six_rigid_modes() {
    for e in cases() {
        let n = e.dofs();
        let k_norm = e.k.iter().map(|v| v * v).sum::<f64>().sqrt();
        for mode in 0..6 {
            let r: Vec<f64> =
                e.x.iter()
                    .flat_map(|p| match mode {
                        0 => [1.0, 0.0, 0.0],
                        1 => [0.0, 1.0, 0.0],
                        2 => [0.0, 0.0, 1.0],
                        // omega x p for omega along x, y, z
                        3 => [0.0, -p[2], p[1]],
                        4 => [p[2], 0.0, -p[0]],
                        _ => [-p[1], p[0], 0.0],
                    })
                    .collect();
            let f = mat_vec(&e.k, n, &r);
            assert!(
                norm(&f) <= 1e-9 * k_norm * norm(&r),
                "{}: rigid mode {mode} stores force {}",
                e.name,
                norm(&f)
            );
        }
        // Exactly six zero eigenvalues (relative 1e-10 of the largest; the seventh well above):
        // no hourglass or condensation mode.
        let km = faer::Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (e.k[i * n + j] + e.k[j * n + i]));
        let ev = km
            .self_adjoint_eigenvalues(faer::Side::Lower)
            .expect("eigenvalues");
        let top = ev[n - 1];
        let zeros = ev.iter().filter(|v| v.abs() < 1e-10 * top).count();
        assert_eq!(zeros, 6, "{}: {zeros} zero eigenvalues", e.name);
        assert!(
            ev[6] > 1e-5 * top,
            "{}: seventh eigenvalue {}",
            e.name,
            ev[6]
        );
        // A pure stretch is not rigid (the check can fail): it stores energy.
        let stretch: Vec<f64> = e.x.iter().flat_map(|p| [p[0], 0.0, 0.0]).collect();
        assert!(norm(&mat_vec(&e.k, n, &stretch)) > 1e-3 * k_norm * norm(&stretch));
    }
}

/// The patch test on one element: u = A x with a general A (strain and rotation) stores
/// `V e^T D e`; relative error 1e-10 (exact integration, rounding only).
#[test]
fn every_element_passes_the_constant_strain_patch_test() {
    let a = [
        [1.0e-3, 0.4e-3, -0.2e-3],
        [-0.1e-3, -0.5e-3, 0.3e-3],
        [0.25e-3, 0.15e-3, 0.8e-3],
    ];
    // Voigt strain (xx, yy, zz, then engineering shears yz, xz, xy and their permutations are
    // all the same for an isotropic D).
    let eps = [
        a[0][0],
        a[1][1],
        a[2][2],
        a[1][2] + a[2][1],
        a[0][2] + a[2][0],
        a[0][1] + a[1][0],
    ];
    let d = MATERIAL.d_matrix();
    let mut energy_density = 0.0;
    for i in 0..6 {
        for j in 0..6 {
            energy_density += eps[i] * d[i][j] * eps[j];
        }
    }
    for e in cases() {
        let n = e.dofs();
        let u: Vec<f64> =
            e.x.iter()
                .flat_map(|p| [0, 1, 2].map(|i| (0..3).map(|j| a[i][j] * p[j]).sum::<f64>()))
                .collect();
        let ku = mat_vec(&e.k, n, &u);
        let energy: f64 = u.iter().zip(&ku).map(|(x, y)| x * y).sum();
        let expected = e.volume * energy_density;
        assert!(
            (energy / expected - 1.0).abs() < 1e-10,
            "{}: u^T K u = {energy}, V e^T D e = {expected}",
            e.name
        );
    }
}

/// Consistent and lumped mass both carry rho V per direction (1e-12 relative); the lumped mass
/// is diagonal with positive entries.
#[test]
fn every_element_mass_carries_rho_v() {
    for e in cases() {
        let n = e.dofs();
        let total = MATERIAL.density_kg_per_m3 * e.volume;
        for (kind, m) in [("consistent", &e.m_consistent), ("lumped", &e.m_lumped)] {
            for d in 0..3 {
                let mut sum = 0.0;
                for i in (d..n).step_by(3) {
                    for j in (d..n).step_by(3) {
                        sum += m[i * n + j];
                    }
                }
                assert!(
                    (sum / total - 1.0).abs() < 1e-12,
                    "{} {kind}: direction {d} carries {sum} of {total} kg",
                    e.name
                );
            }
        }
        for i in 0..n {
            for j in 0..n {
                let v = e.m_lumped[i * n + j];
                if i == j {
                    assert!(v > 0.0, "{}: lumped M[{i}][{i}] = {v}", e.name);
                } else {
                    assert_eq!(v, 0.0, "{}: lumped M[{i}][{j}]", e.name);
                }
            }
        }
    }
}
