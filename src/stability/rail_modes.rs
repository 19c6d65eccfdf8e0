//! The rail's point receptance as a modal model that the state-space system can use: the
//! undamped modes of the beam model ([`super::rail`]) up to a truncation frequency, each a
//! unit-mass coordinate with its participation at the contact and a modal damping ratio, plus
//! one stiff term for the static flexibility of the modes left out,
//!
//! ```text
//! H(w) ~ sum_k phi_k^2 / (w_k^2 - w^2 + 2 i zeta_k w_k w) + r w_r^2 / (w_r^2 - w^2 + ...),
//! r = H(0) - sum_k phi_k^2 / w_k^2
//! ```
//!
//! (modal superposition with a residual flexibility: Craig & Kurdila, Fundamentals of
//! Structural Dynamics, 2006, ch. 11). The modes solve `K x = w^2 M x` with x mass-normalised
//! (`M = L L^T`, the symmetric `L^-1 K L^-T` by faer's self-adjoint eigen solver). The pads'
//! damping is not proportional, so the modal damping matrix `D = X^T C X` is kept whole: its
//! diagonal gives each mode's damping ratio `D_kk / (2 w_k)`, its off-diagonal terms couple the
//! modes (the formula above shows the diagonal only; [`RailModalModel::receptance`] solves the
//! coupled modal equations). `D` is positive semi-definite and the stiffness and mass are
//! those of the beam, so the model is passive: it cannot make the coupled system unstable by
//! itself. Its error against the direct frequency-response solve of the same beam model, which
//! keeps every mode, is measured (tests/stability_rail.rs, docs/stability.md).

// Index loops mirror the matrix formulas term by term.
#![allow(clippy::needless_range_loop)]

use faer::{c64, Mat, Side};
use serde::Serialize;

use super::rail::{BeamModel, Direction, SectionPoint, Track};
use crate::{Error, Result};

/// One modal term at the contact.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RailMode {
    /// Natural angular frequency (rad/s).
    pub omega_rad_per_s: f64,
    /// Modal damping ratio.
    pub damping_ratio: f64,
    /// Mass-normalised displacement at the contact (m per unit coordinate, 1/sqrt(kg)).
    pub participation: f64,
    /// Mass-normalised twist at the contact station (rad per unit coordinate; lateral modes,
    /// zero otherwise and for the lumped residual terms).
    pub twist: f64,
    /// Mass-normalised longitudinal motion of the crown from vertical bending (m per unit
    /// coordinate; vertical modes, zero otherwise and for the lumped residual terms).
    pub crown_axial: f64,
}

impl RailMode {
    /// The term's receptance at angular frequency w.
    pub fn receptance(&self, w: f64) -> c64 {
        let wk = self.omega_rad_per_s;
        c64::new(self.participation * self.participation, 0.0)
            / c64::new(wk * wk - w * w, 2.0 * self.damping_ratio * wk * w)
    }
}

/// The modal model of one direction.
#[derive(Clone, Debug, Serialize)]
pub struct RailModalModel {
    /// Direction.
    pub direction: Direction,
    /// Modes below the truncation frequency, then the residual term (last).
    pub modes: Vec<RailMode>,
    /// Off-diagonal modal damping `(k, l, D_kl)`, k != l, both orders listed (N s/m per unit
    /// coordinates).
    pub damping_coupling: Vec<(usize, usize, f64)>,
    /// Truncation frequency (Hz).
    pub truncation_hz: f64,
    /// Static flexibility at the contact (m/N), from a direct solve.
    pub static_flexibility_m_per_n: f64,
}

impl RailModalModel {
    /// Receptance at f (Hz): `phi^T (W^2 - w^2 I + i w D)^-1 phi` with the coupled damping.
    pub fn receptance(&self, f_hz: f64) -> c64 {
        use faer::linalg::solvers::Solve;
        let w = std::f64::consts::TAU * f_hz;
        let n = self.modes.len();
        let mut a = Mat::<c64>::from_fn(n, n, |i, j| {
            if i == j {
                let m = &self.modes[i];
                let wk = m.omega_rad_per_s;
                c64::new(wk * wk - w * w, 2.0 * m.damping_ratio * wk * w)
            } else {
                c64::new(0.0, 0.0)
            }
        });
        for &(i, j, d) in &self.damping_coupling {
            a[(i, j)] += c64::new(0.0, w * d);
        }
        let phi = Mat::<c64>::from_fn(n, 1, |i, _| c64::new(self.modes[i].participation, 0.0));
        let q = a.partial_piv_lu().solve(&phi);
        (0..n).fold(c64::new(0.0, 0.0), |s, i| {
            s + q[(i, 0)] * self.modes[i].participation
        })
    }
}

/// The modal model of `track` in `direction` at `x_contact_m`, modes up to `truncation_hz`.
pub fn rail_modal_model(
    track: &Track,
    direction: Direction,
    x_contact_m: f64,
    truncation_hz: f64,
) -> Result<RailModalModel> {
    let model = track.beam_model(direction, x_contact_m)?;
    modal_model(&model, direction, truncation_hz)
}

/// The undamped modes of `K x = w^2 M x`: the eigenvalues `w^2` and the mass-normalised modes
/// as columns (`M = L L^T`, the symmetric `S = L^-1 K L^-T` by two triangular solves, its
/// eigenvectors `y`, then `x = L^-T y`).
fn mass_normalised_modes(k: &Mat<f64>, m: &Mat<f64>) -> Result<(Vec<f64>, Mat<f64>)> {
    let llt = m.llt(Side::Lower).map_err(|e| {
        Error::Numerical(format!(
            "rail modes: mass matrix not positive definite: {e:?}"
        ))
    })?;
    let l = llt.L().to_owned();
    // S = L^-1 K L^-T by two triangular solves (K symmetric).
    let mut s = k.clone();
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(
        l.as_ref(),
        s.as_mut(),
        faer::Par::Seq,
    );
    let mut st = s.transpose().to_owned();
    faer::linalg::triangular_solve::solve_lower_triangular_in_place(
        l.as_ref(),
        st.as_mut(),
        faer::Par::Seq,
    );
    let evd = st
        .self_adjoint_eigen(Side::Lower)
        .map_err(|e| Error::Numerical(format!("rail modes: eigen solver failed: {e:?}")))?;
    // x = L^-T y: mass-normalised modes.
    let mut x = evd.U().to_owned();
    faer::linalg::triangular_solve::solve_upper_triangular_in_place(
        l.transpose(),
        x.as_mut(),
        faer::Par::Seq,
    );
    let values = evd.S().column_vector().iter().copied().collect();
    Ok((values, x))
}

/// The modal model of an assembled beam model.
pub fn modal_model(
    model: &BeamModel,
    direction: Direction,
    truncation_hz: f64,
) -> Result<RailModalModel> {
    let n = model.dofs;
    let mut k = Mat::<f64>::zeros(n, n);
    let mut m = Mat::<f64>::zeros(n, n);
    let mut c = Mat::<f64>::zeros(n, n);
    for &(i, j, mv, cv, kv) in &model.entries {
        m[(i, j)] += mv;
        c[(i, j)] += cv;
        k[(i, j)] += kv;
    }
    let (values, x) = mass_normalised_modes(&k, &m)?;
    let w_max = std::f64::consts::TAU * truncation_hz;
    let kept: Vec<usize> = (0..n)
        .filter(|&q| values[q] > 0.0 && values[q] <= w_max * w_max)
        .collect();
    // D = X^T C X over the kept modes, C from its (sparse) entries.
    let damped: Vec<(usize, usize, f64)> = model
        .entries
        .iter()
        .filter(|e| e.3 != 0.0)
        .map(|e| (e.0, e.1, e.3))
        .collect();
    let d = Mat::<f64>::from_fn(kept.len(), kept.len(), |a, b| {
        let (qa, qb) = (kept[a], kept[b]);
        damped
            .iter()
            .map(|&(i, j, cv)| x[(i, qa)] * cv * x[(j, qb)])
            .sum()
    });
    let mut modes = Vec::new();
    for (a, &q) in kept.iter().enumerate() {
        let w2 = values[q];
        let w = w2.sqrt();
        let phi = model.at(SectionPoint::Crown, |d| x[(d, q)]);
        modes.push(RailMode {
            omega_rad_per_s: w,
            damping_ratio: (d[(a, a)] / (2.0 * w)).max(0.0),
            participation: phi,
            twist: model.twist.iter().map(|&(dof, wt)| wt * x[(dof, q)]).sum(),
            crown_axial: model
                .crown_axial
                .iter()
                .map(|&(dof, wt)| wt * x[(dof, q)])
                .sum(),
        });
    }
    let mut damping_coupling = Vec::new();
    for a in 0..kept.len() {
        for b in 0..kept.len() {
            if a != b && d[(a, b)] != 0.0 {
                damping_coupling.push((a, b, d[(a, b)]));
            }
        }
    }
    // The modes above the truncation, lumped by octave. The contact point moves by the main
    // participation and, in the lateral and vertical models, by a second component (the twist,
    // the crown's longitudinal motion from bending); the bin's flexibility of the pair,
    // `B = sum v v^T / w^2` with `v = (main, second)`, is kept exactly by one term per
    // eigenvector of B at the bin's frequency `w_b^2 = sum main^2 / sum (main^2 / w^2)`: a
    // term `sqrt(lambda) w_b e` has `v v^T / w_b^2 = lambda e e^T`. With no second component it
    // is one term of residue `sum main^2`. The last bin takes everything from 4 truncations up.
    let second = |q: usize| -> f64 {
        let of = |w: &[(usize, f64)]| w.iter().map(|&(d, wt)| wt * x[(d, q)]).sum::<f64>();
        of(&model.twist) + of(&model.crown_axial)
    };
    // Per bin: sum main^2, sum main^2 / w^2, damping weight, and B (3 entries).
    let mut bins: Vec<[f64; 6]> = vec![[0.0; 6]; 3];
    for q in 0..n {
        let w2 = values[q];
        if w2 <= w_max * w_max {
            continue;
        }
        let octave = ((w2.sqrt() / w_max).log2().floor() as usize).min(2);
        let phi = model.at(SectionPoint::Crown, |d| x[(d, q)]);
        let extra = second(q);
        let bin = &mut bins[octave];
        bin[0] += phi * phi;
        bin[1] += phi * phi / w2;
        // Damping-ratio weight by flexibility share.
        let mut cx = 0.0;
        for &(i, j, cv) in &damped {
            cx += x[(i, q)] * cv * x[(j, q)];
        }
        bin[2] += phi * phi / w2 * (cx / (2.0 * w2.sqrt())).max(0.0);
        bin[3] += phi * phi / w2;
        bin[4] += phi * extra / w2;
        bin[5] += extra * extra / w2;
    }
    let is_lateral = direction == Direction::Lateral;
    for bin in bins {
        if !(bin[0] > 0.0 && bin[1] > 0.0) {
            continue;
        }
        let wb = (bin[0] / bin[1]).sqrt();
        let damping_ratio = bin[2] / bin[1];
        // Eigenpairs of the symmetric 2 x 2 B.
        let (a, b, c) = (bin[3], bin[4], bin[5]);
        let mean = 0.5 * (a + c);
        let radius = (0.25 * (a - c) * (a - c) + b * b).sqrt();
        for lambda in [mean + radius, mean - radius] {
            if lambda <= 1e-12 * (a + c) || lambda.is_nan() {
                continue;
            }
            // Eigenvector (b, lambda - a) or (lambda - c, b), whichever is better conditioned.
            let (e0, e1) = if (lambda - a).abs() + b.abs() >= (lambda - c).abs() + b.abs() {
                (b, lambda - a)
            } else {
                (lambda - c, b)
            };
            let norm = e0.hypot(e1);
            let (e0, e1) = if norm > 0.0 {
                (e0 / norm, e1 / norm)
            } else {
                (1.0, 0.0)
            };
            let scale = lambda.sqrt() * wb;
            modes.push(RailMode {
                omega_rad_per_s: wb,
                damping_ratio,
                participation: scale * e0,
                twist: if is_lateral { scale * e1 } else { 0.0 },
                crown_axial: if is_lateral { 0.0 } else { scale * e1 },
            });
        }
    }
    let static_flexibility = model.receptance(&[0.0])?[0].re;
    Ok(RailModalModel {
        direction,
        modes,
        damping_coupling,
        truncation_hz,
        static_flexibility_m_per_n: static_flexibility,
    })
}

/// Largest and rms relative error `|H_modal - H| / |H|` of `model` against direct solves `h` at
/// `frequencies_hz`.
pub fn relative_error(model: &RailModalModel, frequencies_hz: &[f64], h: &[c64]) -> (f64, f64) {
    let mut max = 0.0f64;
    let mut sum = 0.0;
    for (&f, hi) in frequencies_hz.iter().zip(h) {
        let e = (model.receptance(f) - hi).norm() / hi.norm().max(f64::MIN_POSITIVE);
        max = max.max(e);
        sum += e * e;
    }
    (max, (sum / h.len().max(1) as f64).sqrt())
}

/// The rail as one modal body at the contact, in track axes. The beams' directions are the
/// rail's own, inclined 1:40 towards the track centre: a displacement `(v', w')` along the
/// rail's lateral and vertical axes is `(v' c - w' s, v' s + w' c)` in track axes (the
/// section's placement, [`crate::mesh::track::place_rail_point`]). A lateral-torsional mode
/// moves the crown by `v'` (its participation) and, at `contact_offset_m` off the rail's centre
/// line, vertically by `y' phi` (its twist); a vertical mode moves the crown along the rail
/// by `-d_C theta` (its bending rotation, the crown `d_C` above the centroid). So the body
/// carries the cross receptances: vertical-lateral through the inclination and the offset,
/// longitudinal-vertical through the crown's height (the lumped residual terms carry neither).
/// Longitudinal terms move the contact along x.
pub fn rail_body(models: &[RailModalModel], contact_offset_m: f64) -> super::system::ModalBody {
    use super::system::{Body, DofTag, ModalBody, ModalDof};
    let (sin, cos) = crate::geometry::rail54e1::INCLINATION_RAD.sin_cos();
    let mut body = ModalBody::default();
    for model in models {
        let offset = body.dofs.len();
        for m in &model.modes {
            let index = body.dofs.len();
            let (lateral, vertical) = match model.direction {
                Direction::Lateral => (m.participation, contact_offset_m * m.twist),
                Direction::Vertical => (0.0, m.participation),
                Direction::Longitudinal => (0.0, 0.0),
            };
            let shape = if model.direction == Direction::Longitudinal {
                [m.participation, 0.0, 0.0]
            } else {
                [
                    m.crown_axial,
                    lateral * cos - vertical * sin,
                    lateral * sin + vertical * cos,
                ]
            };
            let f = m.omega_rad_per_s / std::f64::consts::TAU;
            body.dofs.push(ModalDof {
                omega_rad_per_s: m.omega_rad_per_s,
                damping_ratio: m.damping_ratio,
                contact_shape: shape,
                tag: DofTag {
                    body: Body::Rail,
                    mode: index,
                    label: format!("rail {} {:.0} Hz", model.direction.name(), f),
                    family: None,
                    circles_diameters: None,
                    frequency_hz: f,
                },
            });
        }
        body.damping_coupling.extend(
            model
                .damping_coupling
                .iter()
                .map(|&(i, j, d)| (offset + i, offset + j, d)),
        );
    }
    body
}
