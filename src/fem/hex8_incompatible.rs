//! The incompatible-modes hexahedron ("QM6") of Wilson, Taylor, Doherty & Ghaboussi (1973) with
//! Taylor's correction (Taylor, Beresford & Wilson 1976, "A non-conforming element for stress
//! analysis", IJNME 10, 1211–1219).
//!
//! Why: the trilinear hex8 cannot bend. A pure bending field `u_x ∝ x y`, `u_y ∝ -x²/2 …` needs
//! quadratic terms; the trilinear interpolation replaces them by parasitic shear, so a web or a
//! beam only one or two elements thick is several to tens of per cent too stiff. Wilson's
//! element adds, per displacement component `c`, three internal "bubble" modes
//!
//! ```text
//! u_c(ξ) = Σ_a N_a(ξ) u_{a,c} + Σ_k P_k(ξ) α_{k,c},   P_1 = 1 − ξ², P_2 = 1 − η², P_3 = 1 − ζ²,
//! ```
//!
//! which vanish at the nodes (so they are not shared between elements: the field is
//! non-conforming) and carry exactly the missing quadratic terms.
//!
//! Taylor's correction: with the true Jacobian the incompatible strains `B_α` do not integrate
//! to zero over a distorted element, so a constant-stress state does work on the α's and the
//! patch test fails. Evaluating the bubble derivatives with the Jacobian at the element centre
//! and scaling by `det J0 / det J` (Taylor et al. 1976),
//!
//! ```text
//! ∂P_k/∂x_m ≈ G_{k,m}(ξ) = (det J0 / det J(ξ)) Σ_i (J0⁻¹)_{m i} ∂P_k/∂ξ_i,
//! ```
//!
//! gives `∫ G dV = det J0 · J0⁻¹ ∫_{[-1,1]³} ∂P/∂ξ dξ = 0` exactly (each `∂P_k/∂ξ_k = −2 ξ_k` is
//! odd), also under 2x2x2 Gauss quadrature. Then `K_αu u = ∫ B_αᵀ σ dV = 0` for any linear `u`
//! (constant `σ`), the condensed element reproduces the trilinear element's nodal forces for
//! linear fields, and the patch test passes on distorted meshes.
//!
//! The 9 internal dofs are condensed statically (they carry no mass and no external load):
//!
//! ```text
//! [K_uu K_uα] [u]   [f]                       K = K_uu − K_uα K_αα⁻¹ K_αu,
//! [K_αu K_αα] [α] = [0]   ⇒   α = −K_αα⁻¹ K_αu u,
//! ```
//!
//! with `K_uu` the standard hex8 stiffness ([`super::hex8::element_matrices`], same 2x2x2 Gauss
//! rule), `K_uα = Σ_g B_gᵀ D B_α,g det J_g`, `K_αα = Σ_g B_α,gᵀ D B_α,g det J_g`, and `K_αα⁻¹`
//! applied by a 9x9 Cholesky factorisation. The mass is the standard hex8 mass.
//!
//! Internal dofs are ordered mode-major like the nodal ones: `3 k + c` for bubble `k`,
//! component `c`.

// Index loops mirror the matrix formulas (B, D, J indices); iterator forms would hide them.
#![allow(clippy::needless_range_loop)]

use super::hex8::{self, ElasticMaterial, ElementMatrices};
use super::jacobian;
use crate::mesh::P3;

/// Number of condensed internal dofs: 3 bubbles x 3 components.
const INTERNAL: usize = 9;

/// `K_uα`: rows are the 24 nodal dofs, columns the 9 internal ones.
type CouplingBlock = [[f64; INTERNAL]; 24];
/// `K_αα`.
type InternalBlock = [[f64; INTERNAL]; INTERNAL];

/// Stiffness (incompatible modes, condensed) and mass (consistent or row-sum lumped, as the
/// standard hex8) of one element; `None` for a non-positive Jacobian determinant at a Gauss
/// point or at the centre (inverted or degenerate element).
pub fn element_matrices(
    x: &[P3; 8],
    mat: &ElasticMaterial,
    lumped: bool,
) -> Option<ElementMatrices> {
    let mut em = hex8::element_matrices(x, mat, lumped)?;
    let (k_ua, k_aa) = internal_blocks(x, mat)?;
    condense(&mut em.k, &k_ua, &k_aa)?;
    Some(em)
}

/// The coupling `K_uα` (24x9) and internal `K_αα` (9x9) blocks, 2x2x2 Gauss, with Taylor's
/// centre-Jacobian bubble gradients (module docs).
fn internal_blocks(x: &[P3; 8], mat: &ElasticMaterial) -> Option<(CouplingBlock, InternalBlock)> {
    let d = mat.d_matrix();
    let (_, dn_centre) = hex8::shape([0.0; 3]);
    let (j0, det0) = jacobian::jacobian(x, &dn_centre);
    if det0 <= 0.0 || !det0.is_finite() {
        return None;
    }
    let j0_inv = jacobian::inverse(&j0, det0);
    let gauss = 1.0 / 3f64.sqrt();
    let mut k_ua: CouplingBlock = [[0.0; INTERNAL]; 24];
    let mut k_aa: InternalBlock = [[0.0; INTERNAL]; INTERNAL];
    for &a in &[-gauss, gauss] {
        for &b in &[-gauss, gauss] {
            for &c in &[-gauss, gauss] {
                let xi = [a, b, c];
                let (_, grad, det) = hex8::gradients(x, xi)?;
                let bu = hex8::b_matrix(&grad);
                // Bubble gradients G_k = (det J0 / det J) J0⁻¹ ∂P_k/∂ξ, ∂P_k/∂ξ_i = −2 ξ_k δ_ik.
                let mut bubble_grad = [[0.0; 3]; 3];
                for k in 0..3 {
                    let dp = -2.0 * xi[k] * det0 / det;
                    for m in 0..3 {
                        bubble_grad[k][m] = j0_inv[m][k] * dp;
                    }
                }
                let ba = bubble_b_matrix(&bubble_grad);
                // D B_α det J (6x9)
                let mut dba = [[0.0; INTERNAL]; 6];
                for i in 0..6 {
                    for j in 0..INTERNAL {
                        let mut s = 0.0;
                        for l in 0..6 {
                            s += d[i][l] * ba[l][j];
                        }
                        dba[i][j] = s * det;
                    }
                }
                for i in 0..24 {
                    for j in 0..INTERNAL {
                        let mut s = 0.0;
                        for l in 0..6 {
                            s += bu[l][i] * dba[l][j];
                        }
                        k_ua[i][j] += s;
                    }
                }
                for i in 0..INTERNAL {
                    for j in 0..INTERNAL {
                        let mut s = 0.0;
                        for l in 0..6 {
                            s += ba[l][i] * dba[l][j];
                        }
                        k_aa[i][j] += s;
                    }
                }
            }
        }
    }
    Some((k_ua, k_aa))
}

/// The 6x9 strain matrix of the bubble modes from their gradients `g[k]` (Voigt order and
/// engineering shears as [`hex8::b_matrix`]).
fn bubble_b_matrix(g: &[[f64; 3]; 3]) -> [[f64; INTERNAL]; 6] {
    let mut b = [[0.0; INTERNAL]; 6];
    for k in 0..3 {
        let c = 3 * k;
        b[0][c] = g[k][0];
        b[1][c + 1] = g[k][1];
        b[2][c + 2] = g[k][2];
        b[3][c] = g[k][1];
        b[3][c + 1] = g[k][0];
        b[4][c + 1] = g[k][2];
        b[4][c + 2] = g[k][1];
        b[5][c] = g[k][2];
        b[5][c + 2] = g[k][0];
    }
    b
}

/// `k ← k − K_uα K_αα⁻¹ K_αu` (static condensation); `None` if `K_αα` is not positive definite
/// (only for a degenerate element: the nine bubble strain fields are independent otherwise).
fn condense(k: &mut [[f64; 24]; 24], k_ua: &CouplingBlock, k_aa: &InternalBlock) -> Option<()> {
    let l = cholesky(k_aa)?;
    // X = K_αα⁻¹ K_αu, one column (element dof) at a time: forward then back substitution.
    let mut x = [[0.0; 24]; INTERNAL];
    for col in 0..24 {
        let mut y = [0.0; INTERNAL];
        for i in 0..INTERNAL {
            let mut s = k_ua[col][i];
            for p in 0..i {
                s -= l[i][p] * y[p];
            }
            y[i] = s / l[i][i];
        }
        for i in (0..INTERNAL).rev() {
            let mut s = y[i];
            for p in i + 1..INTERNAL {
                s -= l[p][i] * x[p][col];
            }
            x[i][col] = s / l[i][i];
        }
    }
    for i in 0..24 {
        for j in i..24 {
            let mut s = 0.0;
            for p in 0..INTERNAL {
                s += k_ua[i][p] * x[p][j];
            }
            k[i][j] -= s;
        }
    }
    // The product is symmetric in exact arithmetic; mirror the upper triangle so the element
    // matrix is symmetric to the last bit, as the assembly's lower-triangle storage assumes.
    for i in 0..24 {
        for j in 0..i {
            k[i][j] = k[j][i];
        }
    }
    Some(())
}

/// Lower Cholesky factor `L` (`A = L Lᵀ`) of a symmetric 9x9 matrix; `None` if a pivot is not
/// positive relative to the largest diagonal entry (not positive definite to working precision).
fn cholesky(a: &InternalBlock) -> Option<InternalBlock> {
    let scale = (0..INTERNAL).map(|i| a[i][i].abs()).fold(0.0, f64::max);
    if !(scale.is_finite() && scale > 0.0) {
        return None;
    }
    let mut l = [[0.0; INTERNAL]; INTERNAL];
    for j in 0..INTERNAL {
        let mut pivot = a[j][j];
        for p in 0..j {
            pivot -= l[j][p] * l[j][p];
        }
        if !pivot.is_finite() || pivot <= 1e-12 * scale {
            return None;
        }
        let diag = pivot.sqrt();
        l[j][j] = diag;
        for i in j + 1..INTERNAL {
            let mut s = a[i][j];
            for p in 0..j {
                s -= l[i][p] * l[j][p];
            }
            l[i][j] = s / diag;
        }
    }
    Some(l)
}
