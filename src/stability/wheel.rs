//! The wheel as a modal model at the contact point, from the axisymmetric solver.
//!
//! The axisymmetric solver ([`crate::modal::axisym`]) gives each mode of harmonic n as section fields
//! `(U_r, U_t, U_z)` with `u_r = U_r cos(n theta)`, `u_theta = U_t sin(n theta)`, `u_z = U_z
//! cos(n theta)`, normalised so that `x^T M_n x = 1`, where `M_n` carries the circumferential
//! integral (2 pi for n = 0, pi for n >= 1): the 3D mode is then mass-normalised
//! ([`modal_mass`] checks this by quadrature). A mode of harmonic n >= 1 stands for two 3D
//! modes, the one above and its companion with cos and sin exchanged (`u_r = U_r sin(n theta)`,
//! `u_theta = -U_t cos(n theta)`, `u_z = U_z sin(n theta)`). With the contact at theta = 0 (the
//! bottom of the wheel), the first moves the contact point radially and axially, the second
//! circumferentially; both become modal coordinates. Axes at the contact: radial outward = -z,
//! circumferential = +x (the rolling direction), the wheel axis (section z, the profile
//! coordinate S) = +y (towards the field side).
//!
//! The shape at the contact is interpolated with the Q9 shape functions at the contact point
//! on the tread, `(r, z) = (R + F(S), S)` (S1002: [`crate::geometry::s1002::height_mm`]), so the
//! contact's lateral offset from the web (de Beer, Janssens, Kooijman 2003: it couples axial and
//! radial motion) is in the shapes themselves.
//!
//! Damping: a modal loss factor per group, viscous ratio `zeta = eta / 2`. Defaults (inputs):
//! 1e-4 for modes with n >= 2 nodal diameters (the undamped steel wheel's zero-nodal-circle
//! axial modes are of this order: Thompson, Railway Noise and Vibration, 2009, ch. 5; DATA.md
//! section 8), 1e-3 for n = 0 and n = 1 (they move the hub and axle, whose joints and bearings
//! add damping), 1e-2 for the axle family.
//!
//! Rotation (optional): seen from the fixed contact point, a wheel spinning at Omega turns each
//! n-diameter pair into waves at `omega +- n Omega` (Thompson 2009, ch. 5; the kinematics of the
//! rotating frame, Coriolis and centrifugal stiffening in the wheel left out). In the fixed
//! frame the pair's equations are `q_c'' - 2 n Omega q_s' + (omega^2 - n^2 Omega^2) q_c = Q_c`,
//! `q_s'' + 2 n Omega q_c' + (omega^2 - n^2 Omega^2) q_s = Q_s`, whose free eigenvalues are
//! `i (omega +- n Omega)` exactly.

// Index loops mirror the matrix formulas term by term.
#![allow(clippy::needless_range_loop)]

use serde::{Deserialize, Serialize};

use super::system::{Body, DofTag, Gyroscopic, ModalBody, ModalDof};
use crate::geometry::s1002;
use crate::input::wheel::WheelSpec;
use crate::modal::axisym::{
    self, element, AxisymMode, AxisymModel, AxisymOptions, WheelClamp, WheelModelOptions,
};
use crate::modal::mode::ModeFamily;
use crate::{Error, Result};

/// The largest fmax the wheel model is solved to (Hz): the band in which the axisymmetric
/// solver's labels are unique (docs/modal.md lists repeats only above 5 kHz, and the residual
/// check holds to 10 kHz).
pub const MAX_FMAX_HZ: f64 = 10_000.0;

/// Harmonics solved: 0..=MAX_HARMONIC. The default wheel's lowest n = 20 mode lies far above
/// 10 kHz (n = 12 is already above 8 kHz).
pub const MAX_HARMONIC: u32 = 20;

/// Modal loss factors by group (zeta = eta / 2).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelDamping {
    /// Modes with two or more nodal diameters (wheel families).
    pub loss_factor_n2_plus: f64,
    /// Modes with one nodal diameter.
    pub loss_factor_n1: f64,
    /// Modes with no nodal diameter.
    pub loss_factor_n0: f64,
    /// Axle-family modes.
    pub loss_factor_axle: f64,
}

impl Default for WheelDamping {
    fn default() -> Self {
        WheelDamping {
            loss_factor_n2_plus: 1e-4,
            loss_factor_n1: 1e-3,
            loss_factor_n0: 1e-3,
            loss_factor_axle: 1e-2,
        }
    }
}

impl WheelDamping {
    /// The loss factor of a mode.
    pub fn loss_factor(&self, mode: &AxisymMode) -> f64 {
        if mode.family == ModeFamily::Axle {
            self.loss_factor_axle
        } else {
            match mode.harmonic {
                0 => self.loss_factor_n0,
                1 => self.loss_factor_n1,
                _ => self.loss_factor_n2_plus,
            }
        }
    }

    /// Every loss factor must lie in [0, 1).
    pub fn check(&self, source: &str) -> Result<()> {
        for (v, f) in [
            (self.loss_factor_n2_plus, "loss_factor_n2_plus"),
            (self.loss_factor_n1, "loss_factor_n1"),
            (self.loss_factor_n0, "loss_factor_n0"),
            (self.loss_factor_axle, "loss_factor_axle"),
        ] {
            if !(v.is_finite() && (0.0..1.0).contains(&v)) {
                return Err(Error::input(
                    source,
                    f,
                    format!("must be in [0, 1), got {v}"),
                ));
            }
        }
        Ok(())
    }
}

/// The wheel's modes (axle ends clamped, as the rolling model holds them) with its model.
#[derive(Clone, Debug)]
pub struct WheelModes {
    /// The section model.
    pub model: AxisymModel,
    /// Modes below `fmax_hz`, by frequency.
    pub modes: Vec<AxisymMode>,
    /// The band solved (Hz).
    pub fmax_hz: f64,
    /// Nominal (tape-circle) radius (m).
    pub nominal_radius_m: f64,
    /// Mass of wheel and half axle (kg).
    pub mass_kg: f64,
    /// Wall time of the modal solve (s).
    pub solve_seconds: f64,
}

impl WheelModes {
    /// Solve the wheel of `spec` (with its half axle, both axle ends clamped) up to `fmax_hz`.
    pub fn solve(spec: &WheelSpec, fmax_hz: f64) -> Result<WheelModes> {
        check_fmax(fmax_hz, "--fmax-hz")?;
        Self::solve_band(spec, fmax_hz)
    }

    /// [`WheelModes::solve`] without the check of fmax against [`MAX_FMAX_HZ`]: for the
    /// benchmark, which needs more modes than the labelled band holds and only times them.
    pub fn solve_band(spec: &WheelSpec, fmax_hz: f64) -> Result<WheelModes> {
        let model = AxisymModel::from_wheel(
            spec,
            WheelModelOptions {
                without_axle: false,
                clamp: WheelClamp::AxleEnds,
            },
        )?;
        let opts = AxisymOptions {
            harmonics: (0..=MAX_HARMONIC).collect(),
            fmax_hz,
        };
        let result = axisym::solve(&model, &opts)?;
        let mass_kg = section_mass_kg(&model);
        Ok(WheelModes {
            modes: result.modes.into_iter().filter(|m| !m.is_rigid()).collect(),
            model,
            fmax_hz,
            nominal_radius_m: spec.nominal_radius_mm * 1e-3,
            mass_kg,
            solve_seconds: result.seconds,
        })
    }

    /// The section point of the tread at profile coordinate `s_mm`: `(r, z)` (m).
    pub fn tread_point(&self, s_mm: f64) -> [f64; 2] {
        [
            self.nominal_radius_m + s1002::height_mm(s_mm) * 1e-3,
            s_mm * 1e-3,
        ]
    }

    /// The modal body at the contact point `contact_s_mm` (profile coordinate S), modes up to
    /// `fmax_hz` (at most the solved band), damped by `damping`, optionally spinning at
    /// `spin_rad_per_s` (first-order splitting of the n-diameter pairs).
    pub fn contact_body(
        &self,
        contact_s_mm: f64,
        fmax_hz: f64,
        damping: &WheelDamping,
        spin_rad_per_s: Option<f64>,
    ) -> Result<ModalBody> {
        if !(fmax_hz.is_finite() && fmax_hz > 0.0 && fmax_hz <= self.fmax_hz * (1.0 + 1e-12)) {
            return Err(Error::input(
                "command line",
                "--fmax-hz",
                format!(
                    "must be in (0, {}] Hz, the band of the wheel's modal model, got {fmax_hz}",
                    self.fmax_hz
                ),
            ));
        }
        if !(contact_s_mm.is_finite() && (-30.0..=60.0).contains(&contact_s_mm)) {
            return Err(Error::input(
                "operating point",
                "contact_s_mm",
                format!("the contact must lie on the tread, S in [-30, 60] mm, got {contact_s_mm}"),
            ));
        }
        damping.check("wheel damping")?;
        let p = self.tread_point(contact_s_mm);
        let at = ShapeSampler::new(&self.model, p)?;
        let mut body = ModalBody::default();
        for (index, mode) in self
            .modes
            .iter()
            .filter(|m| m.frequency_hz <= fmax_hz)
            .enumerate()
        {
            let [ur, ut, uz] = at.sample(&mode.shape);
            let omega = std::f64::consts::TAU * mode.frequency_hz;
            let zeta = 0.5 * damping.loss_factor(mode);
            let tag = DofTag {
                body: Body::Wheel,
                mode: index,
                label: format!(
                    "({},{}) {} {:.0} Hz",
                    mode.nodal_circles,
                    mode.nodal_diameters,
                    family_name(mode.family),
                    mode.frequency_hz
                ),
                family: Some(mode.family),
                circles_diameters: Some((mode.nodal_circles, mode.nodal_diameters)),
                frequency_hz: mode.frequency_hz,
            };
            let n = mode.harmonic as f64;
            let split = spin_rad_per_s.filter(|_| mode.harmonic >= 1).map(|s| n * s);
            // omega^2 - n^2 Omega^2 keeps the split frequencies at omega +- n Omega exactly.
            let omega_eff = match split {
                Some(w) => (omega * omega - w * w).max(0.0).sqrt(),
                None => omega,
            };
            // Damping ratio on the effective frequency so that 2 zeta omega stays as given.
            let zeta_eff = if omega_eff > 0.0 {
                zeta * omega / omega_eff
            } else {
                zeta
            };
            if mode.harmonic == 0 {
                body.dofs.push(ModalDof {
                    omega_rad_per_s: omega_eff,
                    damping_ratio: zeta_eff,
                    contact_shape: [ut, uz, -ur],
                    tag,
                });
            } else {
                let first = body.dofs.len();
                body.dofs.push(ModalDof {
                    omega_rad_per_s: omega_eff,
                    damping_ratio: zeta_eff,
                    contact_shape: [0.0, uz, -ur],
                    tag: tag.clone(),
                });
                body.dofs.push(ModalDof {
                    omega_rad_per_s: omega_eff,
                    damping_ratio: zeta_eff,
                    contact_shape: [-ut, 0.0, 0.0],
                    tag,
                });
                if let Some(w) = split {
                    body.gyroscopic.push(Gyroscopic {
                        i: first,
                        j: first + 1,
                        coefficient_rad_per_s: 2.0 * w,
                    });
                }
            }
        }
        Ok(body)
    }
}

/// Lower-case family name.
pub fn family_name(f: ModeFamily) -> &'static str {
    match f {
        ModeFamily::Axial => "axial",
        ModeFamily::Radial => "radial",
        ModeFamily::Circumferential => "circumferential",
        ModeFamily::Axle => "axle",
        ModeFamily::Rigid => "rigid",
    }
}

/// fmax must lie in (0, MAX_FMAX_HZ].
pub fn check_fmax(fmax_hz: f64, field: &str) -> Result<()> {
    if fmax_hz.is_finite() && fmax_hz > 0.0 && fmax_hz <= MAX_FMAX_HZ {
        Ok(())
    } else {
        Err(Error::input(
            "command line",
            field,
            format!(
                "must be in (0, {MAX_FMAX_HZ}] Hz (the band of the wheel's modal model), got {fmax_hz}"
            ),
        ))
    }
}

/// Interpolates section fields at one point of the section (Q9 shape functions).
pub struct ShapeSampler {
    element: [usize; 9],
    weights: [f64; 9],
}

impl ShapeSampler {
    /// The element holding `point` (r, z) and its shape-function values there. A point just
    /// outside the mesh (the tread is meshed with straight element edges between profile
    /// points, so a profile point may lie a few um outside) is taken at the nearest point of
    /// the nearest element, if within 0.5 mm.
    pub fn new(model: &AxisymModel, point: [f64; 2]) -> Result<ShapeSampler> {
        let mesh = &model.mesh;
        let mut best: Option<(f64, usize, [f64; 2])> = None;
        for (e, conn) in mesh.elements.iter().enumerate() {
            let xy: [[f64; 2]; 9] = std::array::from_fn(|k| mesh.nodes[conn[k]]);
            let (lo, hi) = bounding_box(&xy);
            let margin = 1e-3;
            if point[0] < lo[0] - margin
                || point[0] > hi[0] + margin
                || point[1] < lo[1] - margin
                || point[1] > hi[1] + margin
            {
                continue;
            }
            let (xi, dist) = inverse_map(&xy, point);
            if best.is_none_or(|b| dist < b.0) {
                best = Some((dist, e, xi));
            }
        }
        let (dist, e, xi) = best.ok_or_else(|| {
            Error::input(
                "operating point",
                "contact_s_mm",
                format!(
                    "the point (r, z) = ({:.4}, {:.4}) m is not on the wheel section",
                    point[0], point[1]
                ),
            )
        })?;
        // 0.5 mm: far above the tread's faceting (sagitta of a 10 mm chord on the R >= 100 mm
        // profile arcs: 0.1 mm), far below the element size.
        if dist > 5e-4 {
            return Err(Error::input(
                "operating point",
                "contact_s_mm",
                format!(
                    "the tread point lies {:.2} mm from the wheel section mesh",
                    dist * 1e3
                ),
            ));
        }
        let (n, _) = element::shape(xi[0], xi[1]);
        Ok(ShapeSampler {
            element: mesh.elements[e],
            weights: n,
        })
    }

    /// The field `(U_r, U_t, U_z)` at the point.
    pub fn sample(&self, field: &[[f64; 3]]) -> [f64; 3] {
        let mut out = [0.0; 3];
        for (k, &node) in self.element.iter().enumerate() {
            for c in 0..3 {
                out[c] += self.weights[k] * field[node][c];
            }
        }
        out
    }
}

fn bounding_box(xy: &[[f64; 2]; 9]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in xy {
        for c in 0..2 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    (lo, hi)
}

/// Parent coordinates of the point of the element nearest `point` (clamped Newton iteration)
/// and the distance to it (m).
fn inverse_map(xy: &[[f64; 2]; 9], point: [f64; 2]) -> ([f64; 2], f64) {
    let map = |xi: [f64; 2]| {
        let (n, dn) = element::shape(xi[0], xi[1]);
        let mut x = [0.0; 2];
        let mut j = [[0.0; 2]; 2];
        for k in 0..9 {
            for a in 0..2 {
                x[a] += n[k] * xy[k][a];
                j[a][0] += dn[k][0] * xy[k][a];
                j[a][1] += dn[k][1] * xy[k][a];
            }
        }
        (x, j)
    };
    let mut xi = [0.0, 0.0];
    // 30 steps: Newton converges in 3-5 on the mildly curved section elements; the clamp to
    // the parent square makes it a projected iteration for points outside.
    for _ in 0..30 {
        let (x, j) = map(xi);
        let r = [point[0] - x[0], point[1] - x[1]];
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        if det.abs() < f64::MIN_POSITIVE {
            break;
        }
        let d = [
            (j[1][1] * r[0] - j[0][1] * r[1]) / det,
            (-j[1][0] * r[0] + j[0][0] * r[1]) / det,
        ];
        xi = [
            (xi[0] + d[0]).clamp(-1.0, 1.0),
            (xi[1] + d[1]).clamp(-1.0, 1.0),
        ];
        if d[0].abs() + d[1].abs() < 1e-13 {
            break;
        }
    }
    let (x, _) = map(xi);
    (xi, (x[0] - point[0]).hypot(x[1] - point[1]))
}

/// Gauss-Legendre 3-point rule (as the element uses).
const GAUSS3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// `sum over elements of int f(r, z, N) r dA` by 3 x 3 Gauss points.
fn integrate(model: &AxisymModel, f: impl Fn(usize, &[f64; 9]) -> f64) -> f64 {
    let mut total = 0.0;
    for (e, conn) in model.mesh.elements.iter().enumerate() {
        let xy: [[f64; 2]; 9] = std::array::from_fn(|k| model.mesh.nodes[conn[k]]);
        for &(a, wa) in &GAUSS3 {
            for &(b, wb) in &GAUSS3 {
                let (n, dn) = element::shape(a, b);
                let mut r = 0.0;
                let mut j = [[0.0; 2]; 2];
                for k in 0..9 {
                    r += n[k] * xy[k][0];
                    for c in 0..2 {
                        j[c][0] += dn[k][0] * xy[k][c];
                        j[c][1] += dn[k][1] * xy[k][c];
                    }
                }
                let det = (j[0][0] * j[1][1] - j[0][1] * j[1][0]).abs();
                total += wa * wb * det * r * f(e, &n);
            }
        }
    }
    total
}

/// Mass of the body of revolution, `2 pi rho int r dA` (kg).
pub fn section_mass_kg(model: &AxisymModel) -> f64 {
    std::f64::consts::TAU * model.material.density_kg_per_m3 * integrate(model, |_, _| 1.0)
}

/// The 3D modal mass of a mode, `c_n rho int (U_r^2 + U_t^2 + U_z^2) r dA` with `c_n = 2 pi`
/// (n = 0) or pi (n >= 1): 1 for a mass-normalised mode.
pub fn modal_mass(model: &AxisymModel, mode: &AxisymMode) -> f64 {
    let c_n = if mode.harmonic == 0 {
        std::f64::consts::TAU
    } else {
        std::f64::consts::PI
    };
    let rho = model.material.density_kg_per_m3;
    c_n * rho
        * integrate(model, |e, n| {
            let conn = &model.mesh.elements[e];
            let mut u = [0.0; 3];
            for k in 0..9 {
                for c in 0..3 {
                    u[c] += n[k] * mode.shape[conn[k]][c];
                }
            }
            u[0] * u[0] + u[1] * u[1] + u[2] * u[2]
        })
}
