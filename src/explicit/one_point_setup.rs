//! Construction of the one-point element record ([`OnePointElement::new`]): the record's
//! fields in the order they depend on each other, one phase each: the exact volume and mean
//! gradient, their single-precision rounding, the reference stretch `F0`, the hourglass
//! reference vectors, the element's axes at the centre, and the hourglass coefficients.
//!
//! Why the values are rounded to single precision and measured from `F0` is the struct's
//! documentation ([`OnePointElement`]).

// Index loops mirror the tensor notation of the equations (the project's style for kernels);
// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

use super::element::{
    det3, gauss_2x2x2, inverse3, reference_gradients, ElasticMaterial, Hourglass, OnePointElement,
    HOURGLASS_BASE, NODE_NATURAL,
};
use crate::mesh::P3;

/// A 3x3 matrix, rows first.
type Mat3 = [[f64; 3]; 3];

/// Rounds to the nearest single-precision number (kept as f64).
fn single(x: f64) -> f64 {
    x as f32 as f64
}

impl OnePointElement {
    /// Precompute from reference coordinates.
    pub fn new(
        nodes: [usize; 8],
        x: &[P3; 8],
        mat: &ElasticMaterial,
        hourglass: Hourglass,
    ) -> Option<Self> {
        let (mut grad, volume) = mean_gradient(x)?;
        round_gradient(&mut grad);
        let (stretch_inv, stretch_delta) = reference_stretch(x, &grad)?;
        let hourglass_ref = hourglass_reference(x, &stretch_inv);
        let (lambda, mu) = (mat.lambda_pa(), mat.mu_pa());
        let grad_sq: f64 = grad.iter().flat_map(|r| r.iter()).map(|g| g * g).sum();
        let (axes_ref, half) = centre_axes(x);
        let hourglass_axis_coef =
            physical_hourglass_coefficients(hourglass, mat, mu, volume, &half);
        let hourglass_coef =
            isotropic_hourglass_coefficient(hourglass, mat, lambda, mu, volume, grad_sq);
        Some(OnePointElement {
            nodes: nodes.map(|n| n as u32),
            grad,
            stretch_delta,
            hourglass_ref,
            lambda_vol: single(lambda * volume),
            two_mu_vol: single(2.0 * mu * volume),
            hourglass_coef: single(hourglass_coef),
            hourglass_axis_coef: hourglass_axis_coef.map(|r| r.map(single)),
            axes_ref: axes_ref.map(|r| r.map(single)),
            volume_m3: volume,
        })
    }
}

/// The exact volume and the mean gradient of the element (in f64); `None` for an element
/// whose Jacobian is not positive at the centre or a Gauss point, or whose volume is not
/// positive.
fn mean_gradient(x: &[P3; 8]) -> Option<([[f64; 8]; 3], f64)> {
    let (_, det_centre) = reference_gradients(x, [0.0; 3])?;
    // Exact volume of the trilinear map (det J has degree <= 2 per direction, which the
    // 2x2x2 rule integrates exactly) and the mean gradient b_a = (1/V) integral(dN_a/dX dV)
    // of Flanagan & Belytschko (det J dN/dX = cof(J)^T dN/dxi has degree <= 3 per direction:
    // also exact). With the mean gradient a constant stress gives exactly the consistent
    // nodal forces on distorted elements (the patch test), and sum_a b_a X_a^T = I still holds.
    let mut volume = 0.0;
    let mut grad = [[0.0; 8]; 3];
    for p in gauss_2x2x2() {
        let (b, det) = reference_gradients(x, p)?;
        volume += det;
        for j in 0..3 {
            for a in 0..8 {
                grad[j][a] += det * b[j][a];
            }
        }
    }
    for row in grad.iter_mut() {
        for g in row.iter_mut() {
            *g /= volume;
        }
    }
    if !(volume > 0.0) || !(det_centre > 0.0) {
        return None;
    }
    Some((grad, volume))
}

/// Rounds the gradients to single precision, the last one of each row closing the sum so
/// that `sum_a b_a = 0` holds to f64 rounding (translation invariance, see the struct doc).
fn round_gradient(grad: &mut [[f64; 8]; 3]) {
    // Single-precision gradients, the last one closing the sum (see the struct doc).
    for row in grad.iter_mut() {
        let mut sum = 0.0;
        for g in row.iter_mut().take(7) {
            *g = single(*g);
            sum += *g;
        }
        row[7] = 0.0 - sum;
    }
}

/// The reference stretch `F0 = sum_a X_a b_a^T` of the rounded gradients: its inverse (f64,
/// for the hourglass vectors) and `F0 - I` rounded to single precision (the strain is measured
/// from `F0`). `None` when `det F0` is not positive.
fn reference_stretch(x: &[P3; 8], grad: &[[f64; 8]; 3]) -> Option<(Mat3, Mat3)> {
    let mut stretch_ref = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for a in 0..8 {
                stretch_ref[i][j] += x[a][i] * grad[j][a];
            }
        }
    }
    let det_stretch = det3(&stretch_ref);
    if !(det_stretch > 0.0) {
        return None;
    }
    let stretch_inv = inverse3(&stretch_ref, det_stretch);
    let mut stretch_delta = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let identity = if i == j { 1.0 } else { 0.0 };
            stretch_delta[i][j] = single(stretch_ref[i][j] - identity);
        }
    }
    Some((stretch_inv, stretch_delta))
}

/// The hourglass reference vectors `F0^-1 sum_b h_alpha,b X_b` per mode (f64), so that a
/// rigid rotation of any angle gives zero hourglass displacement to f64 rounding.
fn hourglass_reference(x: &[P3; 8], stretch_inv: &[[f64; 3]; 3]) -> [[f64; 3]; 4] {
    let mut hourglass_ref = [[0.0; 3]; 4];
    for (alpha, h) in HOURGLASS_BASE.iter().enumerate() {
        let mut hx = [0.0; 3];
        for a in 0..8 {
            for j in 0..3 {
                hx[j] += h[a] * x[a][j];
            }
        }
        for i in 0..3 {
            hourglass_ref[alpha][i] =
                stretch_inv[i][0] * hx[0] + stretch_inv[i][1] * hx[1] + stretch_inv[i][2] * hx[2];
        }
    }
    hourglass_ref
}

/// The element's reference axes `dX/dxi_r` at the centre (columns of J) and their half
/// lengths `a_r`, which size the physical hourglass stiffness.
fn centre_axes(x: &[P3; 8]) -> ([[f64; 3]; 3], [f64; 3]) {
    // Half lengths a_r = |dX/dxi_r| at the centre.
    let mut axes_ref = [[0.0; 3]; 3];
    for (a, c) in NODE_NATURAL.iter().enumerate() {
        for r in 0..3 {
            for j in 0..3 {
                axes_ref[r][j] += 0.125 * c[r] * x[a][j];
            }
        }
    }
    let half: [f64; 3] = axes_ref.map(|t| (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt());
    (axes_ref, half)
}

/// The physical form's stiffness per hourglass mode and local axis `C_alpha,r` (N/m); zero
/// for the isotropic forms.
fn physical_hourglass_coefficients(
    hourglass: Hourglass,
    mat: &ElasticMaterial,
    mu: f64,
    volume: f64,
    half: &[f64; 3],
) -> [[f64; 3]; 4] {
    let mut hourglass_axis_coef = [[0.0; 3]; 4];
    if let Hourglass::Physical { scale } = hourglass {
        // Modes xi eta, eta zeta, xi zeta: pair (r, s) and the third axis t. With the
        // unnormalised generalised displacement q = 8 d: bending along r stores
        // E (d/a_r)^2 V / 6 = E V q^2 / (2 * 192 a_r^2); the out-of-pair direction carries the
        // shears G d^2 V (1/a_r^2 + 1/a_s^2) / 6. Mode xi eta zeta: E V q^2 / (2 * 576 a_r^2).
        let (e, g) = (mat.youngs_modulus_pa, mu);
        for (alpha, (r, s, t)) in [(0usize, 1usize, 2usize), (1, 2, 0), (0, 2, 1)]
            .into_iter()
            .enumerate()
        {
            let (ar2, as2) = (half[r] * half[r], half[s] * half[s]);
            hourglass_axis_coef[alpha][r] = scale * e * volume / (192.0 * ar2);
            hourglass_axis_coef[alpha][s] = scale * e * volume / (192.0 * as2);
            hourglass_axis_coef[alpha][t] = scale * g * volume * (1.0 / ar2 + 1.0 / as2) / 192.0;
        }
        for r in 0..3 {
            hourglass_axis_coef[3][r] = scale * e * volume / (576.0 * half[r] * half[r]);
        }
    }
    hourglass_axis_coef
}

/// The isotropic forms' hourglass coefficient `C` (stiffness, N/m, or viscous, N s/m); zero
/// for the physical form, whose stiffness is per mode and axis.
fn isotropic_hourglass_coefficient(
    hourglass: Hourglass,
    mat: &ElasticMaterial,
    lambda: f64,
    mu: f64,
    volume: f64,
    grad_sq: f64,
) -> f64 {
    match hourglass {
        Hourglass::Physical { .. } => 0.0,
        Hourglass::Stiffness { kappa } => kappa * (lambda + 2.0 * mu) * volume * grad_sq / 96.0,
        Hourglass::Viscous { kappa } => {
            // Flanagan-Belytschko viscous form: c = kappa rho c_L V^(2/3) / 4 on the mode
            // amplitudes q/8, hence the 1/64 on our unnormalised g.
            kappa
                * mat.density_kg_per_m3
                * mat.dilatational_wave_speed_m_per_s()
                * volume.powf(2.0 / 3.0)
                / 4.0
                / 64.0
        }
    }
}
