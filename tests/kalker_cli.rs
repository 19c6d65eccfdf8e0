//! The `squeal kalker` command: outputs and exit codes (bad input -> 2).

use std::process::Command;

fn squeal(arguments: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(arguments)
        .output()
        .expect("run squeal")
}

/// A fresh folder under the system's temporary directory.
fn temp_dir(tag: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("squeal-kalker-cli-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

/// The JSON summary a command prints before its closing `wrote DIR` line.
fn printed_json(stdout: &[u8]) -> serde_json::Value {
    let text = String::from_utf8_lossy(stdout);
    let json: Vec<&str> = text
        .lines()
        .take_while(|l| !l.starts_with("wrote "))
        .collect();
    serde_json::from_str(&json.join("\n")).expect("a JSON summary on standard output")
}

#[test]
fn hertz_prints_the_patch() {
    let output = squeal(&[
        "kalker",
        "hertz",
        "--normal-force-n",
        "100e3",
        "--wheel-radius-m",
        "0.46",
        "--rail-radius-m",
        "0.3",
    ]);
    assert!(output.status.success());
    let value: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    // docs/references.md, section 5: 7.16 x 5.39 mm, 1238 MPa.
    assert!((value["semi_axis_a_m"].as_f64().unwrap() / 7.16e-3 - 1.0).abs() < 0.005);
    assert!((value["semi_axis_b_m"].as_f64().unwrap() / 5.39e-3 - 1.0).abs() < 0.005);
    assert!((value["peak_pressure_pa"].as_f64().unwrap() / 1238e6 - 1.0).abs() < 0.005);
    assert!(value["approach_m"].as_f64().unwrap() > 0.0);
    assert!(value["ellipticity"].as_f64().unwrap() > 0.0);
}

#[test]
fn force_prescribed_default_mode_with_outputs() {
    let directory = temp_dir("solve");
    let output = squeal(&[
        "kalker",
        "solve",
        "--normal-force-n",
        "120e3",
        "--force-x-n",
        "40e3",
        "--force-y-n",
        "10e3",
        "--mu",
        "0.45",
        "--wheel-y-m",
        "0",
        "--method",
        "fastsim",
        "--out",
        directory.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let value = printed_json(&output.stdout);
    assert!((value["force_x_n"].as_f64().unwrap() - 40e3).abs() < 1e-3);
    assert!(value["xi"].as_f64().unwrap() < 0.0 && value["eta"].as_f64().unwrap() < 0.0);
    assert_eq!(value["unique"], serde_json::Value::Bool(true));
    let csv = std::fs::read_to_string(directory.join("traction.csv")).unwrap();
    assert!(csv.starts_with("x_m,y_m,pn_pa,px_pa,py_pa,state"));
    assert!(csv.contains("adhesion") && csv.contains("slip"));
    assert!(directory.join("summary.json").exists());
    std::fs::remove_dir_all(&directory).ok();
}

#[test]
fn creepage_prescribed_mode() {
    // creep writes traction.csv and summary.json (here into a temporary folder).
    let directory = temp_dir("creep");
    let output = squeal(&[
        "kalker",
        "creep",
        "--normal-force-n",
        "100e3",
        "--xi",
        "1e-3",
        "--mu",
        "0.3",
        "--grid",
        "30",
        "--out",
        directory.to_str().unwrap(),
    ]);
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let value = printed_json(&output.stdout);
    assert!(value["force_x_n"].as_f64().unwrap() < 0.0);
    assert!(directory.join("traction.csv").exists() && directory.join("summary.json").exists());
    std::fs::remove_dir_all(&directory).ok();
}

#[test]
fn bad_input_exits_with_code_2() {
    for arguments in [
        &[
            "kalker",
            "solve",
            "--normal-force-n",
            "120e3",
            "--force-x-n",
            "40e3",
            "--force-y-n",
            "10e3",
            "--mu",
            "0",
        ][..],
        &[
            "kalker",
            "solve",
            "--normal-force-n",
            "-1",
            "--force-x-n",
            "40e3",
            "--force-y-n",
            "10e3",
            "--mu",
            "0.45",
        ][..],
        &[
            "kalker",
            "solve",
            "--normal-force-n",
            "120e3",
            "--force-x-n",
            "60e3",
            "--force-y-n",
            "10e3",
            "--mu",
            "0.45",
        ][..],
        &[
            "kalker",
            "creep",
            "--normal-force-n",
            "100e3",
            "--xi",
            "1e-3",
            "--mu",
            "0.3",
            "--grid",
            "4",
        ][..],
        &["kalker", "hertz", "--normal-force-n", "0"][..],
    ] {
        let output = squeal(arguments);
        assert_eq!(
            output.status.code(),
            Some(2),
            "{arguments:?}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        assert!(String::from_utf8_lossy(&output.stderr).contains("error:"));
    }
}
