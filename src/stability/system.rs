//! The coupled linear system of wheel, contact and rail, and its complex eigenvalues.
//!
//! Each body is a set of modal coordinates with unit modal mass (the wheel's mass-normalised
//! modes, the rail's fitted oscillators): `q_j'' + 2 zeta_j omega_j q_j' + omega_j^2 q_j = Q_j`,
//! plus optional skew (gyroscopic) terms between pairs of coordinates. The body's displacement
//! at the contact point is `u = sum_j phi_j q_j` (`phi_j`: the coordinate's `contact_shape`, in
//! the global axes x along the track, y lateral, z up). The contact joins the two bodies at that
//! point through a linearised law in the global axes,
//!
//! ```text
//! f_wheel = -K_c (u_w - u_r) - C_c (u_w' - u_r'),     f_rail = -f_wheel,
//! ```
//!
//! with `K_c`, `C_c` in general not symmetric (the friction force follows the normal force:
//! mode coupling; the creep force follows the slip velocity: damping, negative with falling
//! friction). With `B = [Phi_w, -Phi_r]` (3 x N) the generalised forces are `B^T f`, so
//!
//! ```text
//! q'' + (C + B^T C_c B) q' + (K + B^T K_c B) q = 0,
//! x' = A x,  A = [[0, I], [-K_t, -C_t]],  x = [q; q'],
//! ```
//!
//! (solved in the similar form with the state `[diag(omega_j) q; q']`, see
//! [`CoupledSystem::state_matrix`]),
//!
//! the first-order (state-space) form of the complex-eigenvalue analysis of friction-induced
//! vibration (Hoffmann, Fischer, Begout, Gaul 2002; Ding, Squicciarini, Thompson, Corradi
//! 2018, who apply it to curve squeal with wheel and rail receptances). The eigenvalues
//! `lambda = sigma + i omega_d` of the real matrix A come from faer's dense non-symmetric
//! eigen solver (Hessenberg reduction and shifted QR); `sigma > 0` is an unstable (growing)
//! vibration at `omega_d / 2 pi` Hz, with growth rate sigma (1/s) and damping ratio
//! `-sigma / |lambda|`.
//!
//! Participation: the eigenvector's coordinates `q_j` weighted by the energy they carry in the
//! eigen-motion, `|q_j|^2 (omega_j^2 + |lambda|^2) / 2` (strain plus kinetic energy of a unit-mass
//! coordinate), summed over the coordinates of one mode (a wheel mode's cos and sin companions)
//! and divided by the total: the shares sum to 1 over wheel and rail.

// Index loops mirror the matrix formulas term by term.
#![allow(clippy::needless_range_loop)]

use faer::Mat;
use serde::Serialize;

use crate::modal::mode::ModeFamily;
use crate::{Error, Result};

/// Which body a coordinate belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, PartialOrd, Ord, Hash)]
#[serde(rename_all = "lowercase")]
pub enum Body {
    /// The wheel (with its half axle).
    Wheel,
    /// The rail (track).
    Rail,
}

/// What a modal coordinate stands for: its body, the mode it is a coordinate of (a wheel mode of
/// harmonic n >= 1 has two, the cos and sin companions) and the mode's label.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct DofTag {
    /// Body.
    pub body: Body,
    /// Index of the mode within its body (companions share it).
    pub mode: usize,
    /// Human label, e.g. "(0,3) axial 1011 Hz" or "rail vertical 5".
    pub label: String,
    /// Wheel mode family (None for the rail).
    pub family: Option<ModeFamily>,
    /// Nodal circles, nodal diameters (wheel modes only).
    pub circles_diameters: Option<(u32, u32)>,
    /// Natural frequency of the uncoupled mode (Hz).
    pub frequency_hz: f64,
}

/// One modal coordinate (unit modal mass).
#[derive(Clone, Debug)]
pub struct ModalDof {
    /// Natural angular frequency (rad/s).
    pub omega_rad_per_s: f64,
    /// Viscous damping ratio zeta (loss factor / 2 at resonance).
    pub damping_ratio: f64,
    /// Displacement at the contact point per unit coordinate, global (x, y, z) (m).
    pub contact_shape: [f64; 3],
    /// What it is.
    pub tag: DofTag,
}

/// A skew (gyroscopic) coupling `q_i'' ... - g q_j'` and `q_j'' ... + g q_i'`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gyroscopic {
    /// First coordinate.
    pub i: usize,
    /// Second coordinate.
    pub j: usize,
    /// Coefficient g (rad/s).
    pub coefficient_rad_per_s: f64,
}

/// A body in modal coordinates.
#[derive(Clone, Debug, Default)]
pub struct ModalBody {
    /// Coordinates.
    pub dofs: Vec<ModalDof>,
    /// Skew couplings between coordinates of this body.
    pub gyroscopic: Vec<Gyroscopic>,
    /// Off-diagonal damping between coordinates of this body `(i, j, c)` (N s/m per unit
    /// coordinates; a symmetric matrix lists both orders): a body whose damping is not
    /// proportional to its modes (the rail's pads).
    pub damping_coupling: Vec<(usize, usize, f64)>,
}

impl ModalBody {
    /// Receptance at the contact point, `H(s) = sum_j phi_j phi_j^T / (s^2 + 2 zeta_j omega_j
    /// s + omega_j^2)` (3 x 3, m/N), for a real or complex `s`; gyroscopic terms and damping
    /// couplings are left out (used for bodies without them).
    pub fn receptance(&self, s: faer::c64) -> [[faer::c64; 3]; 3] {
        let mut h = [[faer::c64::new(0.0, 0.0); 3]; 3];
        for d in &self.dofs {
            let w = d.omega_rad_per_s;
            let den = s * s + s * (2.0 * d.damping_ratio * w) + w * w;
            let inv = faer::c64::new(1.0, 0.0) / den;
            for a in 0..3 {
                for b in 0..3 {
                    h[a][b] += inv * (d.contact_shape[a] * d.contact_shape[b]);
                }
            }
        }
        h
    }
}

/// The linearised contact in global axes: force on the wheel `-K (u_w - u_r) - C (u_w' - u_r')`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct LinearContact {
    /// Stiffness K_c (N/m), row = force component, column = relative displacement component.
    pub stiffness_n_per_m: [[f64; 3]; 3],
    /// Damping C_c (N s/m).
    pub damping_n_s_per_m: [[f64; 3]; 3],
}

/// The coupled system.
#[derive(Clone, Debug)]
pub struct CoupledSystem {
    /// The wheel.
    pub wheel: ModalBody,
    /// The rail (empty: rigid ground).
    pub rail: ModalBody,
    /// The contact between them.
    pub contact: LinearContact,
}

/// One body's share of an eigen-motion.
#[derive(Clone, Debug, Serialize)]
pub struct Participation {
    /// The mode (its first coordinate's tag).
    pub tag: DofTag,
    /// Energy share (0..1).
    pub share: f64,
}

/// One eigenvalue of the coupled system (of a conjugate pair, the one with omega_d > 0).
#[derive(Clone, Debug, Serialize)]
pub struct SystemEigen {
    /// Real part sigma (1/s): the growth rate, > 0 unstable.
    pub growth_rate_per_s: f64,
    /// Imaginary part omega_d (rad/s).
    pub omega_rad_per_s: f64,
    /// omega_d / 2 pi (Hz).
    pub frequency_hz: f64,
    /// Damping ratio -sigma / |lambda|.
    pub damping_ratio: f64,
    /// Modes by decreasing share (those above 1 %, at least the largest).
    pub participation: Vec<Participation>,
}

impl SystemEigen {
    /// The mode with the largest share.
    pub fn dominant(&self) -> &DofTag {
        &self.participation[0].tag
    }
    /// True when the vibration grows.
    pub fn unstable(&self) -> bool {
        self.growth_rate_per_s > 0.0
    }
}

/// Shares below this are not listed (they are still in the total).
const LISTED_SHARE: f64 = 0.01;

impl CoupledSystem {
    /// Number of second-order coordinates (wheel, then rail).
    pub fn len(&self) -> usize {
        self.wheel.dofs.len() + self.rail.dofs.len()
    }

    /// True when neither body has a coordinate.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn tags(&self) -> impl Iterator<Item = &ModalDof> {
        self.wheel.dofs.iter().chain(self.rail.dofs.iter())
    }

    /// Total damping and stiffness matrices (N x N) of the coupled coordinates.
    pub fn matrices(&self) -> (Mat<f64>, Mat<f64>) {
        let nw = self.wheel.dofs.len();
        let n = self.len();
        let mut k = Mat::<f64>::zeros(n, n);
        let mut c = Mat::<f64>::zeros(n, n);
        // B (3 x n): u_w - u_r = B q.
        let b: Vec<[f64; 3]> = self
            .wheel
            .dofs
            .iter()
            .map(|d| d.contact_shape)
            .chain(self.rail.dofs.iter().map(|d| d.contact_shape.map(|v| -v)))
            .collect();
        for (j, d) in self.tags().enumerate() {
            k[(j, j)] = d.omega_rad_per_s * d.omega_rad_per_s;
            c[(j, j)] = 2.0 * d.damping_ratio * d.omega_rad_per_s;
        }
        for (body, offset) in [(&self.wheel, 0), (&self.rail, nw)] {
            for g in &body.gyroscopic {
                c[(offset + g.i, offset + g.j)] -= g.coefficient_rad_per_s;
                c[(offset + g.j, offset + g.i)] += g.coefficient_rad_per_s;
            }
            for &(i, j, d) in &body.damping_coupling {
                c[(offset + i, offset + j)] += d;
            }
        }
        // B^T K_c B and B^T C_c B: first K_c B (3 x n), then the outer product with B.
        let kb: Vec<[f64; 3]> = b
            .iter()
            .map(|bj| mat3_vec(&self.contact.stiffness_n_per_m, bj))
            .collect();
        let cb: Vec<[f64; 3]> = b
            .iter()
            .map(|bj| mat3_vec(&self.contact.damping_n_s_per_m, bj))
            .collect();
        for i in 0..n {
            let bi = b[i];
            if bi == [0.0; 3] {
                continue;
            }
            for j in 0..n {
                k[(i, j)] += dot3(&bi, &kb[j]);
                c[(i, j)] += dot3(&bi, &cb[j]);
            }
        }
        (c, k)
    }

    /// Scale of each coordinate in the state vector: its own natural frequency (1 where that is
    /// zero).
    fn state_scale(&self) -> Vec<f64> {
        self.tags()
            .map(|d| {
                if d.omega_rad_per_s > 0.0 {
                    d.omega_rad_per_s
                } else {
                    1.0
                }
            })
            .collect()
    }

    /// The state matrix (2N x 2N) for the state `[S q; q']`, `S = diag(omega_j)`:
    /// `A = [[0, S], [-K_t S^-1, -C_t]]`, similar to `[[0, I], [-K_t, -C_t]]` (same eigenvalues).
    /// Why scaled: the uncoupled blocks become `[[0, w], [-w, 0]]` (normal matrices), so the
    /// eigenvalues keep their accuracy eps |A| when the frequencies span three decades; without
    /// it an undamped mode at w has condition number about w / 2 and the QR's error grows with
    /// it (measured on the frictionless case-3 system: 7e-6 relative unscaled, 1e-14 scaled).
    pub fn state_matrix(&self) -> Mat<f64> {
        let n = self.len();
        let (c, k) = self.matrices();
        let s = self.state_scale();
        let mut a = Mat::<f64>::zeros(2 * n, 2 * n);
        for i in 0..n {
            a[(i, n + i)] = s[i];
            for j in 0..n {
                a[(n + i, j)] = -k[(i, j)] / s[j];
                a[(n + i, n + j)] = -c[(i, j)];
            }
        }
        a
    }

    /// The complex eigenvalues with omega_d > 0 (one of each conjugate pair) and the real ones
    /// with sigma > 0 (divergence), sorted by frequency, each with its participating modes.
    pub fn eigen(&self) -> Result<Vec<SystemEigen>> {
        let n = self.len();
        if n == 0 {
            return Ok(Vec::new());
        }
        let a = self.state_matrix();
        let evd = a
            .eigen()
            .map_err(|e| Error::Numerical(format!("stability: eigen solver failed: {e:?}")))?;
        let (u, s) = (evd.U(), evd.S());
        let tags: Vec<&ModalDof> = self.tags().collect();
        let scale = self.state_scale();
        let mut out = Vec::new();
        for m in 0..2 * n {
            let lambda = s.column_vector()[m];
            let (sigma, omega) = (lambda.re, lambda.im);
            let magnitude = lambda.norm();
            // A conjugate pair is kept once; a real eigenvalue (overdamped coordinate) only
            // when it grows. The 1e-9 relative threshold is far above rounding (1e-15) and far
            // below any damped frequency of interest.
            let oscillating = omega > 1e-9 * magnitude.max(1.0);
            if !(oscillating || (omega.abs() <= 1e-9 * magnitude.max(1.0) && sigma > 0.0)) {
                continue;
            }
            // q_j = (S q)_j / s_j.
            let participation = participation(
                &tags,
                |j| u[(j, m)].norm_sqr() / (scale[j] * scale[j]),
                magnitude,
            );
            out.push(SystemEigen {
                growth_rate_per_s: sigma,
                omega_rad_per_s: omega.max(0.0),
                frequency_hz: omega.max(0.0) / std::f64::consts::TAU,
                damping_ratio: if magnitude > 0.0 {
                    -sigma / magnitude
                } else {
                    0.0
                },
                participation,
            });
        }
        out.sort_by(|a, b| a.omega_rad_per_s.total_cmp(&b.omega_rad_per_s));
        Ok(out)
    }

    /// The eigenvalues only (both of each conjugate pair), cheaper than [`CoupledSystem::eigen`].
    pub fn eigenvalues(&self) -> Result<Vec<faer::c64>> {
        if self.is_empty() {
            return Ok(Vec::new());
        }
        self.state_matrix()
            .eigenvalues()
            .map_err(|e| Error::Numerical(format!("stability: eigen solver failed: {e:?}")))
    }
}

/// Energy shares per mode from the squared magnitudes of the eigenvector's displacement part.
fn participation(
    dofs: &[&ModalDof],
    magnitude2: impl Fn(usize) -> f64,
    lambda_abs: f64,
) -> Vec<Participation> {
    let mut by_mode: Vec<(DofTag, f64)> = Vec::new();
    let mut total = 0.0;
    for (j, d) in dofs.iter().enumerate() {
        let w = d.omega_rad_per_s;
        let e = magnitude2(j) * (w * w + lambda_abs * lambda_abs);
        total += e;
        match by_mode
            .iter_mut()
            .find(|(t, _)| t.body == d.tag.body && t.mode == d.tag.mode)
        {
            Some(entry) => entry.1 += e,
            None => by_mode.push((d.tag.clone(), e)),
        }
    }
    let total = total.max(f64::MIN_POSITIVE);
    by_mode.sort_by(|a, b| b.1.total_cmp(&a.1));
    let mut out: Vec<Participation> = by_mode
        .into_iter()
        .map(|(tag, e)| Participation {
            tag,
            share: e / total,
        })
        .collect();
    let keep = out
        .iter()
        .position(|p| p.share < LISTED_SHARE)
        .unwrap_or(out.len())
        .max(1);
    out.truncate(keep);
    out
}

/// 3 x 3 matrix times vector.
pub fn mat3_vec(m: &[[f64; 3]; 3], v: &[f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2])
}

/// Dot product of 3-vectors.
pub fn dot3(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
