//! The explicit element's own linearised stiffness (at the reference state) and lumped mass, so
//! that the modal module can solve the very discretisation the engine integrates
//! (docs/architecture.md, "Element technology"): an impulse response of the engine and the
//! eigen-solution of these matrices must agree to a fraction of a percent.
//!
//! One-point element, `u = 0`: with the mean gradients `b_a`,
//! `K_ab,ik = V0 (lambda b_a,i b_b,k + mu b_a,k b_b,i + mu delta_ik b_a . b_b)`, plus the hourglass
//! stiffness `sum_alpha g_alpha,a g_alpha,b C_alpha,ik`, where `C_alpha = sum_r C_alpha,r t_r t_r^T`
//! (physical form, unit reference axes t_r) or `C I` (isotropic form). It takes the element's
//! `F0` (see `OnePointElement`) as I: F0 differs from I by the single-precision rounding of the
//! gradients, ~1e-7, far below what the modal comparison resolves.

// Index loops mirror the tensor notation of the equations.
#![allow(clippy::needless_range_loop)]

use super::element::{OnePointElement, HOURGLASS_BASE};
use super::model::{Elements, Model};
use crate::{Error, Result};

/// Element stiffness (24 x 24, dof `3 a + i`) of a one-point element at the reference state.
pub fn one_point_stiffness(el: &OnePointElement, physical: bool) -> [[f64; 24]; 24] {
    let mut k = [[0.0; 24]; 24];
    let lambda_v = el.lambda_vol;
    let mu_v = 0.5 * el.two_mu_vol;
    let b = |a: usize| [el.grad[0][a], el.grad[1][a], el.grad[2][a]];
    for a in 0..8 {
        let ba = b(a);
        for c in 0..8 {
            let bc = b(c);
            let dot = ba[0] * bc[0] + ba[1] * bc[1] + ba[2] * bc[2];
            for i in 0..3 {
                for m in 0..3 {
                    let mut v = lambda_v * ba[i] * bc[m] + mu_v * ba[m] * bc[i];
                    if i == m {
                        v += mu_v * dot;
                    }
                    k[3 * a + i][3 * c + m] = v;
                }
            }
        }
    }
    // Unit reference axes for the physical form.
    let axes: [[f64; 3]; 3] = el.axes_ref.map(|t| {
        let n = (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
        [t[0] / n, t[1] / n, t[2] / n]
    });
    for alpha in 0..4 {
        let hx = el.hourglass_ref[alpha];
        let g: [f64; 8] = std::array::from_fn(|a| {
            HOURGLASS_BASE[alpha][a]
                - (hx[0] * el.grad[0][a] + hx[1] * el.grad[1][a] + hx[2] * el.grad[2][a])
        });
        let mut c = [[0.0; 3]; 3];
        if physical {
            for (r, t) in axes.iter().enumerate() {
                for i in 0..3 {
                    for m in 0..3 {
                        c[i][m] += el.hourglass_axis_coef[alpha][r] * t[i] * t[m];
                    }
                }
            }
        } else {
            for i in 0..3 {
                c[i][i] = el.hourglass_coef;
            }
        }
        for a in 0..8 {
            for cc in 0..8 {
                for i in 0..3 {
                    for m in 0..3 {
                        k[3 * a + i][3 * cc + m] += g[a] * g[cc] * c[i][m];
                    }
                }
            }
        }
    }
    k
}

/// Global stiffness triplets `(row, column, value)` (duplicates to be summed) of the model's
/// one-point elements at the reference state, dof `3 node + direction`.
pub fn stiffness_triplets(model: &Model) -> Result<Vec<(usize, usize, f64)>> {
    let Elements::OnePoint(els) = &model.elements else {
        return Err(Error::input(
            "model",
            "formulation",
            "the linearised stiffness is available for the one-point element only",
        ));
    };
    if model.viscous_hourglass {
        return Err(Error::input(
            "model",
            "formulation.hourglass",
            "the viscous form has no stiffness",
        ));
    }
    let mut out = Vec::with_capacity(els.len() * 576);
    for el in els {
        let k = one_point_stiffness(el, model.physical_hourglass);
        for a in 0..8 {
            for c in 0..8 {
                for i in 0..3 {
                    for m in 0..3 {
                        out.push((
                            3 * el.nodes[a] as usize + i,
                            3 * el.nodes[c] as usize + m,
                            k[3 * a + i][3 * c + m],
                        ));
                    }
                }
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::explicit::element::{
        one_point_forces, ElasticMaterial, Hourglass, KernelOptions, NODE_NATURAL,
    };

    /// K u equals the kernel's internal force for a small displacement. The kernel is
    /// geometrically nonlinear: the difference is second order, about 4x the strain relative
    /// (measured 4e-5 at strains of 1e-5), so strains of 1e-7 are used and 1e-6 allows rounding.
    #[test]
    fn stiffness_reproduces_the_kernel_forces() {
        let mat = ElasticMaterial {
            density_kg_per_m3: 7850.0,
            youngs_modulus_pa: 210e9,
            poisson_ratio: 0.3,
        };
        let mut x = NODE_NATURAL.map(|c| {
            [
                0.01 * (1.0 + c[0]),
                0.012 * (1.0 + c[1]),
                0.008 * (1.0 + c[2]),
            ]
        });
        x[6][0] += 0.003;
        x[2][2] -= 0.002;
        for (hourglass, physical) in [
            (Hourglass::default(), true),
            (Hourglass::Stiffness { kappa: 0.1 }, false),
        ] {
            let el = OnePointElement::new([0, 1, 2, 3, 4, 5, 6, 7], &x, &mat, hourglass).unwrap();
            let u: [[f64; 3]; 8] = std::array::from_fn(|a| {
                [
                    1e-9 * (a as f64).sin(),
                    2e-9 * (a as f64).cos(),
                    1e-9 * a as f64,
                ]
            });
            let mut f = [[0.0; 3]; 8];
            let opts = KernelOptions {
                physical_hourglass: physical,
                ..Default::default()
            };
            one_point_forces::<false>(&el, &u, &u, opts, &mut f);
            let k = one_point_stiffness(&el, physical);
            let scale = f
                .iter()
                .flat_map(|r| r.iter())
                .fold(0.0f64, |m, v| m.max(v.abs()));
            for a in 0..8 {
                for i in 0..3 {
                    let mut ku = 0.0;
                    for c in 0..8 {
                        for m in 0..3 {
                            ku += k[3 * a + i][3 * c + m] * u[c][m];
                        }
                    }
                    assert!((ku - f[a][i]).abs() < 1e-6 * scale, "{ku} vs {}", f[a][i]);
                }
            }
        }
    }
}
