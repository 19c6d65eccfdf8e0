//! The tiny test case (data/cases/case3-ci.json) as the rolling tests run it: in a temporary
//! directory, edited copies of its files, refusals checked with their words and exit code.
use std::path::Path;

use squeal::rolling::{load_case, simulate, SimulateOptions};
use squeal::table::Table;

pub fn column<'a>(t: &'a Table, name: &str) -> &'a [f64] {
    let k = t
        .headers
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    &t.columns[k]
}

/// Runs `loaded` into a fresh temporary directory named after `tag` (and the process id).
pub fn run_in_temp(
    loaded: &squeal::rolling::LoadedCase,
    tag: &str,
    end_time_s: Option<f64>,
) -> (squeal::rolling::RunRecord, std::path::PathBuf) {
    let dir = std::env::temp_dir().join(format!("{tag}_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let record = simulate(
        loaded,
        &SimulateOptions {
            end_time_s,
            // The region of interest's guard, every step of every run here.
            verify_contact_region: true,
            ..SimulateOptions::new(dir.clone())
        },
    )
    .unwrap();
    (record, dir)
}

/// The tiny case's files copied to a temp dir with `edit` applied to the model scenario and
/// `case_edit` to the case file; returns the dir and the loaded case.
pub fn edited_tiny_case(
    tag: &str,
    edit: (&str, &str),
    case_edit: (&str, &str),
) -> (std::path::PathBuf, squeal::rolling::case::LoadedCase) {
    let dir = std::env::temp_dir().join(format!("squeal_rolling_{tag}_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::copy("data/wheels/ns_intercity_920.json", dir.join("wheel.json")).unwrap();
    let scen = std::fs::read_to_string("data/models/ci-tiny.json")
        .unwrap()
        .replace("../wheels/ns_intercity_920.json", "wheel.json");
    assert!(scen.contains(edit.0), "{}", edit.0);
    std::fs::write(dir.join("ci-tiny.json"), scen.replace(edit.0, edit.1)).unwrap();
    // Copied beside its model scenario in a temporary folder.
    let case = std::fs::read_to_string("data/cases/case3-ci.json")
        .unwrap()
        .replace("../models/ci-tiny.json", "ci-tiny.json");
    assert!(case.contains(case_edit.0), "{}", case_edit.0);
    std::fs::write(
        dir.join("case.json"),
        case.replace(case_edit.0, case_edit.1),
    )
    .unwrap();
    let loaded = load_case(&dir.join("case.json")).unwrap();
    (dir, loaded)
}

fn simulate_in(dir: &Path, loaded: &squeal::rolling::case::LoadedCase) -> squeal::Result<()> {
    simulate(loaded, &SimulateOptions::new(dir.join("out"))).map(|_| ())
}

/// Runs the case, expects an input error (exit code 2) whose text holds every one of `words`,
/// and removes `dir`.
pub fn refused_with(dir: &Path, loaded: &squeal::rolling::case::LoadedCase, words: &[&str]) {
    let err = simulate_in(dir, loaded).expect_err("bad input must be refused");
    let text = err.to_string();
    assert!(words.iter().all(|w| text.contains(w)), "{words:?}: {text}");
    assert_eq!(err.exit_code(), 2, "{text}");
    assert!(!dir.join("out").join("contact_forces.csv").exists());
    let _ = std::fs::remove_dir_all(dir);
}

/// The contact forces and histories of the runs in `whole` and `split` are equal to the last
/// digit (a resumed run against the uninterrupted one), and not trivially short.
pub fn assert_same_outputs(whole: &Path, split: &Path) {
    for f in ["contact_forces.csv", "histories.csv"] {
        let a = std::fs::read_to_string(whole.join(f)).unwrap();
        let b = std::fs::read_to_string(split.join(f)).unwrap();
        assert!(a.lines().count() > 50, "{f} too short");
        assert_eq!(a, b, "{f} differs after resume");
    }
}
