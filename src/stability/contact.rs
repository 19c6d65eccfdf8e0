//! The wheel-rail contact linearised at an operating point.
//!
//! Contact frame (global components): `t1 = (1, 0, 0)` along the track, `t2 = (0, cos d,
//! sin d)` lateral in the contact plane, `n = (0, -sin d, cos d)` the rail's outward normal,
//! with the contact angle d positive when the normal leans towards the track centre (-y), as
//! `kalker::profiles::rail_contact_angle_deg` and the rolling run's instruments define it.
//! `d = u_w - u_r` is the wheel's displacement at the contact relative to the rail's.
//!
//! * Normal: Hertz, `N ~ delta^(3/2)` (approach delta), so `dN/d delta = 3 N / (2 delta)`
//!   (Johnson, Contact Mechanics, 1985, eq. 4.23/4.39; the approach from
//!   [`crate::kalker::HertzContact`]): `delta N = -k_H d_n`.
//! * Tangential: the creep force on the wheel `F(xi, eta, N, mu)` (Kalker's convention,
//!   `crate::kalker`: creepage = slip velocity of the wheel over the rail divided by the
//!   rolling speed V, force opposing it). Perturbed by the contact motion,
//!   `delta xi = d_t1' / V`, `delta eta = d_t2' / V`, the normal force, and the friction
//!   coefficient where it falls with the slip speed `v = V |gamma|`:
//!
//!   ```text
//!   delta F = D_gamma d_t' / V + D_N delta N + D_mu mu'(v) s^T d_t',
//!   ```
//!
//!   `D_gamma = dF/d(xi, eta)`, `D_N = dF/dN`, `D_mu = dF/dmu` at the operating point,
//!   `s = gamma / |gamma|` the slip direction, `mu' = dmu/dv` (s/m) the falling-friction
//!   slope. The `D_N` term is the mode-coupling mechanism (the friction force follows the
//!   normal force: a non-symmetric stiffness; Hoffmann et al. 2002, Chiello et al. 2006,
//!   Ding et al. 2018), the last term the falling-friction (negative slope) mechanism (Heckl &
//!   Abrahams 2000; Ding et al. 2018), and `D_gamma / V` the creep damping.
//!
//! Two tangential laws give the derivatives:
//! * Kalker: central differences of the creep forces of [`crate::kalker::RollingSolver`]
//!   (exact half-space theory or FASTSIM) on the Hertz ellipse at the operating point;
//! * Coulomb (full sliding): `F = -mu N s`, so `D_gamma = -mu N (I - s s^T) / |gamma|`,
//!   `D_N = -mu s`, `D_mu = -N s` (the saturated limit of Kalker's law).
//!
//! Left out: the spin creepage's perturbation (the contact's rotations are not in the modal
//! models), the rotation of the steady creep force with the contact plane (a geometric
//! stiffness of order F / R), contact damping and the patch's transient (the creep forces are
//! steady-state: quasi-static in the contact).

// Index loops mirror the matrix formulas term by term.
#![allow(clippy::needless_range_loop)]

use serde::Serialize;

use super::system::LinearContact;
use crate::kalker::{Creepages, HertzContact, Method, RollingSolver};
use crate::material::Material;
use crate::{Error, Result};

/// The contact frame: unit vectors `[t1, t2, n]` in global components.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ContactFrame {
    /// `[t1, t2, n]`.
    pub axes: [[f64; 3]; 3],
}

impl ContactFrame {
    /// The wheel-rail frame at contact angle `angle_deg` (positive: the normal leans to -y).
    pub fn wheel_rail(angle_deg: f64) -> ContactFrame {
        let (s, c) = angle_deg.to_radians().sin_cos();
        ContactFrame {
            axes: [[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]],
        }
    }
}

/// The linearised tangential and normal law in the contact frame.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TangentialLaw {
    /// Normal force N (N).
    pub normal_force_n: f64,
    /// Hertz normal stiffness k_H (N/m).
    pub normal_stiffness_n_per_m: f64,
    /// Rolling speed V (m/s): creepage = slip velocity / V.
    pub speed_m_per_s: f64,
    /// Operating creepages (xi, eta).
    pub creepage: [f64; 2],
    /// Operating creep forces (Fx, Fy) on the wheel (N).
    pub force_n: [f64; 2],
    /// Friction coefficient at the operating point.
    pub mu: f64,
    /// dF/d(xi, eta) (N per unit creepage), `[row = force component][column = creepage]`.
    pub d_force_d_creepage_n: [[f64; 2]; 2],
    /// dF/dN (-).
    pub d_force_d_normal: [f64; 2],
    /// dF/dmu (N).
    pub d_force_d_mu_n: [f64; 2],
    /// Falling-friction slope dmu/dv (s/m), <= 0 for falling friction.
    pub friction_slope_s_per_m: f64,
}

impl TangentialLaw {
    /// Full sliding with Coulomb friction at creepage `creepage` (non-zero): `F = -mu N s`,
    /// `D_gamma = -mu N (I - s s^T) / |gamma|`, `D_N = -mu s`, `D_mu = -N s`; the falling-
    /// friction slope is zero (set `friction_slope_s_per_m` to add one).
    pub fn coulomb(
        normal_force_n: f64,
        normal_stiffness_n_per_m: f64,
        speed_m_per_s: f64,
        creepage: [f64; 2],
        mu: f64,
    ) -> Result<TangentialLaw> {
        let gamma = creepage[0].hypot(creepage[1]);
        if !(gamma.is_finite() && gamma > 0.0) {
            return Err(Error::input(
                "operating point",
                "xi/eta",
                "the Coulomb (full sliding) law needs a non-zero creepage to give the slip direction",
            ));
        }
        let s = [creepage[0] / gamma, creepage[1] / gamma];
        let f = mu * normal_force_n / gamma;
        Ok(TangentialLaw {
            normal_force_n,
            normal_stiffness_n_per_m,
            speed_m_per_s,
            creepage,
            force_n: [-mu * normal_force_n * s[0], -mu * normal_force_n * s[1]],
            mu,
            d_force_d_creepage_n: std::array::from_fn(|i| {
                std::array::from_fn(|j| -f * ((i == j) as u8 as f64 - s[i] * s[j]))
            }),
            d_force_d_normal: [-mu * s[0], -mu * s[1]],
            d_force_d_mu_n: [-normal_force_n * s[0], -normal_force_n * s[1]],
            friction_slope_s_per_m: 0.0,
        })
    }

    /// Creep force over the traction bound, `|F| / (mu N)`.
    pub fn creep_over_bound(&self) -> f64 {
        self.force_n[0].hypot(self.force_n[1]) / (self.mu * self.normal_force_n)
    }

    /// The slip direction `gamma / |gamma|` (zero without creepage).
    pub fn slip_direction(&self) -> [f64; 2] {
        let g = self.creepage[0].hypot(self.creepage[1]);
        if g > 0.0 {
            [self.creepage[0] / g, self.creepage[1] / g]
        } else {
            [0.0, 0.0]
        }
    }

    /// The contact law in global axes for `frame`.
    pub fn linear_contact(&self, frame: &ContactFrame) -> LinearContact {
        // Local (t1, t2, n) matrices; see the module docs for each term.
        let mut k = [[0.0; 3]; 3];
        let mut c = [[0.0; 3]; 3];
        let kh = self.normal_stiffness_n_per_m;
        k[2][2] = kh;
        let s = self.slip_direction();
        for i in 0..2 {
            k[i][2] = self.d_force_d_normal[i] * kh;
            for j in 0..2 {
                c[i][j] = -self.d_force_d_creepage_n[i][j] / self.speed_m_per_s
                    - self.d_force_d_mu_n[i] * self.friction_slope_s_per_m * s[j];
            }
        }
        LinearContact {
            stiffness_n_per_m: rotate(&k, frame),
            damping_n_s_per_m: rotate(&c, frame),
        }
    }
}

/// `R M R^T` with `R = [t1 t2 n]` as columns: a local-frame matrix in global axes.
fn rotate(m: &[[f64; 3]; 3], frame: &ContactFrame) -> [[f64; 3]; 3] {
    let r = |g: usize, l: usize| frame.axes[l][g];
    std::array::from_fn(|a| {
        std::array::from_fn(|b| {
            let mut sum = 0.0;
            for i in 0..3 {
                for j in 0..3 {
                    sum += r(a, i) * m[i][j] * r(b, j);
                }
            }
            sum
        })
    })
}

/// Which tangential law gives the derivatives.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum TangentialModel {
    /// Kalker's theory by `method` on `elements` x `elements` elements (points).
    Kalker {
        /// Exact half-space or FASTSIM.
        method: Method,
        /// Elements (points) per axis.
        elements: usize,
    },
    /// Saturated Coulomb friction (full sliding).
    Coulomb,
    /// No friction: the normal spring alone (mu = 0).
    Frictionless,
}

/// The contact at an operating point: what the linearisation needs.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ContactState {
    /// Normal force (N).
    pub normal_force_n: f64,
    /// Creepages (spin included; it shifts the operating forces but is not perturbed).
    pub creepages: Creepages,
    /// Friction coefficient at the operating slip speed.
    pub mu: f64,
    /// dmu/dv (s/m).
    pub friction_slope_s_per_m: f64,
    /// Rolling speed (m/s).
    pub speed_m_per_s: f64,
    /// Gap curvature along x (1/m).
    pub curvature_x_per_m: f64,
    /// Gap curvature along y (1/m).
    pub curvature_y_per_m: f64,
    /// Elastic constants of wheel and rail.
    pub material: Material,
}

/// Hertz patch and normal stiffness `3 N / (2 delta)` of a state.
pub fn hertz(state: &ContactState) -> Result<(HertzContact, f64)> {
    let h = HertzContact::from_curvatures(
        state.curvature_x_per_m,
        state.curvature_y_per_m,
        state.normal_force_n,
        state.material,
    )?;
    let k = 1.5 * state.normal_force_n / h.approach_m;
    Ok((h, k))
}

/// Creep forces (Fx, Fy) on the wheel for the state with its normal force, friction and
/// creepages replaced.
pub fn creep_forces(
    state: &ContactState,
    model: TangentialModel,
    normal_force_n: f64,
    mu: f64,
    creepages: &Creepages,
) -> Result<[f64; 2]> {
    match model {
        TangentialModel::Frictionless => Ok([0.0, 0.0]),
        TangentialModel::Coulomb => {
            let g = creepages.xi.hypot(creepages.eta);
            if g == 0.0 {
                return Ok([0.0, 0.0]);
            }
            Ok([
                -mu * normal_force_n * creepages.xi / g,
                -mu * normal_force_n * creepages.eta / g,
            ])
        }
        TangentialModel::Kalker { method, elements } => {
            let h = HertzContact::from_curvatures(
                state.curvature_x_per_m,
                state.curvature_y_per_m,
                normal_force_n,
                state.material,
            )?;
            let solver = RollingSolver::new(&h, mu, method, elements)?;
            let (fx, fy) = solver.forces(creepages)?;
            Ok([fx, fy])
        }
    }
}

/// Relative step of the normal force and of mu in the central differences. Why 1 %: the
/// creep force is smooth in both (the patch grows as N^(1/3)), so the O(h^2) truncation is
/// 1e-4 relative, while the exact solver's discretisation (elements switching between
/// adhesion and slip) makes smaller steps noisy.
const RELATIVE_STEP: f64 = 0.01;

/// Creepage step as a fraction of the saturation creepage `mu N / (G c^2 C11)`: 2 %, for the
/// same reason (truncation 4e-4 relative on a curve that bends over that scale).
const CREEPAGE_STEP: f64 = 0.02;

/// Linearise the contact at `state` with `model`.
pub fn linearise(state: &ContactState, model: TangentialModel) -> Result<TangentialLaw> {
    check_state(state)?;
    let (h, kh) = hertz(state)?;
    let n = state.normal_force_n;
    let mu = state.mu;
    let cr = state.creepages;
    let model = if mu == 0.0 {
        TangentialModel::Frictionless
    } else {
        model
    };
    let base = creep_forces(state, model, n, mu, &cr)?;
    let (d_gamma, d_normal, d_mu) = match model {
        TangentialModel::Frictionless => ([[0.0; 2]; 2], [0.0; 2], [0.0; 2]),
        TangentialModel::Coulomb => {
            let law = TangentialLaw::coulomb(n, kh, state.speed_m_per_s, [cr.xi, cr.eta], mu)?;
            (
                law.d_force_d_creepage_n,
                law.d_force_d_normal,
                law.d_force_d_mu_n,
            )
        }
        TangentialModel::Kalker { method, elements } => {
            let solver = RollingSolver::new(&h, mu, method, elements)?;
            let c11 = crate::kalker::kalker_creep_coefficients(
                (h.semi_axis_a_m / h.semi_axis_b_m).clamp(0.2, 5.0),
                state.material.poisson_ratio,
            )?
            .c11;
            let saturation = mu * n
                / (state.material.shear_modulus_pa() * h.semi_axis_a_m * h.semi_axis_b_m * c11);
            let step = CREEPAGE_STEP * saturation;
            let at = |dxi: f64, deta: f64| -> Result<[f64; 2]> {
                let (fx, fy) = solver.forces(&Creepages {
                    xi: cr.xi + dxi,
                    eta: cr.eta + deta,
                    phi_per_m: cr.phi_per_m,
                })?;
                Ok([fx, fy])
            };
            let (px, mx, py, my) = (
                at(step, 0.0)?,
                at(-step, 0.0)?,
                at(0.0, step)?,
                at(0.0, -step)?,
            );
            let d = std::array::from_fn(|i| {
                [
                    (px[i] - mx[i]) / (2.0 * step),
                    (py[i] - my[i]) / (2.0 * step),
                ]
            });
            let dn = RELATIVE_STEP * n;
            let (np, nm) = (
                creep_forces(state, model, n + dn, mu, &cr)?,
                creep_forces(state, model, n - dn, mu, &cr)?,
            );
            let dm = RELATIVE_STEP * mu;
            let (mp, mm) = (
                creep_forces(state, model, n, mu + dm, &cr)?,
                creep_forces(state, model, n, mu - dm, &cr)?,
            );
            (
                d,
                std::array::from_fn(|i| (np[i] - nm[i]) / (2.0 * dn)),
                std::array::from_fn(|i| (mp[i] - mm[i]) / (2.0 * dm)),
            )
        }
    };
    Ok(TangentialLaw {
        normal_force_n: n,
        normal_stiffness_n_per_m: kh,
        speed_m_per_s: state.speed_m_per_s,
        creepage: [cr.xi, cr.eta],
        force_n: base,
        mu,
        d_force_d_creepage_n: d_gamma,
        d_force_d_normal: d_normal,
        d_force_d_mu_n: d_mu,
        friction_slope_s_per_m: state.friction_slope_s_per_m,
    })
}

/// The state's ranges: Fn > 0, 0 <= mu <= 2, V > 0, finite creepages and slope.
pub fn check_state(state: &ContactState) -> Result<()> {
    let src = "operating point";
    if !(state.normal_force_n.is_finite() && state.normal_force_n > 0.0) {
        return Err(Error::input(
            src,
            "normal_force_n",
            format!(
                "must be > 0 N (the wheel must press on the rail), got {}",
                state.normal_force_n
            ),
        ));
    }
    if !(state.mu.is_finite() && state.mu >= 0.0 && state.mu <= 2.0) {
        return Err(Error::input(
            src,
            "mu",
            format!("must be in [0, 2] (0: frictionless), got {}", state.mu),
        ));
    }
    if !(state.speed_m_per_s.is_finite() && state.speed_m_per_s > 0.0) {
        return Err(Error::input(
            src,
            "speed_m_per_s",
            format!("must be > 0 m/s, got {}", state.speed_m_per_s),
        ));
    }
    for (v, f) in [
        (state.creepages.xi, "xi"),
        (state.creepages.eta, "eta"),
        (state.creepages.phi_per_m, "phi_per_m"),
        (state.friction_slope_s_per_m, "friction_slope_s_per_m"),
    ] {
        if !v.is_finite() {
            return Err(Error::input(src, f, format!("must be finite, got {v}")));
        }
    }
    Ok(())
}
