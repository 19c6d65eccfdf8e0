//! Dataset 58, a function at a nodal DOF (docs/uff-format.md, section 1), and its binary form 58b
//! (section 2).
//!
//! Records 1-5 are ID lines; record 6 names the function type and the response and reference
//! DOFs; record 7 the ordinate type (2 real single, 4 real double, 5 complex single, 6 complex
//! double), the number of values and the abscissa (even: start and step; uneven: one abscissa per
//! value); records 8-11 the data characteristics of the abscissa, the ordinate numerator and
//! denominator and the z axis; record 12 the values (x before y, real before imaginary). In 58b,
//! record 12 is raw IEEE bytes in the header's byte order.

use rustfft::num_complex::Complex;

use super::block::{Block, Context};
use super::fields::{column, integers, parse_real, reals};
use crate::Result;

/// A nodal degree of freedom.
#[derive(Clone, Debug, PartialEq)]
pub struct Dof {
    /// Entity name ("NONE" when unused).
    pub entity: String,
    /// Node label.
    pub node: i64,
    /// Direction: 0 scalar, 1/2/3 +X/+Y/+Z translation, 4/5/6 rotation, negative: the same axis
    /// in the negative sense.
    pub direction: i64,
}

/// One data-characteristics record (records 8-11).
#[derive(Clone, Debug, PartialEq)]
pub struct AxisInfo {
    /// Specific data type: 8 displacement, 11 velocity, 12 acceleration, 13 excitation force,
    /// 17 time, 18 frequency, ... (docs/uff-format.md).
    pub specific_data_type: i64,
    /// Length units exponent.
    pub length_exponent: i64,
    /// Force units exponent.
    pub force_exponent: i64,
    /// Temperature units exponent.
    pub temperature_exponent: i64,
    /// Axis label.
    pub label: String,
    /// Axis units label.
    pub units: String,
}

impl AxisInfo {
    /// An axis of `specific_data_type` with its label and units.
    pub fn new(specific_data_type: i64, label: &str, units: &str) -> Self {
        AxisInfo {
            specific_data_type,
            length_exponent: 0,
            force_exponent: 0,
            temperature_exponent: 0,
            label: label.to_string(),
            units: units.to_string(),
        }
    }
}

/// Abscissa of a function.
#[derive(Clone, Debug, PartialEq)]
pub enum Abscissa {
    /// `x_i = start + i step`.
    Even {
        /// First abscissa.
        start: f64,
        /// Increment.
        step: f64,
    },
    /// One abscissa per value.
    Uneven(Vec<f64>),
}

/// The Fortran field widths of record 12 (docs/uff-format.md, "Record 12"): `6E13.5` for single
/// precision; `4E20.12` for double even; `2(E13.5,E20.12)` and `E13.5,2E20.12` for double
/// uneven real and complex (the abscissa stays single).
fn record12_widths(precision: OrdinatePrecision, complex: bool, even: bool) -> &'static [usize] {
    match (precision, even, complex) {
        (OrdinatePrecision::Single, _, _) => &[13],
        (OrdinatePrecision::Double, true, _) => &[20],
        (OrdinatePrecision::Double, false, false) => &[13, 20],
        (OrdinatePrecision::Double, false, true) => &[13, 20, 20],
    }
}

/// Ordinate precision in the file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum OrdinatePrecision {
    /// 4-byte floats / `E13.5`.
    Single,
    /// 8-byte floats / `E20.12`.
    Double,
}

/// Ordinate values.
#[derive(Clone, Debug, PartialEq)]
pub enum FunctionValues {
    /// Real ordinates.
    Real(Vec<f64>),
    /// Complex ordinates.
    Complex(Vec<Complex<f64>>),
}

impl FunctionValues {
    /// Number of values.
    pub fn len(&self) -> usize {
        match self {
            FunctionValues::Real(v) => v.len(),
            FunctionValues::Complex(v) => v.len(),
        }
    }
    /// Whether there are no values.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// The values as complex numbers (a real value has zero imaginary part).
    pub fn to_complex(&self) -> Vec<Complex<f64>> {
        match self {
            FunctionValues::Real(v) => v.iter().map(|&x| Complex::new(x, 0.0)).collect(),
            FunctionValues::Complex(v) => v.clone(),
        }
    }
}

/// Function type codes of record 6 field 1 that the toolkit names.
pub mod function_type {
    /// Time response.
    pub const TIME_RESPONSE: i64 = 1;
    /// Frequency response function.
    pub const FRF: i64 = 4;
}

/// A dataset 58 (ASCII or binary).
#[derive(Clone, Debug, PartialEq)]
pub struct Function {
    /// Records 1-5.
    pub id_lines: [String; 5],
    /// Function type (record 6 field 1): 1 time response, 4 FRF, ... (docs/uff-format.md).
    pub function_type: i64,
    /// Function identification number.
    pub function_id: i64,
    /// Version / sequence number.
    pub version: i64,
    /// Load case (0: single-point excitation).
    pub load_case: i64,
    /// Response DOF.
    pub response: Dof,
    /// Reference (excitation) DOF.
    pub reference: Dof,
    /// Precision the ordinates were stored in.
    pub precision: OrdinatePrecision,
    /// Abscissa.
    pub abscissa: Abscissa,
    /// Z-axis value.
    pub z_value: f64,
    /// Records 8-11: abscissa, ordinate numerator, ordinate denominator, z axis.
    pub axes: [AxisInfo; 4],
    /// The values (record 12).
    pub values: FunctionValues,
    /// Whether the dataset was binary (58b).
    pub binary: bool,
}

impl Function {
    /// The abscissa of every value.
    pub fn abscissa_values(&self) -> Vec<f64> {
        match &self.abscissa {
            Abscissa::Even { start, step } => (0..self.values.len())
                .map(|i| start + i as f64 * step)
                .collect(),
            Abscissa::Uneven(x) => x.clone(),
        }
    }
}

/// Allocation cap while reading: a corrupt count never reserves more than this up front.
const RESERVE_CAP: usize = 1 << 20;

/// Parses one dataset 58 or 58b block.
pub fn parse(block: &Block, ctx: &Context) -> Result<Function> {
    let lines = &block.lines;
    if lines.len() < 11 {
        return Err(ctx.error(
            "records",
            format!(
                "{} header records; a dataset 58 has 11 before its data",
                lines.len()
            ),
        ));
    }
    let id_lines: [String; 5] = std::array::from_fn(|k| lines[k].clone());

    // Record 6: Format(2(I5,I10),2(1X,10A1,I10,I4)).
    let r6 = &lines[5];
    let by_columns = || -> Option<(Vec<i64>, Dof, Dof)> {
        let head = integers(r6, &[5, 10, 5, 10])?;
        let dof = |name: (usize, usize), node: (usize, usize), dir: (usize, usize)| {
            Some(Dof {
                entity: column(r6, name.0, name.1).to_string(),
                node: column(r6, node.0, node.1).parse().ok()?,
                direction: column(r6, dir.0, dir.1).parse().ok()?,
            })
        };
        Some((
            head,
            dof((32, 41), (42, 51), (52, 55))?,
            dof((57, 66), (67, 76), (77, 80))?,
        ))
    };
    let by_tokens = || -> Option<(Vec<i64>, Dof, Dof)> {
        let t: Vec<&str> = r6.split_whitespace().collect();
        if t.len() != 10 {
            return None;
        }
        let int = |k: usize| t[k].parse::<i64>().ok();
        Some((
            vec![int(0)?, int(1)?, int(2)?, int(3)?],
            Dof {
                entity: t[4].to_string(),
                node: int(5)?,
                direction: int(6)?,
            },
            Dof {
                entity: t[7].to_string(),
                node: int(8)?,
                direction: int(9)?,
            },
        ))
    };
    let (head, response, reference) = by_columns().or_else(by_tokens).ok_or_else(|| {
        ctx.record_error(
            6,
            "DOF identification",
            format!(
                "`{r6}` is not Format(2(I5,I10),2(1X,10A1,I10,I4)): function type, id, \
                 version, load case, response entity/node/direction, reference entity/node/direction"
            ),
        )
    })?;
    for (dof, what) in [(&response, "response"), (&reference, "reference")] {
        if !(-6..=6).contains(&dof.direction) {
            return Err(ctx.record_error(
                6,
                &format!("{what} direction"),
                format!("{}; allowed: -6..=6", dof.direction),
            ));
        }
    }

    // Record 7: Format(3I10,3E13.5).
    let r7 = &lines[6];
    let form = integers(r7, &[10, 10, 10])
        .zip(Some(
            [(31, 43), (44, 56), (57, 69)].map(|(a, b)| parse_real(column(r7, a, b))),
        ))
        .and_then(|(ints, reals)| {
            Some((
                ints,
                [reals[0]?, reals[1].unwrap_or(0.0), reals[2].unwrap_or(0.0)],
            ))
        })
        .or_else(|| {
            let t: Vec<&str> = r7.split_whitespace().collect();
            if t.len() != 6 {
                return None;
            }
            let ints: Option<Vec<i64>> = t[..3].iter().map(|x| x.parse().ok()).collect();
            let reals: Option<Vec<f64>> = t[3..].iter().map(|x| parse_real(x)).collect();
            let reals = reals?;
            Some((ints?, [reals[0], reals[1], reals[2]]))
        })
        .ok_or_else(|| {
            ctx.record_error(
                7,
                "data form",
                format!(
                    "`{r7}` is not Format(3I10,3E13.5): ordinate type, number of values, \
                     spacing, abscissa minimum, increment, z value"
                ),
            )
        })?;
    let (ordinate_type, count, spacing) = (form.0[0], form.0[1], form.0[2]);
    let [start, step, z_value] = form.1;
    let (precision, complex) = match ordinate_type {
        2 => (OrdinatePrecision::Single, false),
        4 => (OrdinatePrecision::Double, false),
        5 => (OrdinatePrecision::Single, true),
        6 => (OrdinatePrecision::Double, true),
        other => {
            return Err(ctx.record_error(
                7,
                "ordinate data type",
                format!(
                    "{other}; allowed: 2 (real single), 4 (real double), 5 (complex single), \
                     6 (complex double)"
                ),
            ))
        }
    };
    let count = usize::try_from(count)
        .ok()
        .filter(|&c| c >= 1)
        .ok_or_else(|| {
            ctx.record_error(
                7,
                "number of values",
                format!("{count}; allowed: 1 or more"),
            )
        })?;
    let even = match spacing {
        1 => true,
        0 => false,
        other => {
            return Err(ctx.record_error(
                7,
                "abscissa spacing",
                format!("{other}; allowed: 0 (uneven) or 1 (even)"),
            ))
        }
    };
    if even && !(step.is_finite() && start.is_finite()) {
        return Err(ctx.record_error(
            7,
            "abscissa",
            format!("minimum {start} and increment {step} must be finite"),
        ));
    }

    // Records 8-11: Format(I10,3I5,2(1X,20A1)).
    let mut axes = Vec::with_capacity(4);
    for (k, line) in lines[7..11].iter().enumerate() {
        let ints = integers(line, &[10, 5, 5, 5])
            .or_else(|| {
                // Labels may be blank: the four integers lead the record.
                let t: Vec<i64> = line
                    .split_whitespace()
                    .take(4)
                    .map_while(|x| x.parse().ok())
                    .collect();
                (t.len() == 4).then_some(t)
            })
            .ok_or_else(|| {
                ctx.record_error(
                    8 + k,
                    "data characteristics",
                    format!(
                        "`{line}` is not Format(I10,3I5,2(1X,20A1)): specific data type, \
                         length, force and temperature exponents, label, units"
                    ),
                )
            })?;
        axes.push(AxisInfo {
            specific_data_type: ints[0],
            length_exponent: ints[1],
            force_exponent: ints[2],
            temperature_exponent: ints[3],
            label: column(line, 27, 46).to_string(),
            units: column(line, 48, 67).to_string(),
        });
    }
    let axes: [AxisInfo; 4] = axes.try_into().expect("four records");

    // Record 12.
    let per_point = usize::from(!even) + if complex { 2 } else { 1 };
    let raw = match &block.binary {
        Some(binary) => decode_binary(binary, count, per_point, precision, even, ctx)?,
        None => {
            let total = count.checked_mul(per_point).ok_or_else(|| {
                ctx.record_error(7, "number of values", format!("{count} is too large"))
            })?;
            let (values, used) = reals(
                &lines[11..],
                total,
                record12_widths(precision, complex, even),
                ctx,
                12,
                "data values",
            )?;
            if 11 + used != lines.len() {
                return Err(ctx.record_error(
                    12,
                    "data values",
                    format!(
                        "{} lines after the {count} values record 7 announced",
                        lines.len() - 11 - used
                    ),
                ));
            }
            values
        }
    };
    if let Some(index) = raw.iter().position(|v| !v.is_finite()) {
        return Err(ctx.record_error(
            12,
            "data values",
            format!("value {} is not finite", index + 1),
        ));
    }
    let mut abscissa_values = Vec::new();
    let mut real = Vec::new();
    let mut complex_values = Vec::new();
    for point in raw.chunks_exact(per_point) {
        let y = if even {
            point
        } else {
            abscissa_values.push(point[0]);
            &point[1..]
        };
        if complex {
            complex_values.push(Complex::new(y[0], y[1]));
        } else {
            real.push(y[0]);
        }
    }
    Ok(Function {
        id_lines,
        function_type: head[0],
        function_id: head[1],
        version: head[2],
        load_case: head[3],
        response,
        reference,
        precision,
        abscissa: if even {
            Abscissa::Even { start, step }
        } else {
            Abscissa::Uneven(abscissa_values)
        },
        z_value,
        axes,
        values: if complex {
            FunctionValues::Complex(complex_values)
        } else {
            FunctionValues::Real(real)
        },
        binary: block.binary.is_some(),
    })
}

/// The values of a 58b record 12, as f64 in file order (x, then re/im or y, per point).
fn decode_binary(
    binary: &super::block::BinaryData,
    count: usize,
    per_point: usize,
    precision: OrdinatePrecision,
    even: bool,
    ctx: &Context,
) -> Result<Vec<f64>> {
    let size = match precision {
        OrdinatePrecision::Single => 4,
        OrdinatePrecision::Double => 8,
    };
    let bytes = &binary.bytes;
    let little = binary.byte_order == 1;
    // Uneven data: the abscissa is 4 bytes by the document and `size` in pyuff's files; the
    // byte count tells which (module documentation of `block`).
    let abscissa_size = if even {
        0
    } else if bytes.len() == count * ((per_point - 1) * size + 4) {
        4
    } else {
        size
    };
    let point_bytes = abscissa_size + (per_point - usize::from(!even)) * size;
    if bytes.len() != count * point_bytes {
        return Err(ctx.record_error(
            12,
            "binary data",
            format!(
                "{} bytes for {count} values of {point_bytes} bytes each",
                bytes.len()
            ),
        ));
    }
    let read = |chunk: &[u8]| -> f64 {
        match chunk.len() {
            4 => {
                let b: [u8; 4] = chunk.try_into().expect("4 bytes");
                f64::from(if little {
                    f32::from_le_bytes(b)
                } else {
                    f32::from_be_bytes(b)
                })
            }
            _ => {
                let b: [u8; 8] = chunk.try_into().expect("8 bytes");
                if little {
                    f64::from_le_bytes(b)
                } else {
                    f64::from_be_bytes(b)
                }
            }
        }
    };
    let mut values = Vec::with_capacity((count * per_point).min(RESERVE_CAP));
    for point in bytes.chunks_exact(point_bytes) {
        let mut offset = 0;
        if !even {
            values.push(read(&point[..abscissa_size]));
            offset = abscissa_size;
        }
        for value in point[offset..].chunks_exact(size) {
            values.push(read(value));
        }
    }
    Ok(values)
}
