//! `squeal mesh` and `squeal profile` from the command line, including every bad-input case
//! the foundation issue lists: a clear message naming the file and field, exit code 2, and no
//! output file written.
use std::path::{Path, PathBuf};
use std::process::Command;

fn squeal() -> Command {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("squeal-cli-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// Copy the demo scenario and wheel into `dir`, applying `edit` to the parsed JSON of `which`.
fn edited_inputs(
    dir: &Path,
    which: &str,
    edit: impl Fn(&mut serde_json::Value),
) -> (PathBuf, PathBuf) {
    let mut scenario: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string("data/models/demo.json").expect("demo"))
            .expect("json");
    let mut wheel: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string("data/wheels/ns_intercity_920.json").expect("wheel"),
    )
    .expect("json");
    scenario["wheel_file"] = serde_json::Value::String("wheel.json".into());
    if which == "wheel" {
        edit(&mut wheel);
    } else {
        edit(&mut scenario);
    }
    let (sp, wp) = (dir.join("scenario.json"), dir.join("wheel.json"));
    std::fs::write(
        &sp,
        serde_json::to_string_pretty(&scenario).expect("encode"),
    )
    .expect("write");
    std::fs::write(&wp, serde_json::to_string_pretty(&wheel).expect("encode")).expect("write");
    (sp, wp)
}

fn expect_input_error(
    tag: &str,
    which: &str,
    edit: impl Fn(&mut serde_json::Value),
    must_mention: &[&str],
) {
    let dir = temp_dir(tag);
    let (scenario, wheel) = edited_inputs(&dir, which, edit);
    let out = dir.join("out");
    let args: Vec<String> = if which == "wheel" {
        vec![
            "mesh".into(),
            "--wheel".into(),
            wheel.display().to_string(),
            "--out".into(),
            out.display().to_string(),
        ]
    } else {
        vec![
            "mesh".into(),
            "--model".into(),
            scenario.display().to_string(),
            "--out".into(),
            out.display().to_string(),
        ]
    };
    let result = squeal().args(&args).output().expect("run squeal");
    let stderr = String::from_utf8_lossy(&result.stderr);
    assert_eq!(result.status.code(), Some(2), "{tag}: stderr {stderr}");
    for m in must_mention {
        assert!(stderr.contains(m), "{tag}: `{m}` missing from: {stderr}");
    }
    assert!(!out.exists(), "{tag}: output written despite the error");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn unknown_field_is_named() {
    expect_input_error(
        "unknown",
        "wheel",
        |w| w["web"]["thicknes_mm"] = 3.into(),
        &["wheel.json", "web", "unknown field `thicknes_mm`"],
    );
}

#[test]
fn missing_field_is_named() {
    expect_input_error(
        "missing",
        "wheel",
        |w| {
            w["hub"]
                .as_object_mut()
                .expect("hub")
                .remove("bore_radius_mm");
        },
        &["wheel.json", "hub", "missing field `bore_radius_mm`"],
    );
}

#[test]
fn negative_and_zero_dimensions_are_rejected() {
    expect_input_error(
        "negative",
        "wheel",
        |w| w["nominal_radius_mm"] = (-460.0).into(),
        &["nominal_radius_mm", "[200, 1000]"],
    );
    expect_input_error(
        "zero",
        "scenario",
        |s| s["track"]["sleeper"]["height_m"] = 0.0.into(),
        &["scenario.json", "track.sleeper.height_m"],
    );
}

#[test]
fn web_thicker_than_rim_is_rejected() {
    expect_input_error(
        "web",
        "wheel",
        |w| w["web"]["thickness_at_rim_mm"] = 150.0.into(),
        &["web.thickness_at_rim_mm", "thinner than the rim"],
    );
}

#[test]
fn circumferential_count_below_eight_is_rejected() {
    expect_input_error(
        "circ",
        "wheel",
        |w| w["mesh"]["circumferential_divisions"] = 4.into(),
        &["mesh.circumferential_divisions", "multiple of 8"],
    );
}

#[test]
fn solution_zone_outside_the_track_is_rejected() {
    expect_input_error(
        "zone",
        "scenario",
        |s| s["track"]["solution_zone"]["start_m"] = 9.5.into(),
        &["track.solution_zone.start_m", "inside the track"],
    );
}

/// The medium-size running arc of the wheel and running zone of the rail: each impossible
/// setting is refused with its field named.
#[test]
fn running_arc_and_running_zone_errors_name_the_field() {
    // Replace `s[group][key]` with `value` in the scenario.
    let set = |group: &'static str, key: &'static str, value: serde_json::Value| {
        move |s: &mut serde_json::Value| s[group][key] = value.clone()
    };
    let arc = |size: f64, centre: f64, width: f64| {
        set(
            "tread_band",
            "running_arc",
            serde_json::json!({
                "element_size_mm": size, "arc_centre_deg": centre, "arc_width_deg": width
            }),
        )
    };
    // The demo's fine band: 6 mm, 155 deg about 72.5 deg; body 20 mm.
    expect_input_error(
        "arc-size",
        "scenario",
        arc(3.0, 72.5, 200.0),
        &["tread_band.running_arc.element_size_mm", "[6, 20]"],
    );
    expect_input_error(
        "arc-narrow",
        "scenario",
        arc(10.0, 72.5, 100.0),
        &["tread_band.running_arc.arc_width_deg", "[155, 350]"],
    );
    expect_input_error(
        "arc-contain",
        "scenario",
        arc(10.0, 0.0, 200.0),
        &[
            "tread_band.running_arc.arc_centre_deg",
            "must contain the fine arc",
        ],
    );
    expect_input_error(
        "arc-opposite",
        "scenario",
        arc(10.0, 82.5, 350.0),
        &["tread_band.running_arc.arc_width_deg", "point opposite"],
    );
    let zone = |start: f64, length: f64, size: f64| {
        set(
            "track",
            "running_zone",
            serde_json::json!({"start_m": start, "length_m": length, "element_length_mm": size}),
        )
    };
    // The demo's rail: 6 m long, solution zone at 6 mm, far size 120 mm.
    expect_input_error(
        "zone-size",
        "scenario",
        zone(1.0, 2.0, 3.0),
        &["track.running_zone.element_length_mm", "[6, 120]"],
    );
    expect_input_error(
        "zone-outside",
        "scenario",
        zone(5.0, 2.0, 10.0),
        &["track.running_zone.start_m", "inside the track"],
    );
    expect_input_error(
        "zone-length",
        "scenario",
        zone(1.0, 0.0, 10.0),
        &["track.running_zone.length_m"],
    );
}

#[test]
fn malformed_json_is_reported_with_its_file() {
    let dir = temp_dir("malformed");
    let path = dir.join("bad.json");
    std::fs::write(&path, "{ \"name\": ").expect("write");
    let out = dir.join("out");
    let result = squeal()
        .args(["mesh", "--wheel", path.to_str().expect("utf8")])
        .args(["--out", out.to_str().expect("utf8")])
        .output()
        .expect("run");
    assert_eq!(result.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&result.stderr).contains("bad.json"));
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn mesh_writes_vtu_msh_and_json() {
    let dir = temp_dir("ok");
    let (vtu, msh, json) = (dir.join("w.vtu"), dir.join("w.msh"), dir.join("q.json"));
    let out = dir.join("mesh");
    let result = squeal()
        .args([
            "mesh",
            "--wheel",
            "data/wheels/ns_intercity_920.json",
            "--out",
            out.to_str().expect("utf8"),
            "--vtu",
            vtu.to_str().expect("utf8"),
            "--msh",
            msh.to_str().expect("utf8"),
            "--json",
            json.to_str().expect("utf8"),
        ])
        .output()
        .expect("run");
    let stdout = String::from_utf8_lossy(&result.stdout);
    assert!(
        result.status.success(),
        "{}",
        String::from_utf8_lossy(&result.stderr)
    );
    assert!(
        stdout.contains("critical time step") && stdout.contains("wheel mass"),
        "{stdout}"
    );
    let q: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).expect("json")).expect("parse");
    assert_eq!(q["inverted_elements"], 0);
    assert!(vtu.exists() && msh.exists());
    // The output folder holds mesh.vtu and quality.json (the same report as --json).
    assert!(out.join("mesh.vtu").exists());
    let folder_q: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(out.join("quality.json")).expect("quality.json"),
    )
    .expect("parse");
    assert_eq!(folder_q, q);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn profiles_print_point_tables() {
    let out = squeal()
        .args(["profile", "s1002", "--csv", "-", "--step-mm", "1"])
        .output()
        .expect("run");
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("s_mm,f_mm"));
    let rows: Vec<(f64, f64)> = lines
        .map(|l| {
            let mut it = l.split(',').map(|v| v.parse::<f64>().expect("number"));
            (it.next().expect("s"), it.next().expect("f"))
        })
        .collect();
    assert!(rows.len() > 135);
    let tip = rows
        .iter()
        .find(|r| (r.0 + 55.0).abs() < 1e-9)
        .expect("S = -55 row");
    assert!((tip.1 - 28.0).abs() < 1e-6);
    // --csv FILE writes the same table and prints the summary instead.
    let dir = temp_dir("profile-csv");
    let file = dir.join("s1002.csv");
    let to_file = squeal()
        .args(["profile", "s1002", "--step-mm", "1", "--csv"])
        .arg(&file)
        .output()
        .expect("run");
    assert!(to_file.status.success());
    assert_eq!(std::fs::read_to_string(&file).expect("csv"), text);
    assert!(String::from_utf8_lossy(&to_file.stdout).contains("S1002:"));
    let _ = std::fs::remove_dir_all(&dir);
    let out = squeal()
        .args(["profile", "54e1", "--csv", "-", "--inclined"])
        .output()
        .expect("run");
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).starts_with("y_mm,z_mm"));
    let bad = squeal()
        .args(["profile", "s1002", "--step-mm", "0"])
        .output()
        .expect("run");
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--step-mm"));
}

#[test]
fn profile_contact_scan_and_gap_tables() {
    let csv_rows = |out: &std::process::Output, header: &str| -> Vec<Vec<f64>> {
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8_lossy(&out.stdout).to_string();
        let mut lines = text.lines().filter(|l| !l.starts_with('#'));
        assert_eq!(lines.next(), Some(header));
        lines
            .map(|l| {
                l.split(',')
                    .map(|v| v.parse::<f64>().expect("number"))
                    .collect()
            })
            .collect()
    };
    let out = squeal()
        .args([
            "profile",
            "contact",
            "--from-mm",
            "-2",
            "--to-mm",
            "2",
            "--step-mm",
            "1",
        ])
        .output()
        .expect("run");
    let rows = csv_rows(
        &out,
        "wheel_y_mm,contact_y_mm,curvature_x_per_m,curvature_y_per_m",
    );
    assert_eq!(rows.len(), 5);
    // A wheel of radius 0.46 m: the rolling curvature 1 / (2 R) is about 1.09 /m at every
    // position (R changes by millimetres across the tread).
    for r in &rows {
        assert!((r[2] - 1.0 / (2.0 * 0.46)).abs() < 0.02, "{r:?}");
        assert!(r[3] > 0.0, "{r:?}");
    }
    let out = squeal()
        .args(["profile", "gap", "--wheel-y-mm", "0", "--step-mm", "0.5"])
        .output()
        .expect("run");
    let rows = csv_rows(&out, "y_mm,gap_um,rail_height_um,wheel_radius_increment_um");
    assert!(rows.len() > 100);
    // The gap is measured from the closest approach (found on a 0.01 mm grid), so it is never
    // negative beyond that grid's rounding and is about zero at the contact.
    let smallest = rows.iter().map(|r| r[1]).fold(f64::INFINITY, f64::min);
    assert!(
        smallest > -0.5 && smallest < 5.0,
        "smallest gap {smallest} um"
    );
    for (args, field) in [
        (
            vec!["profile", "contact", "--from-mm", "3", "--to-mm", "1"],
            "--to-mm",
        ),
        (
            vec!["profile", "gap", "--wheel-radius-m", "5"],
            "--wheel-radius-m",
        ),
        (
            vec!["profile", "gap", "--wheel-y-mm", "-40"],
            "--wheel-y-mm",
        ),
    ] {
        let bad = squeal().args(&args).output().expect("run");
        assert_eq!(bad.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&bad.stderr);
        assert!(err.contains(field) && err.contains("must be in"), "{err}");
    }
}
