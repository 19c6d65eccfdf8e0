//! Writing universal files in the layouts the reader takes (docs/uff-format.md): dataset 164 (units),
//! 2411 and 15 (nodes), 58 (ASCII, in the Fortran formats of its record 12 table) or 58b
//! (little-endian IEEE), and 55. Line ends are LF; empty ID lines are written as `NONE`.

use std::path::Path;

use super::dataset58::{Abscissa, AxisInfo, Function, FunctionValues, OrdinatePrecision};
use super::fields::{format_int, format_real};
use super::{NodalData, Node, UffFile, Units};
use crate::{Error, Result};

fn begin(out: &mut Vec<u8>, number: &str) {
    out.extend_from_slice(format!("    -1\n{number:>6}\n").as_bytes());
}

fn end(out: &mut Vec<u8>) {
    out.extend_from_slice(b"    -1\n");
}

fn line(out: &mut Vec<u8>, text: &str) {
    out.extend_from_slice(text.as_bytes());
    out.push(b'\n');
}

fn id_line(text: &str) -> String {
    let t = text.trim();
    if t.is_empty() {
        "NONE".to_string()
    } else {
        t.chars().take(80).collect()
    }
}

/// Writes `values` `per_line` to a line, each as `format`.
fn value_lines(out: &mut Vec<u8>, values: &[f64], per_line: usize, format: impl Fn(f64) -> String) {
    for chunk in values.chunks(per_line) {
        let text: String = chunk.iter().map(|&v| format(v)).collect();
        line(out, &text);
    }
}

/// Dataset 164.
pub fn units(out: &mut Vec<u8>, units: &Units) {
    begin(out, "164");
    let description: String = units.description.chars().take(20).collect();
    line(
        out,
        &format!(
            "{}{description:<20}{}",
            format_int(units.code, 10),
            format_int(units.temperature_mode, 10)
        ),
    );
    let d = |v: f64| format_real(v, 25, 17, 'D');
    line(
        out,
        &format!(
            "{}{}{}",
            d(units.length_factor),
            d(units.force_factor),
            d(units.temperature_factor)
        ),
    );
    line(out, &d(units.temperature_offset));
    end(out);
}

/// Dataset 2411 (double precision coordinates).
pub fn nodes_2411(out: &mut Vec<u8>, nodes: &[Node]) {
    begin(out, "2411");
    for n in nodes {
        line(
            out,
            &[n.label, n.coordinate_system, n.displacement_system, n.color]
                .map(|v| format_int(v, 10))
                .concat(),
        );
        line(
            out,
            &n.position.map(|c| format_real(c, 25, 16, 'D')).concat(),
        );
    }
    end(out);
}

fn axis_line(axis: &AxisInfo) -> String {
    let label: String = axis.label.chars().take(20).collect();
    let units: String = axis.units.chars().take(20).collect();
    format!(
        "{}{}{}{} {label:<20} {units:<20}",
        format_int(axis.specific_data_type, 10),
        format_int(axis.length_exponent, 5),
        format_int(axis.force_exponent, 5),
        format_int(axis.temperature_exponent, 5)
    )
}

/// Dataset 58 (`binary`: 58b, little-endian IEEE). Errors when an uneven abscissa does not have
/// one value per ordinate.
pub fn function(out: &mut Vec<u8>, f: &Function, binary: bool) -> Result<()> {
    let count = f.values.len();
    let complex = matches!(f.values, FunctionValues::Complex(_));
    let ordinate_type = match (f.precision, complex) {
        (OrdinatePrecision::Single, false) => 2,
        (OrdinatePrecision::Double, false) => 4,
        (OrdinatePrecision::Single, true) => 5,
        (OrdinatePrecision::Double, true) => 6,
    };
    let (spacing, start, step, abscissa) = match &f.abscissa {
        Abscissa::Even { start, step } => (1, *start, *step, None),
        Abscissa::Uneven(x) => {
            if x.len() != count {
                return Err(Error::input(
                    "uff writer",
                    "abscissa",
                    format!("{} abscissa values for {count} ordinates", x.len()),
                ));
            }
            (0, 0.0, 0.0, Some(x))
        }
    };
    // File order per point: x (uneven), then y or re, im.
    let ordinate = f.values.to_complex();
    let mut values = Vec::with_capacity(count * 3);
    for (i, y) in ordinate.iter().enumerate() {
        if let Some(x) = abscissa {
            values.push(x[i]);
        }
        values.push(y.re);
        if complex {
            values.push(y.im);
        }
    }
    let size = match f.precision {
        OrdinatePrecision::Single => 4,
        OrdinatePrecision::Double => 8,
    };
    if binary {
        let byte_count = values.len() * size;
        line(
            out,
            &format!(
                "    -1\n    58b{:>6}{:>6}{:>12}{:>12}{:>6}{:>6}{:>12}{:>12}",
                1, 2, 11, byte_count, 0, 0, 0, 0
            ),
        );
    } else {
        begin(out, "58");
    }
    for text in &f.id_lines {
        line(out, &id_line(text));
    }
    let entity = |e: &str| -> String {
        let e = if e.trim().is_empty() {
            "NONE"
        } else {
            e.trim()
        };
        e.chars().take(10).collect()
    };
    line(
        out,
        &format!(
            "{}{}{}{} {:<10}{}{} {:<10}{}{}",
            format_int(f.function_type, 5),
            format_int(f.function_id, 10),
            format_int(f.version, 5),
            format_int(f.load_case, 10),
            entity(&f.response.entity),
            format_int(f.response.node, 10),
            format_int(f.response.direction, 4),
            entity(&f.reference.entity),
            format_int(f.reference.node, 10),
            format_int(f.reference.direction, 4),
        ),
    );
    line(
        out,
        &format!(
            "{}{}{}{}{}{}",
            format_int(ordinate_type, 10),
            format_int(count as i64, 10),
            format_int(spacing, 10),
            format_real(start, 13, 5, 'E'),
            format_real(step, 13, 5, 'E'),
            format_real(f.z_value, 13, 5, 'E')
        ),
    );
    for axis in &f.axes {
        line(out, &axis_line(axis));
    }
    if binary {
        // Uneven abscissae are written with the ordinate's size, as pyuff does.
        for v in &values {
            match f.precision {
                OrdinatePrecision::Single => out.extend_from_slice(&(*v as f32).to_le_bytes()),
                OrdinatePrecision::Double => out.extend_from_slice(&v.to_le_bytes()),
            }
        }
        end(out);
        return Ok(());
    }
    let single = |v: f64| format_real(v, 13, 5, 'E');
    let double = |v: f64| format_real(v, 20, 12, 'E');
    match (f.precision, abscissa.is_some(), complex) {
        (OrdinatePrecision::Single, _, _) => value_lines(out, &values, 6, single),
        (OrdinatePrecision::Double, false, _) => value_lines(out, &values, 4, double),
        (OrdinatePrecision::Double, true, complex) => {
            // 2(E13.5,E20.12) real, or E13.5,2E20.12 complex: abscissa single precision.
            let per_point = if complex { 3 } else { 2 };
            let points_per_line = if complex { 1 } else { 2 };
            for chunk in values.chunks(per_point * points_per_line) {
                let text: String = chunk
                    .iter()
                    .enumerate()
                    .map(|(k, &v)| {
                        if k % per_point == 0 {
                            single(v)
                        } else {
                            double(v)
                        }
                    })
                    .collect();
                line(out, &text);
            }
        }
    }
    end(out);
    Ok(())
}

/// Dataset 55.
pub fn nodal_data(out: &mut Vec<u8>, data: &NodalData) {
    begin(out, "55");
    for text in &data.id_lines {
        line(out, &id_line(text));
    }
    line(
        out,
        &[
            data.model_type,
            data.analysis_type,
            data.data_characteristic,
            data.specific_data_type,
            if data.complex { 5 } else { 2 },
            data.values_per_node as i64,
        ]
        .map(|v| format_int(v, 10))
        .concat(),
    );
    let mut ints = vec![data.integers.len() as i64, data.reals.len() as i64];
    ints.extend(&data.integers);
    for chunk in ints.chunks(8) {
        line(
            out,
            &chunk.iter().map(|&v| format_int(v, 10)).collect::<String>(),
        );
    }
    let e = |v: f64| format_real(v, 13, 5, 'E');
    value_lines(out, &data.reals, 6, e);
    for node in &data.nodes {
        line(out, &format_int(node.node, 10));
        let values: Vec<f64> = node
            .values
            .iter()
            .flat_map(|c| {
                if data.complex {
                    vec![c.re, c.im]
                } else {
                    vec![c.re]
                }
            })
            .collect();
        value_lines(out, &values, 6, e);
    }
    end(out);
}

/// The bytes of a whole file: units, nodes (2411), functions (58 or 58b), nodal data (55).
pub fn to_bytes(file: &UffFile, binary_functions: bool) -> Result<Vec<u8>> {
    let mut out = Vec::new();
    if let Some(u) = &file.units {
        units(&mut out, u);
    }
    if !file.nodes.is_empty() {
        nodes_2411(&mut out, &file.nodes);
    }
    for f in &file.functions {
        function(&mut out, f, binary_functions)?;
    }
    for d in &file.nodal_data {
        nodal_data(&mut out, d);
    }
    Ok(out)
}

/// Writes `file` to `path` (see [`to_bytes`]).
pub fn write_uff(path: &Path, file: &UffFile, binary_functions: bool) -> Result<()> {
    let bytes = to_bytes(file, binary_functions)?;
    std::fs::write(path, bytes).map_err(|e| Error::io(path, e))
}
