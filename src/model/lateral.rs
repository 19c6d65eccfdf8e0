//! The prescribed lateral displacement of the axle ends (Yang & Li 2019: a
//! displacement history applied to both ends of the half axle from t2 = 16 ms).
//!
//! The history is C1: the displacement and its velocity are continuous, so the axle starts from
//! rest without the velocity step that rings the wheel's n = 0 modes from the hub, and it levels
//! off (zero velocity at the end) so that the flange never reaches the rail. Two forms:
//!
//! - **ramp** (`"shape": "ramp"`): at rest until `start_s`; the velocity rises from 0 to
//!   `velocity_m_per_s` over `rise_time_s` along the smoothstep `S(x) = 3x^2 - 2x^3`, stays
//!   there, and falls back to 0 over `settle_time_s` (the same curve mirrored) so that the axle
//!   stops after `travel_m`. The rise and the settling each cover `V t / 2` (the integral of `S`
//!   over [0, 1] is 1/2), so the cruise lasts `(travel - V (t_rise + t_settle) / 2) / V`. The
//!   displacement is a quartic in the rise and the settling; it is handed to the engine as a
//!   cubic Hermite curve through exact values and velocities at [`KNOTS_PER_TRANSITION`] knots
//!   per transition (interpolation error below `5e-7 V t_rise`).
//! - **table** (`"shape": "table"`): points `(t_k, d_k)` joined by the monotone piecewise-cubic
//!   Hermite interpolant of Fritsch and Carlson (1980, SIAM J. Numer. Anal. 17, 238-246), with
//!   zero velocity at the first and the last point. It starts at 0 m (the preloaded position).
//!
//! Positive displacement is towards +y (the field side), where the flange approaches the rail.

// `!(x > 0.0)` is meant: it also rejects NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use serde::{Deserialize, Serialize};

use super::curve::Curve;
use crate::{Error, Result};

/// Knots of the Hermite curve in each smooth transition of a ramp.
pub const KNOTS_PER_TRANSITION: usize = 16;

/// Largest lateral axle speed accepted (m/s): 18 % of the 100 km/h rolling speed, beyond any
/// lateral creepage that keeps the wheel on the rail; a faster step between two table points
/// is a jump, not a motion.
pub const LATERAL_SPEED_LIMIT_M_PER_S: f64 = 5.0;

/// A smooth ramp: rise, cruise, settle.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LateralRamp {
    /// Onset of the motion (s).
    pub start_s: f64,
    /// Time for the velocity to rise from 0 to `velocity_m_per_s` (s).
    pub rise_time_s: f64,
    /// Cruise velocity (m/s); positive towards +y (field side).
    pub velocity_m_per_s: f64,
    /// Distance travelled when the axle has stopped (m, > 0), in the direction of the velocity.
    pub travel_m: f64,
    /// Time for the velocity to fall back to 0 at the end (s).
    pub settle_time_s: f64,
}

/// A table of displacements.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LateralTable {
    /// Times (s), strictly increasing.
    pub times_s: Vec<f64>,
    /// Lateral displacements (m) at those times; the first is 0.
    pub displacements_m: Vec<f64>,
}

/// Prescribed lateral motion of both axle ends.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "lowercase")]
pub enum LateralMotion {
    /// Smooth rise, cruise and settling.
    Ramp(LateralRamp),
    /// Interpolated table.
    Table(LateralTable),
}

/// Smoothstep `3x^2 - 2x^3` on [0, 1] and its integral `x^3 - x^4 / 2`.
fn smoothstep(x: f64) -> (f64, f64) {
    let x = x.clamp(0.0, 1.0);
    (x * x * (3.0 - 2.0 * x), x * x * x - 0.5 * x * x * x * x)
}

impl LateralRamp {
    /// Start of the settling (s).
    fn settle_start_s(&self) -> f64 {
        let v = self.velocity_m_per_s.abs();
        self.start_s
            + self.rise_time_s
            + (self.travel_m - 0.5 * v * (self.rise_time_s + self.settle_time_s)) / v
    }

    /// Displacement (m) and velocity (m/s) at `t_s`, exact.
    pub fn state(&self, t_s: f64) -> (f64, f64) {
        let v = self.velocity_m_per_s;
        let (t0, tr, ts) = (self.start_s, self.rise_time_s, self.settle_time_s);
        let t1 = self.settle_start_s();
        if t_s <= t0 {
            return (0.0, 0.0);
        }
        let rise_travel = 0.5 * v * tr;
        if t_s <= t0 + tr {
            let (s, int_s) = smoothstep((t_s - t0) / tr);
            return (v * tr * int_s, v * s);
        }
        if t_s <= t1 {
            return (rise_travel + v * (t_s - t0 - tr), v);
        }
        let at_t1 = rise_travel + v * (t1 - t0 - tr);
        let x = ((t_s - t1) / ts).min(1.0);
        let (s, int_s) = smoothstep(x);
        // v (1 - S) integrated: v ts (x - int S).
        (at_t1 + v * ts * (x - int_s), v * (1.0 - s))
    }

    /// Checks of a ramp, field by field (onset, transition times, velocity, travel): each
    /// names its field and range through `err`. The travel must at least cover the rise and
    /// the settling, or the cruise would last a negative time.
    fn check(&self, err: &impl Fn(&str, String) -> Error, end_time_s: f64) -> Result<()> {
        let r = self;
        if !(r.start_s >= 0.0 && r.start_s < end_time_s) {
            return Err(err(
                "start_s",
                format!(
                    "the onset must lie in [0, end_time_s = {end_time_s}) s (got {})",
                    r.start_s
                ),
            ));
        }
        for (name, x) in [
            ("rise_time_s", r.rise_time_s),
            ("settle_time_s", r.settle_time_s),
        ] {
            if !(x > 0.0 && x <= 1.0) {
                return Err(err(
                    name,
                    format!("must lie in (0, 1] s (got {x}); a zero time is a velocity step"),
                ));
            }
        }
        let v = r.velocity_m_per_s;
        if !(v != 0.0 && v.abs() <= LATERAL_SPEED_LIMIT_M_PER_S) {
            return Err(err(
                "velocity_m_per_s",
                format!(
                    "must lie in [-{LATERAL_SPEED_LIMIT_M_PER_S}, \
                     {LATERAL_SPEED_LIMIT_M_PER_S}] m/s and not be 0 (got {v}); \
                     leave lateral_motion out for no motion"
                ),
            ));
        }
        let shortest = 0.5 * v.abs() * (r.rise_time_s + r.settle_time_s);
        if !(r.travel_m >= shortest && r.travel_m <= 0.05) {
            return Err(err(
                "travel_m",
                format!(
                    "must lie in [{shortest:.3e}, 0.05] m (got {}): the rise and the \
                     settling alone cover |v| (rise_time_s + settle_time_s) / 2",
                    r.travel_m
                ),
            ));
        }
        Ok(())
    }
}

impl LateralTable {
    /// The table as data: at least two points, as many displacements as times, finite times,
    /// displacements within 5 cm, times strictly increasing (the interpolant divides by the
    /// time steps).
    fn check_points(&self, err: &impl Fn(&str, String) -> Error) -> Result<()> {
        let t = self;
        if t.times_s.len() < 2 || t.times_s.len() != t.displacements_m.len() {
            return Err(err(
                "times_s",
                format!(
                    "needs at least 2 points and as many displacements as times (got {} \
                     times, {} displacements)",
                    t.times_s.len(),
                    t.displacements_m.len()
                ),
            ));
        }
        for (k, (&tk, &dk)) in t.times_s.iter().zip(&t.displacements_m).enumerate() {
            if !tk.is_finite() {
                return Err(err(
                    &format!("times_s[{k}]"),
                    format!("must be a finite time in s (got {tk})"),
                ));
            }
            if !(dk.is_finite() && dk.abs() <= 0.05) {
                return Err(err(
                    &format!("displacements_m[{k}]"),
                    format!("must lie in [-0.05, 0.05] m (got {dk})"),
                ));
            }
        }
        for k in 1..t.times_s.len() {
            if !(t.times_s[k] > t.times_s[k - 1]) {
                return Err(err(
                    &format!("times_s[{k}]"),
                    format!(
                        "times must increase strictly ({} s follows {} s)",
                        t.times_s[k],
                        t.times_s[k - 1]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The table as a motion (after [`LateralTable::check_points`]): an onset within the run,
    /// a start from the preloaded position (no jump of the axle at the onset), and no step
    /// between two points faster than [`LATERAL_SPEED_LIMIT_M_PER_S`].
    fn check_motion(&self, err: &impl Fn(&str, String) -> Error, end_time_s: f64) -> Result<()> {
        let t = self;
        if !(t.times_s[0] >= 0.0 && t.times_s[0] < end_time_s) {
            return Err(err(
                "times_s[0]",
                format!(
                    "the onset must lie in [0, end_time_s = {end_time_s}) s (got {})",
                    t.times_s[0]
                ),
            ));
        }
        if t.displacements_m[0] != 0.0 {
            return Err(err(
                "displacements_m[0]",
                format!(
                    "must be 0 m, the preloaded position (got {}): anything else is a \
                     jump of the axle at the onset, and the displacement must be \
                     continuous",
                    t.displacements_m[0]
                ),
            ));
        }
        for k in 1..t.times_s.len() {
            let speed = (t.displacements_m[k] - t.displacements_m[k - 1]).abs()
                / (t.times_s[k] - t.times_s[k - 1]);
            if speed > LATERAL_SPEED_LIMIT_M_PER_S {
                return Err(err(
                    &format!("displacements_m[{k}]"),
                    format!(
                        "a step of {:.3e} m in {:.3e} s ({speed:.1} m/s) is a jump: the \
                         lateral speed must stay within {LATERAL_SPEED_LIMIT_M_PER_S} m/s",
                        t.displacements_m[k] - t.displacements_m[k - 1],
                        t.times_s[k] - t.times_s[k - 1]
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// Monotone cubic Hermite slopes (Fritsch-Carlson) with zero slope at both ends.
fn monotone_slopes(t: &[f64], d: &[f64]) -> Vec<f64> {
    let n = t.len();
    let mut slopes = vec![0.0; n];
    let secant: Vec<f64> = (0..n - 1)
        .map(|k| (d[k + 1] - d[k]) / (t[k + 1] - t[k]))
        .collect();
    for k in 1..n - 1 {
        let (a, b) = (secant[k - 1], secant[k]);
        // Zero at a local extremum or a flat piece; otherwise the weighted harmonic mean of the
        // neighbouring secants (Fritsch-Butland form of the Fritsch-Carlson condition), which
        // keeps each piece monotone.
        if a * b <= 0.0 {
            slopes[k] = 0.0;
        } else {
            let (h0, h1) = (t[k] - t[k - 1], t[k + 1] - t[k]);
            let (w0, w1) = (2.0 * h1 + h0, h1 + 2.0 * h0);
            slopes[k] = (w0 + w1) / (w0 / a + w1 / b);
        }
    }
    slopes
}

impl LateralMotion {
    /// Onset of the motion (s): the ramp's start, or the table's first time.
    pub fn onset_s(&self) -> f64 {
        match self {
            LateralMotion::Ramp(r) => r.start_s,
            LateralMotion::Table(t) => t.times_s.first().copied().unwrap_or(0.0),
        }
    }

    /// Time at which the axle has stopped again (s).
    pub fn end_s(&self) -> f64 {
        match self {
            LateralMotion::Ramp(r) => r.settle_start_s() + r.settle_time_s,
            LateralMotion::Table(t) => t.times_s.last().copied().unwrap_or(0.0),
        }
    }

    /// Checks the history against the case's end time; errors name `field` and the range.
    pub fn validate(&self, source: &str, field: &str, end_time_s: f64) -> Result<()> {
        let err = |sub: &str, msg: String| Error::input(source, format!("{field}.{sub}"), msg);
        match self {
            LateralMotion::Ramp(r) => r.check(&err, end_time_s),
            LateralMotion::Table(t) => {
                t.check_points(&err)?;
                t.check_motion(&err, end_time_s)
            }
        }
    }

    /// The displacement history as a C1 curve (m against s) for the axle's prescribed
    /// translation. Call after [`LateralMotion::validate`].
    pub fn curve(&self) -> Result<Curve> {
        match self {
            LateralMotion::Ramp(r) => {
                let mut times = Vec::new();
                let t1 = r.settle_start_s();
                let transitions = [(r.start_s, r.rise_time_s), (t1, r.settle_time_s)];
                for (k, (from, span)) in transitions.into_iter().enumerate() {
                    for j in 0..=KNOTS_PER_TRANSITION {
                        let t = from + span * j as f64 / KNOTS_PER_TRANSITION as f64;
                        // The cruise is linear: the end of the rise joins the settling's start
                        // directly (skip a knot that coincides with the previous one).
                        if k == 1 && j == 0 && times.last().is_some_and(|&l: &f64| t - l < 1e-12) {
                            continue;
                        }
                        times.push(t);
                    }
                }
                let (values, slopes): (Vec<f64>, Vec<f64>) =
                    times.iter().map(|&t| r.state(t)).unzip();
                Curve::hermite(times, values, slopes, "lateral_motion")
            }
            LateralMotion::Table(t) => {
                let slopes = monotone_slopes(&t.times_s, &t.displacements_m);
                Curve::hermite(
                    t.times_s.clone(),
                    t.displacements_m.clone(),
                    slopes,
                    "lateral_motion",
                )
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp() -> LateralRamp {
        LateralRamp {
            start_s: 0.016,
            rise_time_s: 0.001,
            velocity_m_per_s: 0.6,
            travel_m: 0.003,
            settle_time_s: 0.002,
        }
    }

    /// The velocity the engine applies, `(d(t + dt) - d(t)) / dt` at its step, changes from
    /// one step to the next by at most `a_max dt` (plus rounding): no jump anywhere, at the
    /// onset and the stop included. For the ramp `a_max = 1.5 V / t_rise` (the smoothstep's
    /// largest slope); for the table, from the Hermite curve's own derivative.
    #[test]
    fn sampled_velocity_has_no_jump() {
        let dt = 6.889e-7;
        let check = |m: &LateralMotion, a_max: f64| {
            let c = m.curve().unwrap();
            let v = |t: f64| (c.value(t + dt) - c.value(t)) / dt;
            let (mut t, mut last) = (m.onset_s() - 1e-4, 0.0);
            let mut worst: f64 = 0.0;
            while t < m.end_s() + 1e-4 {
                let now = v(t);
                worst = worst.max((now - last).abs());
                last = now;
                t += dt;
            }
            assert!(
                worst <= 1.01 * a_max * dt + 1e-9,
                "{worst} vs {}",
                a_max * dt
            );
            assert_eq!(v(m.onset_s() - 2.0 * dt), 0.0);
            assert!(v(m.end_s() + dt).abs() < 1e-12);
        };
        let r = ramp();
        check(
            &LateralMotion::Ramp(r),
            1.5 * r.velocity_m_per_s / r.rise_time_s,
        );
        let table = LateralMotion::Table(LateralTable {
            times_s: vec![0.016, 0.017, 0.019, 0.022],
            displacements_m: vec![0.0, 0.0004, 0.0020, 0.0030],
        });
        table.validate("case", "lateral_motion", 0.04).unwrap();
        // A bound on |d''|: the largest over a fine sampling of the curve's derivative.
        let c = table.curve().unwrap();
        let h = 1e-7;
        let a_max = (0..60_000)
            .map(|k| {
                let t = 0.016 + k as f64 * 1e-7;
                ((c.derivative(t + h) - c.derivative(t)) / h).abs()
            })
            .fold(0.0, f64::max);
        check(&table, a_max);
    }

    #[test]
    fn ramp_travels_its_distance_and_stops() {
        let r = ramp();
        let m = LateralMotion::Ramp(r);
        m.validate("case", "lateral_motion", 0.04).unwrap();
        let c = m.curve().unwrap();
        assert_eq!(c.value(0.0), 0.0);
        assert_eq!(c.value(0.016), 0.0);
        assert!((c.value(0.04) - 0.003).abs() < 1e-15);
        assert!((m.end_s() - (0.016 + 0.001 + (0.003 - 0.3 * 0.003) / 0.6 + 0.002)).abs() < 1e-15);
        // The Hermite curve follows the exact quartic/linear history (bound in the module doc).
        for k in 0..=4000 {
            let t = 0.0155 + 1e-6 * k as f64;
            let (d, v) = r.state(t);
            assert!((c.value(t) - d).abs() < 5e-7 * 0.6 * 0.001, "t {t}");
            assert!((c.derivative(t) - v).abs() < 1e-3 * 0.6, "t {t}");
        }
    }
}
