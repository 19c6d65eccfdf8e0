//! Squeal on a curve (issue 57) on the tiny test model: a wheelset yawed by its angle of attack
//! (data/cases/curve-ci.json: 2 mrad, 30 km/h, lateral position held, constant mu 0.45), the rim
//! ring it records by nodal diameter, and the per-n analysis of that ring. The long curve runs
//! on the demo meshes run the same code (`.ci/curve-runs`).
//!
//! What is checked against an independent reference:
//! - the rolling kinematics of a yawed wheel: dragged along the rail at V while it rolls
//!   freely about its own axis, its tread at the contact slides sideways at `V sin(psi)` along
//!   the axle, i.e. `V sin(psi) cos(psi)` across the rail (the steady lateral creepage of a
//!   curve, Rudd 1976), towards the field side for psi > 0; a negative psi mirrors it;
//! - friction opposes the slide: the lateral creep force on the wheel and the pressure-weighted
//!   lateral micro-slip have opposite signs (the friction power is dissipated);
//! - the ring's harmonics against a second route to the same rim motion: the ring's n = 0
//!   lateral part is the mean of the ring's lateral velocities, which the rim-mean column of
//!   histories.csv also averages (over the whole rim face rather than one circle).
//!
//! The creep forces against Kalker's theory need the quasi-steady state, which the tiny case
//! does not reach: the wheel web and the rail head have to deflect sideways by about 1 mm
//! (a lateral stiffness of order 25 MN/m against a creep force of order 25 kN) at the slide
//! speed `V psi` (17 um/ms here), some 60 ms, while the tiny model's tread band and rail zone
//! last 6 ms at this speed. That comparison runs on the demo meshes (`--ignored`).
use std::path::Path;

use squeal::analysis::per_n::{analyse_ring, check_required, PerNOptions, RingDirection};
use squeal::rolling::load_case;
use squeal::table::Table;

mod common;
#[allow(dead_code)]
mod tiny_case;
use tiny_case::{column, run_in_temp};

/// The tiny curve case with its angle of attack set to `psi_mrad`.
fn curve_case(psi_mrad: f64) -> squeal::rolling::LoadedCase {
    let mut loaded = load_case(Path::new("data/cases/curve-ci.json")).unwrap();
    loaded.case.curving.as_mut().unwrap().angle_of_attack_mrad = psi_mrad;
    loaded
}

#[test]
fn a_yawed_wheel_slides_sideways_at_v_sin_psi_and_friction_pushes_it_back() {
    let loaded = curve_case(2.0);
    let speed = loaded.case.speed_m_per_s();
    let psi = loaded.case.angle_of_attack_rad();
    let (record, dir) = run_in_temp(&loaded, "squeal_curve", None);
    assert_eq!(record.run.status, "completed");
    let h = Table::read_numeric(&dir.join("histories.csv")).unwrap();
    let f = Table::read_numeric(&dir.join("contact_forces.csv")).unwrap();
    // The first sample, as rolling starts: the tread at the contact moves across the rail at
    // V sin(psi) cos(psi) (16.7 mm/s). 5 %: the contact nodes also carry the preloaded
    // wheel's local deformation rates and the contact's first response (measured 2026-11-29:
    // 1.653e-2 against 1.667e-2 m/s, -0.8 %).
    let tread = column(&h, "contact_tread_lateral_velocity_m_per_s")[0];
    let rigid = speed * psi.sin() * psi.cos();
    assert!(
        (tread - rigid).abs() < 0.05 * rigid,
        "tread lateral velocity {tread} m/s against V sin(psi) cos(psi) = {rigid} m/s"
    );
    // Friction opposes the slide over the run: the creep force's work on the slide is
    // negative on the mean of the last half of the record, and the wheel is pushed towards
    // the track centre (-y).
    let slip = column(&h, "microslip_lateral_m_per_s");
    let fy = column(&f, "lateral_creep_force_n");
    let half = slip.len() / 2;
    let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len() as f64;
    let (slip_mean, fy_mean) = (mean(&slip[half..]), mean(&fy[half.min(fy.len())..]));
    assert!(slip_mean > 0.0, "lateral micro-slip {slip_mean} m/s");
    assert!(fy_mean < 0.0, "lateral creep force {fy_mean} N");
    // The traction bound holds at every node and step (the run's own monitor, 1e-9).
    assert!(record.largest_node_shear_over_bound <= 1.0 + 1e-9);
    // The ring: 24 nodes to n = 8, every harmonic's columns (n = 0 without its sine part).
    let ring: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("ring.json")).unwrap()).unwrap();
    assert_eq!(ring["nodes"].as_array().unwrap().len(), 24);
    let r = Table::read_numeric(&dir.join("ring.csv")).unwrap();
    assert_eq!(r.headers.len(), 1 + 3 + 8 * 6);
    assert_eq!(
        r.columns[0].len(),
        h.columns[0].len(),
        "one ring row per sample"
    );
    // n = 0 is the ring's mean: it follows the rim face's mean (histories.csv) sample by
    // sample. Both average the deformation velocity over the field-side rim face, the ring
    // over one circle of it; their correlation over the record must exceed 0.9.
    let ring_mean = column(&r, "n0_lateral_cos_m_per_s");
    let rim_mean = column(&h, "rim_mean_lateral_velocity_m_per_s");
    let corr = correlation(ring_mean, rim_mean);
    assert!(corr > 0.9, "n = 0 against the rim mean: correlation {corr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The same curve with exact contact (forward-increment Lagrange multipliers,
/// data/cases/curve-ci-exact.json): friction opposes the slide, the traction bound holds, every step's solve converged
/// with no contact node held, and the preload's penalty penetration relaxes at least as fast
/// as `exp(-t / tau)` (nodes that roll in arrive without any).
#[test]
fn an_exact_contact_curve_run_opposes_the_slide_and_relaxes_the_preload_penetration() {
    use squeal::contact::exact::GAP_RELAXATION_S;
    let loaded = load_case(Path::new("data/cases/curve-ci-exact.json")).unwrap();
    let (record, dir) = run_in_temp(&loaded, "squeal_curve_exact", None);
    assert_eq!(record.run.status, "completed");
    let h = Table::read_numeric(&dir.join("histories.csv")).unwrap();
    let f = Table::read_numeric(&dir.join("contact_forces.csv")).unwrap();
    // No check of the tread's velocity at the first sample here: with exact stick the
    // contact nodes that stick move with the rail from the first step (measured 1.06e-2
    // against the rigid slide's 1.67e-2 m/s), where a penalty's first steps let them slide.
    let slip = column(&h, "microslip_lateral_m_per_s");
    let fy = column(&f, "lateral_creep_force_n");
    let mean = |x: &[f64]| x.iter().sum::<f64>() / x.len() as f64;
    let (slip_mean, fy_mean) = (mean(&slip[slip.len() / 2..]), mean(&fy[fy.len() / 2..]));
    assert!(
        slip_mean > 0.0 && fy_mean < 0.0,
        "slip {slip_mean} m/s, force {fy_mean} N"
    );
    assert!(record.largest_node_shear_over_bound <= 1.0 + 1e-9);
    let exact = record
        .exact_contact
        .expect("an exact run records its solve");
    assert_eq!(exact.unconverged_steps, 0);
    assert_eq!(exact.held_node_steps, 0);
    let rolled_s = loaded.case.end_time_s;
    let relaxed = record.deepest_penetration_m * (-rolled_s / GAP_RELAXATION_S).exp();
    assert!(
        exact.final_deepest_penetration_m <= relaxed,
        "{} m left of {} m",
        exact.final_deepest_penetration_m,
        record.deepest_penetration_m
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_negative_angle_of_attack_mirrors_the_slide() {
    // 1 ms: the first samples only.
    let loaded = curve_case(-2.0);
    let (_, dir) = run_in_temp(&loaded, "squeal_curve_mirror", Some(1e-3));
    let h = Table::read_numeric(&dir.join("histories.csv")).unwrap();
    let tread = column(&h, "contact_tread_lateral_velocity_m_per_s")[0];
    let speed = loaded.case.speed_m_per_s();
    let rigid = speed * (-2e-3f64).sin() * (-2e-3f64).cos();
    assert!(
        (tread - rigid).abs() < 0.05 * rigid.abs(),
        "{tread} against {rigid}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_per_n_analysis_reads_the_ring_of_a_short_curve_run() {
    // A 3 ms run: the options and outputs wired end to end (the physics needs the long runs).
    let loaded = curve_case(2.0);
    let (_, dir) = run_in_temp(&loaded, "squeal_curve_per_n", Some(3e-3));
    let options = PerNOptions {
        direction: RingDirection::Radial,
        ..Default::default()
    };
    let a = analyse_ring(&dir, &options).unwrap();
    assert_eq!(a.spectra.len(), 9, "n = 0..8");
    assert!(a.spectra.iter().all(|s| s.median_in_band > 0.0));
    // Every named peak carries a mode of its own n.
    for p in &a.peaks {
        if let Some(m) = &p.mode {
            assert_eq!(m.nodal_diameters as usize, p.n);
        }
    }
    // A required n beyond the ring's n_max is a failure that says so.
    let outcome = &check_required(&a, &[(0, 9)], 10.0)[0];
    assert!(!outcome.passed);
    let _ = std::fs::remove_dir_all(&dir);
}

fn correlation(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len()) as f64;
    let ma = a.iter().sum::<f64>() / n;
    let mb = b.iter().sum::<f64>() / n;
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    sab / (saa * sbb).sqrt()
}

/// Item 1's check on the demo meshes (docs/curving.md, "Criteria fixed before the runs"): the
/// demo case 5 set-up at 100 km/h with no torque, no lateral motion, constant mu 0.45, yawed
/// at 1, 2 and 10 mrad, 40 ms each (about 3 minutes each on 2 cores). Over the last 10 ms the
/// lateral creep force must be quasi-steady (halves within 5 %) and, below saturation (1 and 2
/// mrad), within 10 % of Kalker's exact theory at the run's own contact (eta = sin psi, the
/// spin of its contact angle, the xi of its longitudinal force); saturated (10 mrad) the creep
/// force within 3 % of mu N.
#[test]
#[ignore]
fn yawed_demo_wheel_creep_forces_against_kalker() {
    creep_forces_against_kalker(squeal::contact::Enforcement::Penalty, &[1.0, 2.0, 10.0]);
}

/// The same check with exact contact (`contact_enforcement: exact`): the penalty layer's
/// tangential compliance, one suspect for the factor of two below saturation, is gone.
#[test]
#[ignore]
fn yawed_demo_wheel_creep_forces_against_kalker_with_exact_contact() {
    creep_forces_against_kalker(squeal::contact::Enforcement::Exact, &[2.0, 1.0, 10.0]);
}

fn creep_forces_against_kalker(enforcement: squeal::contact::Enforcement, psis_mrad: &[f64]) {
    use squeal::analysis::creep_check::check_creep_forces;
    let mut failures = Vec::new();
    for &psi_mrad in psis_mrad {
        let mut loaded = load_case(Path::new("data/cases/case5-demo.json")).unwrap();
        let case = &mut loaded.case;
        case.contact_enforcement = enforcement;
        case.name = format!("creep-check-{}-{psi_mrad}mrad", enforcement.word());
        case.end_time_s = 0.04;
        case.torque.max_n_m = 0.0;
        case.lateral_motion = None;
        case.curving = Some(squeal::model::case::CurvingSpec {
            angle_of_attack_mrad: psi_mrad,
        });
        case.friction = squeal::friction::FrictionLaw::Coulomb { mu: 0.45 };
        case.output.patch_times_s.clear();
        let (record, dir) = run_in_temp(
            &loaded,
            &format!("squeal_creep_check_{}_{psi_mrad}", enforcement.word()),
            None,
        );
        assert_eq!(record.run.status, "completed");
        let radius_m = loaded.scenario.wheel.tread_radius_mm(0.0) * 1e-3;
        let material = loaded.scenario.wheel.material;
        let c = check_creep_forces(&loaded, &dir, 30.0, 40.0, radius_m, material).unwrap();
        eprintln!(
            "{} contact, psi {psi_mrad} mrad: N {:.0} N, run (Fx, Fy) ({:.0}, {:.0}) N, halves of Fy {:.0} / {:.0} N \
             (quasi-steady: {}), Kalker ({:.0}, {:.0}) N at xi {:.2e}, eta {:.2e}, phi {:.3} /m; \
             Fy run / Kalker {:.3}; |F| / (mu N) {:.3}",
            enforcement.word(),
            c.normal_force_n,
            c.run_creep_force_n[0],
            c.run_creep_force_n[1],
            c.lateral_halves_n[0],
            c.lateral_halves_n[1],
            c.quasi_steady,
            c.kalker_creep_force_n[0],
            c.kalker_creep_force_n[1],
            c.creepages.xi,
            c.creepages.eta,
            c.creepages.phi_per_m,
            c.lateral_ratio,
            c.saturation
        );
        if !c.quasi_steady {
            failures.push(format!("{psi_mrad} mrad: not quasi-steady"));
        }
        if psi_mrad < 5.0 && (c.lateral_ratio - 1.0).abs() > 0.10 {
            failures.push(format!(
                "{psi_mrad} mrad: Fy run / Kalker {:.3}",
                c.lateral_ratio
            ));
        }
        if psi_mrad >= 5.0 && c.saturation < 0.97 {
            failures.push(format!("{psi_mrad} mrad: |F| / (mu N) {:.3}", c.saturation));
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// Item 6's check on a committed curve run (data/runs/curve/curve-falling-10mrad: 300 ms,
/// falling friction, 10 mrad), over its last 50 ms (the limit-cycle window of docs/curving.md)
/// with the margin fixed before any run was judged (10 dB). What the physics gave, first
/// judged 2026-11-29: all three pass, (0,0) 20.2 dB, (0,3) 10.0 dB (at the margin), (0,4)
/// 12.9 dB above their harmonics' medians; the peaks of (0,3) and (0,4) lie at 1054.7 and
/// 1894.5 Hz, where the struck explicit wheel of the same mesh has them (1053.1, 1898.1 Hz,
/// tests/struck_wheel.rs), 4 and 3 % above the axisymmetric modes.json. Since the check reads
/// the refined maximum (src/analysis/per_n.rs): (0,3) 10.7 dB at 1061.5 Hz, (0,4) 13.2 dB at
/// 1890.6 Hz. A change that moves these makes this test say so; it is not a target.
#[test]
fn the_per_n_check_on_the_committed_falling_friction_curve_run() {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args([
            "check-modes",
            "data/runs/curve/curve-falling-10mrad",
            "--per-n",
            "--from-ms",
            "250",
            "--require",
            "0,0",
            "--require",
            "0,3",
            "--require",
            "0,4",
        ])
        .output()
        .unwrap();
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(out.status.code(), Some(0), "{text}");
    for label in ["(0,0)", "(0,3)", "(0,4)"] {
        assert!(
            text.lines()
                .any(|l| l.contains("pass") && l.contains(label)),
            "{label}: {text}"
        );
    }
}

/// Item 6 on the ring run of paper case 3 (data/runs/ring/case3-demo: the demo meshes, 40 ms,
/// the whole record), the per-n check beside the dominant-peak check it adds to. What the
/// physics gave, first judged 2026-11-29: the dominant-peak check fails (the rim point's three
/// largest peaks are the n = 0 modes (0,0), (1,0), (2,0) at 236, 1383, 1764 Hz, which the
/// lateral ramp rings), and per n all three pass: (0,0) at 238.9 Hz 80.4 dB, (0,3) at 1054.4 Hz
/// 53.8 dB, (0,4) at 1806.1 Hz 47.7 dB above their harmonics' medians. Not a target.
#[test]
fn the_per_n_check_beside_the_dominant_peak_check_on_paper_case_3() {
    let check = |per_n: bool| {
        let mut args = vec!["check-modes", "data/runs/ring/case3-demo"];
        if per_n {
            args.push("--per-n");
        }
        args.extend(["--require", "0,0", "--require", "0,3", "--require", "0,4"]);
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_squeal"))
            .args(&args)
            .output()
            .unwrap();
        // The verdict lines go to stderr, the tables to stdout.
        (
            out.status.code(),
            format!(
                "{}{}",
                String::from_utf8_lossy(&out.stdout),
                String::from_utf8_lossy(&out.stderr)
            ),
        )
    };
    let (code, text) = check(false);
    assert_eq!(code, Some(1), "{text}");
    assert!(
        text.contains("missing (0,3)") && text.contains("missing (0,4)"),
        "{text}"
    );
    let (code, text) = check(true);
    assert_eq!(code, Some(0), "{text}");
    for label in ["(0,0)", "(0,3)", "(0,4)"] {
        assert!(
            text.lines()
                .any(|l| l.contains("pass") && l.contains(label)),
            "{label}: {text}"
        );
    }
}

/// Item 4's growth analysis on the committed curve runs, by the criteria fixed before the runs
/// (docs/curving.md). What the physics gave, first judged 2026-11-29: neither squeals. At 10
/// mrad the lateral n = 5 harmonic, at (0,5) axial (2842 Hz), grows x7.4 from the end of the
/// creep force's build-up (25 ms) to 55-60 ms and settles at x4.9 of it (1.34e-2 m/s, last two
/// 50 ms spans within 6 %): the largest harmonic at the end, below the x10 of a squeal. At 20
/// mrad nothing grows beyond x6.6 (circumferential n = 0); the lateral n = 1 (0,1) at 147 Hz
/// is largest. A change that moves these makes this test say so; they are not targets.
#[test]
fn the_growth_of_the_committed_curve_runs_by_the_fixed_criteria() {
    use squeal::analysis::ring_growth::{ring_growth, GrowthCriteria};
    let criteria = GrowthCriteria::default();
    let g = ring_growth(
        std::path::Path::new("data/runs/curve/curve-falling-10mrad"),
        None,
        &criteria,
        None,
    )
    .unwrap();
    assert!(!g.verdict.squeals, "{}", g.verdict.summary);
    assert!((g.windows.build_up_end_s - 0.025).abs() < 1e-9);
    let lead = &g.harmonics[g.verdict.leading.unwrap()];
    assert_eq!((lead.direction, lead.n), (RingDirection::Lateral, 5));
    assert_eq!(lead.final_mode.as_ref().unwrap().label(), "(0,5)");
    // x4.9 (to one decimal, the table's figure) and a limit cycle.
    assert!(
        (lead.growth_factor - 4.9).abs() < 0.05,
        "{}",
        lead.growth_factor
    );
    assert!(lead.limit_cycle);
    // The envelope's own peak: x7.4 in the window 55-60 ms.
    let peak = lead.envelope_m_per_s.iter().copied().fold(0.0f64, f64::max);
    assert!((peak / lead.build_up_level_m_per_s - 7.4).abs() < 0.05);
    assert_eq!(
        lead.envelope_m_per_s.iter().position(|&e| e == peak),
        Some(11)
    );
    // The first 110 ms alone (as the convergence runs of item 5 last): the same windows and
    // envelopes up to there, whatever followed.
    let g110 = ring_growth(
        std::path::Path::new("data/runs/curve/curve-falling-10mrad"),
        None,
        &criteria,
        Some(0.110),
    )
    .unwrap();
    assert_eq!(g110.windows.start_s.len(), 22);
    let lead110 = g110
        .harmonics
        .iter()
        .find(|h| h.direction == RingDirection::Lateral && h.n == 5)
        .unwrap();
    assert_eq!(lead110.envelope_m_per_s[..], lead.envelope_m_per_s[..22]);
    let g20 = ring_growth(
        std::path::Path::new("data/runs/curve/curve-falling-20mrad"),
        None,
        &criteria,
        None,
    )
    .unwrap();
    assert!(!g20.verdict.squeals, "{}", g20.verdict.summary);
    let lead = &g20.harmonics[g20.verdict.leading.unwrap()];
    assert_eq!((lead.direction, lead.n), (RingDirection::Lateral, 1));
}

/// Item 5 on the committed patch-speed runs (the falling law at the patch's sliding velocity,
/// 300 ms), by the criteria fixed before the runs. What the physics gave, first judged
/// 2026-11-29 (docs/convergence.md): all three squeal, but the winning mode follows the
/// penalty: (0,8) axial at 5941.7 Hz in a limit cycle, x27, +21 /s at penalty x 0.5; (0,8) at
/// 5941.5 Hz, x28, +39 /s at x 1; (0,9) axial at 6984.3 Hz in a limit cycle, x22, +26 /s at
/// x 2; (0,8) at 5940.1 Hz in a limit cycle, x10.1, +7 /s at x 4; (0,6) at 3848.8 Hz, still
/// growing, x11.7, +7 /s at x 8. A change that moves these makes this test say so; they are
/// not targets.
#[test]
fn the_patch_speed_runs_squeal_in_a_mode_that_follows_the_penalty() {
    use squeal::analysis::ring_growth::{ring_growth, GrowthCriteria};
    let judge = |run: &str| {
        let g = ring_growth(
            std::path::Path::new(run),
            None,
            &GrowthCriteria::default(),
            None,
        )
        .unwrap();
        assert!(g.verdict.squeals, "{run}: {}", g.verdict.summary);
        let lead = g.harmonics[g.verdict.leading.unwrap()].clone();
        (
            lead.final_mode.as_ref().unwrap().label(),
            lead.final_peak_hz.unwrap(),
            lead.growth_factor,
            lead.growth_rate_per_s.unwrap(),
            lead.limit_cycle,
        )
    };
    let (mode, f, x, rate, cycle) =
        judge("data/runs/curve/curve-falling-10mrad-patch-penalty-x0.5");
    assert_eq!(mode, "(0,8)");
    // To the tables' digits: 0.1 Hz, x to 0.5, the rate to 1 /s.
    assert!((f - 5941.7).abs() < 0.1 && (x - 26.5).abs() < 0.5 && (rate - 21.0).abs() < 1.0);
    assert!(
        cycle,
        "+8 % on the span before: within the 10 % of a limit cycle"
    );
    let (mode, f, x, rate, cycle) = judge("data/runs/curve/curve-falling-10mrad-patch");
    assert_eq!(mode, "(0,8)");
    // To the tables' digits: 0.1 Hz, x to 0.5, the rate to 1 /s.
    assert!((f - 5941.5).abs() < 0.1 && (x - 28.0).abs() < 0.5 && (rate - 39.0).abs() < 1.0);
    assert!(!cycle, "15 % below the span before: not yet a limit cycle");
    let (mode, f, x, rate, cycle) = judge("data/runs/curve/curve-falling-10mrad-patch-penalty-x2");
    assert_eq!(mode, "(0,9)");
    assert!((f - 6984.3).abs() < 0.1 && (x - 22.0).abs() < 0.5 && (rate - 26.0).abs() < 1.0);
    assert!(cycle);
    let (mode, f, x, rate, cycle) = judge("data/runs/curve/curve-falling-10mrad-patch-penalty-x4");
    assert_eq!(mode, "(0,8)");
    // x to 0.05 here: 10.1 lies just above the squeal threshold of x10.
    assert!((f - 5940.1).abs() < 0.1 && (x - 10.1).abs() < 0.05 && (rate - 7.0).abs() < 1.0);
    assert!(cycle);
    let (mode, f, x, rate, cycle) = judge("data/runs/curve/curve-falling-10mrad-patch-penalty-x8");
    assert_eq!(mode, "(0,6)");
    assert!((f - 3848.8).abs() < 0.1 && (x - 11.7).abs() < 0.05 && (rate - 7.0).abs() < 1.0);
    assert!(!cycle, "+20 % on the span before: still growing");
}

/// A squealing harmonic's figures as docs/curving.md and docs/convergence.md give them: its
/// final peak to the table's 0.1 Hz, its growth factor to `factor_tolerance` (the table's last
/// digit) and its growth rate to 1 /s.
fn assert_squeal_figures(
    lead: &squeal::analysis::ring_growth::HarmonicGrowth,
    peak_hz: f64,
    factor: f64,
    factor_tolerance: f64,
    rate_per_s: f64,
) {
    let (f, x, rate) = (
        lead.final_peak_hz.unwrap(),
        lead.growth_factor,
        lead.growth_rate_per_s.unwrap(),
    );
    assert!(
        (f - peak_hz).abs() < 0.1
            && (x - factor).abs() < factor_tolerance
            && (rate - rate_per_s).abs() < 1.0,
        "{f} Hz, x{x}, {rate} /s"
    );
}

/// Item 2's constant-mu curve runs (penalty contact, node slip speed: the law is constant),
/// by the criteria fixed before the runs. What the physics gave, first judged 2026-11-29
/// (docs/curving.md): at mu 0.45 and 20 mrad the wheel squeals in (0,4) axial at 1890.1 Hz
/// (x20, +12 /s, still growing at 300 ms; judged at 300 ms so that the run's extension to 400
/// ms does not move this); at 10 mrad no harmonic reaches x10 at a named mode (lateral n = 5
/// at 4079.6 Hz, x9.5, levelled off at 400 ms); at mu 0.30 and 10 mrad the wheel squeals in
/// (0,9) axial at 6985.9 Hz (x14, +10 /s). A change that moves these makes this test say so;
/// they are not targets.
#[test]
fn the_constant_mu_curve_runs_by_the_fixed_criteria() {
    use squeal::analysis::ring_growth::{ring_growth, GrowthCriteria, RingGrowth};
    let judge = |run: &str, to_s: Option<f64>| -> RingGrowth {
        ring_growth(Path::new(run), None, &GrowthCriteria::default(), to_s).unwrap()
    };
    let g = judge("data/runs/curve/curve-mu045-20mrad", Some(0.300));
    assert!(g.verdict.squeals, "{}", g.verdict.summary);
    let lead = &g.harmonics[g.verdict.leading.unwrap()];
    assert_eq!((lead.direction, lead.n), (RingDirection::Lateral, 4));
    assert_eq!(lead.final_mode.as_ref().unwrap().label(), "(0,4)");
    assert_squeal_figures(lead, 1890.1, 20.3, 0.5, 12.0);
    assert!(!lead.limit_cycle, "+89 % over the last span");
    let g = judge("data/runs/curve/curve-mu045-10mrad", None);
    assert!(!g.verdict.squeals, "{}", g.verdict.summary);
    let lead = &g.harmonics[g.verdict.leading.unwrap()];
    assert_eq!((lead.direction, lead.n), (RingDirection::Lateral, 5));
    assert!(lead.final_mode.is_none(), "4079.6 Hz is no n = 5 mode");
    assert!((lead.final_peak_hz.unwrap() - 4079.6).abs() < 0.1);
    assert!((lead.growth_factor - 9.5).abs() < 0.05 && lead.limit_cycle);
    let g = judge("data/runs/curve/curve-mu030-10mrad", None);
    assert!(g.verdict.squeals, "{}", g.verdict.summary);
    let lead = &g.harmonics[g.verdict.leading.unwrap()];
    assert_eq!(lead.final_mode.as_ref().unwrap().label(), "(0,9)");
    assert_squeal_figures(lead, 6985.9, 13.9, 0.5, 10.0);
}

/// The constant-mu squeal at 20 mrad again with exact contact (data/runs/curve/
/// curve-mu045-20mrad-exact), by the criteria written before it started (docs/convergence.md,
/// "Exact contact at constant friction"), judged at 300 ms as the penalty run is (the run goes
/// on to 400 ms). What the physics gave, first judged 2026-11-29: it squeals in (0,6) axial at
/// 3851.4 Hz (x151, +18 /s, still growing), not in the penalty run's (0,4), so the penalty
/// run's squeal is not confirmed. A change that moves these makes this test say so; they are
/// not targets.
#[test]
fn the_constant_mu_squeal_with_exact_contact_by_the_fixed_criteria() {
    use squeal::analysis::ring_growth::{ring_growth, GrowthCriteria};
    let judge = |run: &str| {
        ring_growth(
            Path::new(run),
            None,
            &GrowthCriteria::default(),
            Some(0.300),
        )
        .unwrap()
    };
    let exact = judge("data/runs/curve/curve-mu045-20mrad-exact");
    assert!(exact.verdict.squeals, "{}", exact.verdict.summary);
    let lead = &exact.harmonics[exact.verdict.leading.unwrap()];
    assert_eq!((lead.direction, lead.n), (RingDirection::Lateral, 6));
    assert_eq!(lead.final_mode.as_ref().unwrap().label(), "(0,6)");
    assert_squeal_figures(lead, 3851.4, 150.7, 1.0, 18.0);
    assert!(!lead.limit_cycle, "+36 % over the last span");
    // The criterion: the penalty run's squeal is confirmed only by a squeal of the same
    // (m, n); it is not.
    let penalty = judge("data/runs/curve/curve-mu045-20mrad");
    let penalty_lead = &penalty.harmonics[penalty.verdict.leading.unwrap()];
    assert_ne!(
        penalty_lead.final_mode.as_ref().unwrap().label(),
        lead.final_mode.as_ref().unwrap().label()
    );
}

/// The constant-mu squeal at mu 0.30 and 10 mrad again with exact contact (data/runs/curve/
/// curve-mu030-10mrad-exact, 300 ms), by the same criteria. What the physics gave, first judged
/// 2026-11-29: no squeal; lateral n = 8 grew x30.8 to 1.72e-2 m/s at 5113.3 Hz, which no
/// n = 8 mode names, and levelled off; the penalty run's (0,9) reached x2.1 only, so that
/// squeal is not confirmed. A change that moves these makes this test say so; they are not
/// targets.
#[test]
fn the_friction_modifier_run_with_exact_contact_by_the_fixed_criteria() {
    use squeal::analysis::ring_growth::{ring_growth, GrowthCriteria};
    let run = Path::new("data/runs/curve/curve-mu030-10mrad-exact");
    let g = ring_growth(run, None, &GrowthCriteria::default(), None).unwrap();
    assert!(!g.verdict.squeals, "{}", g.verdict.summary);
    let lead = &g.harmonics[g.verdict.leading.unwrap()];
    assert_eq!((lead.direction, lead.n), (RingDirection::Lateral, 8));
    assert!(lead.final_mode.is_none(), "5113 Hz is no n = 8 mode");
    // To the docs' digits.
    assert!((lead.final_peak_hz.unwrap() - 5113.3).abs() < 0.1);
    assert!((lead.growth_factor - 30.8).abs() < 0.05 && lead.limit_cycle);
    let n9 = g
        .harmonics
        .iter()
        .find(|h| (h.direction, h.n) == (RingDirection::Lateral, 9))
        .unwrap();
    assert_eq!(n9.final_mode.as_ref().unwrap().label(), "(0,9)");
    assert!((n9.growth_factor - 2.1).abs() < 0.05 && !n9.squeals);
}

/// Item 5 with the contact enforced exactly (data/runs/curve/curve-falling-10mrad-patch-exact,
/// 300 ms), by the criteria written before it was judged (docs/convergence.md, "Exact
/// contact"). What the physics gave, first judged 2026-11-29: no squeal; every harmonic rises
/// x4 to x9 together, the most circumferential n = 4 (x9.3), the largest at the end radial
/// n = 5 at 5572.0 Hz (no mode), 6.27e-2 m/s; the solve converged at every step. A change that
/// moves these makes this test say so; they are not targets.
#[test]
fn the_exact_contact_run_by_the_fixed_criteria() {
    use squeal::analysis::ring_growth::{ring_growth, GrowthCriteria};
    let run = Path::new("data/runs/curve/curve-falling-10mrad-patch-exact");
    let g = ring_growth(run, None, &GrowthCriteria::default(), None).unwrap();
    assert!(!g.verdict.squeals, "{}", g.verdict.summary);
    let lead = &g.harmonics[g.verdict.leading.unwrap()];
    assert_eq!((lead.direction, lead.n), (RingDirection::Radial, 5));
    assert!(lead.final_mode.is_none());
    // To the table's digits.
    assert!((lead.final_peak_hz.unwrap() - 5572.0).abs() < 0.1);
    assert!((lead.final_level_m_per_s - 6.27e-2).abs() < 5e-5);
    let most = g
        .harmonics
        .iter()
        .max_by(|a, b| a.growth_factor.total_cmp(&b.growth_factor))
        .unwrap();
    assert_eq!(
        (most.direction, most.n),
        (RingDirection::Circumferential, 4)
    );
    assert!((most.growth_factor - 9.3).abs() < 0.05);
    let record: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(run.join("run.json")).unwrap()).unwrap();
    assert_eq!(record["exact_contact"]["unconverged_steps"], 0);
    assert_eq!(record["exact_contact"]["held_node_steps"], 0);
}

/// The exact run again with the time step halved (data/runs/curve/
/// curve-falling-10mrad-patch-exact-dt-x0.5, 300 ms), by the same criteria and item 5's
/// tolerances (docs/convergence.md, "Exact contact"; written before either run was judged):
/// the verdict the same, the leading harmonic the same (direction, n), its final peak within
/// 3 % and its final level within 30 % of the full step's. What it gave, first judged
/// 2026-11-29: no squeal, radial n = 5 at 5573.9 Hz, 5.80e-2 m/s (full step: 5572.0 Hz,
/// 6.27e-2 m/s).
#[test]
fn the_exact_contact_run_with_the_step_halved_agrees_by_the_fixed_tolerances() {
    use squeal::analysis::ring_growth::{ring_growth, GrowthCriteria};
    let judge = |run: &str| {
        let g = ring_growth(Path::new(run), None, &GrowthCriteria::default(), None).unwrap();
        let lead = g.harmonics[g.verdict.leading.unwrap()].clone();
        (g.verdict.squeals, lead)
    };
    let (full_squeals, full) = judge("data/runs/curve/curve-falling-10mrad-patch-exact");
    let (half_squeals, half) = judge("data/runs/curve/curve-falling-10mrad-patch-exact-dt-x0.5");
    assert_eq!(full_squeals, half_squeals);
    assert!(!half_squeals);
    assert_eq!((full.direction, full.n), (half.direction, half.n));
    let (f_full, f_half) = (full.final_peak_hz.unwrap(), half.final_peak_hz.unwrap());
    assert!(
        (f_half / f_full - 1.0).abs() <= 0.03,
        "{f_half} against {f_full} Hz"
    );
    let level = half.final_level_m_per_s / full.final_level_m_per_s;
    assert!((level - 1.0).abs() <= 0.30, "level ratio {level}");
    // The figures as recorded in docs/convergence.md, to their digits.
    assert!((f_half - 5573.9).abs() < 0.1 && (half.final_level_m_per_s - 5.80e-2).abs() < 5e-5);
}

#[test]
fn the_report_of_a_ring_run_opens_with_its_verdict_and_growth_wants_a_ring() {
    let out = std::env::temp_dir().join(format!("squeal_curve_report_{}", std::process::id()));
    common::run_squeal(&["report", "data/runs/curve/curve-falling-10mrad"], &out);
    let md = std::fs::read_to_string(out.join("index.md")).unwrap();
    // The first section after the title is the verdict, then the nodal-diameter section.
    let headings: Vec<&str> = md.lines().filter(|l| l.starts_with("## ")).collect();
    assert_eq!(headings[0], "## Does the wheel squeal?");
    assert_eq!(headings[1], "## Nodal diameters: the rim ring by harmonic");
    assert!(md.contains("**no squeal: no harmonic grew x10"), "{md}");
    for file in [
        "per_n_map_curve-falling-10mrad.png",
        "ring_envelopes_curve-falling-10mrad.png",
    ] {
        assert!(out.join(file).exists(), "{file}");
    }
    let _ = std::fs::remove_dir_all(&out);
    // `growth --per-n` on a run without a ring: exit 2 naming ring.csv.
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["growth", "data/runs/case1-paper", "--per-n", "--out"])
        .arg(std::env::temp_dir().join("squeal_growth_no_ring"))
        .output()
        .unwrap();
    assert_eq!(status.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&status.stderr).contains("ring.csv"));
}

/// Item 5's halved step (`time_stepping.step_scale` 0.5): the run steps at half the engine's
/// step, and a smooth quantity converges as a second-order scheme's should: the
/// contact's normal force over the last millisecond of a 2 ms run agrees with the full step's
/// within 1 % (the central-difference error is O(dt^2), about 1e-4 of the force at these
/// steps; 1 % leaves room for the contact's stick-slip switching, which moves with the step).
#[test]
fn a_halved_step_runs_at_half_the_step_and_gives_the_same_contact_force() {
    let mean_tail = |dir: &Path| {
        let f = Table::read_numeric(&dir.join("contact_forces.csv")).unwrap();
        let t = column(&f, "time_s");
        let n = column(&f, "normal_force_n");
        let tail: Vec<f64> = t
            .iter()
            .zip(n)
            .filter(|(t, _)| **t >= 1e-3)
            .map(|(_, n)| *n)
            .collect();
        tail.iter().sum::<f64>() / tail.len() as f64
    };
    let step = |dir: &Path| {
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.join("status.json")).unwrap())
                .unwrap();
        s["time_step_s"].as_f64().unwrap()
    };
    let loaded = curve_case(2.0);
    let (_, full) = run_in_temp(&loaded, "squeal_curve_dt1", Some(2e-3));
    let mut halved = curve_case(2.0);
    halved.case.time_stepping.step_scale = 0.5;
    let (_, half) = run_in_temp(&halved, "squeal_curve_dt05", Some(2e-3));
    // The engine fits a whole number of steps into each output sample interval (rounding the
    // step down), so the two steps are each rounded to that grid: half within 2 % (measured
    // 3.175e-7 against 6.25e-7 s, 0.508).
    let ratio = step(&half) / step(&full);
    assert!((ratio - 0.5).abs() < 0.01, "step ratio {ratio}");
    let (a, b) = (mean_tail(&full), mean_tail(&half));
    assert!((a - b).abs() < 0.01 * a, "{a} N against {b} N");
    let _ = std::fs::remove_dir_all(&full);
    let _ = std::fs::remove_dir_all(&half);
}

/// The tiny curve case at 20 mrad (sliding within 2 ms) with the paper's falling friction read
/// at the patch's sliding velocity (`friction_slip_speed: patch`), 2 ms, five patch snapshots:
/// in each, every slave at the traction bound carries one and the same coefficient
/// (|shear| / pressure equal to 1e-9 across the patch) within the law's range [mu_d, mu_s]
/// (measured 2026-11-29: two nodes at 0.4722 and at 0.4817 in the snapshots at 1.25 and 1.5 ms;
/// with each node's own speed the same snapshots hold one node at the bound each, at 0.364 and
/// 0.454). The coefficients' definition is checked by hand in tests/contact.rs.
#[test]
fn falling_friction_at_the_patch_speed_gives_every_sliding_node_one_coefficient() {
    // Per snapshot: the at-bound nodes' |shear| / pressure.
    let at_bound_ratios = |slip: &str| -> Vec<Vec<f64>> {
        // Through the case file's words, as a user writes them.
        let mut loaded = curve_case(20.0);
        loaded.case.friction = squeal::contact::FrictionLaw::Falling {
            mu_static: 0.5,
            mu_dynamic: 0.32,
            decay_s_per_m: 6.0,
        };
        loaded.case.friction_slip_speed = serde_json::from_value(slip.into()).unwrap();
        loaded.case.output.patch_times_s = vec![1.0e-3, 1.25e-3, 1.5e-3, 1.75e-3, 1.95e-3];
        let (record, dir) = run_in_temp(&loaded, &format!("squeal_curve_slip_{slip}"), Some(2e-3));
        assert_eq!(record.run.status, "completed");
        let mut snapshots = Vec::new();
        let mut files: Vec<_> = std::fs::read_dir(dir.join("patches"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "csv"))
            .collect();
        files.sort();
        for patch in files {
            let t = Table::read_numeric(&patch).unwrap();
            let (p, bound) = (column(&t, "pressure_pa"), column(&t, "slip_by_bound"));
            let (sx, sy, sz) = (
                column(&t, "shear_x_pa"),
                column(&t, "shear_y_pa"),
                column(&t, "shear_z_pa"),
            );
            snapshots.push(
                (0..p.len())
                    .filter(|&i| bound[i] > 0.5 && p[i] > 0.0)
                    .map(|i| (sx[i] * sx[i] + sy[i] * sy[i] + sz[i] * sz[i]).sqrt() / p[i])
                    .collect(),
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
        snapshots
    };
    let spread = |r: &[f64]| {
        let lo = r.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = r.iter().cloned().fold(0.0, f64::max);
        (hi - lo) / hi
    };
    let patch = at_bound_ratios("patch");
    // The tiny mesh's patch holds a few nodes: the snapshots with two or more at the bound
    // make the comparison, and there must be some.
    let compared: Vec<&Vec<f64>> = patch.iter().filter(|r| r.len() >= 2).collect();
    assert!(
        !compared.is_empty(),
        "no snapshot with two nodes at the bound: {patch:?}"
    );
    for r in compared {
        assert!(spread(r) < 1e-9, "patch speed: coefficients {r:?}");
        assert!(r.iter().all(|mu| (0.32..=0.5).contains(mu)), "{r:?}");
    }
}
