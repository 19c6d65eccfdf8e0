//! A user's files survive byte for byte whatever a command is asked to do with them (issue 53):
//! an `--overwrite` whose new run fails before it starts writing, an `--overwrite` of the
//! current folder or of a folder squeal did not make, a report asked to replace a folder that
//! is not a report. Each scenario runs the release binary in a fresh folder and compares every
//! file afterwards with what was there before.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn squeal(cwd: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run squeal")
}

fn fresh(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("squeal_safety_{tag}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Every file below `dir` (relative path -> bytes).
fn snapshot(dir: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut files = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                let rel = path.strip_prefix(dir).unwrap().to_path_buf();
                files.insert(rel, std::fs::read(&path).unwrap());
            }
        }
    }
    files
}

fn repo(path: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(path)
        .display()
        .to_string()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Item 1: the old run stays when the new one fails before it starts writing (here its model
/// puts the wheel 5 mm above the rail: the contact check refuses it before the preload).
#[test]
fn a_failed_overwrite_keeps_the_old_run() {
    let dir = fresh("overwrite_fails");
    let case = repo("data/cases/case3-ci.json");
    let first = squeal(
        &dir,
        &[
            "simulate",
            "--quiet",
            "--case",
            &case,
            "--end-time-ms",
            "0.1",
            "--out",
            "run",
        ],
    );
    assert!(first.status.success(), "{}", stderr(&first));
    let before = snapshot(&dir.join("run"));
    // The same case on a copy of its model with the wheel lifted by 5 mm.
    let mut model: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(repo("data/models/ci-tiny.json")).unwrap())
            .unwrap();
    model["wheel_file"] = repo("data/wheels/ns_intercity_920.json").into();
    model["wheel_position"]["initial_gap_mm"] = 5.0.into();
    let lifted_model = dir.join("lifted-model.json");
    std::fs::write(&lifted_model, model.to_string()).unwrap();
    let mut lifted: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&case).unwrap()).unwrap();
    lifted["model_scenario"] = lifted_model.display().to_string().into();
    let lifted_case = dir.join("lifted-case.json");
    std::fs::write(&lifted_case, lifted.to_string()).unwrap();
    let failed = squeal(
        &dir,
        &[
            "simulate",
            "--quiet",
            "--overwrite",
            "--case",
            lifted_case.to_str().unwrap(),
            "--out",
            "run",
        ],
    );
    assert_ne!(failed.status.code(), Some(0), "the lifted wheel ran");
    assert_eq!(snapshot(&dir.join("run")), before, "{}", stderr(&failed));
    // Nothing left beside it: no set-aside or staging folder.
    let names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        names.iter().all(|n| !n.starts_with('.')),
        "left behind: {names:?}"
    );
    // Item 12: a new run that fails leaves no folder: neither its own nor the parents it made.
    let nested = squeal(
        &dir,
        &[
            "simulate",
            "--quiet",
            "--case",
            lifted_case.to_str().unwrap(),
            "--out",
            "new/deeper/run",
        ],
    );
    assert_ne!(nested.status.code(), Some(0), "the lifted wheel ran");
    assert!(!dir.join("new").exists(), "{}", stderr(&nested));
    // A new run that works does replace it.
    let second = squeal(
        &dir,
        &[
            "simulate",
            "--quiet",
            "--overwrite",
            "--case",
            &case,
            "--end-time-ms",
            "0.05",
            "--out",
            "run",
        ],
    );
    assert!(second.status.success(), "{}", stderr(&second));
    assert_ne!(snapshot(&dir.join("run")), before);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Items 2 and 3: `--overwrite` never deletes the current folder, a folder above it, or a
/// folder of files squeal did not write.
#[test]
fn overwrite_refuses_folders_squeal_did_not_make() {
    let dir = fresh("overwrite_refused");
    let work = dir.join("work");
    std::fs::create_dir_all(work.join("notes")).unwrap();
    std::fs::write(work.join("thesis.tex"), "chapter 1").unwrap();
    std::fs::write(work.join("notes/data.csv"), "time_s,x\n0,1\n").unwrap();
    let before = snapshot(&dir);
    let case = repo("data/cases/case3-ci.json");
    for out in [".", "..", "../work", "notes"] {
        let refused = squeal(
            &work,
            &[
                "simulate",
                "--quiet",
                "--overwrite",
                "--case",
                &case,
                "--out",
                out,
            ],
        );
        let err = stderr(&refused);
        assert_eq!(refused.status.code(), Some(2), "--out {out}: {err}");
        assert!(err.contains("refusing"), "--out {out}: {err}");
        assert_eq!(snapshot(&dir), before, "--out {out} changed files");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 4: a report replaces a report folder, never a folder of other files.
#[test]
fn a_report_never_replaces_a_folder_that_is_not_a_report() {
    let dir = fresh("report_refused");
    std::fs::create_dir_all(dir.join("data")).unwrap();
    std::fs::write(dir.join("data/measurements.csv"), "a,b\n1,2\n").unwrap();
    let before = snapshot(&dir);
    let run = repo("data/runs/case3-paper-calibrated");
    let refused = squeal(&dir, &["report", &run, "--out", "data"]);
    let err = stderr(&refused);
    assert_eq!(refused.status.code(), Some(2), "{err}");
    assert!(err.contains("refusing"), "{err}");
    assert_eq!(snapshot(&dir), before);
    // A report folder is replaced by the next report.
    let first = squeal(&dir, &["report", &run, "--out", "r"]);
    assert!(first.status.success(), "{}", stderr(&first));
    let again = squeal(&dir, &["report", &run, "--out", "r"]);
    assert!(again.status.success(), "{}", stderr(&again));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 5: no command writes over its own input: a CSV given as the output of `wav` (both
/// spellings) and `psd`, a run directory given as the folder a report replaces.
#[test]
fn no_output_is_written_over_an_input() {
    let dir = fresh("input_as_output");
    let source = repo("data/runs/case3-paper-calibrated/histories.csv");
    std::fs::copy(&source, dir.join("h.csv")).unwrap();
    let run = dir.join("run");
    std::fs::create_dir_all(&run).unwrap();
    for f in ["histories.csv", "modes.json", "run.json"] {
        std::fs::copy(
            repo(&format!("data/runs/case3-paper-calibrated/{f}")),
            run.join(f),
        )
        .unwrap();
    }
    let before = snapshot(&dir);
    let column = "lateral_velocity_m_per_s";
    for args in [
        vec!["wav", "h.csv", "--column", column, "--out", "h.csv"],
        vec![
            "wav", "--csv", "h.csv", "--column", column, "--out", "h.csv",
        ],
        vec!["psd", "h.csv", "--column", column, "--out", "h.csv"],
        vec!["report", "run", "--out", "run"],
    ] {
        let refused = squeal(&dir, &args);
        let err = stderr(&refused);
        assert_eq!(refused.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains("an input of this command"), "{args:?}: {err}");
        assert_eq!(snapshot(&dir), before, "{args:?} changed files");
    }
    // Outputs beside a run's files are fine: identify writes its tables into the run.
    let beside = squeal(&dir, &["identify", "run", "--out", "run"]);
    assert!(beside.status.success(), "{}", stderr(&beside));
    assert_eq!(
        std::fs::read(run.join("histories.csv")).unwrap(),
        before[Path::new("run/histories.csv")]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 9: two runs whose folders share a name (`a/run`, `b/run`: here paper cases 4 and 3)
/// each get their own sections and chart files, named after as much of their paths as tells
/// them apart; every image the page shows exists, and the two runs' charts differ.
#[test]
fn a_report_on_two_runs_of_one_folder_name_keeps_both() {
    let dir = fresh("report_same_name");
    for (parent, run) in [
        ("a", "data/runs/case4-paper"),
        ("b", "data/runs/case3-paper"),
    ] {
        let to = dir.join(parent).join("run");
        std::fs::create_dir_all(&to).unwrap();
        for entry in std::fs::read_dir(repo(run)).unwrap() {
            let path = entry.unwrap().path();
            if path.is_file() {
                std::fs::copy(&path, to.join(path.file_name().unwrap())).unwrap();
            }
        }
    }
    let out = squeal(&dir, &["report", "a/run", "b/run", "--out", "r"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let md = std::fs::read_to_string(dir.join("r/index.md")).unwrap();
    assert!(md.contains("`a-run`") && md.contains("`b-run`"), "{md}");
    let images: Vec<&str> = md
        .split("](")
        .skip(1)
        .filter_map(|s| s.split(')').next())
        .filter(|s| s.ends_with(".png") || s.ends_with(".svg"))
        .collect();
    for image in &images {
        assert!(dir.join("r").join(image).exists(), "{image} is missing");
    }
    let force_charts: Vec<&&str> = images
        .iter()
        .filter(|i| i.starts_with("contact_forces_"))
        .collect();
    assert_eq!(force_charts.len(), 2, "{images:?}");
    assert_ne!(force_charts[0], force_charts[1]);
    assert_ne!(
        std::fs::read(dir.join("r").join(force_charts[0])).unwrap(),
        std::fs::read(dir.join("r").join(force_charts[1])).unwrap()
    );
    let _ = std::fs::remove_dir_all(&dir);
}
