//! `squeal simulate` from the command line: a run stopped by a signal keeps its work (exit code
//! 130, status `interrupted`, a checkpoint) and `--resume` goes on from it; bad input exits 2.
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

fn squeal() -> Command {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
}

fn temp_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("squeal-cli-sim-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    dir
}

/// The tiny CI case with a longer end time (so that a signal lands inside the rolling run) and
/// the model path made absolute (the copy lives in a temp directory).
fn long_tiny_case(dir: &Path, end_time_s: f64) -> PathBuf {
    let mut case: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string("data/cases/case3-ci.json").expect("case"))
            .expect("json");
    let model = std::fs::canonicalize("data/models/ci-tiny.json").expect("model");
    case["model_scenario"] = serde_json::Value::String(model.display().to_string());
    case["end_time_s"] = serde_json::json!(end_time_s);
    case["output"]["vtu_times_s"] = serde_json::json!([]);
    let path = dir.join("case.json");
    std::fs::write(&path, serde_json::to_string_pretty(&case).unwrap()).unwrap();
    path
}

fn column(csv: &str, name: &str) -> Vec<f64> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let k = header.iter().position(|h| *h == name).expect("column");
    lines
        .map(|l| l.split(',').nth(k).unwrap().parse::<f64>().unwrap())
        .collect()
}

/// Samples every 20 us (50 kHz): consecutive times differ by one interval everywhere, across
/// the stop, to the rounding of the printed times (1e-9 relative), up to `end_ms`.
fn assert_samples_without_gap_or_repeat(out: &Path, end_ms: f64) {
    for file in ["contact_forces.csv", "histories.csv"] {
        let t = column(&std::fs::read_to_string(out.join(file)).unwrap(), "time_s");
        assert!(t.len() > 10, "{file}: {} rows", t.len());
        for w in t.windows(2) {
            assert!(
                ((w[1] - w[0]) - 2e-5).abs() < 1e-9,
                "{file}: samples at {} and {} s",
                w[0],
                w[1]
            );
        }
        assert!(
            *t.last().unwrap() > end_ms * 1e-3 - 4e-5,
            "{file} ends at {}",
            t.last().unwrap()
        );
    }
}

/// `squeal simulate --resume` of `case` in `out` until `end_ms`, as it came out.
fn resume(case: &Path, out: &Path, end_ms: f64) -> std::process::Output {
    squeal()
        .args(["simulate", "--quiet", "--resume", "--case"])
        .arg(case)
        .arg("--out")
        .arg(out)
        .args(["--end-time-ms", &format!("{end_ms}")])
        .output()
        .expect("resume")
}

/// A copy of the files (not the subfolders) of run folder `from` in a new folder `to`.
fn copy_run_files(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for entry in std::fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        if entry.file_type().unwrap().is_file() {
            std::fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
        }
    }
}

/// `squeal simulate --resume` of `case` in `out` until `end_ms`; it must succeed.
fn resume_until(case: &Path, out: &Path, end_ms: f64) {
    let resumed = resume(case, out, end_ms);
    assert!(
        resumed.status.success(),
        "{}",
        String::from_utf8_lossy(&resumed.stderr)
    );
}

fn read_json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// A resume of the run in `out` with a case or model that differs from the one the run
/// started with (issue 53, item 6) is refused with exit 2, naming every field that changed,
/// and leaves the folder byte for byte as it was: the speed and mu changed in the case, the
/// wheel's Young's modulus in the model (a change the checkpoint's mesh-and-mass fingerprint
/// cannot see), and, with `run.json` removed so that no field can be named, the checkpoint's
/// own stamp refuses the changed case. A changed end time and description are accepted (the
/// caller's resume goes on with them).
fn refuse_resumes_with_other_values(dir: &Path, case: &Path, out: &Path, end_ms: f64) {
    let original: serde_json::Value = read_json(case);
    let model_path = PathBuf::from(original["model_scenario"].as_str().unwrap());
    let changed_case = |edit: &dyn Fn(&mut serde_json::Value), name: &str| -> PathBuf {
        let mut value = original.clone();
        edit(&mut value);
        let path = dir.join(name);
        std::fs::write(&path, serde_json::to_string_pretty(&value).unwrap()).unwrap();
        path
    };
    // The model with a stiffer wheel: its own copy of the wheel file.
    let mut wheel = read_json(Path::new("data/wheels/ns_intercity_920.json"));
    wheel["material"]["youngs_modulus_pa"] = serde_json::json!(2.1e11 * 1.01);
    let wheel_path = dir.join("stiffer-wheel.json");
    std::fs::write(&wheel_path, serde_json::to_string_pretty(&wheel).unwrap()).unwrap();
    let mut model = read_json(&model_path);
    model["wheel_file"] = serde_json::json!(wheel_path.display().to_string());
    let stiffer_model = dir.join("stiffer-model.json");
    std::fs::write(
        &stiffer_model,
        serde_json::to_string_pretty(&model).unwrap(),
    )
    .unwrap();

    let speed_and_mu = changed_case(
        &|c| {
            c["speed_km_per_h"] = serde_json::json!(50.0);
            c["friction"]["mu"] = serde_json::json!(0.3);
            c["description"] = serde_json::json!("a description may change");
        },
        "speed-and-mu.json",
    );
    let stiffer = changed_case(
        &|c| c["model_scenario"] = serde_json::json!(stiffer_model.display().to_string()),
        "stiffer.json",
    );
    // (case, whether run.json is removed first, what the message must name)
    let attempts: [(&Path, bool, &[&str]); 3] = [
        (
            &speed_and_mu,
            false,
            &["speed_km_per_h: 100.0 -> 50.0", "friction.mu: 0.45 -> 0.3"],
        ),
        (
            &stiffer,
            false,
            &["model: wheel.material.youngs_modulus_pa"],
        ),
        (
            &speed_and_mu,
            true,
            &["checkpoint", "another case or model"],
        ),
    ];
    for (k, (changed, without_record, named)) in attempts.into_iter().enumerate() {
        let copy = dir.join(format!("changed-{k}"));
        copy_run_files(out, &copy);
        if without_record {
            std::fs::remove_file(copy.join("run.json")).unwrap();
        }
        let before = folder_bytes(&copy);
        let refused = resume(changed, &copy, end_ms);
        let err = String::from_utf8_lossy(&refused.stderr);
        assert_eq!(refused.status.code(), Some(2), "attempt {k}: {err}");
        for name in named {
            assert!(
                err.contains(name),
                "attempt {k} does not name {name:?}: {err}"
            );
        }
        assert!(
            !err.contains("description: "),
            "attempt {k}: the description may change: {err}"
        );
        assert_eq!(
            folder_bytes(&copy),
            before,
            "attempt {k}: the refused resume changed the folder"
        );
    }
}

/// Every file of a folder (not its subfolders) with its bytes.
fn folder_bytes(dir: &Path) -> Vec<(std::ffi::OsString, Vec<u8>)> {
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap())
        .filter(|e| e.file_type().unwrap().is_file())
        .map(|e| (e.file_name(), std::fs::read(e.path()).unwrap()))
        .collect();
    files.sort();
    files
}

/// A run killed outright (SIGKILL: no handler, nothing flushed) after a periodic checkpoint
/// leaves `status.json` and `run.json` of that checkpoint, with status `running` (a second run
/// into its folder while it goes is refused); the resume
/// goes on from the checkpoint without a repeated or missing sample, and its `run.json` lists
/// the killed segment up to its checkpoint, with its wall time and the preload.
#[cfg(unix)]
#[test]
fn a_run_killed_after_a_checkpoint_resumes_with_its_record() {
    let dir = temp_dir("sigkill");
    let mut case: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(long_tiny_case(&dir, 0.05)).unwrap())
            .unwrap();
    // A checkpoint every 200 steps: the first comes within a second or two of rolling.
    case["output"]["checkpoint_every_steps"] = serde_json::json!(200);
    let case_path = dir.join("case-ckpt.json");
    std::fs::write(&case_path, serde_json::to_string_pretty(&case).unwrap()).unwrap();
    let out = dir.join("run");
    let mut child = squeal()
        .args(["simulate", "--quiet", "--case"])
        .arg(&case_path)
        .arg("--out")
        .arg(&out)
        .spawn()
        .expect("spawn squeal");
    let started = Instant::now();
    // Wait for a checkpoint's record, then for the run to go on past it.
    let checkpoint_time = |out: &Path| -> Option<f64> {
        let text = std::fs::read_to_string(out.join("status.json")).ok()?;
        let status: serde_json::Value = serde_json::from_str(&text).ok()?;
        (status["status"] == "running").then(|| status["time_s"].as_f64())?
    };
    let mut seen = None;
    loop {
        assert!(
            started.elapsed() < Duration::from_secs(600),
            "no checkpoint was recorded"
        );
        if let Some(status) = child.try_wait().unwrap() {
            panic!("squeal exited before the kill: {status}");
        }
        match (seen, checkpoint_time(&out)) {
            (None, Some(t)) => seen = Some(t),
            (Some(t0), Some(t)) if t > t0 => break,
            _ => {}
        }
        std::thread::sleep(Duration::from_millis(10));
    }
    // A resume started while the run still goes is refused (exit 2), naming the process, and
    // leaves the run alone.
    let beside = squeal()
        .args(["simulate", "--quiet", "--resume", "--case"])
        .arg(&case_path)
        .arg("--out")
        .arg(&out)
        .output()
        .expect("second run");
    let err = String::from_utf8_lossy(&beside.stderr);
    assert_eq!(beside.status.code(), Some(2), "{err}");
    assert!(
        err.contains(&format!("process {}", child.id())) && err.contains("--out"),
        "{err}"
    );
    assert!(child.try_wait().unwrap().is_none(), "the run stopped");
    let kill = Command::new("kill")
        .args(["-KILL", &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(kill.success());
    let _ = child.wait();
    let status = read_json(&out.join("status.json"));
    assert_eq!(status["status"], "running", "{status}");
    let checkpoint_s = status["time_s"].as_f64().unwrap();
    let at_checkpoint = read_json(&out.join("run.json"));
    assert_eq!(at_checkpoint["run"]["status"], "running");
    assert_eq!(at_checkpoint["run"]["time_s"], status["time_s"]);
    assert!(!at_checkpoint["static_preload"].is_null() || !at_checkpoint["preload"].is_null());

    // The killed run's claim on the folder is left behind, stale: the resume takes it over.
    assert!(out.join("run.lock").exists());
    let end_ms = checkpoint_s * 1e3 + 0.2;
    resume_until(&case_path, &out, end_ms);
    assert!(!out.join("run.lock").exists());
    assert_samples_without_gap_or_repeat(&out, end_ms);
    let merged = read_json(&out.join("run.json"));
    assert_eq!(merged["run"]["status"], "completed");
    assert_eq!(merged["static_preload"], at_checkpoint["static_preload"]);
    assert_eq!(merged["preload"], at_checkpoint["preload"]);
    let segments = merged["segments"].as_array().expect("segments");
    assert_eq!(segments.len(), 2, "{merged}");
    assert_eq!(segments[0]["status"], "killed");
    assert_eq!(segments[0]["from_s"], 0.0);
    assert_eq!(segments[0]["to_s"], status["time_s"]);
    assert_eq!(segments[1]["from_s"], status["time_s"]);
    let killed_wall_s = segments[0]["wall_s"].as_f64().unwrap();
    assert!(killed_wall_s > 0.0);
    assert_eq!(killed_wall_s, status["wall_s"].as_f64().unwrap());
    let total = merged["total_wall_s"].as_f64().unwrap();
    let parts = killed_wall_s + merged["run"]["wall_s"].as_f64().unwrap();
    assert!(
        (total - parts).abs() <= 1e-9 * parts,
        "{total} against {parts}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[cfg(unix)]
#[test]
fn sigterm_stops_with_a_checkpoint_and_resume_goes_on() {
    let dir = temp_dir("sigterm");
    // 50 ms of the tiny case: tens of seconds of rolling, so the signal, sent as soon as the
    // rolling run has written its first samples, arrives long before the end.
    let case = long_tiny_case(&dir, 0.05);
    let out = dir.join("run");
    let mut child = squeal()
        .args(["simulate", "--quiet", "--case"])
        .arg(&case)
        .arg("--out")
        .arg(&out)
        .spawn()
        .expect("spawn squeal");
    let started = Instant::now();
    let histories = out.join("histories.csv");
    while std::fs::metadata(&histories).map(|m| m.len()).unwrap_or(0) == 0 {
        assert!(
            started.elapsed() < Duration::from_secs(600),
            "the rolling run never started"
        );
        if let Some(status) = child.try_wait().unwrap() {
            panic!("squeal exited before the signal: {status}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let kill = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(kill.success());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "exit status {status}");
    let record = read_json(&out.join("status.json"));
    assert_eq!(record["status"], "interrupted", "{record}");
    let stopped_at_s = record["time_s"].as_f64().unwrap();
    assert!(stopped_at_s > 0.0 && stopped_at_s < 0.05, "{stopped_at_s}");
    assert!(out.join("checkpoint.bin").exists());
    // The run wrote its wheel modes when it started: the axisymmetric modes of the case's
    // wheel held at its axle ends (no rigid mode), with the (0,3) axial mode squeal needs.
    let modes_path = out.join("modes.json");
    let modes = read_json(&modes_path);
    let modes = modes.as_array().expect("modes.json is an array");
    assert!(modes.iter().all(|m| m["family"] != "rigid"), "rigid modes");
    assert!(modes
        .iter()
        .any(|m| m["family"] == "axial" && m["nodal_circles"] == 0 && m["nodal_diameters"] == 3));
    let modes_written = std::fs::metadata(&modes_path).unwrap().modified().unwrap();
    let first = read_json(&out.join("run.json"));
    assert!(
        !first["static_preload"].is_null() || !first["preload"].is_null(),
        "the first segment ran a preload: {first}"
    );

    // A resume whose outputs were lost is refused, naming the file, and leaves the folder as
    // it was: histories.csv deleted, contact_forces.csv cut to its first half.
    let end_ms = stopped_at_s * 1e3 + 0.2;
    type Spoil = fn(&Path);
    let damage: [(&str, Spoil); 2] = [
        ("histories.csv", |p| std::fs::remove_file(p).unwrap()),
        ("contact_forces.csv", |p| {
            let text = std::fs::read_to_string(p).unwrap();
            let lines: Vec<&str> = text.lines().collect();
            std::fs::write(p, lines[..lines.len() / 2].join("\n") + "\n").unwrap();
        }),
    ];
    for (file, spoil) in damage {
        let copy = dir.join(format!("damaged-{file}"));
        copy_run_files(&out, &copy);
        spoil(&copy.join(file));
        let status_before = std::fs::read(copy.join("status.json")).unwrap();
        let refused = resume(&case, &copy, end_ms);
        let err = String::from_utf8_lossy(&refused.stderr);
        assert_eq!(refused.status.code(), Some(2), "{file}: {err}");
        assert!(
            err.contains(file) && err.contains("--resume"),
            "{file}: {err}"
        );
        assert_eq!(
            std::fs::read(copy.join("status.json")).unwrap(),
            status_before,
            "{file}: the refused resume rewrote status.json"
        );
    }

    refuse_resumes_with_other_values(&dir, &case, &out, end_ms);

    // Resume for 0.2 ms more: completes, and the histories go on without a gap or a repeat.
    resume_until(&case, &out, end_ms);
    let record = read_json(&out.join("status.json"));
    assert_eq!(record["status"], "completed", "{record}");
    assert_samples_without_gap_or_repeat(&out, end_ms);
    // The resume kept the modes of the first segment, and the analysis reads the run
    // directory as the run left it.
    let modes_kept = std::fs::metadata(&modes_path).unwrap().modified().unwrap();
    assert_eq!(modes_kept, modes_written);
    let identify = squeal()
        .args(["identify", "--peaks", "2", "--from-ms", "0", "--out"])
        .arg(dir.join("identify"))
        .arg(&out)
        .output()
        .unwrap();
    assert!(
        identify.status.success(),
        "{}",
        String::from_utf8_lossy(&identify.stderr)
    );
    // The resume's run.json keeps the whole run's record (src/rolling/record.rs): the preload
    // and the loaded wheel from the first segment, which the resume neither runs nor measures,
    // extremes over both segments, and both segments listed.
    let merged = read_json(&out.join("run.json"));
    assert_eq!(merged["preload"], first["preload"]);
    assert_eq!(merged["static_preload"], first["static_preload"]);
    for field in ["wheel_centre_m", "rolling_radius_m", "preload_load_error"] {
        assert_eq!(
            merged["model"][field], first["model"][field],
            "model.{field}"
        );
    }
    assert!(
        merged["deepest_penetration_m"].as_f64().unwrap()
            >= first["deepest_penetration_m"].as_f64().unwrap()
    );
    let segments = merged["segments"].as_array().expect("segments");
    assert_eq!(segments.len(), 2, "{merged}");
    assert_eq!(segments[0]["status"], "interrupted");
    assert_eq!(segments[0]["to_s"], first["run"]["time_s"]);
    assert_eq!(segments[1]["from_s"], first["run"]["time_s"]);
    assert_eq!(segments[1]["status"], "completed");
    let total = merged["total_wall_s"].as_f64().unwrap();
    let parts =
        first["run"]["wall_s"].as_f64().unwrap() + merged["run"]["wall_s"].as_f64().unwrap();
    assert!(
        (total - parts).abs() <= 1e-9 * parts,
        "{total} against {parts}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn missing_case_file_names_it_and_exits_2() {
    let dir = temp_dir("missing");
    let out = squeal()
        .args([
            "simulate",
            "--quiet",
            "--case",
            "no/such/case.json",
            "--out",
        ])
        .arg(dir.join("run"))
        .output()
        .expect("run squeal");
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("no/such/case.json") && err.contains("--case"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A lateral history that jumps at its onset, or ends after the run, and a forward guide
/// switched off under a prescribed creepage: exit 2 naming the case file and the field with
/// its allowed range, and nothing written.
#[test]
fn bad_lateral_motion_and_forward_guide_exit_2_and_write_nothing() {
    let dir = temp_dir("bad-lateral");
    let edits: Vec<(serde_json::Value, serde_json::Value, &str, &str)> = vec![
        (
            serde_json::json!("lateral_motion"),
            serde_json::json!({"shape": "table", "times_s": [0.001, 0.0015],
                "displacements_m": [0.0002, 0.0003]}),
            "lateral_motion.displacements_m[0]",
            "must be 0 m",
        ),
        (
            serde_json::json!("lateral_motion"),
            serde_json::json!({"shape": "ramp", "start_s": 0.5, "rise_time_s": 0.001,
                "velocity_m_per_s": 0.6, "travel_m": 0.003, "settle_time_s": 0.002}),
            "lateral_motion.start_s",
            "[0, end_time_s",
        ),
        (
            serde_json::json!("hold_forward_speed"),
            serde_json::json!(false),
            "hold_forward_speed",
            "prescribed creepage",
        ),
    ];
    for (k, (field, value, name, range)) in edits.into_iter().enumerate() {
        let path = long_tiny_case(&dir, 0.002);
        let mut case: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        case[field.as_str().unwrap()] = value;
        if name == "hold_forward_speed" {
            case["torque"]["max_n_m"] = serde_json::json!(0.0);
            case["creepage"] = serde_json::json!({"start": 0.0, "end": 0.001, "start_s": 0.0,
                "end_s": 0.001});
        }
        std::fs::write(&path, serde_json::to_string_pretty(&case).unwrap()).unwrap();
        let run = dir.join(format!("run{k}"));
        let out = squeal()
            .args(["simulate", "--quiet", "--case"])
            .arg(&path)
            .arg("--out")
            .arg(&run)
            .output()
            .expect("run squeal");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        assert!(
            err.contains("case.json") && err.contains(name) && err.contains(range),
            "{name}: {err}"
        );
        assert!(!run.exists(), "{name}: {} was written", run.display());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The standard output of a command that must have succeeded (its error output otherwise).
fn success_stdout(out: std::process::Output) -> String {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).to_string()
}

/// The number after `key=` in a bench's output.
fn key_value(text: &str, key: &str) -> f64 {
    text.split_whitespace()
        .find_map(|w| w.strip_prefix(&format!("{key}=")))
        .unwrap_or_else(|| panic!("{key} missing in {text}"))
        .parse()
        .expect("number")
}

#[test]
fn bench_rolling_splits_a_step_and_refuses_bad_step_counts() {
    let bench = |steps: &str| {
        squeal()
            .args([
                "bench",
                "rolling",
                "--case",
                "data/cases/case3-ci.json",
                "--steps",
                steps,
            ])
            .output()
            .expect("run")
    };
    let text = success_stdout(bench("5"));
    let value = |key: &str| key_value(&text, key);
    // Parts are timed apart, so only their signs and the share's range are certain.
    let (step, elements, contact) = (
        value("ms_per_step"),
        value("elements_ms"),
        value("contact_ms"),
    );
    assert!(step > 0.0 && elements > 0.0 && contact > 0.0, "{text}");
    let share = value("contact_share");
    assert!(share > 0.0 && share < 1.5, "{text}");
    assert_eq!(value("elements"), 9702.0, "the tiny model's element count");
    // The region of interest searches part of the slaves; the level partition's work fraction
    // lies in (0, 1].
    assert!(value("searched_slaves") < value("contact_slaves"), "{text}");
    let work = value("multi_rate_element_work");
    assert!(work > 0.0 && work <= 1.0, "{text}");
    let bad = bench("0");
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--steps"));
}

/// `squeal bench preload` times the static preload of a case by either method, without a
/// rolling run: the implicit solve lands on the static load to its residual (measured +4e-7 on
/// the tiny case; asserted 1e-4), and a method name it does not know exits 2.
#[test]
fn bench_preload_times_both_methods() {
    let bench = |method: &str| {
        squeal()
            .args([
                "bench",
                "preload",
                "--case",
                "data/cases/case3-ci.json",
                "--preload",
                method,
            ])
            .output()
            .expect("run")
    };
    for method in ["implicit", "dynamic-relaxation"] {
        let text = success_stdout(bench(method));
        let value = |key: &str| key_value(&text, key);
        assert!(value("preload_seconds") > 0.0, "{text}");
        assert_eq!(value("elements"), 9702.0, "{text}");
        if method == "implicit" {
            assert!(value("load_error").abs() < 1e-4, "{text}");
            assert!(value("factor_entries") > 0.0, "{text}");
        } else {
            // The tiny case's relaxation budget (2 500 steps) is a smoke setting.
            assert_eq!(value("iterations_or_steps"), 2500.0, "{text}");
        }
    }
    let bad = bench("sideways");
    assert_eq!(bad.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&bad.stderr).contains("--preload"));
}

/// A run directory is never overwritten by mistake: a non-empty folder is refused (the old
/// files untouched), `--overwrite` replaces it whole, `--resume` without a checkpoint is refused
/// before anything is created, and a failed report leaves nothing behind.
#[test]
fn runs_and_reports_are_never_overwritten_or_misplaced() {
    let dir = temp_dir("safety");
    let run = dir.join("run");
    std::fs::create_dir_all(&run).unwrap();
    // An earlier run (its record and modes), which --overwrite may replace.
    std::fs::write(run.join("modes.json"), "[]").unwrap();
    std::fs::write(run.join("run.json"), "{}").unwrap();
    let simulate = |extra: &[&str]| {
        squeal()
            .args([
                "simulate",
                "--case",
                "data/cases/case3-ci.json",
                "--end-time-ms",
                "0.2",
                "--quiet",
                "--out",
            ])
            .arg(&run)
            .args(extra)
            .output()
            .expect("run")
    };
    let refused = simulate(&[]);
    assert_eq!(refused.status.code(), Some(2));
    let err = String::from_utf8_lossy(&refused.stderr);
    assert!(
        err.contains("--out") && err.contains("--overwrite"),
        "{err}"
    );
    let names: Vec<_> = std::fs::read_dir(&run).unwrap().collect();
    assert_eq!(names.len(), 2, "the refused run wrote into the folder");
    let replaced = simulate(&["--overwrite"]);
    assert!(
        replaced.status.success(),
        "{}",
        String::from_utf8_lossy(&replaced.stderr)
    );
    // The old run's modes.json was replaced by the new run's (it writes its wheel's modes when
    // it starts), not kept.
    let modes = std::fs::read_to_string(run.join("modes.json")).unwrap();
    assert_ne!(modes.trim(), "[]", "the old run's file stayed");
    assert!(run.join("histories.csv").exists());

    let fresh = dir.join("never");
    let resumed = squeal()
        .args([
            "simulate",
            "--case",
            "data/cases/case3-ci.json",
            "--resume",
            "--out",
        ])
        .arg(&fresh)
        .output()
        .expect("run");
    assert_eq!(resumed.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&resumed.stderr).contains("--resume"));
    assert!(!fresh.exists(), "a refused resume created its folder");

    // A report over a folder without histories fails and leaves no report folder. (That a
    // report's name cannot leave its folder is tests/cli_deprecated.rs's: only the deprecated
    // --name/--reports take a name.)
    let reports = dir.join("reports");
    let empty = dir.join("empty-run");
    std::fs::create_dir_all(&empty).unwrap();
    let failed = squeal()
        .args(["report", &empty.display().to_string(), "--out"])
        .arg(reports.join("x"))
        .output()
        .expect("run");
    assert_ne!(failed.status.code(), Some(0));
    assert!(
        !reports.join("x").exists() && !has_stage(&reports),
        "the failed report left files"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Whether a leftover hidden stage folder sits in `dir`.
fn has_stage(dir: &Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|entries| {
        entries
            .flatten()
            .any(|e| e.file_name().to_string_lossy().contains(".partial-"))
    })
}
