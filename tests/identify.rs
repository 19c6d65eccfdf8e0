//! Mode-to-peak identification on synthetic signals built from known modes plus noise, and
//! `squeal check-modes` from the command line (both outcomes and the bad-input cases).
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use std::process::Command;

use squeal::analysis::identify::{parse_required, Direction, ModeFamily, ModeRef};
use squeal::analysis::{analyse_run, AnalysisOptions};

fn mode(f: f64, family: ModeFamily, m: u32, n: u32) -> ModeRef {
    ModeRef {
        frequency_hz: f,
        family,
        nodal_circles: m,
        nodal_diameters: n,
    }
}

/// Paper-like wheel modes (a few hundred Hz umbrella mode, (0,3) ~1 kHz, (0,4) ~2 kHz, ...).
fn modes() -> Vec<ModeRef> {
    vec![
        mode(0.0, ModeFamily::Rigid, 0, 0),
        mode(300.0, ModeFamily::Axial, 0, 0),
        mode(480.0, ModeFamily::Axial, 0, 2),
        mode(1050.0, ModeFamily::Axial, 0, 3),
        mode(2000.0, ModeFamily::Axial, 0, 4),
        mode(3050.0, ModeFamily::Axial, 0, 5),
        mode(1700.0, ModeFamily::Radial, 0, 2),
        mode(2620.0, ModeFamily::Radial, 0, 3),
        mode(3900.0, ModeFamily::Circumferential, 0, 1),
    ]
}

/// Tones (Hz, amplitude) plus seeded uniform noise, sampled at 20 kHz for 2 s.
fn write_run(dir: &Path, column: &str, tones: &[(f64, f64)]) {
    std::fs::create_dir_all(dir).expect("dir");
    let fs = 20_000.0;
    let mut state = 0x9e37_79b9_7f4a_7c15u64;
    let mut csv = format!("time_s,{column}\n");
    for i in 0..40_000 {
        let t = i as f64 / fs;
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let noise = ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.2;
        let v: f64 = tones
            .iter()
            .map(|(f, a)| a * (2.0 * PI * f * t).sin())
            .sum::<f64>()
            + noise;
        csv.push_str(&format!("{t:.8},{v:.10}\n"));
    }
    std::fs::write(dir.join("histories.csv"), csv).expect("write");
    std::fs::write(
        dir.join("modes.json"),
        serde_json::to_string(&modes()).expect("json"),
    )
    .expect("write");
}

fn temp(tag: &str) -> PathBuf {
    std::env::temp_dir().join(format!("squeal-identify-{tag}-{}", std::process::id()))
}

#[test]
fn lateral_peaks_get_axial_labels_and_a_stray_peak_stays_unexplained() {
    let dir = temp("lateral");
    // Modal frequencies shifted by 1 % (as an explicit mesh would), and a tone at 2400 Hz
    // with no axial mode within 5 % (2000 and 3050 Hz are 17 % and 27 % away).
    write_run(
        &dir,
        "lateral_velocity_m_per_s",
        &[(303.0, 1.0), (1060.0, 0.8), (2020.0, 0.6), (2400.0, 0.7)],
    );
    let options = AnalysisOptions {
        peaks: 4,
        ..Default::default()
    };
    let a = analyse_run(&dir, &options).expect("analysis");
    assert_eq!(a.direction, Direction::Lateral);
    let mut by_freq = a.identifications.clone();
    by_freq.sort_by(|x, y| x.peak_frequency_hz.total_cmp(&y.peak_frequency_hz));
    let labels: Vec<String> = by_freq
        .iter()
        .map(|i| {
            i.mode
                .as_ref()
                .map(|m| m.label())
                .unwrap_or_else(|| "unexplained".into())
        })
        .collect();
    assert_eq!(labels, ["(0,0)", "(0,3)", "(0,4)", "unexplained"]);
    // Peak frequencies refined to well under a bin (1.22 Hz).
    for (i, f) in by_freq.iter().zip([303.0, 1060.0, 2020.0, 2400.0]) {
        assert!(
            (i.peak_frequency_hz - f).abs() < 0.5,
            "{} vs {f}",
            i.peak_frequency_hz
        );
    }
    let d = by_freq[1].difference_percent.expect("difference");
    assert!((d - 100.0 * (1060.0 - 1050.0) / 1050.0).abs() < 0.05, "{d}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn vertical_signal_sees_radial_modes_only() {
    let dir = temp("vertical");
    // 1705 Hz: radial (0,2) at 1700; 2005 Hz: only an axial mode nearby -> unexplained.
    write_run(
        &dir,
        "vertical_velocity_m_per_s",
        &[(1705.0, 1.0), (2005.0, 0.8)],
    );
    let a = analyse_run(
        &dir,
        &AnalysisOptions {
            signal: "vertical".into(),
            peaks: 2,
            ..Default::default()
        },
    )
    .expect("analysis");
    let mut ids = a.identifications.clone();
    ids.sort_by(|x, y| x.peak_frequency_hz.total_cmp(&y.peak_frequency_hz));
    assert_eq!(
        ids[0].mode.as_ref().map(|m| (m.family, m.label())),
        Some((ModeFamily::Radial, "(0,2)".to_string()))
    );
    assert!(ids[1].mode.is_none());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn malformed_required_modes_are_rejected() {
    assert_eq!(parse_required("0,3").expect("ok"), (0, 3));
    assert_eq!(parse_required("(1, 4)").expect("ok"), (1, 4));
    for bad in ["0;3", "a,b", "1", "-1,2", "0,3,1", ""] {
        let e = parse_required(bad).expect_err(bad).to_string();
        assert!(e.contains("--require") && e.contains("e.g. 0,3"), "{e}");
    }
}

fn squeal(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .output()
        .expect("run squeal")
}

#[test]
fn check_modes_passes_and_fails_with_reasons() {
    let dir = temp("check");
    write_run(
        &dir,
        "lateral_velocity_m_per_s",
        &[(303.0, 1.0), (1060.0, 0.8), (2020.0, 0.6)],
    );
    let d = dir.to_str().expect("utf8");
    let ok = squeal(&[
        "check-modes",
        "--require",
        "0,0",
        "--require",
        "0,3",
        "--require",
        "0,4",
        "--direction",
        "lateral",
        d,
    ]);
    assert_eq!(
        ok.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    // (0,5) exists at 3050 Hz but has no peak; (2,7) does not exist at all.
    let missing = squeal(&[
        "check-modes",
        "--require",
        "0,3",
        "--require",
        "0,5",
        "--require",
        "2,7",
        "--direction",
        "lateral",
        d,
    ]);
    assert_eq!(missing.status.code(), Some(1));
    let err = String::from_utf8_lossy(&missing.stderr);
    assert!(err.contains("(0,5) at 3050.0 Hz is not among"), "{err}");
    assert!(err.contains("(2,7): no such mode"), "{err}");
    // identify writes the paper-style table.
    let out = temp("check-out");
    let id = squeal(&[
        "identify",
        "--direction",
        "lateral",
        d,
        "--out",
        out.to_str().expect("utf8"),
    ]);
    assert!(id.status.success());
    let md = std::fs::read_to_string(out.join("identification.md")).expect("md");
    assert!(md.contains(
        "| dominant frequency (Hz) | rim mean/point | modal frequency (Hz) | mode | family | difference (%) |"
    ));
    assert!(out.join("identification.csv").exists() && out.join("identification.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&out);
}

#[test]
fn check_modes_bad_input_exits_2() {
    let dir = temp("bad");
    write_run(&dir, "lateral_velocity_m_per_s", &[(303.0, 1.0)]);
    let d = dir.to_str().expect("utf8");
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["check-modes", "--require", "0-3", d], "--require"),
        (
            vec!["check-modes", "--require", "0,3", "--column", "radial", d],
            "available: time_s, lateral_velocity_m_per_s",
        ),
        (
            vec!["check-modes", "--require", "0,3", "--fmax-hz", "20000", d],
            "Nyquist",
        ),
        (
            vec!["check-modes", "--require", "0,3", "--from-ms", "5000", d],
            "--from-ms",
        ),
        (
            vec![
                "check-modes",
                "--require",
                "0,3",
                "--from-ms",
                "100",
                "--to-ms",
                "50",
                d,
            ],
            "--to-ms",
        ),
        (
            vec![
                "check-modes",
                "--require",
                "0,3",
                "--resolution-hz",
                "-5",
                d,
            ],
            "--resolution-hz",
        ),
    ];
    for (args, needle) in cases {
        let o = squeal(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(
            String::from_utf8_lossy(&o.stderr).contains(needle),
            "{args:?}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let empty = temp("empty");
    std::fs::create_dir_all(&empty).expect("dir");
    let o = squeal(&[
        "check-modes",
        "--require",
        "0,3",
        empty.to_str().expect("utf8"),
    ]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no histories.csv"));
    let _ = std::fs::remove_dir_all(&dir);
    let _ = std::fs::remove_dir_all(&empty);
}

/// The default wheel's (1,0) at 1767 Hz and (0,4) at 1839 Hz, 70 Hz apart, and an n = 0
/// umbrella mode: modes of a run directory for the rim-ratio tests.
fn close_modes() -> Vec<ModeRef> {
    vec![
        mode(231.0, ModeFamily::Axial, 0, 0),
        mode(1015.0, ModeFamily::Axial, 0, 3),
        mode(1767.0, ModeFamily::Axial, 1, 0),
        mode(1839.0, ModeFamily::Axial, 0, 4),
    ]
}

/// A rolling-like record at 50 kHz: the rim point carries `point` tones, the rim mean `mean`
/// tones (an n = 0 mode moves both alike, an n >= 1 mode only the point), both with seeded
/// noise 1e-3 of the tones.
fn write_rim_run(dir: &Path, duration_s: f64, point: &[(f64, f64)], mean: &[(f64, f64)]) {
    std::fs::create_dir_all(dir).expect("dir");
    let fs = 50_000.0;
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut noise = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((state >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 2e-3
    };
    let tone = |tones: &[(f64, f64)], t: f64| -> f64 {
        tones
            .iter()
            .map(|(f, a)| a * (2.0 * PI * f * t + 0.3).sin())
            .sum()
    };
    let mut csv =
        String::from("time_s,lateral_velocity_m_per_s,rim_mean_lateral_velocity_m_per_s\n");
    let n = (duration_s * fs).round() as usize;
    for i in 0..n {
        let t = i as f64 / fs;
        let (p, m) = (tone(point, t) + noise(), tone(mean, t) + noise());
        csv.push_str(&format!("{t:.8},{p:.10},{m:.10}\n"));
    }
    std::fs::write(dir.join("histories.csv"), csv).expect("write");
    std::fs::write(
        dir.join("modes.json"),
        serde_json::to_string(&close_modes()).expect("json"),
    )
    .expect("write");
}

fn labelled(a: &squeal::analysis::RunAnalysis) -> Vec<(f64, Option<String>, f64)> {
    let mut v: Vec<(f64, Option<String>, f64)> = a
        .identifications
        .iter()
        .map(|i| {
            (
                i.peak_frequency_hz,
                i.mode.as_ref().map(|m| m.label()),
                i.rim_mean_over_point.expect("ratio"),
            )
        })
        .collect();
    v.sort_by(|x, y| x.0.total_cmp(&y.0));
    v
}

/// One peak near 1.8 kHz in a 24 ms window (one Hann segment, main lobe +-83 Hz): by frequency
/// alone the closer mode wins; the rim ratio decides. A (0,4) tone at 1800 Hz (nearer (1,0) at
/// 1767 Hz) is (0,4), since the rim mean does not see it; a (1,0) tone at 1810 Hz (nearer (0,4)
/// at 1839) is (1,0), since the whole rim carries it. Breaking the ratio (mean = point) turns the
/// first into (1,0): the test fails without the gate.
#[test]
fn rim_ratio_tells_zero_four_from_one_zero_in_one_peak() {
    let dir = temp("rim-04");
    write_rim_run(&dir, 0.024, &[(1800.0, 1.0)], &[]);
    let options = AnalysisOptions {
        peaks: 1,
        band_hz: (500.0, 5000.0),
        ..Default::default()
    };
    let a = analyse_run(&dir, &options).expect("analysis");
    assert!(
        a.window.spectrum.contains("zero-padded"),
        "{}",
        a.window.spectrum
    );
    assert!(a.psd.frequency_resolution_hz <= 50.0);
    let got = labelled(&a);
    assert_eq!(got[0].1.as_deref(), Some("(0,4)"), "{got:?}");
    assert!(got[0].2 <= 0.2, "{got:?}");

    write_rim_run(&dir, 0.024, &[(1810.0, 1.0)], &[(1810.0, 0.9)]);
    let got = labelled(&analyse_run(&dir, &options).expect("analysis"));
    assert_eq!(got[0].1.as_deref(), Some("(1,0)"), "{got:?}");
    assert!(got[0].2 >= 0.5, "{got:?}");

    // A mixed peak (the mean carries 40 % of the power) gets no mode.
    write_rim_run(&dir, 0.024, &[(1800.0, 1.0)], &[(1800.0, 0.63)]);
    let a = analyse_run(&dir, &options).expect("analysis");
    assert!(
        a.identifications[0].mode.is_none(),
        "{:?}",
        a.identifications
    );
    assert_eq!(
        a.identifications[0].rim_motion,
        Some(squeal::analysis::identify::RimMotion::Mixed)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Both modes at once, 70 Hz apart, in an 80 ms window (main lobe +-25 Hz): two peaks, each with
/// its own ratio and label. The n = 0 umbrella mode keeps n = 0.
#[test]
fn rim_ratio_labels_two_close_modes_and_keeps_n0_peaks() {
    let dir = temp("rim-both");
    write_rim_run(
        &dir,
        0.08,
        &[(231.0, 2.0), (1767.0, 1.0), (1839.0, 1.0)],
        &[(231.0, 1.8), (1767.0, 0.9)],
    );
    let options = AnalysisOptions {
        peaks: 3,
        band_hz: (100.0, 5000.0),
        ..Default::default()
    };
    let got = labelled(&analyse_run(&dir, &options).expect("analysis"));
    let labels: Vec<Option<&str>> = got.iter().map(|g| g.1.as_deref()).collect();
    assert_eq!(
        labels,
        [Some("(0,0)"), Some("(1,0)"), Some("(0,4)")],
        "{got:?}"
    );
    assert!(
        got[0].2 >= 0.5 && got[1].2 >= 0.5 && got[2].2 <= 0.2,
        "{got:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A window that starts later than the record: the lateral-motion onset of run.json by default,
/// --from-ms when given; the spectrum covers only that span.
#[test]
fn window_starts_at_the_lateral_onset_of_run_json() {
    let dir = temp("onset");
    write_rim_run(&dir, 0.04, &[(1015.0, 1.0)], &[]);
    let run = serde_json::json!({"settings": {"lateral_motion": {"shape": "ramp", "start_s": 0.016,
        "rise_time_s": 0.001, "velocity_m_per_s": 0.6, "travel_m": 0.003, "settle_time_s": 0.002}}});
    std::fs::write(dir.join("run.json"), run.to_string()).expect("write");
    let a = analyse_run(&dir, &AnalysisOptions::default()).expect("analysis");
    assert!((a.window.from_s - 0.016).abs() < 1e-9, "{:?}", a.window);
    assert!(a.window.start_from.contains("lateral-motion onset"));
    let a = analyse_run(
        &dir,
        &AnalysisOptions {
            from_s: Some(0.03),
            ..Default::default()
        },
    )
    .expect("analysis");
    assert!((a.window.from_s - 0.03).abs() < 1e-9);
    // 10 ms at 50 kHz: one segment of 500 samples, padded for 50 Hz bins.
    assert_eq!(a.psd.params.nperseg, 500);
    let _ = std::fs::remove_dir_all(&dir);
}

/// On a real run: the committed 1 mm case 4 (velocity-step lateral motion from 16 ms) rings the
/// n = 0 modes from the hub, and its dominant lateral peaks after 16 ms stay n = 0: the rim mean
/// carries them.
#[test]
fn n0_peaks_of_the_committed_case4_run_stay_n0() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/runs/case4-paper");
    let a = analyse_run(
        &dir,
        &AnalysisOptions {
            from_s: Some(0.016),
            ..Default::default()
        },
    )
    .expect("analysis");
    for i in &a.identifications {
        assert_eq!(
            i.rim_motion,
            Some(squeal::analysis::identify::RimMotion::Common),
            "{:?}",
            a.identifications
        );
        if let Some(m) = &i.mode {
            assert_eq!(m.nodal_diameters, 0, "{:?}", a.identifications);
        }
    }
}

/// The rim columns carry their direction after the prefix; the n >= 1 column (rim point less
/// rim mean) gets only modes with nodal diameters, since its rim mean is zero by construction.
#[test]
fn rim_columns_name_their_direction_and_n1_column_gets_no_n0_mode() {
    for (name, d) in [
        (
            "rim_mean_lateral_velocity_m_per_s",
            Some(Direction::Lateral),
        ),
        (
            "rim_point_minus_mean_lateral_velocity_m_per_s",
            Some(Direction::Lateral),
        ),
        (
            "rim_mean_vertical_velocity_m_per_s",
            Some(Direction::Vertical),
        ),
        ("contact_rail_lateral_velocity_m_per_s", None),
    ] {
        assert_eq!(Direction::from_signal_name(name), d, "{name}");
    }
    let dir = temp("n1");
    // A tone at 240 Hz in the n >= 1 column, next to the n = 0 umbrella mode (0,0) at 231 Hz
    // (as leakage of the rim mean would put there), gets no label; a (0,3) tone gets (0,3).
    std::fs::create_dir_all(&dir).expect("dir");
    let fs = 50_000.0;
    let mut csv = String::from("time_s,rim_point_minus_mean_lateral_velocity_m_per_s\n");
    for i in 0..2000 {
        let t = i as f64 / fs;
        let v = (2.0 * PI * 240.0 * t).sin() + 0.5 * (2.0 * PI * 1015.0 * t).sin();
        csv.push_str(&format!("{t:.8},{v:.10}\n"));
    }
    std::fs::write(dir.join("histories.csv"), csv).expect("write");
    std::fs::write(
        dir.join("modes.json"),
        serde_json::to_string(&close_modes()).expect("json"),
    )
    .expect("write");
    let a = analyse_run(
        &dir,
        &AnalysisOptions {
            signal: "rim_point_minus_mean_lateral_velocity_m_per_s".into(),
            peaks: 2,
            band_hz: (100.0, 5000.0),
            ..Default::default()
        },
    )
    .expect("analysis");
    let got = labelled(&a);
    assert_eq!(got[0].1, None, "{got:?}");
    assert_eq!(got[1].1.as_deref(), Some("(0,3)"), "{got:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
