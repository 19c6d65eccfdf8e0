//! The static preload of the rolling model: dynamic relaxation and the implicit solve
//! (Newton's method, `explicit::statics`) against each other and against the static wheel load,
//! the start of the rolling run from either, the errors of a preload that cannot be done, and
//! the 1 mm static patch against Hertz.
use std::path::Path;
use std::time::Instant;

use squeal::model::case::PreloadMethod;
use squeal::rolling::{load_case, simulate, LoadedCase, SimulateOptions, StopFlag};
use squeal::table::Table;

#[allow(dead_code)] // the helpers this file does not use
mod tiny_case;
use tiny_case::{column, edited_tiny_case, refused_with, run_in_temp};

/// What the comparison reads of a preloaded run: the vertical contact force at the first two
/// samples, the patch's contact nodes and its pressure-weighted semi-axes `sqrt(5 <x²>)`,
/// `sqrt(5 <y²>)` (Hertz: `a`, `b`), the load error, and the preload's wall time.
#[derive(Debug)]
struct Preloaded {
    vertical_n: [f64; 2],
    load_n: f64,
    load_error: f64,
    contact_nodes: usize,
    semi_axes_m: [f64; 2],
    seconds: f64,
}

/// Runs `loaded` with `method` for two samples and a patch snapshot at the start.
fn preloaded(loaded: &LoadedCase, method: PreloadMethod, tag: &str) -> Preloaded {
    let mut loaded = LoadedCase {
        case: loaded.case.clone(),
        scenario: loaded.scenario.clone(),
        source: loaded.source.clone(),
    };
    loaded.case.preload.method = method;
    loaded.case.output.patch_times_s = vec![0.0];
    let interval = 1.0 / loaded.case.output.sample_rate_hz;
    let start = Instant::now();
    let (record, dir) = run_in_temp(&loaded, tag, Some(1.5 * interval));
    let seconds = start.elapsed().as_secs_f64();
    let forces = Table::read(&dir.join("contact_forces.csv")).unwrap();
    let vertical = column(&forces, "vertical_force_n");
    let snap: squeal::kalker::snapshot::PatchSnapshot = serde_json::from_str(
        &std::fs::read_to_string(dir.join("patches/patch_0000000.0us.json")).unwrap(),
    )
    .unwrap();
    let (_, semi_axes_m) = patch_centre_and_semi_axes(&snap);
    let _ = std::fs::remove_dir_all(&dir);
    Preloaded {
        vertical_n: [vertical[0], vertical[1]],
        load_n: record.model.static_wheel_load_n,
        load_error: record.model.preload_load_error,
        contact_nodes: snap.points.len(),
        semi_axes_m,
        seconds,
    }
}

/// The comparison: wheel load, normal force and patch size within 0.5 % of each other,
/// and a smooth rolling start from either (the vertical force changes by under 1 % over the
/// first sample interval).
fn assert_preloads_agree(implicit: &Preloaded, relaxed: &Preloaded) {
    let rel = |a: f64, b: f64| (a / b - 1.0).abs();
    eprintln!("implicit {implicit:?}\nrelaxation {relaxed:?}");
    assert!(implicit.load_error.abs() < 0.005, "{implicit:?}");
    assert!(relaxed.load_error.abs() < 0.005, "{relaxed:?}");
    assert!(rel(implicit.vertical_n[0], relaxed.vertical_n[0]) < 0.005);
    for run in [implicit, relaxed] {
        assert!(rel(run.vertical_n[0], run.load_n) < 0.005, "{run:?}");
    }
    assert_eq!(implicit.contact_nodes, relaxed.contact_nodes);
    for k in 0..2 {
        assert!(
            rel(implicit.semi_axes_m[k], relaxed.semi_axes_m[k]) < 0.005,
            "semi-axis {k}: {:?} vs {:?}",
            implicit.semi_axes_m,
            relaxed.semi_axes_m
        );
    }
    for run in [implicit, relaxed] {
        let jump = rel(run.vertical_n[1], run.vertical_n[0]);
        assert!(jump < 0.01, "start jump {jump}: {run:?}");
    }
}

/// Implicit preload against dynamic relaxation on the tiny case. The relaxation runs to a
/// 0.1 % load error (20 000 steps), so that the comparison measures the two methods and not
/// the relaxation's unfinished settling (its 2 500-step default leaves a third of the load
/// missing on this model: it is a smoke case).
#[test]
fn implicit_preload_matches_dynamic_relaxation_on_the_tiny_case() {
    let mut loaded = load_case(Path::new("data/cases/case3-ci.json")).unwrap();
    loaded.case.preload.max_steps = 40_000;
    loaded.case.preload.load_tolerance = 0.001;
    loaded.case.preload.tolerance = 1e-4;
    let implicit = preloaded(&loaded, PreloadMethod::Implicit, "squeal_preload_implicit");
    let relaxed = preloaded(
        &loaded,
        PreloadMethod::DynamicRelaxation,
        "squeal_preload_relaxed",
    );
    assert_preloads_agree(&implicit, &relaxed);
    // The implicit solve lands on the static load to its residual.
    assert!(implicit.load_error.abs() < 1e-4, "{implicit:?}");
}

/// The implicit preload with conjugate gradients (`implicit_iterative`) against the one with a
/// Cholesky factor on the tiny case: the same equilibrium to the Newton tolerance, so the
/// issue's 0.5 % holds with room, and both land on the static load to their residual.
#[test]
fn iterative_preload_matches_the_direct_one_on_the_tiny_case() {
    let mut loaded = load_case(Path::new("data/cases/case3-ci.json")).unwrap();
    loaded.case.preload.tolerance = 1e-4;
    let direct = preloaded(&loaded, PreloadMethod::Implicit, "squeal_preload_direct");
    let iterative = preloaded(
        &loaded,
        PreloadMethod::ImplicitIterative,
        "squeal_preload_iterative",
    );
    assert_preloads_agree(&iterative, &direct);
    for run in [&direct, &iterative] {
        assert!(run.load_error.abs() < 1e-4, "{run:?}");
    }
}

/// The same on the demo model (`cargo test --release --test rolling_preload -- --ignored demo
/// --nocapture`, recorded by `.ci/long`).
#[test]
#[ignore]
fn demo_implicit_preload_matches_dynamic_relaxation() {
    let mut loaded = load_case(Path::new("data/cases/case3-demo.json")).unwrap();
    loaded.case.preload.max_steps = 60_000;
    loaded.case.preload.load_tolerance = 0.001;
    loaded.case.preload.tolerance = 1e-4;
    let implicit = preloaded(&loaded, PreloadMethod::Implicit, "squeal_demo_implicit");
    let relaxed = preloaded(
        &loaded,
        PreloadMethod::DynamicRelaxation,
        "squeal_demo_relaxed",
    );
    let iterative = preloaded(
        &loaded,
        PreloadMethod::ImplicitIterative,
        "squeal_demo_iterative",
    );
    eprintln!(
        "preload wall time (run of two samples included): implicit {:.1} s, relaxation {:.1} s, \
         implicit with conjugate gradients {:.1} s",
        implicit.seconds, relaxed.seconds, iterative.seconds
    );
    assert_preloads_agree(&implicit, &relaxed);
    assert_preloads_agree(&iterative, &relaxed);
    assert!(implicit.load_error.abs() < 1e-4, "{implicit:?}");
    assert!(iterative.load_error.abs() < 1e-4, "{iterative:?}");
}

/// The implicit preload lowers a wheel placed 0.8 mm above its rail: the approach steps of the
/// falling wheelset (held only by the regularisation) bring it down, and the wheel carries its
/// static load.
#[test]
fn implicit_preload_lowers_a_raised_wheel() {
    let (dir, loaded) = edited_tiny_case(
        "gap_implicit",
        ("\"initial_gap_mm\": 0.0", "\"initial_gap_mm\": 0.8"),
        ("\"max_steps\": 2500", "\"max_steps\": 2500"),
    );
    let (record, out) = run_in_temp(&loaded, "squeal_preload_raised", Some(2e-5));
    let report = record.static_preload.expect("implicit preload report");
    eprintln!(
        "{report:?}; load error {:+.2e}",
        record.model.preload_load_error
    );
    assert!(record.model.preload_load_error.abs() < 1e-3);
    // The 0.8 mm fall is made of approach steps of at most 0.2 mm (no solve), then Newton
    // steps in contact.
    assert!(report.approach_steps >= 4, "{report:?}");
    let _ = std::fs::remove_dir_all(&out);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A wheel placed 0.8 mm above the rail passes the check on the meshes (at most 1 mm) but is
/// not in contact after a 200-step dynamic relaxation (0.3 ms of the 13 ms a 0.8 mm fall
/// takes): an error naming the step limit and the initial gap, not a silent run of a flying wheel. (The implicit
/// preload lowers the same wheel onto its rail: `implicit_preload_lowers_a_raised_wheel`.)
#[test]
fn wheel_not_in_contact_after_preload_is_an_error() {
    let (dir, loaded) = edited_tiny_case(
        "gap",
        ("\"initial_gap_mm\": 0.0", "\"initial_gap_mm\": 0.8"),
        (
            "\"max_steps\": 2500",
            "\"method\": \"dynamic_relaxation\", \"max_steps\": 200",
        ),
    );
    // 200 relaxation steps do not close a 0.8 mm gap: the step limit is named first, the gap
    // as the other way out (issue 53, item 13).
    refused_with(
        &dir,
        &loaded,
        &["preload.max_steps", "step limit", "initial_gap_mm"],
    );
}

/// A stop asked for during the static preload ends the run with `Error::Interrupted` (exit code
/// 130, the shell's code for an interrupted command), not with a half-relaxed start.
#[test]
fn stop_during_the_preload_is_an_interruption() {
    let loaded = load_case(Path::new("data/cases/case3-ci.json")).unwrap();
    let dir = std::env::temp_dir().join(format!("squeal_rolling_stop_{}", std::process::id()));
    let stop = StopFlag::new();
    stop.request();
    let err = simulate(
        &loaded,
        &SimulateOptions {
            stop,
            ..SimulateOptions::new(dir.clone())
        },
    )
    .expect_err("a stopped preload must not start the run");
    assert!(matches!(err, squeal::Error::Interrupted(_)), "{err}");
    assert!(err.to_string().contains("preload"), "{err}");
    assert_eq!(err.exit_code(), 130);
    let _ = std::fs::remove_dir_all(&dir);
}

/// The normal force equals the applied load within 1 % after the preload. The preload of
/// the tiny model is asked for the load within 0.2 % (its load criterion, beside the residual):
/// it must get there within its step budget, record the error it reached, and the run's first
/// sample must show the vertical contact force (the normal force's vertical part plus friction,
/// zero at rest) balancing `(m_wheelset + m_sprung) g` within 0.5 %: the margin over 0.2 % is
/// for the step from the relaxed state (velocities zeroed, friction restored) to the first
/// sample.
#[test]
fn preloaded_wheel_carries_the_static_load() {
    let mut loaded = load_case(Path::new("data/cases/case3-ci.json")).unwrap();
    loaded.case.preload.method = PreloadMethod::DynamicRelaxation;
    loaded.case.preload.max_steps = 20_000;
    loaded.case.preload.damping_per_s = 450.0;
    loaded.case.preload.load_tolerance = 0.002;
    let (record, dir) = run_in_temp(&loaded, "squeal_rolling_static", Some(2e-5));
    let preload = record.preload.expect("preload report");
    assert!(preload.converged, "{preload:?}");
    let error = record.model.preload_load_error;
    assert!(error.abs() < 0.002, "preload load error {error}");
    let forces = Table::read(&dir.join("contact_forces.csv")).unwrap();
    let vertical = column(&forces, "vertical_force_n")[0];
    let load = record.model.static_wheel_load_n;
    eprintln!(
        "preload {} steps, load error {:+.3} %; first sample {vertical:.1} N of {load:.1} N",
        preload.steps,
        100.0 * error
    );
    assert!(
        (vertical - load).abs() < 0.005 * load,
        "vertical contact force {vertical} N vs static wheel load {load} N"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Static normal contact at 1 mm (`data/cases/static-hertz.json`, 251 k elements;
/// `cargo test --release --test rolling_preload -- --ignored static`, about 25 minutes). Passed on
/// 2026-11-23 with the wheel 28 mm to the field side (contact 2.6 mm from the rail centre, inside
/// the crown's R300 arc) and the preload's load criterion: 45 400 preload steps, residual 8e-5,
/// N 109.6 kN of 109.7 kN; a 8.59 mm (Hertz 8.32, +3.2 %), b 3.81 mm (3.57, +6.7 %), peak
/// 1620 MPa (1762, -8.1 %), 123 contact nodes. (At the tape circle the patch straddled the
/// R300|R80 junction: b +33 %; and a residual-only preload stopped with 12.6 % of the load
/// missing.) Checks the patch of the preloaded wheel against Hertz for the local
/// curvatures of S1002 on 54E1 at 1:40 at the measured normal force. Semi-axes from the
/// pressure-weighted second moments, which for a Hertz pressure `p0 sqrt(1 - x²/a² - y²/b²)`
/// are `a² / 5` and `b² / 5`; peak pressure against `3 N / (2 pi a b)`. 10 %: the issue's
/// tolerance (nodal pressures on a 1 mm grid over a patch of about 17 x 8 mm).
#[test]
#[ignore]
fn static_patch_at_1mm_matches_hertz() {
    static_patch_matches_hertz("data/cases/static-hertz.json", "squeal_static_hertz");
}

/// The same static contact on a band fine only on a strip of the tread
/// (`data/cases/static-hertz-strip.json`: `hertz-1mm-strip.json`, the 1 mm band fine from S =
/// 15 to 42 mm and 5 mm deep, growing by 1.3 outside; 95 k elements instead of 251 k):
/// the patch against Hertz with the same 10 % (239 s on the idle 2-core machine). Measured 2026-11-26 (a run
/// of the case by `squeal simulate`, before this test existed): N 110.0 kN, a 8.60 mm, b 3.88 mm,
/// peak 1620 MPa, 114 contact nodes, against 8.59 / 3.81 / 1620 on the uniform band.
#[test]
#[ignore]
fn static_patch_on_a_fine_strip_matches_hertz() {
    static_patch_matches_hertz(
        "data/cases/static-hertz-strip.json",
        "squeal_static_hertz_strip",
    );
}

/// The same static contact on the demo's 6 mm bands with 1 mm inserts around the patch
/// (`data/cases/static-hertz-insert.json`: `hertz-insert.json`, `tread_band.insert` and
/// `track.rail_insert`), with the implicit preload: the patch against Hertz with the same 10 %.
/// Its elements are a fifth of the fine strip's, so it runs in the suite.
#[test]
fn static_patch_on_1mm_inserts_matches_hertz() {
    static_patch_matches_hertz(
        "data/cases/static-hertz-insert.json",
        "squeal_static_hertz_insert",
    );
}

/// Runs the static case `case` and checks its patch against Hertz (the tests above).
fn static_patch_matches_hertz(case: &str, tag: &str) {
    use squeal::kalker::hertz::HertzContact;
    use squeal::kalker::snapshot::PatchSnapshot;
    let loaded = load_case(Path::new(case)).unwrap();
    let (record, dir) = run_in_temp(&loaded, tag, None);
    // Dynamic relaxation reports its steps, the implicit preload its Newton iterations.
    let (residual, steps) = match (&record.preload, &record.static_preload) {
        (Some(p), _) => (p.relative_residual, format!("{} steps", p.steps)),
        (None, Some(s)) => (s.relative_residual, format!("{} iterations", s.iterations)),
        (None, None) => panic!("no preload recorded"),
    };
    let snap: PatchSnapshot = serde_json::from_str(
        &std::fs::read_to_string(dir.join("patches/patch_0000000.0us.json")).unwrap(),
    )
    .unwrap();
    let ([_, yc], [a, b]) = patch_centre_and_semi_axes(&snap);
    let peak = snap
        .points
        .iter()
        .map(|p| p.pressure_pa)
        .fold(0.0, f64::max);
    let wheel_y_m = loaded.scenario.scenario.wheel_position.tape_circle_y_mm * 1e-3;
    let radius_m = loaded.scenario.wheel.nominal_radius_mm * 1e-3;
    let contact = squeal::kalker::profiles::s1002_on_54e1(wheel_y_m, radius_m).unwrap();
    let hertz = HertzContact::from_curvatures(
        contact.curvature_x_per_m,
        contact.curvature_y_per_m,
        snap.normal_force_n,
        squeal::kalker::Material::STEEL,
    )
    .unwrap();
    eprintln!(
        "preload residual {:.2e} ({}); N {:.1} kN (static load {:.1} kN); patch a {:.2} mm \
         b {:.2} mm p_max {:.0} MPa ({} nodes, centre y {:.1} mm); Hertz a {:.2} mm b {:.2} mm \
         p0 {:.0} MPa at contact y {:.1} mm",
        residual,
        steps,
        snap.normal_force_n / 1e3,
        record.model.static_wheel_load_n / 1e3,
        a * 1e3,
        b * 1e3,
        peak / 1e6,
        snap.points.len(),
        yc * 1e3,
        hertz.semi_axis_a_m * 1e3,
        hertz.semi_axis_b_m * 1e3,
        hertz.peak_pressure_pa / 1e6,
        contact.contact_y_m * 1e3
    );
    let forces = Table::read(&dir.join("contact_forces.csv")).unwrap();
    let vertical = column(&forces, "vertical_force_n")[0];
    let load = record.model.static_wheel_load_n;
    assert!(
        (vertical - load).abs() < 0.01 * load,
        "{vertical} vs {load}"
    );
    for (what, fe, reference) in [
        ("a", a, hertz.semi_axis_a_m),
        ("b", b, hertz.semi_axis_b_m),
        ("p0", peak, hertz.peak_pressure_pa),
    ] {
        assert!(
            (fe - reference).abs() < 0.1 * reference,
            "{what}: FE {fe} vs Hertz {reference}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Pressure-weighted centre `[x, y]` and semi-axes `[a, b]` (m) of a patch snapshot: for a
/// Hertzian (half-ellipsoid) pressure the second moment about the centre along an axis is a
/// fifth of the semi-axis squared, so `a = sqrt(5 <(x - xc)²>)`.
fn patch_centre_and_semi_axes(
    snap: &squeal::kalker::snapshot::PatchSnapshot,
) -> ([f64; 2], [f64; 2]) {
    let total: f64 = snap.points.iter().map(|p| p.pressure_pa).sum();
    let mean = |f: &dyn Fn(&squeal::kalker::snapshot::PatchPoint) -> f64| {
        snap.points
            .iter()
            .map(|p| p.pressure_pa * f(p))
            .sum::<f64>()
            / total
    };
    let (xc, yc) = (mean(&|p| p.x_m), mean(&|p| p.y_m));
    (
        [xc, yc],
        [
            (5.0 * mean(&|p| (p.x_m - xc).powi(2))).sqrt(),
            (5.0 * mean(&|p| (p.y_m - yc).powi(2))).sqrt(),
        ],
    )
}
