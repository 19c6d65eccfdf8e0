//! Rolling contact on the tiny test model (data/scenarios/case3-ci.json, 2 ms): the whole
//! `squeal simulate` path (model build, preload, rolling start, contact, outputs) and the
//! invariants every case must keep. The demo cases run the same code on finer meshes.
use std::path::Path;

use squeal::report::run_report::Table;
use squeal::rolling::{load_case, simulate, SimulateOptions};

fn column<'a>(t: &'a Table, name: &str) -> &'a [f64] {
    let k = t
        .headers
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    &t.columns[k]
}

#[test]
fn tiny_case_runs_and_keeps_the_contact_invariants() {
    let loaded = load_case(Path::new("data/scenarios/case3-ci.json")).unwrap();
    let dir = std::env::temp_dir().join(format!("squeal_rolling_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let record = simulate(
        &loaded,
        &SimulateOptions {
            out_dir: dir.clone(),
            resume: false,
            progress: false,
            end_time_s: None,
        },
    )
    .unwrap();
    assert_eq!(record.run.status, "completed");
    assert!(
        record.longest_contact_loss_s < squeal::rolling::LIFT_OFF_LIMIT_S,
        "lift-off {}",
        record.longest_contact_loss_s
    );
    for f in [
        "histories.csv",
        "contact_forces.csv",
        "energy.csv",
        "run.json",
        "status.json",
        "patches/patch_0001500.0us.json",
        "snapshot_0002000.0us.vtu",
    ] {
        assert!(dir.join(f).exists(), "{f} missing");
    }
    let forces = Table::read(&dir.join("contact_forces.csv")).unwrap();
    let creep = column(&forces, "creep_force_n");
    let bound = column(&forces, "traction_bound_n");
    let normal = column(&forces, "normal_force_n");
    let deepest = column(&forces, "max_penetration_m");
    // The return mapping never leaves a node above mu |f_N|, so neither can the sums.
    for k in 0..creep.len() {
        assert!(
            creep[k] <= bound[k] * (1.0 + 1e-9) + 1e-9,
            "sample {k}: creep {} > bound {}",
            creep[k],
            bound[k]
        );
        // Penetration stays below 5 % of the 10 mm band element (penalty chosen for that).
        assert!(
            deepest[k] < 0.05 * 0.010,
            "sample {k}: penetration {} m",
            deepest[k]
        );
    }
    // The wheel is on the rail: the largest normal force is of the order of the 110 kN
    // static load (the tiny case's preload is short, so the load still oscillates).
    let peak = normal.iter().copied().fold(0.0, f64::max);
    assert!(
        peak > 0.3 * record.model.static_wheel_load_n
            && peak < 3.0 * record.model.static_wheel_load_n,
        "peak normal force {peak}"
    );
    // Wheel vibration columns in the rotating frame are finite and far below the rolling
    // speed (27.8 m/s): the rigid rolling motion is not in them.
    let hist = Table::read(&dir.join("histories.csv")).unwrap();
    for c in [
        "lateral_velocity_m_per_s",
        "vertical_velocity_m_per_s",
        "longitudinal_velocity_m_per_s",
    ] {
        let v = column(&hist, c);
        assert!(
            v.iter().all(|x| x.is_finite() && x.abs() < 2.0),
            "{c}: {:?}",
            v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_case_files_name_the_field() {
    let dir = std::env::temp_dir().join(format!("squeal_rolling_bad_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string("data/scenarios/case3-ci.json").unwrap();
    let cases = [
        (
            "\"penalty_scale\": 0.1",
            "\"penalty_scale\": -1.0",
            "penalty_scale",
        ),
        ("\"mu\": 0.45", "\"mu\": 7.0", "friction"),
        ("\"end_time_s\": 0.002", "\"end_time_s\": 5.0", "end_time_s"),
        (
            "\"model_scenario\": \"ci-tiny.json\"",
            "\"model_scenario\": \"missing.json\"",
            "model_scenario",
        ),
    ];
    for (from, to, field) in cases {
        assert!(text.contains(from), "{from}");
        let path = dir.join("case.json");
        // The model scenario is looked up beside the case file.
        std::fs::copy("data/scenarios/ci-tiny.json", dir.join("ci-tiny.json")).unwrap();
        std::fs::copy("data/wheels/ns_intercity_920.json", dir.join("wheel.json")).unwrap();
        let scen = std::fs::read_to_string(dir.join("ci-tiny.json"))
            .unwrap()
            .replace("../wheels/ns_intercity_920.json", "wheel.json");
        std::fs::write(dir.join("ci-tiny.json"), scen).unwrap();
        std::fs::write(&path, text.replace(from, to)).unwrap();
        let err = match load_case(&path) {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{field}: accepted"),
        };
        assert!(err.contains(field), "{field}: {err}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A wheel placed 5 mm above the rail is not in contact after the preload: an error naming the
/// initial gap, not a silent run of a flying wheel.
#[test]
fn wheel_not_in_contact_after_preload_is_an_error() {
    let dir = std::env::temp_dir().join(format!("squeal_rolling_gap_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy("data/wheels/ns_intercity_920.json", dir.join("wheel.json")).unwrap();
    let scen = std::fs::read_to_string("data/scenarios/ci-tiny.json")
        .unwrap()
        .replace("../wheels/ns_intercity_920.json", "wheel.json")
        .replace("\"initial_gap_mm\": 0.0", "\"initial_gap_mm\": 5.0");
    assert!(scen.contains("\"initial_gap_mm\": 5.0"));
    std::fs::write(dir.join("ci-tiny.json"), scen).unwrap();
    let case = std::fs::read_to_string("data/scenarios/case3-ci.json")
        .unwrap()
        .replace("\"max_steps\": 2500", "\"max_steps\": 200");
    std::fs::write(dir.join("case.json"), case).unwrap();
    let loaded = load_case(&dir.join("case.json")).unwrap();
    let err = simulate(
        &loaded,
        &SimulateOptions {
            out_dir: dir.join("out"),
            resume: false,
            progress: false,
            end_time_s: None,
        },
    )
    .expect_err("a flying wheel must be an error");
    assert!(err.to_string().contains("initial_gap_mm"), "{err}");
    assert_eq!(err.exit_code(), 2);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run stopped at 1 ms and resumed from its checkpoint writes the same contact forces and
/// histories as the uninterrupted 2 ms run (the engine is deterministic).
#[test]
fn resumed_run_matches_the_uninterrupted_one() {
    let loaded = load_case(Path::new("data/scenarios/case3-ci.json")).unwrap();
    let base = std::env::temp_dir().join(format!("squeal_rolling_resume_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    let opts = |dir: &str, resume: bool, end: Option<f64>| SimulateOptions {
        out_dir: base.join(dir),
        resume,
        progress: false,
        end_time_s: end,
    };
    simulate(&loaded, &opts("whole", false, None)).unwrap();
    simulate(&loaded, &opts("split", false, Some(0.001))).unwrap();
    let resumed = simulate(&loaded, &opts("split", true, None)).unwrap();
    assert_eq!(resumed.run.status, "completed");
    for f in ["contact_forces.csv", "histories.csv"] {
        let a = std::fs::read_to_string(base.join("whole").join(f)).unwrap();
        let b = std::fs::read_to_string(base.join("split").join(f)).unwrap();
        assert!(a.lines().count() > 50, "{f} too short");
        assert_eq!(a, b, "{f} differs after resume");
    }
    let _ = std::fs::remove_dir_all(&base);
}
