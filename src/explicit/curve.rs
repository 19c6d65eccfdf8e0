//! Piecewise-linear time curves (load and motion histories).
//!
//! `value(t)` interpolates linearly between the points `(t_k, v_k)` and holds the end values
//! outside `[t_0, t_last]`, the convention of LS-DYNA's `*DEFINE_CURVE`.

use serde::{Deserialize, Serialize};

use crate::{Error, Result};

/// A piecewise-linear curve `v(t)` with strictly increasing times.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Curve {
    /// Times (s), strictly increasing.
    pub times_s: Vec<f64>,
    /// Values at those times (unit given by the field that holds the curve).
    pub values: Vec<f64>,
}

impl Curve {
    /// A validated curve; `field` names it in errors.
    pub fn new(times_s: Vec<f64>, values: Vec<f64>, field: &str) -> Result<Curve> {
        let curve = Curve { times_s, values };
        curve.validate("curve", field)?;
        Ok(curve)
    }

    /// A constant curve.
    pub fn constant(value: f64) -> Curve {
        Curve {
            times_s: vec![0.0],
            values: vec![value],
        }
    }

    /// A ramp from 0 at `start_s` to `value` at `end_s`, then constant.
    pub fn ramp(start_s: f64, end_s: f64, value: f64) -> Curve {
        Curve {
            times_s: vec![start_s, end_s],
            values: vec![0.0, value],
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

    /// Value at time `t_s` (linear interpolation, end values held).
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
        let w = (t_s - t[k]) / (t[k + 1] - t[k]);
        self.values[k] + w * (self.values[k + 1] - self.values[k])
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
    fn rejects_non_increasing_times() {
        let e = Curve::new(vec![0.0, 1.0, 1.0], vec![0.0, 1.0, 2.0], "torque").unwrap_err();
        let text = e.to_string();
        assert!(text.contains("torque.times_s[2]"), "{text}");
        assert_eq!(e.exit_code(), 2);
        assert!(Curve::new(vec![], vec![], "x").is_err());
        assert!(Curve::new(vec![0.0], vec![f64::NAN], "x").is_err());
    }
}
