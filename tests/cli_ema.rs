//! `squeal ema` and `--hammer FILE.uff`: the command line of the experimental modal analysis.
//!
//! - `squeal ema` on the pyuff fixtures recovers the known modes and writes its files
//!   (estimated shapes as a universal file our reader takes back);
//! - bad options exit 2 with the option named and nothing written;
//! - a test synthesised from an FE model's own modes at a few of its nodes, given to
//!   `squeal modes --hammer`, pairs every test mode with the FE mode it came from (MAC > 0.99,
//!   frequency within 0.1 %), though the modes were numbered and labelled by nothing but the
//!   test's FRFs.

use std::path::{Path, PathBuf};
use std::process::Command;

use rustfft::num_complex::Complex;
use squeal::testdata::uff::{
    self, Abscissa, AxisInfo, Dof, Function, FunctionValues, Node, UffFile, Units,
};

fn temp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("squeal_cli_ema_{name}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn fixture(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/uff")
        .join(name)
}

fn squeal(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn ema_writes_modes_diagram_and_a_readable_shapes_file() {
    let dir = temp("run");
    let out = dir.join("ema");
    let uff_path = fixture("frf_binary.uff");
    let run = squeal(&[
        "ema",
        "--uff",
        uff_path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    for name in [
        "modes.csv",
        "modes.json",
        "modes.uff",
        "stabilisation.csv",
        "stabilisation.png",
        "stabilisation.svg",
    ] {
        assert!(out.join(name).exists(), "{name}");
    }
    let shapes = uff::read_uff(&out.join("modes.uff")).unwrap();
    let f: Vec<f64> = shapes
        .nodal_data
        .iter()
        .map(|d| d.frequency_hz().unwrap())
        .collect();
    assert_eq!(f.len(), 3);
    // The fixture's modes (tests/ema.rs checks the estimator; here the file carries them):
    // 6 significant digits of the eigenvalue in E13.5.
    for (got, want) in f.iter().zip([420.0, 1130.0, 2050.0]) {
        assert!((got / want - 1.0).abs() < 1e-5, "{got} vs {want}");
    }
    // Peak picking writes the same files but no diagram.
    let out = dir.join("peaks");
    let run = squeal(&[
        "ema",
        "--method",
        "peak-picking",
        "--uff",
        uff_path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(run.status.success());
    assert!(out.join("modes.csv").exists() && !out.join("stabilisation.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_ema_options_exit_2_naming_the_option_and_write_nothing() {
    let dir = temp("bad");
    let uff_path = fixture("frf_ascii.uff");
    let not_uff = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/hammer/synthetic_example.csv");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["--max-order", "3"], "--max-order"),
        (vec!["--max-order", "0"], "--max-order"),
        (vec!["--max-order", "400"], "--max-order"),
        (vec!["--fmax-hz", "5000"], "--fmin-hz/--fmax-hz"),
        (vec!["--fmin-hz", "-1"], "--fmin-hz/--fmax-hz"),
        (
            vec!["--fmin-hz", "2000", "--fmax-hz", "1000"],
            "--fmin-hz/--fmax-hz",
        ),
    ];
    for (k, (extra, field)) in cases.iter().enumerate() {
        let out = dir.join(format!("out{k}"));
        let mut args = vec![
            "ema",
            "--uff",
            uff_path.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend(extra);
        let run = squeal(&args);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{extra:?}: {stderr}");
        assert!(
            stderr.contains(field) && stderr.contains("allowed"),
            "{extra:?}: {stderr}"
        );
        assert!(!out.exists(), "{extra:?} wrote {}", out.display());
    }
    let out = dir.join("csv");
    let run = squeal(&[
        "ema",
        "--uff",
        not_uff.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let stderr = String::from_utf8_lossy(&run.stderr);
    assert_eq!(run.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("synthetic_example.csv") && stderr.contains("line 1"),
        "{stderr}"
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A steel bar 400 x 20 x 30 mm clamped at x = 0 (10 x 1 x 1 incompatible hexahedra, as
/// `squeal modes --mesh` builds it), its own modes below 1500 Hz with 1 % damping, "measured" in
/// Y and Z at four top-edge nodes with the hammer at the tip in Z. Modes without Z motion at the
/// tip (bending in Y) are not excited, so they are absent from the test: each test mode must
/// still find its own FE mode, not a neighbour in frequency.
#[test]
fn fe_modes_are_recovered_from_a_test_synthesised_from_them() {
    let dir = temp("bar");
    let bar = squeal::mesh::cuboid([10, 1, 1], [0.4, 0.02, 0.03], 1);
    let volume = squeal::mesh::volume::VolumeMesh::from(&bar);
    let mesh_file = dir.join("bar.vtu");
    squeal::mesh::vtu::write_volume(&volume, &mesh_file, &[]).unwrap();
    let model = squeal::model::modal::mesh_model(
        volume,
        squeal::material::Material::STEEL,
        &squeal::model::modal::Clamp::parse("x<0.001").unwrap(),
        squeal::fem::Hex8Kind::Incompatible,
        Some(1),
    )
    .unwrap();
    let fmax_hz = 1500.0;
    let run = squeal::modal::pipeline::solve_and_classify(&model, fmax_hz, 1).unwrap();
    let nodes = model.node_positions_m().to_vec();
    let flexible: Vec<usize> = (0..run.shapes.len())
        .filter(|&k| !run.shapes[k].2)
        .collect();
    assert!(
        flexible.len() >= 3,
        "{} flexible modes below {fmax_hz} Hz",
        flexible.len()
    );
    // Test points: the top edge y = 0.02, z = 0.03 at x = 0.1, 0.2, 0.3, 0.4 m; DOFs Y and Z.
    let labels: Vec<usize> = [0.1, 0.2, 0.3, 0.4]
        .iter()
        .map(|&x| squeal::testdata::ema::uff_modes::nearest_node(&nodes, [x, 0.02, 0.03]).0)
        .collect();
    let dofs: Vec<(usize, i64)> = labels.iter().flat_map(|&n| [(n, 2), (n, 3)]).collect();
    // Reference: the tip node in Z.
    let tip = labels[3];
    let participation = |k: usize| run.shapes[k].3[tip][2];
    let largest = flexible
        .iter()
        .map(|&k| participation(k).abs())
        .fold(0.0, f64::max);
    // Modes the hammer excites (the others have no Z motion at the tip: bending in Y).
    let excited: Vec<usize> = flexible
        .iter()
        .copied()
        .filter(|&k| participation(k).abs() > 0.01 * largest)
        .collect();
    println!(
        "FE modes below {fmax_hz} Hz: {:?}; excited: {:?}",
        flexible
            .iter()
            .map(|&k| run.shapes[k].0)
            .collect::<Vec<_>>(),
        excited.iter().map(|&k| run.shapes[k].0).collect::<Vec<_>>()
    );
    let step_hz = 0.5;
    let count = (fmax_hz / step_hz) as usize + 1;
    let functions: Vec<Function> = dofs
        .iter()
        .map(|&(node, direction)| {
            let values = (0..count)
                .map(|i| {
                    let w = 2.0 * std::f64::consts::PI * i as f64 * step_hz;
                    excited
                        .iter()
                        .map(|&k| {
                            let wr = 2.0 * std::f64::consts::PI * run.shapes[k].0;
                            let phi = run.shapes[k].3[node][(direction - 1) as usize];
                            Complex::new(phi * participation(k), 0.0)
                                / Complex::new(wr * wr - w * w, 2.0 * 0.01 * wr * w)
                        })
                        .sum()
                })
                .collect();
            Function {
                id_lines: Default::default(),
                function_type: 4,
                function_id: 1,
                version: 0,
                load_case: 0,
                response: Dof {
                    entity: "bar".into(),
                    node: node as i64 + 1,
                    direction,
                },
                reference: Dof {
                    entity: "bar".into(),
                    node: tip as i64 + 1,
                    direction: 3,
                },
                precision: uff::OrdinatePrecision::Double,
                abscissa: Abscissa::Even {
                    start: 0.0,
                    step: step_hz,
                },
                z_value: 0.0,
                axes: [
                    AxisInfo::new(18, "Frequency", "Hz"),
                    AxisInfo::new(8, "Displacement", "m"),
                    AxisInfo::new(13, "Force", "N"),
                    AxisInfo::new(0, "NONE", "NONE"),
                ],
                values: FunctionValues::Complex(values),
                binary: true,
            }
        })
        .collect();
    // Node coordinates in millimetres (dataset 164 says so): the reader converts.
    let test = UffFile {
        units: Some(Units {
            code: 10,
            description: "MN: mm (newton)".into(),
            length_factor: 1000.0,
            ..Units::si()
        }),
        nodes: labels
            .iter()
            .map(|&n| Node {
                label: n as i64 + 1,
                coordinate_system: 0,
                displacement_system: 0,
                color: 1,
                position: nodes[n].map(|c| c * 1000.0),
            })
            .collect(),
        functions,
        ..Default::default()
    };
    let test_file = dir.join("bar_test.uff");
    uff::write::write_uff(&test_file, &test, true).unwrap();

    let out = dir.join("modes");
    let run_cli = squeal(&[
        "modes",
        "--mesh",
        mesh_file.to_str().unwrap(),
        "--clamp",
        "x<0.001",
        "--fmax-hz",
        "1500",
        "--hammer",
        test_file.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&run_cli.stdout);
    assert!(
        run_cli.status.success(),
        "{}\n{stdout}",
        String::from_utf8_lossy(&run_cli.stderr)
    );
    for name in [
        "test_pairs.csv",
        "mac.csv",
        "mac.png",
        "stabilisation.png",
        "comparison.md",
        "modal_chart.png",
    ] {
        assert!(out.join(name).exists(), "{name}");
    }
    let pairs = std::fs::read_to_string(out.join("test_pairs.csv")).unwrap();
    println!("{pairs}");
    let rows: Vec<Vec<String>> = pairs
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    assert_eq!(
        rows.len(),
        excited.len(),
        "one test mode per excited FE mode"
    );
    let fe_frequency_hz: Vec<f64> = run.records.iter().map(|r| r.frequency_hz).collect();
    for (row, &k) in rows.iter().zip(&excited) {
        // The pair's FE mode is the record holding the mode the test was made of.
        let fe_mode: usize = row[4].parse().unwrap();
        assert!(
            run.records[fe_mode - 1].members.contains(&k),
            "{row:?} vs FE mode {k} ({fe_frequency_hz:?})"
        );
        let error_percent: f64 = row[6].parse().unwrap();
        let mac: f64 = row[7].parse().unwrap();
        // Noise-free synthesis from the FE modes themselves: LSCF returns their frequencies to
        // far better than 0.1 % and shapes whose MAC with the source is ~1.
        assert!(error_percent.abs() < 0.1 && mac > 0.99, "{row:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
