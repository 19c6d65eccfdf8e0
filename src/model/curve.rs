//! Time curves (load and motion histories): piecewise linear, or piecewise cubic Hermite.
//!
//! `value(t)` interpolates between the points `(t_k, v_k)` and holds the end values outside
//! `[t_0, t_last]`, the convention of LS-DYNA's `*DEFINE_CURVE`. Without slopes the
//! interpolation is linear (C0: the derivative jumps at the points). With a slope `d_k` at every
//! point it is the cubic Hermite interpolant (C1: value and derivative continuous at the
//! points),
//!
//! `v(t) = h00(s) v_k + h10(s) h d_k + h01(s) v_(k+1) + h11(s) h d_(k+1)`, `s = (t - t_k) / h`,
//! `h = t_(k+1) - t_k`, with `h00 = 2s^3 - 3s^2 + 1`, `h10 = s^3 - 2s^2 + s`,
//! `h01 = -2s^3 + 3s^2`, `h11 = s^3 - s^2`.
//!
//! A prescribed displacement made of such a curve has a continuous velocity: a moving support
//! starts without the velocity step that rings a structure's low modes. For the held end values
//! to join smoothly, the end slopes must be zero.

use serde::{Deserialize, Serialize};

use crate::{Error, Result};

/// A curve `v(t)` with strictly increasing times: piecewise linear, or cubic Hermite when
/// `slopes` holds one derivative per point.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Curve {
    /// Times (s), strictly increasing.
    pub times_s: Vec<f64>,
    /// Values at those times (unit given by the field that holds the curve).
    pub values: Vec<f64>,
    /// Derivatives `dv/dt` at those times (value unit per second); empty: linear
    /// interpolation.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub slopes: Vec<f64>,
}

impl Curve {
    /// A validated curve; `field` names it in errors.
    pub fn new(times_s: Vec<f64>, values: Vec<f64>, field: &str) -> Result<Curve> {
        let curve = Curve {
            times_s,
            values,
            slopes: Vec::new(),
        };
        curve.validate("curve", field)?;
        Ok(curve)
    }

    /// A validated cubic Hermite curve (C1) through `(t_k, v_k)` with derivatives `d_k`.
    pub fn hermite(
        times_s: Vec<f64>,
        values: Vec<f64>,
        slopes: Vec<f64>,
        field: &str,
    ) -> Result<Curve> {
        let curve = Curve {
            times_s,
            values,
            slopes,
        };
        curve.validate("curve", field)?;
        Ok(curve)
    }

    /// A constant curve.
    pub fn constant(value: f64) -> Curve {
        Curve {
            times_s: vec![0.0],
            values: vec![value],
            slopes: Vec::new(),
        }
    }

    /// A ramp from 0 at `start_s` to `value` at `end_s`, then constant.
    pub fn ramp(start_s: f64, end_s: f64, value: f64) -> Curve {
        Curve {
            times_s: vec![start_s, end_s],
            values: vec![0.0, value],
            slopes: Vec::new(),
        }
    }

    /// Checks: at least one point, same lengths, finite values, strictly increasing times.
    pub fn validate(&self, source_name: &str, field: &str) -> Result<()> {
        if self.times_s.is_empty() || self.times_s.len() != self.values.len() {
            return Err(Error::input(
                source_name,
                field,
                format!(
                    "a curve needs as many values as times and at least one point (got {} times, {} values)",
                    self.times_s.len(),
                    self.values.len()
                ),
            ));
        }
        if !self.slopes.is_empty() && self.slopes.len() != self.times_s.len() {
            return Err(Error::input(
                source_name,
                field,
                format!(
                    "a Hermite curve needs one slope per point (got {} times, {} slopes)",
                    self.times_s.len(),
                    self.slopes.len()
                ),
            ));
        }
        if self.slopes.iter().any(|d| !d.is_finite()) {
            return Err(Error::input(
                source_name,
                format!("{field}.slopes"),
                "slopes must be finite numbers",
            ));
        }
        for (k, (t, v)) in self.times_s.iter().zip(&self.values).enumerate() {
            if !t.is_finite() || !v.is_finite() {
                return Err(Error::input(
                    source_name,
                    format!("{field}[{k}]"),
                    "times and values must be finite numbers",
                ));
            }
        }
        for k in 1..self.times_s.len() {
            if self.times_s[k] <= self.times_s[k - 1] {
                return Err(Error::input(
                    source_name,
                    format!("{field}.times_s[{k}]"),
                    format!(
                        "times must increase strictly ({} s follows {} s)",
                        self.times_s[k],
                        self.times_s[k - 1]
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Value at time `t_s` (linear or cubic Hermite interpolation, end values held).
    pub fn value(&self, t_s: f64) -> f64 {
        let t = &self.times_s;
        let n = t.len();
        if t_s <= t[0] {
            return self.values[0];
        }
        if t_s >= t[n - 1] {
            return self.values[n - 1];
        }
        // Binary search for the interval t[k] <= t_s < t[k+1].
        let k = t.partition_point(|&tk| tk <= t_s) - 1;
        let h = t[k + 1] - t[k];
        let w = (t_s - t[k]) / h;
        if self.slopes.is_empty() {
            return self.values[k] + w * (self.values[k + 1] - self.values[k]);
        }
        let (w2, w3) = (w * w, w * w * w);
        let h00 = 2.0 * w3 - 3.0 * w2 + 1.0;
        let h10 = w3 - 2.0 * w2 + w;
        let h01 = -2.0 * w3 + 3.0 * w2;
        let h11 = w3 - w2;
        h00 * self.values[k]
            + h10 * h * self.slopes[k]
            + h01 * self.values[k + 1]
            + h11 * h * self.slopes[k + 1]
    }

    /// Derivative `dv/dt` at time `t_s` (zero outside the points, where the ends are held).
    pub fn derivative(&self, t_s: f64) -> f64 {
        let t = &self.times_s;
        let n = t.len();
        if n < 2 || t_s < t[0] || t_s >= t[n - 1] {
            return 0.0;
        }
        let k = t.partition_point(|&tk| tk <= t_s) - 1;
        let h = t[k + 1] - t[k];
        let w = (t_s - t[k]) / h;
        if self.slopes.is_empty() {
            return (self.values[k + 1] - self.values[k]) / h;
        }
        let w2 = w * w;
        let dh00 = 6.0 * w2 - 6.0 * w;
        let dh10 = 3.0 * w2 - 4.0 * w + 1.0;
        let dh01 = -6.0 * w2 + 6.0 * w;
        let dh11 = 3.0 * w2 - 2.0 * w;
        (dh00 * self.values[k] + dh01 * self.values[k + 1]) / h
            + dh10 * self.slopes[k]
            + dh11 * self.slopes[k + 1]
    }

    /// Largest absolute value (for scaling checks).
    pub fn max_abs(&self) -> f64 {
        self.values.iter().fold(0.0, |m, v| m.max(v.abs()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_and_holds_ends() {
        let c = Curve::new(vec![0.0, 1.0, 3.0], vec![0.0, 2.0, -2.0], "c").unwrap();
        assert_eq!(c.value(-1.0), 0.0);
        assert_eq!(c.value(0.5), 1.0);
        assert_eq!(c.value(2.0), 0.0);
        assert_eq!(c.value(9.0), -2.0);
        assert_eq!(c.max_abs(), 2.0);
    }

    #[test]
    fn hermite_reproduces_a_cubic_and_its_derivative() {
        // A cubic is reproduced exactly by its Hermite interpolant (the basis spans cubics).
        let f = |t: f64| 2.0 - t + 0.5 * t * t - 0.25 * t * t * t;
        let df = |t: f64| -1.0 + t - 0.75 * t * t;
        let times = vec![0.0, 0.7, 1.5, 3.0];
        let c = Curve::hermite(
            times.clone(),
            times.iter().map(|&t| f(t)).collect(),
            times.iter().map(|&t| df(t)).collect(),
            "c",
        )
        .unwrap();
        // Inside the points (the end value is held after the last, with zero derivative).
        for k in 0..300 {
            let t = 0.01 * k as f64;
            assert!((c.value(t) - f(t)).abs() < 1e-12, "t {t}");
            assert!((c.derivative(t) - df(t)).abs() < 1e-12, "t {t}");
        }
        assert_eq!(c.value(5.0), f(3.0));
        assert_eq!(c.derivative(5.0), 0.0);
    }

    #[test]
    fn hermite_needs_one_slope_per_point() {
        let e = Curve::hermite(vec![0.0, 1.0], vec![0.0, 1.0], vec![0.0], "lateral").unwrap_err();
        assert!(e.to_string().contains("one slope per point"), "{e}");
        assert!(Curve::hermite(vec![0.0, 1.0], vec![0.0, 1.0], vec![0.0, f64::NAN], "x").is_err());
    }

    #[test]
    fn rejects_non_increasing_times() {
        let e = Curve::new(vec![0.0, 1.0, 1.0], vec![0.0, 1.0, 2.0], "torque").unwrap_err();
        let text = e.to_string();
        assert!(text.contains("torque.times_s[2]"), "{text}");
        assert_eq!(e.exit_code(), 2);
        assert!(Curve::new(vec![], vec![], "x").is_err());
        assert!(Curve::new(vec![0.0], vec![f64::NAN], "x").is_err());
    }
}
