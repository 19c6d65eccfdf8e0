//! The isoparametric map shared by the solid elements: `J[i][k] = sum_a dN_a/dxi_i x_a,k`,
//! `det J`, and physical gradients `dN_a/dx_k = sum_i (J^-1)[k][i] dN_a/dxi_i`.

use crate::mesh::P3;

/// Jacobian `J[i][k] = d x_k / d xi_i` of an `N`-node element and its determinant.
pub fn jacobian<const N: usize>(x: &[P3; N], dn: &[[f64; 3]; N]) -> ([[f64; 3]; 3], f64) {
    let mut j = [[0.0; 3]; 3];
    for a in 0..N {
        for i in 0..3 {
            for k in 0..3 {
                j[i][k] += dn[a][i] * x[a][k];
            }
        }
    }
    let det = j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1])
        - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
        + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0]);
    (j, det)
}

/// Physical gradients of the shape functions and `det J`; `None` if `det J <= 0` (inverted or
/// degenerate element) or not finite.
pub fn physical_gradients<const N: usize>(
    x: &[P3; N],
    dn: &[[f64; 3]; N],
) -> Option<([[f64; 3]; N], f64)> {
    let (j, det) = jacobian(x, dn);
    if det <= 0.0 || !det.is_finite() {
        return None;
    }
    let inv = inverse(&j, det);
    let mut g = [[0.0; 3]; N];
    for a in 0..N {
        for k in 0..3 {
            g[a][k] = (0..3).map(|i| inv[k][i] * dn[a][i]).sum();
        }
    }
    Some((g, det))
}

/// The inverse of a 3x3 matrix with (non-zero) determinant `det`, by cofactors.
pub fn inverse(j: &[[f64; 3]; 3], det: f64) -> [[f64; 3]; 3] {
    [
        [
            (j[1][1] * j[2][2] - j[1][2] * j[2][1]) / det,
            (j[0][2] * j[2][1] - j[0][1] * j[2][2]) / det,
            (j[0][1] * j[1][2] - j[0][2] * j[1][1]) / det,
        ],
        [
            (j[1][2] * j[2][0] - j[1][0] * j[2][2]) / det,
            (j[0][0] * j[2][2] - j[0][2] * j[2][0]) / det,
            (j[0][2] * j[1][0] - j[0][0] * j[1][2]) / det,
        ],
        [
            (j[1][0] * j[2][1] - j[1][1] * j[2][0]) / det,
            (j[0][1] * j[2][0] - j[0][0] * j[2][1]) / det,
            (j[0][0] * j[1][1] - j[0][1] * j[1][0]) / det,
        ],
    ]
}

/// Volume `sum_g det J(xi_g) w_g` of an `N`-node element by a quadrature `rule` (points, weights),
/// with `reference_gradients(xi)` the shape functions' reference derivatives; negative or zero
/// for an inverted element.
pub fn volume_by_rule<const N: usize>(
    x: &[P3; N],
    rule: &[([f64; 3], f64)],
    reference_gradients: impl Fn([f64; 3]) -> [[f64; 3]; N],
) -> f64 {
    rule.iter()
        .map(|&(xi, w)| jacobian(x, &reference_gradients(xi)).1 * w)
        .sum()
}

/// The 6 x 3N strain-displacement matrix of N nodes from their physical gradients (Voigt xx,
/// yy, zz, xy, yz, zx with engineering shears; dofs node-major `3 a + c`). `D` must be `3 N`
/// (stable Rust cannot write `3 * N` as a const generic); checked on entry.
pub fn b_matrix<const N: usize, const D: usize>(g: &[[f64; 3]; N]) -> [[f64; D]; 6] {
    assert_eq!(
        D,
        3 * N,
        "strain-displacement matrix of {N} nodes has {} columns",
        3 * N
    );
    let mut b = [[0.0; D]; 6];
    for (a, ga) in g.iter().enumerate() {
        let c = 3 * a;
        b[0][c] = ga[0];
        b[1][c + 1] = ga[1];
        b[2][c + 2] = ga[2];
        b[3][c] = ga[1];
        b[3][c + 1] = ga[0];
        b[4][c + 1] = ga[2];
        b[4][c + 2] = ga[1];
        b[5][c] = ga[2];
        b[5][c + 2] = ga[0];
    }
    b
}
