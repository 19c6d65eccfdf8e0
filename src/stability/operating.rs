//! The operating point: normal force, creepages, friction, and where the contact sits, from a
//! rolling case file or from a run directory at a time.
//!
//! * From a case (`data/cases/case*.json`): the static wheel load (sprung mass and the
//!   wheel with its half axle, times g), the contact point of S1002 on 54E1 at 1:40 for the
//!   wheel's tape-circle position ([`crate::kalker::profiles::s1002_on_54e1`]: contact point,
//!   Hertz curvatures; contact angle from the rail's slope there), the spin `-sin(d) / R`,
//!   the longitudinal creep force `T / R` of the driving torque (the forward guide holds the
//!   speed, so the torque is carried by the rail: docs/operating-point.md), a lateral creepage
//!   given by the user (default 0.18 %, the calibrated case 3 at 17.58 ms; signed as the
//!   case's lateral motion: the wheel sliding towards the field side has eta > 0), and the
//!   longitudinal creepage that gives `T / R` with it (Kalker's exact theory, bisection).
//! * From a run directory and a time: the contact forces of `contact_forces.csv` (normal
//!   force, the friction parts), the contact's wheel S, rail y and angle there (linear
//!   between samples), the wheel's position along the rail from `histories.csv`, and the
//!   creepages that Kalker's exact theory returns for those forces (as CONTACT does with the
//!   FE forces: Yang & Li 2019; `squeal kalker compare`), with the Hertz curvatures of the
//!   profiles at the run's contact point.
//!
//! Friction: the case's law. Falling friction `mu(v) = mu_d + (mu_s - mu_d) exp(-c v)` is taken
//! at the rigid slip speed `v = V sqrt(xi^2 + eta^2)` (the creepages depend on mu, so the two
//! are iterated to a fixed point) with the slope `dmu/dv = -c (mu_s - mu_d) exp(-c v)`.

use std::path::Path;

use serde::Serialize;

use super::contact::ContactState;
use crate::friction::FrictionLaw;
use crate::kalker::profiles;
use crate::kalker::{solve_force_prescribed, Creepages, HertzContact, Method, RollingSolver};
use crate::material::Material;
use crate::model::case::{LateralMotion, LoadedCase};
use crate::table::{interpolate, Table};
use crate::{Error, Result};

/// Standard gravity (m/s^2), as the rolling model's preload uses it.
pub const GRAVITY_M_PER_S2: f64 = 9.81;

/// Default lateral creepage of a case-file operating point: 0.18 % (case 3 at 17.58 ms,
/// docs/operating-point.md).
pub const DEFAULT_ETA: f64 = 0.0018;

/// Elements per axis of the exact Kalker solutions that find the creepages (30: the creep
/// force within 0.5 % of the 60 x 60 solution on the reference contact, at a tenth of its cost).
pub const KALKER_ELEMENTS: usize = 30;

/// An operating point.
#[derive(Clone, Debug, Serialize)]
pub struct OperatingPoint {
    /// Where it came from.
    pub origin: String,
    /// Rolling speed (m/s).
    pub speed_m_per_s: f64,
    /// Normal force (N).
    pub normal_force_n: f64,
    /// Creepages (xi, eta, spin).
    pub creepages: Creepages,
    /// Creep forces (Fx, Fy) on the wheel (N).
    pub creep_force_n: [f64; 2],
    /// Friction coefficient at the operating slip speed.
    pub mu: f64,
    /// Falling-friction slope dmu/dv (s/m).
    pub friction_slope_s_per_m: f64,
    /// Contact angle (degrees, positive: the normal leans towards the track centre).
    pub contact_angle_deg: f64,
    /// Contact point on the wheel: profile coordinate S (mm).
    pub contact_s_mm: f64,
    /// Contact point on the rail: lateral position (m).
    pub contact_rail_y_m: f64,
    /// Rolling radius at the contact (m).
    pub rolling_radius_m: f64,
    /// Hertz gap curvatures (1/m) along x and y.
    pub curvature_per_m: [f64; 2],
    /// The wheel's position along the rail (m).
    pub wheel_x_m: f64,
    /// What Kalker's force-prescribed solution said ("unique", or saturated).
    pub kalker_note: String,
}

impl OperatingPoint {
    /// The contact state the linearisation needs.
    pub fn contact_state(&self, material: Material) -> ContactState {
        ContactState {
            normal_force_n: self.normal_force_n,
            creepages: self.creepages,
            mu: self.mu,
            friction_slope_s_per_m: self.friction_slope_s_per_m,
            speed_m_per_s: self.speed_m_per_s,
            curvature_x_per_m: self.curvature_per_m[0],
            curvature_y_per_m: self.curvature_per_m[1],
            material,
        }
    }
}

/// Friction coefficient and slope dmu/dv of a law at slip speed v.
pub fn friction_at(law: &FrictionLaw, slip_speed_m_per_s: f64) -> (f64, f64) {
    let v = slip_speed_m_per_s.abs();
    match *law {
        FrictionLaw::Coulomb { mu } => (mu, 0.0),
        FrictionLaw::Falling {
            mu_static,
            mu_dynamic,
            decay_s_per_m,
        } => (
            law.mu(v),
            -decay_s_per_m * (mu_static - mu_dynamic) * (-decay_s_per_m * v).exp(),
        ),
    }
}

/// Contact geometry of the profiles: (contact rail y, wheel S (mm), angle (deg), curvatures).
fn profile_geometry(wheel_y_m: f64, radius_m: f64) -> Result<(f64, f64, f64, [f64; 2])> {
    let c = profiles::s1002_on_54e1(wheel_y_m, radius_m)?;
    let angle = profiles::rail_contact_angle_deg(c.contact_y_m).ok_or_else(|| {
        Error::input(
            "operating point",
            "wheel_position.tape_circle_y_mm",
            "the contact lies beyond the rail head",
        )
    })?;
    Ok((
        c.contact_y_m,
        c.contact_s_mm,
        angle,
        [c.curvature_x_per_m, c.curvature_y_per_m],
    ))
}

/// The operating point of a case file with lateral creepage `eta` (None: [`DEFAULT_ETA`] with
/// the sign of the case's lateral motion); `wheel_mass_kg` is the wheel with its half axle.
pub fn from_case(
    loaded: &LoadedCase,
    wheel_mass_kg: f64,
    nominal_radius_m: f64,
    eta: Option<f64>,
    material: Material,
) -> Result<OperatingPoint> {
    let case = &loaded.case;
    let source = loaded.source.display().to_string();
    let wheel_y_m = loaded.scenario.scenario.wheel_position.tape_circle_y_mm * 1e-3;
    let (rail_y, s_mm, angle, curvature) = profile_geometry(wheel_y_m, nominal_radius_m)?;
    let radius = nominal_radius_m + crate::geometry::s1002::height_mm(s_mm) * 1e-3;
    let normal_force_n = (case.sprung_mass_kg + wheel_mass_kg) * GRAVITY_M_PER_S2;
    let speed = case.speed_km_per_h / 3.6;
    let fx_target = case.torque.max_n_m / radius;
    let sign = match &case.lateral_motion {
        Some(LateralMotion::Ramp(r)) if r.velocity_m_per_s < 0.0 => -1.0,
        _ => 1.0,
    };
    // A yawed wheelset slides sideways at sin(psi) (towards the field side for psi > 0).
    let eta = eta.unwrap_or(match case.curving {
        Some(c) => c.angle_of_attack_rad().sin(),
        None => sign * DEFAULT_ETA,
    });
    let phi = -angle.to_radians().sin() / radius;
    let hertz =
        HertzContact::from_curvatures(curvature[0], curvature[1], normal_force_n, material)?;
    // Friction and creepage to a fixed point (one pass for Coulomb friction).
    let (mut mu, mut slope) = friction_at(&case.friction, 0.0);
    let mut xi = 0.0;
    let mut forces = [0.0; 2];
    for _ in 0..50 {
        let solver = RollingSolver::new(&hertz, mu, Method::Exact, KALKER_ELEMENTS)?;
        let (x, f) = longitudinal_creepage(&solver, fx_target, eta, phi, &source)?;
        xi = x;
        forces = f;
        let (m, s) = friction_at(&case.friction, speed * xi.hypot(eta));
        let converged = (m - mu).abs() <= 1e-9;
        (mu, slope) = (m, s);
        if converged {
            break;
        }
    }
    Ok(OperatingPoint {
        origin: format!("case file {source} (eta {:.3} %)", 100.0 * eta),
        speed_m_per_s: speed,
        normal_force_n,
        creepages: Creepages {
            xi,
            eta,
            phi_per_m: phi,
        },
        creep_force_n: forces,
        mu,
        friction_slope_s_per_m: slope,
        contact_angle_deg: angle,
        contact_s_mm: s_mm,
        contact_rail_y_m: rail_y,
        rolling_radius_m: radius,
        curvature_per_m: curvature,
        wheel_x_m: loaded.scenario.scenario.wheel_position.x_m,
        kalker_note: "longitudinal creepage for F_x = T / R at the given eta".into(),
    })
}

/// Where the contact of a run sample sits: wheel S (mm), rail y (m), contact angle (deg), the
/// profiles' Hertz curvatures there, and a note when they are the rigid profiles' (a run
/// without the contact position columns).
#[allow(clippy::type_complexity)]
fn sample_geometry(
    loaded: &LoadedCase,
    sample: &RunSample,
    nominal_radius_m: f64,
) -> Result<(f64, f64, f64, [f64; 2], &'static str)> {
    Ok(match sample.contact {
        Some((s_mm, rail_y, angle)) => {
            // Curvatures of the profiles at the run's contact point (the wheel's tape circle
            // then at rail y - S); the rigid profiles' own contact point where that gap is not
            // Hertzian.
            let wheel_y_m = rail_y - s_mm * 1e-3;
            let curvature = match crate::kalker::geometry::curvatures_at(
                nominal_radius_m,
                |y| profiles::wheel_radius_offset_m(y, wheel_y_m),
                |y| profiles::rail_top_height_m(y).unwrap_or(f64::NAN),
                rail_y,
                5e-4,
            ) {
                Ok((a, b)) => [a, b],
                Err(_) => profile_geometry(wheel_y_m, nominal_radius_m)?.3,
            };
            (s_mm, rail_y, angle, curvature, "")
        }
        None => {
            let wheel_y_m = loaded.scenario.scenario.wheel_position.tape_circle_y_mm * 1e-3
                + sample.wheel_y_displacement_m;
            let (rail_y, s_mm, angle, curvature) = profile_geometry(wheel_y_m, nominal_radius_m)?;
            (
                s_mm,
                rail_y,
                angle,
                curvature,
                "; contact point of the rigid profiles (the run has no contact position columns)",
            )
        }
    })
}

/// Kalker's exact creep forces for a run sample at the lateral creepage `eta`: the sample's
/// normal force, the profiles' curvatures and the spin `-sin(angle) / R` at its contact
/// point, and the longitudinal creepage that gives the sample's longitudinal creep force
/// (bisection), with the case's friction law at the rigid slip speed (a fixed point for
/// falling friction). Returns the creepages, the forces (Fx, Fy) and mu.
pub fn kalker_forces_at_sample(
    loaded: &LoadedCase,
    sample: &RunSample,
    nominal_radius_m: f64,
    material: Material,
    eta: f64,
) -> Result<(Creepages, [f64; 2], f64)> {
    let source = sample.run_dir.display().to_string();
    let (s_mm, _, angle, curvature, _) = sample_geometry(loaded, sample, nominal_radius_m)?;
    let radius = nominal_radius_m + crate::geometry::s1002::height_mm(s_mm) * 1e-3;
    let speed = loaded.case.speed_km_per_h / 3.6;
    let phi = -angle.to_radians().sin() / radius;
    let hertz =
        HertzContact::from_curvatures(curvature[0], curvature[1], sample.normal_force_n, material)?;
    let (mut mu, _) = friction_at(&loaded.case.friction, 0.0);
    let mut out = None;
    for _ in 0..50 {
        let solver = RollingSolver::new(&hertz, mu, Method::Exact, KALKER_ELEMENTS)?;
        let (xi, forces) =
            longitudinal_creepage(&solver, sample.creep_force_n[0], eta, phi, &source)?;
        let (m, _) = friction_at(&loaded.case.friction, speed * xi.hypot(eta));
        let converged = (m - mu).abs() <= 1e-9;
        out = Some((
            Creepages {
                xi,
                eta,
                phi_per_m: phi,
            },
            forces,
            mu,
        ));
        mu = m;
        if converged {
            break;
        }
    }
    out.ok_or_else(|| Error::Numerical("no Kalker solution".into()))
}

/// The longitudinal creepage at which `F_x(xi, eta) = fx_target` (bisection on the monotone
/// force), with the forces there.
fn longitudinal_creepage(
    solver: &RollingSolver,
    fx_target: f64,
    eta: f64,
    phi: f64,
    source: &str,
) -> Result<(f64, [f64; 2])> {
    let force = |xi: f64| -> Result<[f64; 2]> {
        let (fx, fy) = solver.forces(&Creepages {
            xi,
            eta,
            phi_per_m: phi,
        })?;
        Ok([fx, fy])
    };
    // F_x falls with xi (the force opposes the slip); 5 % creepage is far in full slip.
    let (mut lo, mut hi) = (-0.05, 0.05);
    let (f_lo, f_hi) = (force(lo)?[0], force(hi)?[0]);
    if !(f_hi <= fx_target && fx_target <= f_lo) {
        return Err(Error::input(
            source,
            "torque.max_n_m",
            format!(
                "the longitudinal creep force T / R = {fx_target:.0} N is above what friction carries \
                 with eta = {eta:.4} (at most {:.0} N): the creep force must stay below mu Fn",
                f_lo.abs().max(f_hi.abs())
            ),
        ));
    }
    // 60 halvings of 0.1: 1e-19, below any meaningful creepage.
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if force(mid)?[0] > fx_target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let xi = 0.5 * (lo + hi);
    Ok((xi, force(xi)?))
}

/// What a run directory says at one time: the contact forces, where the contact sits and where
/// the wheel is, read and checked without the wheel's modal model (so that a bad `--time-ms`
/// fails before the modes are solved).
#[derive(Clone, Debug)]
pub struct RunSample {
    /// The run directory.
    pub run_dir: std::path::PathBuf,
    /// Time (ms).
    pub time_ms: f64,
    /// Normal force (N, > 0).
    pub normal_force_n: f64,
    /// Creep forces (Fx, Fy) on the wheel (N).
    pub creep_force_n: [f64; 2],
    /// Contact on the wheel (profile S, mm), on the rail (y, m) and its angle (deg); None for a
    /// run written before these columns existed.
    pub contact: Option<(f64, f64, f64)>,
    /// Lateral displacement of the wheel centre (m; 0 if the run has no such column).
    pub wheel_y_displacement_m: f64,
    /// The wheel's position along the rail (m).
    pub wheel_x_m: f64,
}

/// Read `contact_forces.csv` and `histories.csv` of `run_dir` at `time_ms` (linear between
/// samples). Errors name the file and column, or `--time-ms` with the run's time range.
pub fn read_run_sample(loaded: &LoadedCase, run_dir: &Path, time_ms: f64) -> Result<RunSample> {
    let path = run_dir.join("contact_forces.csv");
    let source = path.display().to_string();
    let table = Table::read(&path)?;
    let col = |name: &str| {
        table.column(name).ok_or_else(|| {
            Error::input(
                &source,
                name,
                "missing column (a run of `squeal simulate` writes it)",
            )
        })
    };
    let t = col("time_s")?;
    if t.len() < 2 {
        return Err(Error::input(&source, "time_s", "fewer than two samples"));
    }
    let (t0, t1) = (t[0], t[t.len() - 1]);
    let time_s = time_ms * 1e-3;
    if !(time_s.is_finite() && time_s >= t0 && time_s <= t1) {
        return Err(Error::input(
            "command line",
            "--time-ms",
            format!(
                "must lie within the run {}, [{:.3}, {:.3}] ms, got {time_ms}",
                run_dir.display(),
                t0 * 1e3,
                t1 * 1e3
            ),
        ));
    }
    let at = |name: &str| -> Result<f64> { Ok(interpolate(t, col(name)?, time_s)) };
    let normal_force_n = at("normal_force_n")?;
    if !(normal_force_n.is_finite() && normal_force_n > 0.0) {
        return Err(Error::input(
            &source,
            "normal_force_n",
            format!(
                "the wheel is not pressed on the rail at {time_ms} ms (Fn = {normal_force_n:.1} N): \
                 the analysis needs Fn > 0"
            ),
        ));
    }
    let creep_force_n = [
        at("longitudinal_creep_force_n")?,
        at("lateral_creep_force_n")?,
    ];
    let geometry = [
        "contact_wheel_s_mm",
        "contact_rail_y_mm",
        "contact_angle_deg",
    ];
    let contact = if geometry.iter().all(|c| table.column(c).is_some()) {
        Some((at(geometry[0])?, at(geometry[1])? * 1e-3, at(geometry[2])?))
    } else {
        None
    };
    let histories = Table::read(&run_dir.join("histories.csv"))?;
    let history = |name: &str| match (histories.column("time_s"), histories.column(name)) {
        (Some(th), Some(x)) if !th.is_empty() => interpolate(th, x, time_s),
        _ => 0.0,
    };
    Ok(RunSample {
        run_dir: run_dir.to_path_buf(),
        time_ms,
        normal_force_n,
        creep_force_n,
        contact,
        wheel_y_displacement_m: history("wheel_centre_y_displacement_m"),
        wheel_x_m: loaded.scenario.scenario.wheel_position.x_m
            + history("wheel_centre_x_displacement_m"),
    })
}

/// The operating point of a run sample (see [`read_run_sample`]). A run without the contact
/// position columns (written before they existed) takes the rigid profiles' contact point at
/// the wheel's lateral position then (the tape circle moved by the wheel centre's lateral
/// displacement), which is said in the origin.
pub fn from_run_sample(
    loaded: &LoadedCase,
    sample: &RunSample,
    nominal_radius_m: f64,
    material: Material,
) -> Result<OperatingPoint> {
    let source = sample
        .run_dir
        .join("contact_forces.csv")
        .display()
        .to_string();
    let time_ms = sample.time_ms;
    let normal_force_n = sample.normal_force_n;
    let [fx, fy] = sample.creep_force_n;
    let wheel_x_m = sample.wheel_x_m;
    let (s_mm, rail_y, angle, curvature, geometry_note) =
        sample_geometry(loaded, sample, nominal_radius_m)?;
    let radius = nominal_radius_m + crate::geometry::s1002::height_mm(s_mm) * 1e-3;
    let speed = loaded.case.speed_km_per_h / 3.6;
    let phi = -angle.to_radians().sin() / radius;
    let hertz =
        HertzContact::from_curvatures(curvature[0], curvature[1], normal_force_n, material)?;
    let law = &loaded.case.friction;
    let (mut mu, mut slope) = friction_at(law, 0.0);
    let mut result = None;
    for _ in 0..50 {
        let bound = mu * normal_force_n;
        if fx.hypot(fy) > bound * (1.0 + crate::kalker::inverse::SATURATION_TOLERANCE) {
            return Err(Error::input(
                &source,
                "creep_force_n",
                format!(
                    "at {time_ms} ms the creep force {:.0} N exceeds mu Fn = {bound:.0} N (mu {mu:.3}): \
                     outside the model, which needs |F| <= mu Fn",
                    fx.hypot(fy)
                ),
            ));
        }
        let solver = RollingSolver::new(&hertz, mu, Method::Exact, KALKER_ELEMENTS)?;
        let r = solve_force_prescribed(
            &solver,
            (hertz.semi_axis_a_m, hertz.semi_axis_b_m),
            fx,
            fy,
            phi,
        )?;
        let (m, s) = friction_at(law, speed * r.creepages.xi.hypot(r.creepages.eta));
        let converged = (m - mu).abs() <= 1e-9;
        (mu, slope) = (m, s);
        result = Some(r);
        if converged {
            break;
        }
    }
    let r = result.ok_or_else(|| Error::Numerical("operating point: no Kalker solution".into()))?;
    Ok(OperatingPoint {
        origin: format!(
            "run {} at {time_ms} ms{geometry_note}",
            sample.run_dir.display()
        ),
        speed_m_per_s: speed,
        normal_force_n,
        creepages: r.creepages,
        creep_force_n: [fx, fy],
        mu,
        friction_slope_s_per_m: slope,
        contact_angle_deg: angle,
        contact_s_mm: s_mm,
        contact_rail_y_m: rail_y,
        rolling_radius_m: radius,
        curvature_per_m: curvature,
        wheel_x_m,
        kalker_note: r.note,
    })
}
