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
    /// A custom failed condition.
    pub fn require(&self, ok: bool, field: &str, message: impl FnOnce() -> String) -> Result<()> {
        if ok {
            Ok(())
        } else {
            Err(Error::input(self.source_name, field, message()))
        }
    }
}
