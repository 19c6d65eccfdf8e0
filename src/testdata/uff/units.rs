//! Dataset 164, units (docs/uff-format.md, section 6): record 1 (I10,20A1,I10) the units code, its
//! description and the temperature mode; record 2 (3D25.17, four values over two lines) the
//! length, force and temperature factors and the temperature offset. A value in the file's
//! units converts to SI by dividing by the factor.

use super::block::Context;
use super::fields::{column, reals};
use crate::Result;

/// The units of a universal file.
#[derive(Clone, Debug, PartialEq)]
pub struct Units {
    /// 1 SI (metre, newton), 2 BG (foot, pound force), ... 5 MM (mm, milli-newton), ...
    pub code: i64,
    /// The description (documentation only).
    pub description: String,
    /// 1 absolute, 2 relative.
    pub temperature_mode: i64,
    /// SI length = file length / `length_factor`.
    pub length_factor: f64,
    /// SI force = file force / `force_factor`.
    pub force_factor: f64,
    /// SI temperature = file temperature / `temperature_factor`.
    pub temperature_factor: f64,
    /// Temperature offset.
    pub temperature_offset: f64,
}

impl Units {
    /// SI units (metre, newton, kelvin factors 1, offset 273.15 as the SI example files have).
    pub fn si() -> Self {
        Units {
            code: 1,
            description: "SI: Meter (newton)".to_string(),
            temperature_mode: 2,
            length_factor: 1.0,
            force_factor: 1.0,
            temperature_factor: 1.0,
            temperature_offset: 273.15,
        }
    }
}

/// Parses a dataset 164.
pub fn parse(lines: &[String], ctx: &Context) -> Result<Units> {
    let Some(r1) = lines.first() else {
        return Err(ctx.error("records", "empty units dataset"));
    };
    let tokens: Vec<&str> = r1.split_whitespace().collect();
    let code = column(r1, 1, 10)
        .parse::<i64>()
        .ok()
        .or_else(|| tokens.first()?.parse().ok())
        .ok_or_else(|| {
            ctx.record_error(
                1,
                "units code",
                format!("`{r1}` does not start with an integer"),
            )
        })?;
    // Fortran reads a blank integer field as 0: Simcenter Testlab leaves the temperature mode
    // blank. A line that stops before column 31 but ends with an integer is hand-edited, its
    // fields separated by blanks.
    let mode_field = column(r1, 31, 40);
    let temperature_mode = mode_field
        .parse::<i64>()
        .ok()
        .or_else(|| {
            if r1.trim_end().len() < 31 {
                tokens.last()?.parse().ok().or(Some(0))
            } else {
                mode_field.is_empty().then_some(0)
            }
        })
        .ok_or_else(|| {
            ctx.record_error(
                1,
                "temperature mode",
                format!("`{r1}` does not end with an integer"),
            )
        })?;
    let (factors, used) = reals(&lines[1..], 4, &[25], ctx, 2, "factors")?;
    if 1 + used != lines.len() {
        return Err(ctx.record_error(2, "factors", "lines after the four factors"));
    }
    for (value, what) in factors.iter().zip(["length", "force", "temperature"]) {
        if !(value.is_finite() && *value > 0.0) {
            return Err(ctx.record_error(
                2,
                &format!("{what} factor"),
                format!("{value}; allowed: finite and > 0"),
            ));
        }
    }
    Ok(Units {
        code,
        description: column(r1, 11, 30).to_string(),
        temperature_mode,
        length_factor: factors[0],
        force_factor: factors[1],
        temperature_factor: factors[2],
        temperature_offset: factors[3],
    })
}
