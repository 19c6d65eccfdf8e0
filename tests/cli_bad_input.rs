//! Bad input across every subcommand, table-driven: each row must exit with its code (2 for
//! input, 1 for I/O), name the file or field and the allowed range (or the values allowed),
//! and write nothing: every command runs in a fresh empty folder with absolute input paths and
//! relative outputs, and the folder must still be empty afterwards.

use std::path::{Path, PathBuf};
use std::process::Command;

fn fixtures() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("squeal_bad_input_fx_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A 10 kHz signal with a 300 Hz tone, a header-only CSV, an empty file, a run directory.
    let mut csv = String::from("time_s,x_m\n");
    for i in 0..2000 {
        let t = i as f64 * 1e-4;
        csv.push_str(&format!(
            "{t},{}\n",
            (2.0 * std::f64::consts::PI * 300.0 * t).sin()
        ));
    }
    std::fs::write(dir.join("s.csv"), &csv).unwrap();
    std::fs::write(dir.join("header.csv"), "time_s,x_m\n").unwrap();
    std::fs::write(dir.join("empty.csv"), "").unwrap();
    std::fs::write(dir.join("bad.json"), "{ not json").unwrap();
    // Item 11: a PSD that overflows, a header naming a column twice.
    let mut big = String::from("time_s,x_m\n");
    for i in 0..64 {
        big.push_str(&format!(
            "{},{}\n",
            i as f64 * 1e-4,
            if i % 2 == 0 { 1e308 } else { -1e308 }
        ));
    }
    std::fs::write(dir.join("big.csv"), big).unwrap();
    std::fs::write(
        dir.join("twice.csv"),
        csv.replacen("time_s,x_m", "time_s,x_m,x_m", 1)
            .lines()
            .enumerate()
            .map(|(k, l)| {
                if k == 0 {
                    l.to_string()
                } else {
                    format!("{l},0")
                }
            })
            .collect::<Vec<_>>()
            .join("\n"),
    )
    .unwrap();
    // A ring run (data/runs/ring/case1-demo) whose run.json is garbage.
    let ring_run = Path::new(env!("CARGO_MANIFEST_DIR")).join("data/runs/ring/case1-demo");
    let garbage = dir.join("garbage");
    std::fs::create_dir_all(&garbage).unwrap();
    for f in ["histories.csv", "modes.json"] {
        std::fs::copy(ring_run.join(f), garbage.join(f)).unwrap();
    }
    std::fs::write(garbage.join("run.json"), "{ garbage").unwrap();
    // Item 13: a run whose lateral-motion onset (run.json) lies at the record's last sample:
    // growth without --from-ms must not blame an option the user did not give.
    let late = dir.join("late");
    std::fs::create_dir_all(&late).unwrap();
    for f in ["histories.csv", "modes.json"] {
        std::fs::copy(ring_run.join(f), late.join(f)).unwrap();
    }
    std::fs::write(
        late.join("run.json"),
        r#"{"settings": {"lateral_motion": {"start_s": 0.04, "velocity_m_per_s": 0.1}}}"#,
    )
    .unwrap();
    let run = dir.join("run");
    std::fs::create_dir_all(&run).unwrap();
    let mut h = String::from("time_s,lateral_rim_velocity_m_per_s\n");
    for i in 0..2000 {
        let t = i as f64 * 1e-4;
        h.push_str(&format!(
            "{t},{}\n",
            (2.0 * std::f64::consts::PI * 1000.0 * t).sin()
        ));
    }
    std::fs::write(run.join("histories.csv"), h).unwrap();
    // A folder that is not a run directory (no histories.csv).
    std::fs::create_dir_all(dir.join("norun")).unwrap();
    // Curve cases with one thing wrong each (issue 57): the tiny curve case with its model
    // named by absolute path.
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    let curve: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data.join("cases/curve-ci.json")).unwrap())
            .unwrap();
    let ramp: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data.join("cases/case3-ci.json")).unwrap())
            .unwrap();
    let write_case = |name: &str, edit: &dyn Fn(&mut serde_json::Value)| {
        let mut c = curve.clone();
        c["model_scenario"] = serde_json::json!(data.join("models/ci-tiny.json"));
        edit(&mut c);
        std::fs::write(dir.join(name), serde_json::to_string_pretty(&c).unwrap()).unwrap();
    };
    write_case("aoa60.json", &|c| {
        c["curving"]["angle_of_attack_mrad"] = serde_json::json!(60.0)
    });
    write_case("ring20.json", &|c| {
        c["output"]["ring"] = serde_json::json!({"nodes": 20, "n_max": 10})
    });
    write_case("ring7.json", &|c| {
        c["output"]["ring"] = serde_json::json!({"nodes": 7, "n_max": 3})
    });
    write_case("yaw_and_ramp.json", &|c| {
        c["lateral_motion"] = ramp["lateral_motion"].clone()
    });
    write_case("step2.json", &|c| {
        c["time_stepping"] = serde_json::json!({"step_scale": 2.0})
    });
    write_case("slip.json", &|c| {
        c["friction_slip_speed"] = "contact".into()
    });
    write_case("frkey.json", &|c| c["friction"]["mu_typo"] = 0.3.into());
    write_case("enforce.json", &|c| {
        c["contact_enforcement"] = "lagrange".into()
    });
    // Item 13: a relaxation preload cut off before the wheel is down is blamed on its step
    // limit, not on the initial gap.
    write_case("preload5.json", &|c| {
        c["preload"]["method"] = "dynamic_relaxation".into();
        c["preload"]["max_steps"] = 5.into();
    });
    write_case("exact_mr.json", &|c| {
        c["contact_enforcement"] = "exact".into();
        c["time_stepping"] = serde_json::json!({"multi_rate": "on"});
    });
    // Item 11: a patch snapshot whose points carry no pressure (paper case 3's at 17 ms with
    // every pressure set to 0).
    let mut snapshot: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(data.join("runs/case3-paper/patches/patch_0017000.0us.json"))
            .unwrap(),
    )
    .unwrap();
    for point in snapshot["points"].as_array_mut().unwrap() {
        point["pressure_pa"] = 0.0.into();
    }
    std::fs::write(dir.join("nopressure.json"), snapshot.to_string()).unwrap();
    snapshot["mu"] = 5.0.into();
    std::fs::write(dir.join("mu5.json"), snapshot.to_string()).unwrap();
    // Item 13: a one-hexahedron legacy VTK mesh with its top and bottom faces swapped
    // (inverted: det J < 0).
    let mut inverted = String::from(
        "# vtk DataFile Version 3.0\ninverted\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 8 double\n",
    );
    for p in [
        "0 0 0", "1 0 0", "1 1 0", "0 1 0", "0 0 1", "1 0 1", "1 1 1", "0 1 1",
    ] {
        inverted.push_str(p);
        inverted.push('\n');
    }
    inverted.push_str("CELLS 1 9\n8 4 5 6 7 0 1 2 3\nCELL_TYPES 1\n12\n");
    std::fs::write(dir.join("inverted.vtk"), inverted).unwrap();
    dir
}

/// Words that state an allowed range, the allowed values or form, or what was expected.
const RANGE_WORDS: [&str; 18] = [
    "range",
    "must",
    "allowed",
    "possible values",
    "available",
    "need",
    "expected",
    "at least",
    "applies to",
    "plain name",
    "is not in",
    "non-negative",
    "does not exist",
    "cannot open",
    "without --resume",
    "cannot be used with",
    "give one",
    "bound",
];

#[test]
fn bad_inputs_exit_with_their_code_name_the_field_and_write_nothing() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("data");
    let fx = fixtures();
    let wheel = data
        .join("wheels/ns_intercity_920.json")
        .display()
        .to_string();
    let demo = data.join("models/demo.json").display().to_string();
    let case = data.join("cases/case3-ci.json").display().to_string();
    let s = fx.join("s.csv").display().to_string();
    // Item 13: an output folder under a file (ENOTDIR, os error 20, said in words).
    let under_file = format!("{s}/o");
    let header = fx.join("header.csv").display().to_string();
    let empty = fx.join("empty.csv").display().to_string();
    let bad_json = fx.join("bad.json").display().to_string();
    let run = fx.join("run").display().to_string();
    let norun = fx.join("norun").display().to_string();
    let missing = fx.join("missing.json").display().to_string();
    let big = fx.join("big.csv").display().to_string();
    let twice = fx.join("twice.csv").display().to_string();
    let garbage = fx.join("garbage").display().to_string();
    let ring_run = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("data/runs/ring/case1-demo")
        .display()
        .to_string();
    let slip = fx.join("slip.json").display().to_string();
    let enforce = fx.join("enforce.json").display().to_string();
    let exact_mr = fx.join("exact_mr.json").display().to_string();
    let preload5 = fx.join("preload5.json").display().to_string();
    let late = fx.join("late").display().to_string();
    let inverted = fx.join("inverted.vtk").display().to_string();
    let frkey = fx.join("frkey.json").display().to_string();
    let nopressure = fx.join("nopressure.json").display().to_string();
    let mu5 = fx.join("mu5.json").display().to_string();
    let aoa60 = fx.join("aoa60.json").display().to_string();
    let ring20 = fx.join("ring20.json").display().to_string();
    let ring7 = fx.join("ring7.json").display().to_string();
    let step2 = fx.join("step2.json").display().to_string();
    let yaw_and_ramp = fx.join("yaw_and_ramp.json").display().to_string();
    let frf = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/uff/frf_ascii.uff")
        .display()
        .to_string();
    let modes55 = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fixtures/uff/modes55.uff")
        .display()
        .to_string();
    // A universal file cut inside its first dataset, and one with a bad ordinate type.
    let ascii = std::fs::read_to_string(&frf).unwrap();
    std::fs::write(fx.join("cut.uff"), &ascii[..2000]).unwrap();
    let cut = fx.join("cut.uff").display().to_string();
    std::fs::write(
        fx.join("type3.uff"),
        ascii.replacen("         6      3001", "         3      3001", 1),
    )
    .unwrap();
    let type3 = fx.join("type3.uff").display().to_string();
    // (arguments, exit code, words the message must hold besides a range word)
    let rows: Vec<(Vec<&str>, i32, Vec<&str>)> = vec![
        // psd
        // A device instead of a file is read without end: refused before reading (item 10).
        (
            vec!["psd", &s, "--column", "x_m", "--out", &under_file],
            1,
            vec!["s.csv", "is a file, where a folder is needed"],
        ),
        (
            vec!["psd", "/dev/zero", "--column", "x_m", "--out", "o"],
            2,
            vec!["/dev/zero", "regular file"],
        ),
        (
            vec![
                "cwt",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--fmin-hz",
                "100",
                "--fmax-hz",
                "1000",
                "--voices",
                "100000",
            ],
            2,
            vec!["--voices", "[1, 64]"],
        ),
        (
            vec!["psd", &s, "--column", "x_m", "--out", "o", "--nperseg", "1"],
            2,
            vec!["nperseg"],
        ),
        (
            vec!["psd", &s, "--column", "x_m", "--out", "o", "--nperseg", "0"],
            2,
            vec!["nperseg"],
        ),
        (
            vec![
                "psd",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--nperseg",
                "99999",
            ],
            2,
            vec!["nperseg"],
        ),
        (
            vec!["psd", &s, "--column", "x_m", "--out", "o", "--overlap", "1"],
            2,
            vec!["overlap"],
        ),
        (
            vec![
                "psd",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--overlap",
                "-0.5",
            ],
            2,
            vec!["overlap"],
        ),
        (
            vec![
                "psd",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--fmax-hz",
                "20000",
            ],
            2,
            vec!["--fmax-hz"],
        ),
        (
            vec![
                "psd",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--fmin-hz",
                "-5",
            ],
            2,
            vec!["--fmin-hz"],
        ),
        (
            vec!["psd", &s, "--column", "x_m", "--out", "o", "--peaks", "0"],
            2,
            vec!["--peaks"],
        ),
        (
            vec![
                "psd",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--min-separation-hz",
                "-1",
            ],
            2,
            vec!["--min-separation-hz"],
        ),
        (
            vec![
                "psd", &s, "--column", "x_m", "--out", "o", "--window", "kaiser",
            ],
            2,
            vec!["window"],
        ),
        (
            vec![
                "psd",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--detrend",
                "quadratic",
            ],
            2,
            vec!["detrend"],
        ),
        (
            vec![
                "psd",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--scaling",
                "power",
            ],
            2,
            vec!["scaling"],
        ),
        (
            vec!["psd", &s, "--column", "x_m", "--out", "o", "--rank", "size"],
            2,
            vec!["rank"],
        ),
        (
            vec!["psd", &s, "--column", "y", "--out", "o"],
            2,
            vec!["s.csv", "available columns: time_s, x_m"],
        ),
        (
            vec!["psd", &empty, "--column", "x_m", "--out", "o"],
            2,
            vec!["empty.csv", "header"],
        ),
        (
            vec!["psd", &header, "--column", "x_m", "--out", "o"],
            2,
            vec!["header.csv", "samples"],
        ),
        (
            vec!["psd", &missing, "--column", "x_m", "--out", "o"],
            2,
            vec!["missing.json"],
        ),
        (
            vec!["psd", &norun, "--column", "x_m", "--out", "o"],
            2,
            vec!["norun/histories.csv"],
        ),
        // cwt and wav
        (
            vec![
                "cwt",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--fmin-hz",
                "100",
                "--fmax-hz",
                "9000",
            ],
            2,
            vec!["fmax"],
        ),
        (
            vec![
                "cwt",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--fmin-hz",
                "-1",
                "--fmax-hz",
                "1000",
            ],
            2,
            vec!["fmin"],
        ),
        (
            vec![
                "cwt",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--fmin-hz",
                "100",
                "--fmax-hz",
                "1000",
                "--voices",
                "0",
            ],
            2,
            vec!["voices"],
        ),
        (
            vec![
                "cwt",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--fmin-hz",
                "100",
                "--fmax-hz",
                "1000",
                "--time-stride",
                "0",
            ],
            2,
            vec!["stride"],
        ),
        (
            vec![
                "wav",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--sample-rate-hz",
                "0",
            ],
            2,
            vec!["--sample-rate-hz", "[8000, 384000]"],
        ),
        // A rate that would resample for minutes into gigabytes (issue 53, item 10).
        (
            vec![
                "wav",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--sample-rate-hz",
                "4000000000",
            ],
            2,
            vec!["--sample-rate-hz", "[8000, 384000]"],
        ),
        (
            vec![
                "wav",
                &s,
                "--column",
                "x_m",
                "--out",
                "o",
                "--sample-rate-hz",
                "-44100",
            ],
            2,
            vec!["--sample-rate-hz"],
        ),
        (
            vec!["wav", &s, "--column", "nope", "--out", "o"],
            2,
            vec!["nope"],
        ),
        // identify, check-modes, growth, report
        (
            vec!["identify", &run, "--fmax-hz", "20000", "--out", "o"],
            2,
            vec!["--fmax", "Nyquist"],
        ),
        (
            vec!["identify", &run, "--fmin-hz", "-3", "--out", "o"],
            2,
            vec!["fmin"],
        ),
        (
            vec!["identify", &run, "--fmin-hz", "-5", "--out", "o"],
            2,
            vec!["fmin"],
        ),
        (
            vec!["identify", &run, "--peaks", "0", "--out", "o"],
            2,
            vec!["--peaks"],
        ),
        (
            vec!["identify", &run, "--resolution-hz", "-5", "--out", "o"],
            2,
            vec!["resolution"],
        ),
        // Item 13: a spacing finer than the longest FFT was blamed on the internal `nfft`.
        (
            vec!["identify", &run, "--resolution-hz", "1e-9", "--out", "o"],
            2,
            vec!["--resolution-hz", "longest FFT"],
        ),
        // Item 13: the Welch parameters are named as the options that set them.
        (
            vec![
                "psd",
                &run,
                "--column",
                "lateral_rim_velocity_m_per_s",
                "--nperseg",
                "1",
            ],
            2,
            vec!["field `--nperseg`", "2..="],
        ),
        (
            vec!["identify", &run, "--column", "nothing", "--out", "o"],
            2,
            vec!["nothing"],
        ),
        (
            vec!["identify", &run, "--direction", "radial", "--out", "o"],
            2,
            vec!["radial", "lateral, vertical, longitudinal"],
        ),
        (
            vec![
                "identify",
                &run,
                "--direction",
                "lateral",
                "--column",
                "lateral_rim_velocity_m_per_s",
                "--out",
                "o",
            ],
            2,
            vec!["--direction", "--column"],
        ),
        (
            vec!["identify", &missing, "--out", "o"],
            2,
            vec!["RUN_DIR", "histories.csv"],
        ),
        (
            vec!["check-modes", &run, "--require", "0,x"],
            2,
            vec!["--require"],
        ),
        // Item 13: a negative count is our message, not clap's "use '-- -1'".
        (
            vec!["check-modes", &run, "--require", "-1,3"],
            2,
            vec!["--require", "`-1,3` is not a mode label", "non-negative"],
        ),
        (
            vec![
                "check-modes",
                &run,
                "--require",
                "0,3",
                "--fmax-hz",
                "99999",
            ],
            2,
            vec!["--fmax"],
        ),
        (
            vec![
                "check-modes",
                &run,
                "--require",
                "0,3",
                "--direction",
                "sideways",
            ],
            2,
            vec!["sideways"],
        ),
        (
            vec!["growth", &run, "--half-width", "0", "--out", "o"],
            2,
            vec!["half"],
        ),
        (
            vec!["growth", &run, "--window-ms", "-4", "--out", "o"],
            2,
            vec!["--window-ms"],
        ),
        // Issue 53, item 11: what used to pass silently.
        (
            vec!["psd", &big, "--column", "x_m", "--out", "o"],
            2,
            vec!["big.csv", "overflows"],
        ),
        (
            vec!["psd", &twice, "--column", "x_m", "--out", "o"],
            2,
            vec!["twice.csv", "`x_m` appears twice"],
        ),
        (
            vec!["identify", &garbage, "--out", "o"],
            2,
            vec!["run.json"],
        ),
        (
            vec!["growth", &ring_run, "--from-ms", "-5", "--out", "o"],
            2,
            vec!["--from-ms", "-5 ms"],
        ),
        (
            vec!["growth", &ring_run, "--window-ms", "100", "--out", "o"],
            2,
            vec!["--window-ms", "longer than the record"],
        ),
        (
            vec!["growth", &run, "--mode", "3", "--out", "o"],
            2,
            vec!["--mode"],
        ),
        (
            vec!["report", &run, "--stability", &missing, "--out", "o"],
            2,
            vec!["missing.json"],
        ),
        // profile
        (
            vec!["profile", "s1002", "--step-mm", "0"],
            2,
            vec!["--step-mm"],
        ),
        (
            vec!["profile", "s1002", "--step-mm", "-1"],
            2,
            vec!["--step-mm"],
        ),
        (
            vec!["profile", "gap", "--wheel-y-mm", "-40"],
            2,
            vec!["--wheel-y-mm"],
        ),
        (
            vec!["profile", "contact", "--from-mm", "5", "--to-mm", "1"],
            2,
            vec!["--to-mm"],
        ),
        (
            vec!["profile", "gap", "--wheel-radius-m", "0"],
            2,
            vec!["--wheel-radius-m"],
        ),
        (
            vec!["profile", "54e1", "--section-mm", "0.1"],
            2,
            vec!["--section-mm", "[0.5, 10]"],
        ),
        (vec!["profile", "u60"], 2, vec!["u60"]),
        // ema
        (
            vec!["ema", "--uff", &frf, "--out", "o", "--max-order", "7"],
            2,
            vec!["--max-order"],
        ),
        (
            vec!["ema", "--uff", &frf, "--out", "o", "--max-order", "-2"],
            2,
            vec!["--max-order"],
        ),
        (
            vec!["ema", "--uff", &frf, "--out", "o", "--fmax-hz", "9000"],
            2,
            vec!["--fmax-hz"],
        ),
        (
            vec!["ema", "--uff", &frf, "--out", "o", "--fmin-hz", "-5"],
            2,
            vec!["--fmin-hz"],
        ),
        (
            vec!["ema", "--uff", &frf, "--out", "o", "--method", "guess"],
            2,
            vec!["--method"],
        ),
        (
            vec!["ema", "--uff", &cut, "--out", "o"],
            2,
            vec!["cut.uff", "dataset 58"],
        ),
        (
            vec!["ema", "--uff", &type3, "--out", "o"],
            2,
            vec!["type3.uff", "record 7"],
        ),
        (
            vec!["ema", "--uff", &modes55, "--out", "o"],
            2,
            vec!["modes55.uff", "FRF"],
        ),
        (
            vec!["ema", "--uff", &missing, "--out", "o"],
            2,
            vec!["missing.json"],
        ),
        // kalker
        (
            vec!["kalker", "hertz", "--normal-force-n", "-1"],
            2,
            vec!["--normal-force-n", "(0, 1e8] N"],
        ),
        // Item 13: a force far beyond any wheel's was "all pressure vanished".
        (
            vec![
                "kalker",
                "creep",
                "--normal-force-n",
                "1e300",
                "--mu",
                "0.3",
            ],
            2,
            vec!["--normal-force-n", "(0, 1e8] N"],
        ),
        // Item 13: a snapshot's own friction coefficient is named as its field, not as `--mu`.
        (
            vec!["kalker", "compare", "--snapshot", &mu5, "--out", "o"],
            2,
            vec!["mu5.json", "field `mu`"],
        ),
        (
            vec![
                "kalker",
                "hertz",
                "--normal-force-n",
                "100000",
                "--poisson-ratio",
                "0.7",
            ],
            2,
            vec!["--poisson-ratio"],
        ),
        (
            vec![
                "kalker",
                "hertz",
                "--normal-force-n",
                "100000",
                "--poisson-ratio",
                "0.6",
            ],
            2,
            vec!["--poisson-ratio", "[0, 0.5)"],
        ),
        (
            vec![
                "kalker",
                "hertz",
                "--normal-force-n",
                "100000",
                "--youngs-modulus-pa",
                "-1",
            ],
            2,
            vec!["--youngs-modulus-pa"],
        ),
        (
            vec![
                "kalker",
                "hertz",
                "--normal-force-n",
                "100000",
                "--wheel-y-m",
                "0.05",
            ],
            2,
            vec!["wheel-y"],
        ),
        (
            vec![
                "kalker",
                "hertz",
                "--normal-force-n",
                "100000",
                "--wheel-radius-m",
                "0",
            ],
            2,
            vec!["wheel-radius"],
        ),
        (
            vec![
                "kalker",
                "creep",
                "--normal-force-n",
                "100000",
                "--mu",
                "-0.3",
            ],
            2,
            vec!["mu"],
        ),
        (
            vec![
                "kalker",
                "creep",
                "--normal-force-n",
                "100000",
                "--mu",
                "0.3",
                "--grid",
                "1",
            ],
            2,
            vec!["grid"],
        ),
        (
            vec![
                "kalker",
                "solve",
                "--normal-force-n",
                "100000",
                "--force-x-n",
                "1000",
                "--force-y-n",
                "0",
                "--mu",
                "0.3",
                "--phi-per-m",
                "NaN",
            ],
            2,
            vec!["--phi-per-m"],
        ),
        (
            vec![
                "kalker",
                "solve",
                "--normal-force-n",
                "120000",
                "--force-x-n",
                "60000",
                "--force-y-n",
                "10000",
                "--mu",
                "0.45",
            ],
            2,
            vec!["--force-x-n/--force-y-n"],
        ),
        // mesh, modes, axisym
        (
            vec!["mesh", "--wheel", &missing, "--out", "o"],
            2,
            vec!["missing.json"],
        ),
        (
            vec!["mesh", "--wheel", &bad_json, "--out", "o"],
            2,
            vec!["bad.json"],
        ),
        (
            vec!["mesh", "--wheel", &wheel, "--msh", "o.stl"],
            2,
            vec!["--msh", "o.stl"],
        ),
        (
            vec!["mesh", "--wheel", &wheel, "--vtu", "o.msh"],
            2,
            vec!["--vtu", "o.msh"],
        ),
        (
            vec!["mesh", "--wheel", &wheel, "--out", "a", "--out", "b"],
            2,
            vec!["--out", "one output folder"],
        ),
        (
            vec!["modes", "--wheel", &wheel, "--fmax-hz", "-10", "--out", "o"],
            2,
            vec!["--fmax-hz"],
        ),
        (
            vec![
                "modes",
                "--wheel",
                &wheel,
                "--element-size-mm",
                "1",
                "--out",
                "o",
            ],
            2,
            vec!["--element-size-mm"],
        ),
        (
            vec!["modes", "--wheel", &wheel, "--slices", "0", "--out", "o"],
            2,
            vec!["slices"],
        ),
        (
            vec![
                "modes",
                "--wheel",
                &wheel,
                "--density-kg-per-m3",
                "-7850",
                "--out",
                "o",
            ],
            2,
            vec!["--density-kg-per-m3"],
        ),
        (
            vec![
                "modes",
                "--wheel",
                &wheel,
                "--density-kg-per-m3",
                "7850",
                "--out",
                "o",
            ],
            2,
            vec!["--density-kg-per-m3", "--mesh"],
        ),
        (
            vec!["modes", "--wheel", &wheel, "--clamp", "q<1", "--out", "o"],
            2,
            vec!["clamp"],
        ),
        (
            vec![
                "modes",
                "--wheel",
                &wheel,
                "--revolved-sectors",
                "2",
                "--out",
                "o",
            ],
            2,
            vec!["sectors"],
        ),
        (
            vec![
                "axisym",
                "--wheel",
                &wheel,
                "--harmonics",
                "5..2",
                "--out",
                "o",
            ],
            2,
            vec!["harmonics"],
        ),
        (
            vec!["axisym", "--wheel", &wheel, "--fmax-hz", "0", "--out", "o"],
            2,
            vec!["fmax"],
        ),
        (
            vec![
                "axisym",
                "--wheel",
                &wheel,
                "--element-size-mm",
                "0.01",
                "--out",
                "o",
            ],
            2,
            vec!["element-size"],
        ),
        (
            vec!["axisym", "--wheel", &missing, "--out", "o"],
            2,
            vec!["missing.json"],
        ),
        // simulate, bench, stability
        (
            vec!["simulate", "--case", &missing, "--out", "o"],
            2,
            vec!["missing.json"],
        ),
        (
            vec![
                "simulate",
                "--case",
                &case,
                "--end-time-ms",
                "-1",
                "--out",
                "o",
            ],
            2,
            vec!["--end-time-ms"],
        ),
        (
            vec![
                "simulate",
                "--case",
                &case,
                "--end-time-ms",
                "5000",
                "--out",
                "o",
            ],
            2,
            vec!["--end-time-ms"],
        ),
        (
            vec![
                "simulate",
                "--case",
                &case,
                "--preload",
                "sideways",
                "--out",
                "o",
            ],
            2,
            vec!["--preload"],
        ),
        (
            vec!["simulate", "--case", &case, "--resume", "--out", "o"],
            2,
            vec!["--resume", "checkpoint"],
        ),
        (
            vec!["simulate", "--case", &demo, "--out", "o"],
            2,
            vec!["demo.json"],
        ),
        (
            vec!["bench", "rolling", "--case", &case, "--steps", "0"],
            2,
            vec!["--steps"],
        ),
        (
            vec!["bench", "rolling", "--case", &missing],
            2,
            vec!["missing.json"],
        ),
        (
            vec!["bench", "preload", "--case", &missing],
            2,
            vec!["missing.json"],
        ),
        (
            vec!["bench", "modal", "--mtx", &missing, "--slices", "0"],
            2,
            vec!["slices"],
        ),
        (
            vec!["bench", "modal", "--mtx", &missing, "--shift-hz", "20000"],
            2,
            vec!["--shift-hz", "(0, fmax = 10000] Hz"],
        ),
        (
            vec!["bench", "modal", "--mtx", &missing, "--fmax-hz", "0"],
            2,
            vec!["--fmax-hz", "(0, 1e6] Hz"],
        ),
        (
            vec!["stability", "--case", &case, "--time-ms", "3", "--out", "o"],
            2,
            vec!["--time-ms", "RUN_DIR"],
        ),
        (
            vec![
                "stability",
                "--case",
                &case,
                "--normal-force-n",
                "-1",
                "--out",
                "o",
            ],
            2,
            vec!["--normal-force-n", "> 0 N"],
        ),
        (
            vec![
                "stability",
                "--case",
                &case,
                "--sweep",
                "friction-slope-s-per-m=0..1:1",
                "--out",
                "o",
            ],
            2,
            vec!["--sweep", "friction-slope-s-per-m"],
        ),
        (
            vec!["stability", "--case", &missing, "--out", "o"],
            2,
            vec!["missing.json"],
        ),
        // Curving and the rim ring (issue 57).
        (
            vec!["simulate", "--case", &step2, "--out", "o"],
            2,
            vec!["step2.json", "time_stepping.step_scale", "[0.05, 1]"],
        ),
        (
            vec!["simulate", "--case", &frkey, "--out", "o"],
            2,
            vec![
                "frkey.json",
                "friction",
                "unknown field `mu_typo`",
                "expected",
            ],
        ),
        (
            vec!["kalker", "compare", "--snapshot", &nopressure, "--out", "o"],
            2,
            vec!["nopressure.json", "pressure_pa", "must be positive"],
        ),
        (
            vec!["simulate", "--case", &slip, "--out", "o"],
            2,
            vec!["slip.json", "friction_slip_speed", "node", "patch"],
        ),
        (
            vec!["simulate", "--case", &enforce, "--out", "o"],
            2,
            vec!["enforce.json", "contact_enforcement", "penalty", "exact"],
        ),
        (
            vec!["simulate", "--case", &exact_mr, "--out", "o"],
            2,
            vec!["exact_mr.json", "time_stepping.multi_rate", "exact contact"],
        ),
        (
            vec!["growth", &late, "--out", "o"],
            2,
            vec!["--from-ms (not given)", "lateral-motion onset", "must"],
        ),
        (
            vec!["modes", "--mesh", &inverted, "--out", "o"],
            2,
            vec!["inverted.vtk", "element 0 is inverted", "must be positive"],
        ),
        (
            vec!["simulate", "--case", &preload5, "--out", "o"],
            2,
            vec![
                "preload5.json",
                "preload.max_steps",
                "step limit",
                "2..=100000000",
            ],
        ),
        (
            vec!["simulate", "--case", &aoa60, "--out", "o"],
            2,
            vec!["aoa60.json", "curving.angle_of_attack_mrad", "[-50, 50]"],
        ),
        (
            vec!["simulate", "--case", &ring20, "--out", "o"],
            2,
            vec!["ring20.json", "output.ring.nodes", "2 n_max + 1 = 21"],
        ),
        (
            // 7 nodes are enough for n <= 3, but no circle of the tiny wheel (48 around)
            // holds 7 equally spaced nodes.
            vec!["simulate", "--case", &ring7, "--out", "o"],
            2,
            vec!["ring7.json", "output.ring.nodes", "divisor"],
        ),
        (
            vec!["simulate", "--case", &yaw_and_ramp, "--out", "o"],
            2,
            vec!["yaw_and_ramp.json", "curving", "lateral_motion"],
        ),
        (
            vec!["check-modes", &run, "--per-n", "--require", "0,3"],
            2,
            vec!["ring.csv", "output.ring"],
        ),
        (
            vec![
                "identify",
                &run,
                "--per-n",
                "--direction",
                "vertical",
                "--out",
                "o",
            ],
            2,
            vec!["--direction", "radial"],
        ),
        (
            vec!["identify", &run, "--direction", "radial", "--out", "o"],
            2,
            vec!["--direction", "--per-n"],
        ),
        (
            vec![
                "check-modes",
                &run,
                "--per-n",
                "--require",
                "0,3",
                "--margin-db",
                "-1",
            ],
            2,
            vec!["--margin-db", ">= 0"],
        ),
    ];
    assert!(rows.len() >= 95, "{} rows", rows.len());
    let mut failures = Vec::new();
    for (k, (args, code, words)) in rows.iter().enumerate() {
        let cwd = std::env::temp_dir().join(format!("squeal_bad_input_{k}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&cwd);
        std::fs::create_dir_all(&cwd).unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_squeal"))
            .args(args)
            .current_dir(&cwd)
            .output()
            .expect("run");
        let err = String::from_utf8_lossy(&out.stderr).to_string();
        let mut problems = Vec::new();
        if out.status.code() != Some(*code) {
            problems.push(format!("exit {:?}, expected {code}", out.status.code()));
        }
        for w in words {
            if !err.contains(w) {
                problems.push(format!("message lacks `{w}`"));
            }
        }
        // I/O errors name the file; input errors also state what is allowed.
        if *code == 2 && !RANGE_WORDS.iter().any(|w| err.contains(w)) {
            problems.push("message states no allowed range or values".into());
        }
        let left: Vec<String> = std::fs::read_dir(&cwd)
            .unwrap()
            .flatten()
            .map(|e| e.file_name().to_string_lossy().to_string())
            .collect();
        if !left.is_empty() {
            problems.push(format!("wrote {left:?}"));
        }
        if err.contains("panicked") {
            problems.push("panicked".into());
        }
        // Issue 53, item 13: no raw OS error numbers, no hidden stage folder's name.
        for raw in ["os error", ".partial-"] {
            if err.contains(raw) {
                problems.push(format!("message shows `{raw}`"));
            }
        }
        if !problems.is_empty() {
            failures.push(format!(
                "{args:?}: {} | {}",
                problems.join("; "),
                err.trim()
            ));
        }
        let _ = std::fs::remove_dir_all(&cwd);
    }
    let _ = std::fs::remove_dir_all(&fx);
    assert!(
        failures.is_empty(),
        "{} of {} bad inputs misbehaved:\n{}",
        failures.len(),
        rows.len(),
        failures.join("\n")
    );
}
