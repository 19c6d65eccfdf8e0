//! The one-command pipeline at a reduced size (the tiny case, 2 ms): it completes and its
//! report holds every section. The full default run (`cargo run --release`) is the ignored
//! test below.
use std::path::Path;

use squeal::pipeline::{run_pipeline, PipelineOptions};
use squeal::rolling::load_case;

#[test]
fn reduced_default_run_writes_a_complete_report() {
    let case = load_case(Path::new("data/cases/case3-ci.json")).unwrap();
    let dir = std::env::temp_dir().join(format!("squeal_pipeline_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let summary = run_pipeline(
        &case,
        &PipelineOptions {
            out_dir: dir.clone(),
            end_time_s: None,
            progress: false,
        },
    )
    .unwrap();
    // The wheel modes are those of the wheelset held at its axle ends, as the rolling model
    // holds it: no rigid modes, and the (0,0) axial mode near 229 Hz (the demo cases' lateral
    // vibration peaks at 227-234 Hz), not the free wheelset's 334 Hz.
    let modes: Vec<serde_json::Value> =
        serde_json::from_str(&std::fs::read_to_string(summary.run_dir.join("modes.json")).unwrap())
            .unwrap();
    assert!(modes.iter().all(|m| m["family"] != "rigid"), "rigid modes");
    let first_axial_00 = modes
        .iter()
        .find(|m| m["family"] == "axial" && m["nodal_diameters"] == 0 && m["nodal_circles"] == 0)
        .and_then(|m| m["frequency_hz"].as_f64())
        .unwrap();
    assert!(
        (200.0..260.0).contains(&first_axial_00),
        "(0,0) axial at {first_axial_00} Hz"
    );
    let md = std::fs::read_to_string(dir.join("index.md")).unwrap();
    for section in [
        "Wheel vibration",
        "Wavelet power",
        "Contact forces",
        "Listen",
        "Run metadata",
        "Wheel modes",
        "Dominant frequencies and wheel modes",
    ] {
        assert!(
            md.contains(section),
            "section {section} missing: {:?}",
            summary.sections
        );
    }
    assert!(summary.report_html.exists());
    assert!(summary.run_dir.join("contact_forces.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The full default run, as `cargo run --release` does it (7-12 minutes on 2 cores): the
/// wheel modes by the axisymmetric solver, calibrated case 3 on the demo meshes with 2 mm
/// inserts for 40 ms, the report. It completes; its report has the operating-point and squeal
/// sections, and its patches at the paper's instants are resolved (at least 8 nodes across,
/// issue 24 item 6); case 3 meets the paper's operating point as the calibration asked (|Fy|
/// 20.3 kN +- 20 % at 17.58 ms and 36.8 kN +- 15 % at 18.54 ms, first saturation at 19.0 +-
/// 0.5 ms; docs/operating-point.md, where the inserts' calibration meets them at their edges);
/// and the dominant lateral peak is the (0,0) axial mode with a rim-mean/point ratio of an
/// n = 0 mode. Run: `cargo test --release --test pipeline -- --ignored full_default_run
/// --nocapture` (`.ci/long full_default_run` records it).
#[test]
#[ignore]
fn full_default_run() {
    let case = squeal::rolling::embedded_default_case().unwrap();
    let dir = std::env::temp_dir().join(format!("squeal_default_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let started = std::time::Instant::now();
    let summary = run_pipeline(
        &case,
        &PipelineOptions {
            out_dir: dir.clone(),
            end_time_s: None,
            progress: false,
        },
    )
    .unwrap();
    eprintln!(
        "default pipeline: {:.0} s wall; stages {:?}",
        started.elapsed().as_secs_f64(),
        summary.stage_wall_s
    );
    assert!(summary.report_html.exists());
    for section in [
        "Operating point against the paper's Table 3",
        "Squeal modes over time (wavelet ridges)",
        "Lateral wheel vibration: rim against hub",
    ] {
        assert!(
            summary.sections.iter().any(|s| s == section),
            "{section}: {:?}",
            summary.sections
        );
    }
    // The paper's five snapshot instants (17.07-19.0 ms) fall on the inserts: their charts
    // state at least 8 nodes across ("Resolution: A x B nodes across the patch, ...").
    let md = std::fs::read_to_string(summary.report_html.with_file_name("index.md")).unwrap();
    let across: Vec<usize> = md
        .lines()
        .filter_map(|l| l.strip_prefix("Resolution: "))
        .filter_map(|l| {
            let (a, rest) = l.split_once(" x ")?;
            let b = rest.split_once(' ')?.0;
            Some(a.parse::<usize>().ok()?.min(b.parse().ok()?))
        })
        .collect();
    eprintln!("nodes across the patch, per snapshot: {across:?}");
    let resolved = across
        .iter()
        .filter(|&&n| n >= squeal::report::patch_maps::RESOLVED_NODES_ACROSS)
        .count();
    assert!(resolved >= 5, "resolved snapshots: {across:?}");
    let op = squeal::report::table3::operating_point(&summary.run_dir)
        .unwrap()
        .expect("case 3 operating point");
    let (a, b) = (&op.instants[0], &op.instants[1]);
    eprintln!(
        "case 3: |Fy| {:.2} kN at 17.58 ms, {:.2} kN at 18.54 ms, first saturation {:?} ms",
        a.lateral_kn, b.lateral_kn, op.first_saturation_ms
    );
    assert!((a.lateral_kn / 20.3 - 1.0).abs() <= 0.20);
    assert!((b.lateral_kn / 36.8 - 1.0).abs() <= 0.15);
    assert!((op.first_saturation_ms.expect("saturates") - 19.0).abs() <= 0.5);
    let analysis = squeal::analysis::analyse_run(
        &summary.run_dir,
        &squeal::analysis::AnalysisOptions::default(),
    )
    .unwrap();
    let first = &analysis.identifications[0];
    eprintln!("dominant lateral peak: {first:?}");
    let mode = first.mode.as_ref().expect("explained");
    assert_eq!((mode.nodal_circles, mode.nodal_diameters), (0, 0));
    assert!(
        first.rim_mean_over_point.expect("ratio")
            >= squeal::analysis::identify::COMMON_MOTION_RATIO
    );
    let _ = std::fs::remove_dir_all(&dir);
}
