//! `squeal axisym` from the command line: outputs on a good run, and bad input reported with
//! the file / field / allowed range and exit code 2, never a panic.
use std::path::PathBuf;
use std::process::{Command, Output};

fn squeal() -> Command {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("squeal-axisym-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

const WHEEL: &str = "data/wheels/ns_intercity_920.json";

fn run(args: &[&str]) -> Output {
    squeal().args(args).output().expect("run squeal")
}

fn assert_bad_input(out: &Output, needles: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "stderr: {err}");
    for n in needles {
        assert!(err.contains(n), "`{n}` not in: {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

/// A coarse, fast run writes modes.json (readable as ModeRef), modes.csv with the documented
/// header, and prints the solve time.
#[test]
fn writes_modes_json_and_csv() {
    let dir = temp_dir("ok");
    // A coarse hub-clamped wheel without axle, harmonics 2-4 below 3 kHz; `extra` appended.
    let coarse = |extra: &[&str]| {
        let mut args = vec![
            "axisym",
            "--wheel",
            WHEEL,
            "--harmonics",
            "2..4",
            "--fmax-hz",
            "3000",
            "--element-size-mm",
            "20",
            "--without-axle",
            "--clamp",
            "hub-bore",
            "--out",
            dir.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        run(&args)
    };
    let out = coarse(&[]);
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout} {}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("modes below 3000 Hz in"), "{stdout}");
    let modes: Vec<squeal::analysis::identify::ModeRef> =
        serde_json::from_str(&std::fs::read_to_string(dir.join("modes.json")).unwrap()).unwrap();
    assert!(!modes.is_empty());
    assert!(modes.iter().all(|m| (2..=4).contains(&m.nodal_diameters)));
    assert!(modes.iter().any(|m| m.label() == "(0,2)"));
    let csv = std::fs::read_to_string(dir.join("modes.csv")).unwrap();
    assert!(csv.starts_with(
        "index,frequency_hz,family,nodal_circles,nodal_diameters,harmonic,residual\n"
    ));
    assert_eq!(csv.lines().count(), modes.len() + 1);
    // The paper's modal chart beside the tables: the FE series of the zero-circle axial modes
    // drawn; with a hammer test, its measured series too.
    let png = std::fs::read(dir.join("modal_chart.png")).unwrap();
    assert!(png.starts_with(b"\x89PNG"));
    let svg = std::fs::read_to_string(dir.join("modal_chart.svg")).unwrap();
    assert!(
        svg.contains("Axial m=0, FE") && !svg.contains("measured"),
        "FE series"
    );
    let with_test = coarse(&["--hammer", "data/hammer/synthetic_example.csv"]);
    assert!(with_test.status.success());
    let svg = std::fs::read_to_string(dir.join("modal_chart.svg")).unwrap();
    assert!(svg.contains("measured"), "measured series");
    // A universal file's mode shapes (datasets 55, 420/1130/2050 Hz): paired by frequency, as
    // the table says, and drawn.
    let with_uff = coarse(&["--hammer", "tests/fixtures/uff/modes55.uff"]);
    assert!(
        with_uff.status.success(),
        "{}",
        String::from_utf8_lossy(&with_uff.stderr)
    );
    let table = std::fs::read_to_string(dir.join("comparison.md")).unwrap();
    assert_eq!(table.matches("nearest FE frequency").count(), 3, "{table}");
    let svg = std::fs::read_to_string(dir.join("modal_chart.svg")).unwrap();
    assert!(
        svg.contains("measured"),
        "measured series from the universal file"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn missing_wheel_file_is_named() {
    let out = run(&["axisym", "--wheel", "no/such/wheel.json"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_ne!(out.status.code(), Some(0));
    assert!(err.contains("no/such/wheel.json"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_harmonics_ranges() {
    for h in ["5..2", "a..3", "0..1000", "-1"] {
        let arg = format!("--harmonics={h}");
        let out = run(&["axisym", "--wheel", WHEEL, &arg]);
        assert_bad_input(&out, &["--harmonics"]);
    }
}

#[test]
fn bad_fmax_and_element_size() {
    let out = run(&["axisym", "--wheel", WHEEL, "--fmax-hz=-5"]);
    assert_bad_input(&out, &["--fmax-hz", "(0, 1e6]"]);
    let out = run(&["axisym", "--wheel", WHEEL, "--element-size-mm", "0.1"]);
    assert_bad_input(&out, &["--element-size-mm", "[1, 50]"]);
}

#[test]
fn bad_wheel_field_is_named() {
    let dir = temp_dir("badwheel");
    let mut wheel: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(WHEEL).unwrap()).unwrap();
    wheel["web"]["thickness_at_rim_mm"] = serde_json::json!(200.0);
    let path = dir.join("wheel.json");
    std::fs::write(&path, serde_json::to_string(&wheel).unwrap()).unwrap();
    let out = run(&["axisym", "--wheel", path.to_str().unwrap()]);
    assert_bad_input(&out, &["wheel.json", "web.thickness_at_rim_mm"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn axle_ends_without_axle_is_rejected() {
    let out = run(&[
        "axisym",
        "--wheel",
        WHEEL,
        "--without-axle",
        "--clamp",
        "axle-ends",
    ]);
    assert_bad_input(&out, &["--clamp", "axle-ends"]);
}

#[test]
fn band_without_modes_is_reported() {
    let out = run(&[
        "axisym",
        "--wheel",
        WHEEL,
        "--harmonics",
        "5",
        "--fmax-hz",
        "10",
        "--element-size-mm",
        "20",
        "--without-axle",
    ]);
    assert_bad_input(&out, &["--fmax-hz", "no mode below 10 Hz"]);
}
