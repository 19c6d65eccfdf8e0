//! Range checks of input fields: every check fails with [`Error::Input`], which names the file,
//! the field (its full path in the file) and the allowed range, and exits with status 2.

use crate::{Error, Result};

/// Range checks that produce [`Error::Input`] naming the file and field.
pub struct Checker<'a> {
    /// File (or source) name used in messages.
    pub source_name: &'a str,
}

impl Checker<'_> {
    /// `value` must be finite and strictly positive.
    pub fn positive(&self, field: &str, value: f64) -> Result<()> {
        if value.is_finite() && value > 0.0 {
            Ok(())
        } else {
            Err(Error::input(
                self.source_name,
                field,
                format!("must be a finite number > 0, got {value}"),
            ))
        }
    }
    /// `value` must lie in `[lo, hi]`.
    pub fn within(&self, field: &str, value: f64, lo: f64, hi: f64) -> Result<()> {
        if value.is_finite() && value >= lo && value <= hi {
            Ok(())
        } else {
            Err(Error::input(
                self.source_name,
                field,
                format!("must be in [{lo}, {hi}], got {value}"),
            ))
        }
    }
    /// `value` must be finite and `>= 0`.
    pub fn non_negative(&self, field: &str, value: f64) -> Result<()> {
        if value.is_finite() && value >= 0.0 {
            Ok(())
        } else {
            Err(Error::input(
                self.source_name,
                field,
                format!("must be a finite number >= 0, got {value}"),
            ))
        }
    }
    /// `value` must lie in the open interval `(lo, hi)`.
    pub fn within_open(&self, field: &str, value: f64, lo: f64, hi: f64) -> Result<()> {
        if value.is_finite() && value > lo && value < hi {
            Ok(())
        } else {
            Err(Error::input(
                self.source_name,
                field,
                format!("must be in ({lo}, {hi}), got {value}"),
            ))
        }
    }
    /// `value` must lie in `(lo, hi]`.
    pub fn above_at_most(&self, field: &str, value: f64, lo: f64, hi: f64) -> Result<()> {
        if value.is_finite() && value > lo && value <= hi {
            Ok(())
        } else {
            Err(Error::input(
                self.source_name,
                field,
                format!("must be in ({lo}, {hi}], got {value}"),
            ))
        }
    }
    /// A custom failed condition.
    pub fn require(&self, ok: bool, field: &str, message: impl FnOnce() -> String) -> Result<()> {
        if ok {
            Ok(())
        } else {
            Err(Error::input(self.source_name, field, message()))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each check at its bounds, just outside them, and on NaN and infinity.
    #[test]
    fn checks_hold_their_bounds_and_refuse_non_finite_values() {
        let c = Checker {
            source_name: "f.json",
        };
        assert!(c.positive("a", 1e-300).is_ok() && c.positive("a", 0.0).is_err());
        assert!(c.non_negative("a", 0.0).is_ok() && c.non_negative("a", -1e-300).is_err());
        assert!(
            c.within("a", 1.0, 0.0, 1.0).is_ok() && c.within("a", 1.0 + 1e-15, 0.0, 1.0).is_err()
        );
        assert!(c.within_open("a", 0.5, 0.0, 1.0).is_ok());
        assert!(
            c.within_open("a", 0.0, 0.0, 1.0).is_err()
                && c.within_open("a", 1.0, 0.0, 1.0).is_err()
        );
        assert!(
            c.above_at_most("a", 1.0, 0.0, 1.0).is_ok()
                && c.above_at_most("a", 0.0, 0.0, 1.0).is_err()
        );
        for bad in [f64::NAN, f64::INFINITY] {
            assert!(c.positive("a", bad).is_err());
            assert!(c.non_negative("a", bad).is_err());
            assert!(c
                .within("a", bad, f64::NEG_INFINITY, f64::INFINITY)
                .is_err());
            assert!(c
                .within_open("a", bad, f64::NEG_INFINITY, f64::INFINITY)
                .is_err());
            assert!(c
                .above_at_most("a", bad, f64::NEG_INFINITY, f64::INFINITY)
                .is_err());
        }
        // The message names the file, the field and the range.
        let e = c
            .within_open("sleeper.poisson_ratio", 0.5, -1.0, 0.5)
            .unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("f.json")
                && text.contains("sleeper.poisson_ratio")
                && text.contains("(-1, 0.5)"),
            "{text}"
        );
        assert_eq!(e.exit_code(), 2);
    }
}
