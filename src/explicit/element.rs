//! Hexahedral element kernels of the explicit engine (total Lagrangian, St. Venant-Kirchhoff).
//!
//! Kinematics, for an element with reference node positions `X_a` and displacements `u_a`:
//! - displacement gradient `H = sum_a u_a (x) b_a`, with `b_a = dN_a/dX` in the reference
//!   configuration; deformation gradient `F = I + H`;
//! - Green-Lagrange strain `E = (H + H^T + H^T H) / 2` (formed from `H`, not from `F^T F - I`,
//!   so that strains of 1e-6 keep all their digits);
//! - second Piola-Kirchhoff stress `S = lambda tr(E) I + 2 mu E`; first Piola `P = F S`;
//! - nodal internal forces `f_a = V0 P b_a`, the gradient of the stored energy
//!   `W = V0 (lambda/2 tr(E)^2 + mu E:E)`.
//!
//! `E` vanishes for any rigid motion `x = R X + c`, however large the rotation, so a spinning
//! wheel stays unstrained.
//!
//! One-point integration uses the mean gradient `b_a = (1/V) integral(dN_a/dX dV)`
//! (Flanagan & Belytschko), which passes the constant-stress patch test on distorted elements. The four hourglass modes
//! (Flanagan & Belytschko 1981, Int. J. Numer. Meth. Eng. 17, 679-706) are the base vectors
//! `h_1 = xi eta`, `h_2 = eta zeta`, `h_3 = xi zeta`, `h_4 = xi eta zeta` at the nodes; their
//! projections orthogonal to every linear field are `g_alpha,a = h_alpha,a - (sum_b h_alpha,b X_b) . b_a`
//! and the generalised hourglass displacements `q_alpha = sum_a g_alpha,a u_a` (3-vectors).
//! Because `g` annihilates every field linear in X (rigid rotations included), `q` is zero for
//! a rigid motion of any size and rotates with the body. Stiffness form: potential
//! `W_hg = C/2 sum_alpha |q_alpha|^2`, forces `f_a = C sum_alpha g_alpha,a q_alpha`; viscous form:
//! `f_a = C_v sum_alpha g_alpha,a qdot_alpha` with `qdot` from the nodal velocities.
//! The coefficient `C = kappa (lambda + 2 mu) V0 (sum_a |b_a|^2) / 96`: for a cube of side h,
//! `kappa = 1` gives the hourglass stiffness `(lambda + 2 mu) h` of a unit-amplitude mode, close to
//! the fully integrated element's (4/3 E h); the default `kappa = 0.1` follows common practice
//! for the stiffness form.
//!
//! The fully integrated option evaluates the same energy at the 2x2x2 Gauss points (no hourglass
//! modes, but shear locking in bending): it is the comparison reference the issue asks for.

// Index loops mirror the tensor notation of the equations (the project's style for kernels);
// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::needless_range_loop, clippy::neg_cmp_op_on_partial_ord)]

use serde::{Deserialize, Serialize};

use crate::mesh::P3;

/// Isotropic linear elastic material (St. Venant-Kirchhoff in the engine): the crate's one
/// material type.
pub use crate::material::Material as ElasticMaterial;

/// Hourglass control of the one-point element.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "form", rename_all = "lowercase")]
pub enum Hourglass {
    /// Physical stiffness (default): each mode and local direction gets the stiffness that the
    /// mode's linear strain field would store in a rectangular element with its parasitic shear
    /// removed (the enhanced-strain / incompatible-mode idea of Belytschko & Bindeman 1993,
    /// Comput. Methods Appl. Mech. Eng. 105, 225-260). For mode `xi eta` along xi that is pure
    /// bending, `W = E V d^2 / (6 a_xi^2)` for a mode amplitude d, so one element through the
    /// thickness bends like a beam. The directions are the element's current axes, so the
    /// stiffness turns with the body.
    Physical {
        /// Multiplier of the physical stiffness (1 = as derived).
        scale: f64,
    },
    /// Stiffness form with coefficient kappa (conservative; its energy is reported).
    Stiffness {
        /// Dimensionless coefficient (0.01-0.3 in practice).
        kappa: f64,
    },
    /// Viscous form: `C_v = kappa rho c_L V0^(2/3) / 4` per mode (dissipative).
    Viscous {
        /// Dimensionless coefficient.
        kappa: f64,
    },
}

impl Default for Hourglass {
    fn default() -> Self {
        Hourglass::Physical { scale: 1.0 }
    }
}

impl Hourglass {
    /// The coefficient (kappa or scale).
    pub fn coefficient(&self) -> f64 {
        match *self {
            Hourglass::Physical { scale } => scale,
            Hourglass::Stiffness { kappa } | Hourglass::Viscous { kappa } => kappa,
        }
    }
}

/// Element formulation.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Formulation {
    /// One-point integration with hourglass control (the production element).
    OnePoint {
        /// Hourglass control.
        hourglass: Hourglass,
    },
    /// 2x2x2 Gauss integration (reference; slower, locks in bending).
    Full,
}

impl Default for Formulation {
    fn default() -> Self {
        Formulation::OnePoint {
            hourglass: Hourglass::default(),
        }
    }
}

/// Hourglass base vectors at the nodes (VTK node order), see the module documentation.
pub const HOURGLASS_BASE: [[f64; 8]; 4] = [
    [1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0],
    [1.0, 1.0, -1.0, -1.0, -1.0, -1.0, 1.0, 1.0],
    [1.0, -1.0, -1.0, 1.0, -1.0, 1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0, 1.0, 1.0, -1.0, 1.0, -1.0],
];

/// Natural coordinates of the nodes (VTK order), defined with the mesh's node ordering.
pub use crate::mesh::hex::NODE_NATURAL;

/// Trilinear shape functions at natural point `p`.
pub fn shape_functions(p: [f64; 3]) -> [f64; 8] {
    let mut n = [0.0; 8];
    for (a, c) in NODE_NATURAL.iter().enumerate() {
        n[a] = 0.125 * (1.0 + c[0] * p[0]) * (1.0 + c[1] * p[1]) * (1.0 + c[2] * p[2]);
    }
    n
}

/// Reference gradients `dN_a/dX` (rows x, y, z) and the Jacobian determinant at natural point
/// `p`; `None` when the Jacobian is not positive (inverted or degenerate element).
pub fn reference_gradients(x: &[P3; 8], p: [f64; 3]) -> Option<([[f64; 8]; 3], f64)> {
    let mut dn = [[0.0; 8]; 3]; // dN/dxi, dN/deta, dN/dzeta
    for (a, c) in NODE_NATURAL.iter().enumerate() {
        let (f0, f1, f2) = (1.0 + c[0] * p[0], 1.0 + c[1] * p[1], 1.0 + c[2] * p[2]);
        dn[0][a] = 0.125 * c[0] * f1 * f2;
        dn[1][a] = 0.125 * c[1] * f0 * f2;
        dn[2][a] = 0.125 * c[2] * f0 * f1;
    }
    // J[i][j] = d x_j / d xi_i
    let mut jac = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            jac[i][j] = (0..8).map(|a| dn[i][a] * x[a][j]).sum();
        }
    }
    let det = det3(&jac);
    if !(det > 0.0) || !det.is_finite() {
        return None;
    }
    let inv = inverse3(&jac, det);
    // dN/dX_j = sum_i (J^-1)[j][i] dN/dxi_i
    let mut grad = [[0.0; 8]; 3];
    for j in 0..3 {
        for a in 0..8 {
            grad[j][a] = inv[j][0] * dn[0][a] + inv[j][1] * dn[1][a] + inv[j][2] * dn[2][a];
        }
    }
    Some((grad, det))
}

/// Determinant of a 3x3 matrix.
pub fn det3(m: &[[f64; 3]; 3]) -> f64 {
    m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
}

/// Inverse of a 3x3 matrix with known determinant.
pub fn inverse3(m: &[[f64; 3]; 3], det: f64) -> [[f64; 3]; 3] {
    let d = 1.0 / det;
    [
        [
            (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * d,
            (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * d,
            (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * d,
        ],
        [
            (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * d,
            (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * d,
            (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * d,
        ],
        [
            (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * d,
            (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * d,
            (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * d,
        ],
    ]
}

/// Gauss points of the 2x2x2 rule (weights 1).
pub fn gauss_2x2x2() -> [[f64; 3]; 8] {
    let g = 1.0 / 3f64.sqrt();
    let mut pts = [[0.0; 3]; 8];
    for (k, c) in NODE_NATURAL.iter().enumerate() {
        pts[k] = [c[0] * g, c[1] * g, c[2] * g];
    }
    pts
}

/// Row-sum lumped nodal masses `m_a = rho * integral(N_a dV)` by 2x2x2 Gauss integration
/// (equal to `rho V / 8` for a parallelepiped). `None` for an inverted element.
pub fn lumped_masses(x: &[P3; 8], density_kg_per_m3: f64) -> Option<[f64; 8]> {
    let mut m = [0.0; 8];
    for p in gauss_2x2x2() {
        let (_, det) = reference_gradients(x, p)?;
        let n = shape_functions(p);
        for a in 0..8 {
            m[a] += density_kg_per_m3 * n[a] * det;
        }
    }
    Some(m)
}

/// Data of one one-point element.
///
/// Single-precision geometry: the fast kernel ([`super::batch`]) streams every element's data
/// from memory once per step and is bound by the bytes moved, so it stores the gradients, the
/// hourglass axes and the coefficients as f32 (as LS-DYNA's default single-precision build
/// does). They are rounded when the record is built (`OnePointElement::new`, in
/// `one_point_setup.rs`), so that this (reference) element and the batched kernel use
/// identical values. Rounding must not break the invariances the issue asks for exactly:
/// - translation: the last gradient is minus the sum of the others, so `sum_a b_a = 0` holds to
///   f64 rounding (the wheelset travels more than a metre);
/// - rotation: with rounded gradients `F0 = sum_a X_a b_a^T` differs from I by ~1e-7, so the
///   strain is measured from F0, `E = (F^T F - F0^T F0) / 2` with `F = F0 + H` (total
///   Lagrangian St. Venant-Kirchhoff about the reference F0), and the hourglass vectors use
///   `F0^-1 sum_b h_alpha,b X_b` in f64: a rigid rotation of any angle then gives zero strain
///   and zero hourglass displacement to f64 rounding.
///
/// What the rounding does cost is a perturbation of ~1e-7 of the element's stiffness (its
/// gradients and coefficients), far below discretisation and material uncertainties.
#[derive(Clone, Copy, Debug)]
#[repr(C)]
pub struct OnePointElement {
    /// Nodes (VTK order).
    pub nodes: [u32; 8],
    /// Mean gradient `b_a = (1/V) integral(dN_a/dX dV)` rounded to single precision, rows x, y,
    /// z; `b_7 = -(b_0 + ... + b_6)` summed in that order in f64.
    pub grad: [[f64; 8]; 3],
    /// `F0 - I`, `F0 = sum_a X_a b_a^T` with the stored gradients (~1e-7), rounded to single
    /// precision.
    pub stretch_delta: [[f64; 3]; 3],
    /// `F0^-1 sum_b h_alpha,b X_b` per hourglass mode (f64).
    pub hourglass_ref: [[f64; 3]; 4],
    /// `lambda * V0` (N m).
    pub lambda_vol: f64,
    /// `2 mu * V0` (N m).
    pub two_mu_vol: f64,
    /// Hourglass coefficient `C` (N/m), stiffness or viscous (N s/m) by the formulation
    /// (isotropic forms).
    pub hourglass_coef: f64,
    /// Physical form: stiffness per mode and local axis `C_alpha,r` (N/m).
    pub hourglass_axis_coef: [[f64; 3]; 4],
    /// Physical form: reference axes `dX/dxi_r` at the centre (columns of J), m.
    pub axes_ref: [[f64; 3]; 3],
    /// Reference volume (m^3).
    pub volume_m3: f64,
}

/// What a kernel call returns besides the forces (only filled when asked for).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ElementEnergy {
    /// Stored strain energy (J).
    pub strain_j: f64,
    /// Hourglass energy of the stiffness form (J).
    pub hourglass_j: f64,
    /// Smallest `det F` (1 undeformed; <= 0 inverted).
    pub min_det_f: f64,
}

/// Small 3x3 helpers written out as plain loops (the compiler unrolls them).
#[inline(always)]
fn strain_and_stress(
    h: &[[f64; 3]; 3],
    delta: &[[f64; 3]; 3],
    lambda: f64,
    two_mu: f64,
) -> ([[f64; 3]; 3], [[f64; 3]; 3]) {
    // E = (F^T F - F0^T F0) / 2 with F = F0 + H, F0 = I + delta:
    //   E = (H + H^T) / 2 + (K^T H + H^T K) / 2, K = delta + H / 2,
    // written in H so that a small strain is not the difference of two numbers near 1.
    let mut k = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            k[i][j] = delta[i][j] + 0.5 * h[i][j];
        }
    }
    let mut e = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let mut acc = h[i][j] + h[j][i];
            for m in 0..3 {
                acc += k[m][i] * h[m][j] + h[m][i] * k[m][j];
            }
            e[i][j] = 0.5 * acc;
        }
    }
    let tr = e[0][0] + e[1][1] + e[2][2];
    let mut s = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            s[i][j] = two_mu * e[i][j];
        }
        s[i][i] += lambda * tr;
    }
    (e, s)
}

/// First Piola-Kirchhoff stress `P = F S` with `F = I + d`.
#[inline(always)]
fn first_piola(d: &[[f64; 3]; 3], s: &[[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let mut p = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            p[i][j] = s[i][j] + d[i][0] * s[0][j] + d[i][1] * s[1][j] + d[i][2] * s[2][j];
        }
    }
    p
}

/// Options of a kernel evaluation.
#[derive(Clone, Copy, Debug, Default)]
pub struct KernelOptions {
    /// Viscous hourglass form (else stiffness).
    pub viscous_hourglass: bool,
    /// Physical hourglass stiffness (per mode and axis) instead of the isotropic forms.
    pub physical_hourglass: bool,
    /// Stiffness-proportional (Rayleigh beta) damping time (s); 0 = none.
    pub stiffness_damping_s: f64,
}

/// Internal forces of one one-point element (written to `force`, 8 nodes x 3), with energies
/// when `ENERGY` is true. `u` and `v` are the nodal displacement and velocity arrays.
///
/// Kept in one piece: the reference kernel, written as the formulas read, against which the batched
/// kernel is checked.
#[inline(always)]
pub fn one_point_forces<const ENERGY: bool>(
    el: &OnePointElement,
    u: &[[f64; 3]],
    v: &[[f64; 3]],
    opts: KernelOptions,
    force: &mut [[f64; 3]; 8],
) -> ElementEnergy {
    let mut ue = [[0.0; 8]; 3];
    for a in 0..8 {
        let n = el.nodes[a] as usize;
        let d = u[n];
        ue[0][a] = d[0];
        ue[1][a] = d[1];
        ue[2][a] = d[2];
    }
    // H_ij = sum_a u_ai b_aj
    let mut h = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let mut acc = 0.0;
            for a in 0..8 {
                acc += ue[i][a] * el.grad[j][a];
            }
            h[i][j] = acc;
        }
    }
    // F = F0 + H = I + d (see `OnePointElement`).
    let mut d = h;
    for i in 0..3 {
        for j in 0..3 {
            d[i][j] += el.stretch_delta[i][j];
        }
    }
    let (e, mut s) = strain_and_stress(&h, &el.stretch_delta, el.lambda_vol, el.two_mu_vol);
    let mut energy = ElementEnergy::default();
    if ENERGY {
        let tr = e[0][0] + e[1][1] + e[2][2];
        let mut ee = 0.0;
        for i in 0..3 {
            for j in 0..3 {
                ee += e[i][j] * e[i][j];
            }
        }
        energy.strain_j = 0.5 * el.lambda_vol * tr * tr + 0.5 * el.two_mu_vol * ee;
        // Volume ratio det(F F0^-1).
        let identity_plus = |m: &[[f64; 3]; 3]| {
            let mut f = *m;
            for i in 0..3 {
                f[i][i] += 1.0;
            }
            f
        };
        energy.min_det_f = det3(&identity_plus(&d)) / det3(&identity_plus(&el.stretch_delta));
    }
    let mut ve = [[0.0; 8]; 3];
    let needs_velocity = opts.viscous_hourglass || opts.stiffness_damping_s > 0.0;
    if needs_velocity {
        for a in 0..8 {
            let d = v[el.nodes[a] as usize];
            ve[0][a] = d[0];
            ve[1][a] = d[1];
            ve[2][a] = d[2];
        }
    }
    if opts.stiffness_damping_s > 0.0 {
        // Rayleigh stiffness-proportional damping: S += beta C : Edot,
        // Edot = (Hdot^T F + F^T Hdot) / 2 = (Hdot + Hdot^T + Hdot^T d + d^T Hdot) / 2.
        let mut hd = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                let mut acc = 0.0;
                for a in 0..8 {
                    acc += ve[i][a] * el.grad[j][a];
                }
                hd[i][j] = acc;
            }
        }
        let mut ed = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                let mut cross = 0.0;
                for k in 0..3 {
                    cross += hd[k][i] * d[k][j] + d[k][i] * hd[k][j];
                }
                ed[i][j] = 0.5 * (hd[i][j] + hd[j][i] + cross);
            }
        }
        let beta = opts.stiffness_damping_s;
        let tr = ed[0][0] + ed[1][1] + ed[2][2];
        for i in 0..3 {
            for j in 0..3 {
                s[i][j] += beta * el.two_mu_vol * ed[i][j];
            }
            s[i][i] += beta * el.lambda_vol * tr;
        }
    }
    let p = first_piola(&d, &s);
    for a in 0..8 {
        for i in 0..3 {
            force[a][i] =
                p[i][0] * el.grad[0][a] + p[i][1] * el.grad[1][a] + p[i][2] * el.grad[2][a];
        }
    }
    // Hourglass: g_alpha,a = h_alpha,a - (hX_alpha . b_a) with hX_alpha = F0^-1 sum_b h_alpha,b
    // X_b (so that sum_a g_alpha,a X_a = 0: linear fields, rigid rotations included, give no
    // hourglass displacement); q_alpha = sum_a g_alpha,a w_a with w = u (stiffness form) or v
    // (viscous form).
    let mut hourglass_energy = 0.0;
    if opts.physical_hourglass {
        // Current element axes t_r = F t_r0 = t_r0 + d t_r0 (the reference axes carried by the
        // element's mean deformation), normalised.
        let mut axes = el.axes_ref;
        for (r, t0) in el.axes_ref.iter().enumerate() {
            for i in 0..3 {
                axes[r][i] += d[i][0] * t0[0] + d[i][1] * t0[1] + d[i][2] * t0[2];
            }
        }
        for t in axes.iter_mut() {
            let inv = 1.0 / (t[0] * t[0] + t[1] * t[1] + t[2] * t[2]).sqrt();
            t[0] *= inv;
            t[1] *= inv;
            t[2] *= inv;
        }
        for alpha in 0..4 {
            let hx = el.hourglass_ref[alpha];
            let base = &HOURGLASS_BASE[alpha];
            let mut g = [0.0; 8];
            for a in 0..8 {
                g[a] = base[a]
                    - (hx[0] * el.grad[0][a] + hx[1] * el.grad[1][a] + hx[2] * el.grad[2][a]);
            }
            let mut q = [0.0; 3];
            for i in 0..3 {
                let mut acc = 0.0;
                for a in 0..8 {
                    acc += g[a] * ue[i][a];
                }
                q[i] = acc;
            }
            // Generalised force sum_r C_r (q . t_r) t_r.
            let mut qt = [0.0; 3];
            for r in 0..3 {
                let t = axes[r];
                let p = q[0] * t[0] + q[1] * t[1] + q[2] * t[2];
                let c = el.hourglass_axis_coef[alpha][r] * p;
                if ENERGY {
                    hourglass_energy += 0.5 * c * p;
                }
                qt[0] += c * t[0];
                qt[1] += c * t[1];
                qt[2] += c * t[2];
            }
            for a in 0..8 {
                for i in 0..3 {
                    force[a][i] += g[a] * qt[i];
                }
            }
        }
        energy.hourglass_j = hourglass_energy;
        return energy;
    }
    let w = if opts.viscous_hourglass { &ve } else { &ue };
    let coef = el.hourglass_coef;
    for alpha in 0..4 {
        let hx = el.hourglass_ref[alpha];
        let base = &HOURGLASS_BASE[alpha];
        let mut g = [0.0; 8];
        for a in 0..8 {
            g[a] =
                base[a] - (hx[0] * el.grad[0][a] + hx[1] * el.grad[1][a] + hx[2] * el.grad[2][a]);
        }
        let mut q = [0.0; 3];
        for i in 0..3 {
            let mut acc = 0.0;
            for a in 0..8 {
                acc += g[a] * w[i][a];
            }
            q[i] = acc * coef;
        }
        if ENERGY && !opts.viscous_hourglass {
            hourglass_energy += 0.5 * (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]) / coef.max(1e-300);
        }
        for a in 0..8 {
            for i in 0..3 {
                force[a][i] += g[a] * q[i];
            }
        }
    }
    energy.hourglass_j = hourglass_energy;
    energy
}

/// Data of one fully integrated element (2x2x2 Gauss points).
#[derive(Clone, Debug)]
pub struct FullElement {
    /// Nodes.
    pub nodes: [u32; 8],
    /// `dN_a/dX` at each Gauss point.
    pub grad: [[[f64; 8]; 3]; 8],
    /// `det J` (weight 1) at each Gauss point (m^3).
    pub det: [f64; 8],
    /// Lame lambda (Pa).
    pub lambda_pa: f64,
    /// 2 mu (Pa).
    pub two_mu_pa: f64,
}

impl FullElement {
    /// Precompute from reference coordinates.
    pub fn new(nodes: [usize; 8], x: &[P3; 8], mat: &ElasticMaterial) -> Option<Self> {
        let mut grad = [[[0.0; 8]; 3]; 8];
        let mut det = [0.0; 8];
        for (g, p) in gauss_2x2x2().into_iter().enumerate() {
            let (b, d) = reference_gradients(x, p)?;
            grad[g] = b;
            det[g] = d;
        }
        Some(FullElement {
            nodes: nodes.map(|n| n as u32),
            grad,
            det,
            lambda_pa: mat.lambda_pa(),
            two_mu_pa: 2.0 * mat.mu_pa(),
        })
    }
    /// Reference volume (m^3).
    pub fn volume_m3(&self) -> f64 {
        self.det.iter().sum()
    }
}

/// Internal forces of a fully integrated element (no hourglass, no damping options).
pub fn full_forces<const ENERGY: bool>(
    el: &FullElement,
    u: &[[f64; 3]],
    beta_s: f64,
    v: &[[f64; 3]],
    force: &mut [[f64; 3]; 8],
) -> ElementEnergy {
    let mut ue = [[0.0; 8]; 3];
    let mut ve = [[0.0; 8]; 3];
    for a in 0..8 {
        let n = el.nodes[a] as usize;
        for i in 0..3 {
            ue[i][a] = u[n][i];
            ve[i][a] = v[n][i];
        }
    }
    *force = [[0.0; 3]; 8];
    let mut energy = ElementEnergy {
        min_det_f: f64::INFINITY,
        ..Default::default()
    };
    for g in 0..8 {
        let b = &el.grad[g];
        let w = el.det[g];
        let mut h = [[0.0; 3]; 3];
        let mut hd = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                let (mut acc, mut accd) = (0.0, 0.0);
                for a in 0..8 {
                    acc += ue[i][a] * b[j][a];
                    accd += ve[i][a] * b[j][a];
                }
                h[i][j] = acc;
                hd[i][j] = accd;
            }
        }
        let (e, mut s) = strain_and_stress(&h, &[[0.0; 3]; 3], el.lambda_pa * w, el.two_mu_pa * w);
        if beta_s > 0.0 {
            let mut ed = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    let mut cross = 0.0;
                    for k in 0..3 {
                        cross += hd[k][i] * h[k][j] + h[k][i] * hd[k][j];
                    }
                    ed[i][j] = 0.5 * (hd[i][j] + hd[j][i] + cross);
                }
            }
            let tr = ed[0][0] + ed[1][1] + ed[2][2];
            for i in 0..3 {
                for j in 0..3 {
                    s[i][j] += beta_s * el.two_mu_pa * w * ed[i][j];
                }
                s[i][i] += beta_s * el.lambda_pa * w * tr;
            }
        }
        if ENERGY {
            let tr = e[0][0] + e[1][1] + e[2][2];
            let ee: f64 = e.iter().flat_map(|r| r.iter()).map(|x| x * x).sum();
            energy.strain_j += w * (0.5 * el.lambda_pa * tr * tr + 0.5 * el.two_mu_pa * ee);
            let fmat = [
                [1.0 + h[0][0], h[0][1], h[0][2]],
                [h[1][0], 1.0 + h[1][1], h[1][2]],
                [h[2][0], h[2][1], 1.0 + h[2][2]],
            ];
            energy.min_det_f = energy.min_det_f.min(det3(&fmat));
        }
        let p = first_piola(&h, &s);
        for a in 0..8 {
            for i in 0..3 {
                force[a][i] += p[i][0] * b[0][a] + p[i][1] * b[1][a] + p[i][2] * b[2][a];
            }
        }
    }
    energy
}

#[cfg(test)]
mod tests {
    use super::*;

    const STEEL: ElasticMaterial = ElasticMaterial {
        density_kg_per_m3: 7850.0,
        youngs_modulus_pa: 210e9,
        poisson_ratio: 0.3,
    };

    fn distorted_hex() -> [P3; 8] {
        let mut x = NODE_NATURAL.map(|c| {
            [
                0.01 * (1.0 + c[0]),
                0.012 * (1.0 + c[1]),
                0.008 * (1.0 + c[2]),
            ]
        });
        x[6][0] += 0.003;
        x[2][2] -= 0.002;
        x[5][1] += 0.001;
        x
    }

    fn forces_of(u: &[[f64; 3]; 8], x: &[P3; 8]) -> ([[f64; 3]; 8], ElementEnergy) {
        forces_with(u, x, Hourglass::default())
    }

    fn forces_with(
        u: &[[f64; 3]; 8],
        x: &[P3; 8],
        hourglass: Hourglass,
    ) -> ([[f64; 3]; 8], ElementEnergy) {
        let el = OnePointElement::new([0, 1, 2, 3, 4, 5, 6, 7], x, &STEEL, hourglass).unwrap();
        let mut f = [[0.0; 3]; 8];
        let opts = KernelOptions {
            physical_hourglass: matches!(hourglass, Hourglass::Physical { .. }),
            ..Default::default()
        };
        let e = one_point_forces::<true>(&el, u, &[[0.0; 3]; 8], opts, &mut f);
        (f, e)
    }

    #[test]
    fn large_rigid_rotation_gives_no_force() {
        // Rotation of 40 degrees about an oblique axis plus a translation: E = 0 and q = 0.
        let x = distorted_hex();
        let (ax, ang) = ([0.3f64, 0.8, -0.5], 40f64.to_radians());
        let n = (ax[0] * ax[0] + ax[1] * ax[1] + ax[2] * ax[2]).sqrt();
        let k = [ax[0] / n, ax[1] / n, ax[2] / n];
        let (c, s) = (ang.cos(), ang.sin());
        let rot = |p: P3| -> P3 {
            let kd = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
            let kx = [
                k[1] * p[2] - k[2] * p[1],
                k[2] * p[0] - k[0] * p[2],
                k[0] * p[1] - k[1] * p[0],
            ];
            [0, 1, 2].map(|i| p[i] * c + kx[i] * s + k[i] * kd * (1.0 - c))
        };
        let u: [[f64; 3]; 8] = std::array::from_fn(|a| {
            let r = rot(x[a]);
            [r[0] - x[a][0] + 0.1, r[1] - x[a][1], r[2] - x[a][2] - 0.2]
        });
        let (f, e) = forces_of(&u, &x);
        let scale = STEEL.youngs_modulus_pa * 1e-4; // force of a unit strain on ~1 cm^2
        for fa in f {
            for c in fa {
                assert!(c.abs() < 1e-9 * scale, "{c}");
            }
        }
        assert!(
            e.strain_j.abs() < 1e-20 && e.hourglass_j.abs() < 1e-20,
            "{e:?}"
        );
        assert!((e.min_det_f - 1.0).abs() < 1e-12);
    }

    /// Central finite differences of W = strain + hourglass against the kernel's forces. The
    /// Flanagan-Belytschko stiffness form is exactly conservative (1e-5: the cubic/quartic terms
    /// and rounding of energies ~1e-2 J). The physical form turns its stiffness with the current
    /// element axes and neglects the axes' derivative, an O(strain) relative error of the
    /// hourglass force: 1e-3 here, with strains of 1e-3.
    #[test]
    fn forces_are_the_gradient_of_the_energy() {
        let x = distorted_hex();
        let u: [[f64; 3]; 8] = std::array::from_fn(|a| {
            [
                1e-5 * (a as f64).sin(),
                2e-5 * (a as f64 * 1.3).cos(),
                -1e-5 * (a as f64 * 0.7).sin(),
            ]
        });
        for (hourglass, tol) in [
            (Hourglass::Stiffness { kappa: 0.1 }, 1e-5),
            (Hourglass::default(), 1e-3),
        ] {
            let (f, _) = forces_with(&u, &x, hourglass);
            let h = 1e-9;
            for a in 0..8 {
                for i in 0..3 {
                    let mut up = u;
                    up[a][i] += h;
                    let mut dn = u;
                    dn[a][i] -= h;
                    let (_, ep) = forces_with(&up, &x, hourglass);
                    let (_, em) = forces_with(&dn, &x, hourglass);
                    let fd =
                        (ep.strain_j + ep.hourglass_j - em.strain_j - em.hourglass_j) / (2.0 * h);
                    let scale = f
                        .iter()
                        .flat_map(|r| r.iter())
                        .fold(0.0f64, |m, v| m.max(v.abs()));
                    assert!(
                        (fd - f[a][i]).abs() < tol * scale,
                        "{hourglass:?} {a} {i}: {fd} vs {}",
                        f[a][i]
                    );
                }
            }
        }
    }

    #[test]
    fn constant_strain_patch_matches_hookes_law() {
        // Uniaxial strain eps in x on the distorted element: internal forces must sum to zero
        // and the stress resultant equals sigma_xx = (lambda + 2 mu) eps on the x faces. For a
        // linear field the hourglass part is zero exactly.
        let x = distorted_hex();
        let eps = 1e-6;
        let u: [[f64; 3]; 8] = std::array::from_fn(|a| [eps * x[a][0], 0.0, 0.0]);
        let (f, e) = forces_of(&u, &x);
        let sum: [f64; 3] = [0, 1, 2].map(|i| f.iter().map(|fa| fa[i]).sum());
        let el = OnePointElement::new([0, 1, 2, 3, 4, 5, 6, 7], &x, &STEEL, Hourglass::default())
            .unwrap();
        let expected_energy =
            0.5 * (STEEL.lambda_pa() + 2.0 * STEEL.mu_pa()) * eps * eps * el.volume_m3;
        for s in sum {
            assert!(s.abs() < 1e-9);
        }
        assert!(e.hourglass_j < 1e-12 * expected_energy);
        // Green strain adds eps^2/2 relative: 1e-6.
        assert!((e.strain_j / expected_energy - 1.0).abs() < 1e-5);
    }

    #[test]
    fn full_and_one_point_agree_on_constant_strain() {
        let x = distorted_hex();
        let u: [[f64; 3]; 8] =
            std::array::from_fn(|a| [1e-6 * x[a][1], 2e-6 * x[a][2], -1e-6 * x[a][0]]);
        let (f1, e1) = forces_of(&u, &x);
        let full = FullElement::new([0, 1, 2, 3, 4, 5, 6, 7], &x, &STEEL).unwrap();
        let mut f2 = [[0.0; 3]; 8];
        let e2 = full_forces::<true>(&full, &u, 0.0, &[[0.0; 3]; 8], &mut f2);
        // Same linear field: the stresses agree. The one-point element's gradients, Lame
        // factors and F0 are single-precision numbers (relative rounding 6e-8 each), so its
        // energy may differ by a few 1e-7; 1e-6 bounds that with room, while a formulation
        // error (a wrong F0 term, say) would show at O(1).
        assert!(
            (e1.strain_j / e2.strain_j - 1.0).abs() < 1e-6,
            "{} {}",
            e1.strain_j,
            e2.strain_j
        );
        for a in 0..8 {
            for i in 0..3 {
                assert!((f1[a][i] - f2[a][i]).abs() < 1e-6 * f2[a][i].abs().max(1.0));
            }
        }
    }

    #[test]
    fn lumped_mass_sums_to_rho_v() {
        let x = distorted_hex();
        let m = lumped_masses(&x, 7850.0).unwrap();
        let v = FullElement::new([0, 1, 2, 3, 4, 5, 6, 7], &x, &STEEL)
            .unwrap()
            .volume_m3();
        assert!((m.iter().sum::<f64>() / (7850.0 * v) - 1.0).abs() < 1e-12);
        assert!(m.iter().all(|&mi| mi > 0.0));
    }
}
