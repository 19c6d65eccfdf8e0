//! Universal files: the reader against files written by an independent writer (pyuff 2.5.8,
//! `tests/fixtures/uff/make_uff_fixtures.py`), whose truth is in `expected.json`; our writer
//! through our reader in every dataset-58 layout; malformed files refused with the dataset and
//! record named.

use std::path::{Path, PathBuf};

use rustfft::num_complex::Complex;
use serde_json::Value;
use squeal::testdata::uff::{
    self, Abscissa, AxisInfo, Dof, Function, FunctionValues, NodalData, NodalValues, Node,
    OrdinatePrecision, UffFile, Units,
};

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/uff")
        .join(name)
}

fn expected() -> Value {
    serde_json::from_str(&std::fs::read_to_string(fixture("expected.json")).unwrap()).unwrap()
}

/// The FRF samples of expected.json as (response node, index, value).
fn samples() -> Vec<(i64, usize, Complex<f64>)> {
    expected()["frf_samples"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            (
                s["response_node"].as_i64().unwrap(),
                s["index"].as_u64().unwrap() as usize,
                Complex::new(s["re"].as_f64().unwrap(), s["im"].as_f64().unwrap()),
            )
        })
        .collect()
}

fn check_frf_file(name: &str, relative_tolerance: f64) {
    let file = uff::read_uff(&fixture(name)).unwrap();
    let truth = expected();
    assert_eq!(file.functions.len(), 4, "{name}");
    let axis = &truth["frequency_axis"];
    for (k, f) in file.functions.iter().enumerate() {
        assert_eq!(f.function_type, 4, "{name}: FRF");
        assert_eq!(f.response.node, k as i64 + 1);
        assert_eq!(f.response.direction, 3);
        assert_eq!(f.reference.node, truth["reference_node"].as_i64().unwrap());
        assert_eq!(f.precision, OrdinatePrecision::Double);
        assert_eq!(f.values.len(), axis["count"].as_u64().unwrap() as usize);
        assert_eq!(
            f.abscissa,
            Abscissa::Even {
                start: axis["start_hz"].as_f64().unwrap(),
                step: axis["step_hz"].as_f64().unwrap()
            }
        );
        assert_eq!(
            [8, 9, 10].map(|r| f.axes[r - 8].specific_data_type),
            [18, 8, 13],
            "frequency, displacement over force"
        );
    }
    for (node, index, value) in samples() {
        let f = &file.functions[(node - 1) as usize];
        let got = f.values.to_complex()[index];
        for (a, b) in [(got.re, value.re), (got.im, value.im)] {
            assert!(
                (a - b).abs() <= relative_tolerance * b.abs(),
                "{name}: node {node} index {index}: {a} vs {b}"
            );
        }
    }
}

/// Binary f64 data are the truth bit for bit; ASCII `%20.11e` keeps 12 significant digits of
/// each part, so each part is within 5e-12 of itself (half a unit in the 12th digit).
#[test]
fn pyuff_frfs_read_exactly_in_binary_and_to_twelve_digits_in_ascii() {
    check_frf_file("frf_binary.uff", 0.0);
    check_frf_file("frf_ascii.uff", 5e-12);
    // pyuff's own 58b files under-count complex data (24008 declared, 48016 follow): the
    // length that reaches the closing line is taken.
    check_frf_file("frf_binary_pyuff.uff", 0.0);
    let file = uff::read_uff(&fixture("frf_binary.uff")).unwrap();
    assert!(file.functions.iter().all(|f| f.binary));
}

#[test]
fn nodes_units_and_mode_shapes_match_the_fixture_model() {
    let truth = expected();
    let coordinates: Vec<Vec<f64>> =
        serde_json::from_value(truth["coordinates_m"].clone()).unwrap();
    for name in ["nodes15.uff", "nodes2411.uff"] {
        let file = uff::read_uff(&fixture(name)).unwrap();
        assert_eq!(file.nodes.len(), 4);
        for (node, xyz) in file.nodes.iter().zip(&coordinates) {
            // Both files hold these coordinates exactly (0.1 is written as 1.00000E-01).
            assert_eq!(node.position.to_vec(), *xyz, "{name}");
        }
    }
    let units = uff::read_uff(&fixture("units164.uff"))
        .unwrap()
        .units
        .unwrap();
    assert_eq!((units.code, units.temperature_mode), (1, 2));
    assert_eq!(
        [
            units.length_factor,
            units.force_factor,
            units.temperature_factor
        ],
        [1.0; 3]
    );
    assert!((units.temperature_offset - 273.15).abs() < 1e-12);

    let modes = uff::read_uff(&fixture("modes55.uff")).unwrap().nodal_data;
    let model = &truth["model"];
    assert_eq!(modes.len(), 3);
    for (r, mode) in modes.iter().enumerate() {
        assert_eq!(mode.analysis_type, 2);
        assert_eq!(mode.mode_number(), Some(r as i64 + 1));
        assert_eq!(mode.frequency_hz(), model["frequencies_hz"][r].as_f64());
        assert_eq!(mode.damping_ratio(), model["damping_ratios"][r].as_f64());
        for (k, node) in mode.nodes.iter().enumerate() {
            let phi = model["mode_shapes"][r][k].as_f64().unwrap();
            assert_eq!(node.node, k as i64 + 1);
            assert_eq!(
                node.values,
                vec![
                    Complex::new(0.0, 0.0),
                    Complex::new(0.0, 0.0),
                    Complex::new(phi, 0.0)
                ]
            );
        }
    }
}

/// Deterministic test values over several decades, both signs.
fn values(count: usize, seed: u64) -> Vec<f64> {
    let mut state = seed;
    (0..count)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let unit = (state >> 11) as f64 / (1u64 << 53) as f64;
            (unit - 0.5) * 10f64.powi((state % 13) as i32 - 8)
        })
        .collect()
}

fn function(precision: OrdinatePrecision, complex: bool, even: bool, seed: u64) -> Function {
    let count = 37; // not a multiple of any values-per-line count: partial last lines
    let y = values(2 * count, seed);
    Function {
        id_lines: [
            format!("function {seed}"),
            String::new(),
            "25-Nov-26 12:00:00".into(),
            "NONE".into(),
            "NONE".into(),
        ],
        function_type: if complex { 4 } else { 1 },
        function_id: seed as i64,
        version: 0,
        load_case: 0,
        response: Dof {
            entity: "wheel".into(),
            node: 100 + seed as i64,
            direction: -2,
        },
        reference: Dof {
            entity: "NONE".into(),
            node: 7,
            direction: 3,
        },
        precision,
        abscissa: if even {
            Abscissa::Even {
                start: 2.5,
                step: 0.5,
            }
        } else {
            Abscissa::Uneven((0..count).map(|i| 1.0 + 0.25 * (i * i) as f64).collect())
        },
        z_value: 0.0,
        axes: [
            AxisInfo::new(18, "Frequency", "Hz"),
            AxisInfo::new(12, "Acceleration", "m/s^2"),
            AxisInfo::new(13, "Force", "N"),
            AxisInfo::new(0, "NONE", "NONE"),
        ],
        values: if complex {
            FunctionValues::Complex(
                y.chunks_exact(2)
                    .map(|c| Complex::new(c[0], c[1]))
                    .collect(),
            )
        } else {
            FunctionValues::Real(y[..count].to_vec())
        },
        binary: false,
    }
}

/// Relative error of a value written with `digits` significant digits: half a unit in the last.
fn close(a: f64, b: f64, digits: i32) -> bool {
    (a - b).abs() <= 0.5 * 10f64.powi(1 - digits) * b.abs() * (1.0 + 1e-9)
}

#[test]
fn our_writer_round_trips_through_our_reader_in_every_layout() {
    let mut file = UffFile {
        units: Some(Units {
            code: 5,
            description: "MM (milli newton)".into(),
            temperature_mode: 1,
            length_factor: 1000.0,
            force_factor: 1000.0,
            temperature_factor: 1.0,
            temperature_offset: 273.15,
        }),
        nodes: vec![Node {
            label: 12,
            coordinate_system: 0,
            displacement_system: 0,
            color: 8,
            position: [460.0, -12.5, 0.125],
        }],
        ..Default::default()
    };
    let mut seed = 1;
    for precision in [OrdinatePrecision::Single, OrdinatePrecision::Double] {
        for complex in [false, true] {
            for even in [true, false] {
                file.functions
                    .push(function(precision, complex, even, seed));
                seed += 1;
            }
        }
    }
    file.nodal_data.push(NodalData {
        id_lines: std::array::from_fn(|k| format!("mode line {k}")),
        model_type: 1,
        analysis_type: 3,
        data_characteristic: 2,
        specific_data_type: 8,
        complex: true,
        values_per_node: 3,
        integers: vec![1, 4],
        reals: vec![-12.5, 6283.0, 1.0, 0.0, 0.0, 0.0],
        nodes: (1..=3)
            .map(|n| NodalValues {
                node: n,
                values: vec![Complex::new(0.5 * n as f64, -0.25); 3],
            })
            .collect(),
    });
    for binary in [false, true] {
        let bytes = uff::write::to_bytes(&file, binary).unwrap();
        let back = uff::parse_uff(&bytes, "round trip").unwrap();
        assert_eq!(back.units, file.units);
        assert_eq!(back.nodes, file.nodes);
        assert_eq!(
            back.node_position_m(12),
            Some([0.46, -0.0125, 0.000125]),
            "dataset 164's length factor gives metres"
        );
        assert_eq!(back.nodal_data, file.nodal_data, "values exact at 6 digits");
        assert_eq!(back.functions.len(), file.functions.len());
        for (a, b) in back.functions.iter().zip(&file.functions) {
            assert_eq!(a.binary, binary);
            assert_eq!(
                (
                    &a.id_lines[0],
                    &a.id_lines[1],
                    a.function_type,
                    a.function_id
                ),
                (
                    &b.id_lines[0],
                    &"NONE".to_string(),
                    b.function_type,
                    b.function_id
                )
            );
            assert_eq!(
                (&a.response, &a.reference, a.precision),
                (&b.response, &b.reference, b.precision)
            );
            assert_eq!(a.axes, b.axes);
            // Significant digits kept: ASCII E13.5 6, E20.12 13; binary f32 ~7.2, f64 exact.
            let digits = match (binary, a.precision) {
                (false, OrdinatePrecision::Single) => 6,
                (false, OrdinatePrecision::Double) => 13,
                (true, OrdinatePrecision::Single) => 7,
                (true, OrdinatePrecision::Double) => 17,
            };
            let (got, want) = (a.values.to_complex(), b.values.to_complex());
            assert_eq!(got.len(), want.len());
            for (g, w) in got.iter().zip(&want) {
                assert!(
                    close(g.re, w.re, digits) && close(g.im, w.im, digits),
                    "{g} vs {w}"
                );
            }
            // Uneven abscissae: E13.5 in ASCII (6 digits), the ordinate's size in binary.
            let abscissa_digits = if binary { digits } else { 6 };
            for (x, y) in a.abscissa_values().iter().zip(b.abscissa_values()) {
                assert!(close(*x, y, abscissa_digits), "{x} vs {y}");
            }
        }
    }
}

fn error_of(text: &str) -> String {
    let err = uff::parse_uff(text.as_bytes(), "bad.uff").unwrap_err();
    assert_eq!(err.exit_code(), 2, "{err}");
    err.to_string()
}

#[test]
fn malformed_files_name_the_dataset_record_and_allowed_values() {
    let good = std::fs::read_to_string(fixture("modes55.uff")).unwrap();
    assert!(uff::parse_uff(good.as_bytes(), "good").is_ok());
    // Text outside a block, a missing closing line, an empty file.
    assert!(error_of("hello\n").contains("outside a dataset"));
    assert!(
        error_of("    -1\n    15\n         1         0         0         8  0.0 0.0 0.0\n")
            .contains("must end")
    );
    assert!(error_of("").contains("no dataset"));
    // Dataset 55 with a data type that is neither real nor complex.
    let bad = good.replacen("         2         3", "         7         3", 1);
    let text = error_of(&bad);
    assert!(
        text.contains("dataset 55") && text.contains("record 6") && text.contains("allowed: 2"),
        "{text}"
    );
    // A node value that is not a number.
    let bad = good.replacen("0.00000e+00", "0.0000x+00", 1);
    assert!(error_of(&bad).contains("is not a number"));

    let frf = std::fs::read(fixture("frf_binary.uff")).unwrap();
    // A 58b block cut short: neither byte count reaches the closing line.
    let cut = &frf[..frf.len() / 5];
    let err = uff::parse_uff(cut, "cut.uff").unwrap_err().to_string();
    assert!(
        err.contains("binary data") && err.contains("closing"),
        "{err}"
    );
    // Ordinate type 3 does not exist.
    let ascii = std::fs::read_to_string(fixture("frf_ascii.uff")).unwrap();
    let bad = ascii.replacen("         6      3001", "         3      3001", 1);
    let text = error_of(&bad);
    assert!(
        text.contains("record 7")
            && text.contains("ordinate data type")
            && text.contains("allowed"),
        "{text}"
    );
    // Fewer values than record 7 announces.
    let bad = ascii.replacen("      3001", "      3002", 1);
    assert!(
        error_of(&bad).contains("6002 of 6004 values"),
        "{}",
        error_of(&bad)
    );
}

/// `values` as one record line in Fortran fields of `widths` (repeated) that fill their
/// columns: a negative value leaves no blank before its sign (`1.234567E+00-2.500000E-01`).
fn glued_line(values: &[f64], widths: &[usize]) -> String {
    values
        .iter()
        .zip(widths.iter().cycle())
        .map(|(&v, &w)| uff::fields::format_real(v, w, w - 7, 'E'))
        .collect()
}

/// Whether a line holds two values with no blank between them: an exponent's two digits
/// followed by a minus sign.
fn glued(line: &str) -> bool {
    let b = line.as_bytes();
    (4..b.len()).any(|i| {
        b[i] == b'-' && b[i - 1].is_ascii_digit() && b[i - 2].is_ascii_digit() && b[i - 4] == b'E'
    })
}

/// Issue 53, items 14 and 15: data records written in fixed columns with no blank before a
/// minus sign (pyuff's `sample_test` dataset 55 files) are read by their field widths, in
/// datasets 55 and 58 (double precision, uneven, complex: `E13.5,2E20.12`); a dataset 164 with
/// a blank temperature-mode field (Simcenter Testlab) reads it as Fortran does, 0.
#[test]
fn fixed_width_records_without_blanks_and_blank_integer_fields_read_as_fortran_does() {
    // Dataset 55: the fixture's mode shapes replaced by glued negative values.
    let text = std::fs::read_to_string(fixture("modes55.uff")).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let shape = |node: usize| [-0.125 * node as f64, -2.5e-3, 1.0 / node as f64];
    let mut replaced = 0;
    for k in 1..lines.len() {
        let node: Option<usize> = lines[k - 1].trim().parse().ok();
        let is_values = lines[k].contains("e+") || lines[k].contains("e-");
        if let (Some(node @ 1..=4), true) = (node, is_values) {
            if lines[k - 1].len() == 10 {
                lines[k] = glued_line(&shape(node), &[13]);
                replaced += 1;
            }
        }
    }
    assert_eq!(replaced, 12, "three modes of four nodes");
    assert!(lines.iter().any(|l| glued(l)), "a glued pair");
    let file = uff::parse_uff(lines.join("\n").as_bytes(), "glued55.uff").unwrap();
    for mode in &file.nodal_data {
        for node in &mode.nodes {
            let want = shape(node.node as usize);
            for (got, want) in node.values.iter().zip(want) {
                // E13.5 with 6 decimals written: the value to 7 significant digits.
                assert!(
                    (got.re - want).abs() <= 1e-6 * want.abs(),
                    "{got} vs {want}"
                );
            }
        }
    }

    // Dataset 58, double precision, uneven, complex: record 12 rewritten glued.
    let f = function(OrdinatePrecision::Double, true, false, 7);
    let bytes = uff::write::to_bytes(
        &UffFile {
            functions: vec![f],
            ..Default::default()
        },
        false,
    )
    .unwrap();
    let text = String::from_utf8(bytes).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let start = lines.iter().position(|l| l.trim() == "58").unwrap() + 12;
    let end = start
        + lines[start..]
            .iter()
            .position(|l| l.trim() == "-1")
            .unwrap();
    let mut expected = Vec::new();
    for line in &mut lines[start..end] {
        let values: Vec<f64> = line
            .split_whitespace()
            .map(|t| t.replace('D', "E").parse().unwrap())
            .collect();
        *line = glued_line(&values, &[13, 20, 20]);
        let mut at = 0;
        for w in [13, 20, 20].iter().cycle().take(values.len()) {
            expected.push(line[at..at + w].trim().parse::<f64>().unwrap());
            at += w;
        }
    }
    assert!(lines[start..end]
        .iter()
        .any(|l| l.contains("E+00-") || l.contains("E-01-")));
    let file = uff::parse_uff(lines.join("\n").as_bytes(), "glued58.uff").unwrap();
    let g = &file.functions[0];
    let (Abscissa::Uneven(x), FunctionValues::Complex(y)) = (&g.abscissa, &g.values) else {
        panic!("an uneven complex function");
    };
    let read: Vec<f64> = x
        .iter()
        .zip(y)
        .flat_map(|(x, y)| [*x, y.re, y.im])
        .collect();
    // Exactly the numbers written, field by field.
    assert_eq!(read, expected);

    // Dataset 164 with its temperature mode left blank.
    let units = std::fs::read_to_string(fixture("units164.uff"))
        .unwrap()
        .replace("Meter (newton)         2", "Meter (newton)          ");
    let file = uff::parse_uff(units.as_bytes(), "testlab164.uff").unwrap();
    let units = file.units.unwrap();
    assert_eq!((units.code, units.temperature_mode), (1, 0));
    assert_eq!(units.description, "Meter (newton)");
}
