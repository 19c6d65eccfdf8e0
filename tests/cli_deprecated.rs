//! The previous release's spellings (issue 52, docs/cli.md): each still works for this release,
//! does what its new spelling does, and says so in one line on standard error. Remove this file
//! with the hidden aliases, the semantic forms and `RENAMED` (src/cli/grammar.rs) in the next
//! release.
//!
//! Every command runs in a fresh temporary folder with absolute input paths and relative
//! outputs, so that whatever it writes (its default `out/...` or `reports/...` folder too) lands
//! there and the two spellings' files can be compared. The committed runs under data/runs/ are
//! only read.

use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

/// What every deprecation note holds (`warning: OLD is deprecated, use NEW; ...`).
const NOTE: &str = "is deprecated, use";

/// How the files the two spellings write are compared.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Files {
    /// The same file names (relative to each command's folder).
    Same,
    /// The old spelling's files are among the new one's: `mesh --out X.vtu` wrote only that
    /// file; `--vtu X.vtu` writes it and the output folder (out/mesh/<name>) as well.
    OldAmongNew,
}

/// One deprecated spelling and its replacement.
struct Pair {
    old: Vec<String>,
    new: Vec<String>,
    /// The deprecated spelling as the note names it (`--scenario`, `--csv FILE`).
    old_name: &'static str,
    /// The start of what the note says to use instead (`--case`, `--direction`).
    new_name: &'static str,
    files: Files,
    /// Whether standard output may differ (a command that prints its own timing).
    timed: bool,
    /// The exit code both spellings must give.
    code: i32,
}

impl Pair {
    /// The pair with both spellings expected to exit with `code`.
    fn exits(self, code: i32) -> Pair {
        Pair { code, ..self }
    }
}

fn pair(old: &str, new: &str, old_name: &'static str, new_name: &'static str) -> Pair {
    Pair {
        old: words(old),
        new: words(new),
        old_name,
        new_name,
        files: Files::Same,
        timed: false,
        code: 0,
    }
}

/// The words of a command line, with `@name` replaced by the absolute path of a repository
/// file (`@data/wheels/ns_intercity_920.json`). No word holds a space.
fn words(line: &str) -> Vec<String> {
    line.split_whitespace()
        .map(|w| match w.strip_prefix('@') {
            Some(rel) => repo(rel),
            None => w.to_string(),
        })
        .collect()
}

fn repo(rel: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join(rel)
        .display()
        .to_string()
}

/// A fresh empty folder.
fn fresh(path: &Path) -> PathBuf {
    let _ = std::fs::remove_dir_all(path);
    std::fs::create_dir_all(path).expect("temp dir");
    path.to_path_buf()
}

fn squeal(args: &[String], cwd: &Path) -> Output {
    Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(args)
        .current_dir(cwd)
        .output()
        .expect("run squeal")
}

/// The files below `dir`, as sorted relative paths.
fn files_below(dir: &Path) -> Vec<String> {
    fn walk(base: &Path, dir: &Path, found: &mut Vec<String>) {
        for entry in std::fs::read_dir(dir).expect("read dir").flatten() {
            let path = entry.path();
            if path.is_dir() {
                walk(base, &path, found);
            } else {
                let rel = path.strip_prefix(base).expect("below base");
                found.push(rel.display().to_string());
            }
        }
    }
    let mut found = Vec::new();
    walk(dir, dir, &mut found);
    found.sort();
    found
}

fn text(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).to_string()
}

/// Standard error without the deprecation notes.
fn without_notes(stderr: &str) -> Vec<&str> {
    stderr.lines().filter(|l| !l.contains(NOTE)).collect()
}

/// Every deprecated spelling of this release, beside its new form. Inputs are small: the
/// committed runs (a second at most per command), the default wheel, the tiny CI model, Kalker
/// (milliseconds). `simulate`, `bench` and `stability` get an input that fails right after
/// parsing (a case file that does not exist, a time outside the run): the two spellings must
/// fail alike.
fn pairs() -> Vec<Pair> {
    // A committed run, its histories, a run with the growth column, a wheel, a model.
    let run = "@data/runs/case3-paper";
    let calibrated = "@data/runs/case3-paper-calibrated";
    let csv = "@data/runs/case3-paper/histories.csv --column lateral_velocity_m_per_s";
    let wheel = "@data/wheels/ns_intercity_920.json";
    let model = "@data/models/ci-tiny.json";
    let case = "@data/cases/case3-paper.json";
    let missing = "@no/such/case.json";
    let hertz = "kalker hertz --normal-force-n 100e3";
    let solve = "--mu 0.45 --method fastsim --grid 20 --out o";
    let pairs = vec![
        // File nouns.
        pair(
            &format!("simulate --scenario {missing} --out o"),
            &format!("simulate --case {missing} --out o"),
            "--scenario",
            "--case",
        )
        .exits(2),
        pair(
            &format!("bench rolling --scenario {missing} --steps 1"),
            &format!("bench rolling --case {missing} --steps 1"),
            "--scenario",
            "--case",
        )
        .exits(2),
        pair(
            &format!("bench preload --scenario {missing}"),
            &format!("bench preload --case {missing}"),
            "--scenario",
            "--case",
        )
        .exits(2),
        Pair {
            timed: true,
            ..pair(
                &format!("mesh --scenario {model} --out o"),
                &format!("mesh --model {model} --out o"),
                "--scenario",
                "--model",
            )
        },
        // Units.
        pair(
            &format!("identify {run} --fmin 100 --out o"),
            &format!("identify {run} --fmin-hz 100 --out o"),
            "--fmin",
            "--fmin-hz",
        ),
        pair(
            &format!("identify {run} --fmax 4000 --out o"),
            &format!("identify {run} --fmax-hz 4000 --out o"),
            "--fmax",
            "--fmax-hz",
        ),
        pair(
            &format!("check-modes {run} --require 0,3 --fmin 100"),
            &format!("check-modes {run} --require 0,3 --fmin-hz 100"),
            "--fmin",
            "--fmin-hz",
        )
        .exits(1),
        pair(
            &format!("check-modes {run} --require 0,3 --fmax 4000"),
            &format!("check-modes {run} --require 0,3 --fmax-hz 4000"),
            "--fmax",
            "--fmax-hz",
        )
        .exits(1),
        pair(
            &format!("psd {csv} --peak-fmin 100 --out o"),
            &format!("psd {csv} --fmin-hz 100 --out o"),
            "--peak-fmin",
            "--fmin-hz",
        ),
        pair(
            &format!("psd {csv} --peak-fmax 4000 --out o"),
            &format!("psd {csv} --fmax-hz 4000 --out o"),
            "--peak-fmax",
            "--fmax-hz",
        ),
        pair(
            &format!("cwt {csv} --fmin 100 --fmax-hz 1000 --time-stride 20 --out o"),
            &format!("cwt {csv} --fmin-hz 100 --fmax-hz 1000 --time-stride 20 --out o"),
            "--fmin",
            "--fmin-hz",
        ),
        pair(
            &format!("cwt {csv} --fmin-hz 100 --fmax 1000 --time-stride 20 --out o"),
            &format!("cwt {csv} --fmin-hz 100 --fmax-hz 1000 --time-stride 20 --out o"),
            "--fmax",
            "--fmax-hz",
        ),
        pair(
            &format!("wav {csv} --rate 8000 --out o"),
            &format!("wav {csv} --sample-rate-hz 8000 --out o"),
            "--rate",
            "--sample-rate-hz",
        ),
        pair(
            "kalker hertz --fn 100e3",
            hertz,
            "--fn",
            "--normal-force-n",
        ),
        pair(
            &format!("kalker solve --normal-force-n 120e3 --fx 40e3 --force-y-n 10e3 {solve}"),
            &format!("kalker solve --normal-force-n 120e3 --force-x-n 40e3 --force-y-n 10e3 {solve}"),
            "--fx",
            "--force-x-n",
        ),
        pair(
            &format!("kalker solve --normal-force-n 120e3 --force-x-n 40e3 --fy 10e3 {solve}"),
            &format!("kalker solve --normal-force-n 120e3 --force-x-n 40e3 --force-y-n 10e3 {solve}"),
            "--fy",
            "--force-y-n",
        ),
        pair(
            &format!("{hertz} --wheel-radius 0.46"),
            &format!("{hertz} --wheel-radius-m 0.46"),
            "--wheel-radius",
            "--wheel-radius-m",
        ),
        pair(
            &format!("{hertz} --rail-radius 0.3"),
            &format!("{hertz} --rail-radius-m 0.3"),
            "--rail-radius",
            "--rail-radius-m",
        ),
        // `--old=value` too.
        pair(
            &format!("{hertz} --wheel-y=-0.0025"),
            &format!("{hertz} --wheel-y-m=-0.0025"),
            "--wheel-y",
            "--wheel-y-m",
        ),
        pair(
            &format!("{hertz} --e 2.1e11"),
            &format!("{hertz} --youngs-modulus-pa 2.1e11"),
            "--e",
            "--youngs-modulus-pa",
        ),
        pair(
            &format!("{hertz} --nu 0.28"),
            &format!("{hertz} --poisson-ratio 0.28"),
            "--nu",
            "--poisson-ratio",
        ),
        pair(
            &format!("kalker creep --normal-force-n 100e3 --xi -1e-3 --phi 0.1 {solve}"),
            &format!("kalker creep --normal-force-n 100e3 --xi -1e-3 --phi-per-m 0.1 {solve}"),
            "--phi",
            "--phi-per-m",
        ),
        pair(
            &format!("stability --case {missing} --fn 100e3 --out o"),
            &format!("stability --case {missing} --normal-force-n 100e3 --out o"),
            "--fn",
            "--normal-force-n",
        )
        .exits(2),
        pair(
            &format!("stability --case {missing} --fx 1000 --force-y-n 0 --out o"),
            &format!("stability --case {missing} --force-x-n 1000 --force-y-n 0 --out o"),
            "--fx",
            "--force-x-n",
        )
        .exits(2),
        pair(
            &format!("stability --case {missing} --force-x-n 1000 --fy 0 --out o"),
            &format!("stability --case {missing} --force-x-n 1000 --force-y-n 0 --out o"),
            "--fy",
            "--force-y-n",
        )
        .exits(2),
        pair(
            &format!("stability --case {missing} --friction-slope -0.1 --out o"),
            &format!("stability --case {missing} --friction-slope-s-per-m -0.1 --out o"),
            "--friction-slope",
            "--friction-slope-s-per-m",
        )
        .exits(2),
        pair(
            "bench modal --mtx @no/such/mtx --fmax 1000",
            "bench modal --mtx @no/such/mtx --fmax-hz 1000",
            "--fmax",
            "--fmax-hz",
        )
        // A missing input file is bad input (issue 53, item 13: exit 2 throughout).
        .exits(2),
        // Signals.
        pair(
            &format!("identify {run} --signal lateral --out o"),
            &format!("identify {run} --direction lateral --out o"),
            "--signal",
            "--direction",
        ),
        pair(
            &format!("identify {run} --signal rim_mean_lateral_velocity_m_per_s --out o"),
            &format!("identify {run} --column rim_mean_lateral_velocity_m_per_s --out o"),
            "--signal",
            "--column",
        ),
        pair(
            &format!("check-modes {run} --require 0,3 --signal vertical"),
            &format!("check-modes {run} --require 0,3 --direction vertical"),
            "--signal",
            "--direction",
        )
        .exits(1),
        pair(
            &format!("check-modes {run} --require 0,3 --signal lateral_velocity_m_per_s"),
            &format!("check-modes {run} --require 0,3 --column lateral_velocity_m_per_s"),
            "--signal",
            "--column",
        )
        .exits(1),
        pair(
            &format!("growth {calibrated} --signal rim_point_minus_mean_lateral_velocity_m_per_s --out o"),
            &format!("growth {calibrated} --column rim_point_minus_mean_lateral_velocity_m_per_s --out o"),
            "--signal",
            "--column",
        ),
        // Positional inputs.
        pair(
            &format!("stability --case {case} --run {run} --time-ms 1e6 --out o"),
            &format!("stability --case {case} {run} --time-ms 1e6 --out o"),
            "--run RUN_DIR",
            "RUN_DIR (positional)",
        )
        .exits(2),
        pair(
            &format!("psd --csv {csv} --out o"),
            &format!("psd {csv} --out o"),
            "--csv FILE",
            "FILE (a positional SOURCE)",
        ),
        pair(
            &format!("cwt --csv {csv} --fmin-hz 100 --fmax-hz 1000 --time-stride 20 --out o"),
            &format!("cwt {csv} --fmin-hz 100 --fmax-hz 1000 --time-stride 20 --out o"),
            "--csv FILE",
            "FILE (a positional SOURCE)",
        ),
        pair(
            &format!("wav --csv {csv} --out o"),
            &format!("wav {csv} --out o"),
            "--csv FILE",
            "FILE (a positional SOURCE)",
        ),
        // Output.
        pair(
            &format!("report {run} --name n --reports r"),
            &format!("report {run} --out r/n"),
            "--name/--reports",
            "--out REPORTS/NAME",
        ),
        pair(
            &format!("report {run} --name n"),
            &format!("report {run} --out reports/n"),
            "--name/--reports",
            "--out REPORTS/NAME",
        ),
        pair(
            &format!("wav {csv} --out o/lateral_velocity_m_per_s.wav"),
            &format!("wav {csv} --out o"),
            "--out FILE.wav",
            "--out DIR",
        ),
        Pair {
            files: Files::OldAmongNew,
            timed: true,
            ..pair(
                &format!("mesh --wheel {wheel} --out w.vtu"),
                &format!("mesh --wheel {wheel} --vtu w.vtu"),
                "--out FILE.vtu",
                "--vtu",
            )
        },
        Pair {
            files: Files::OldAmongNew,
            timed: true,
            ..pair(
                &format!("mesh --wheel {wheel} --out w.msh"),
                &format!("mesh --wheel {wheel} --msh w.msh"),
                "--out FILE.msh",
                "--msh",
            )
        },
        // Format options.
        pair(
            "profile s1002 --csv --step-mm 1",
            "profile s1002 --csv - --step-mm 1",
            "--csv (no value)",
            "--csv -",
        ),
        pair(
            &format!("{hertz} --json"),
            hertz,
            "--json (no value)",
            "nothing (the JSON is printed)",
        ),
        // Subcommand and sweep name.
        pair(
            &format!("kalker --normal-force-n 120e3 --force-x-n 40e3 --force-y-n 10e3 {solve}"),
            &format!("kalker solve --normal-force-n 120e3 --force-x-n 40e3 --force-y-n 10e3 {solve}"),
            "squeal kalker OPTIONS",
            "squeal kalker solve",
        ),
        pair(
            &format!("stability --case {case} --sweep friction-slope=0..1:1 --out o"),
            &format!("stability --case {case} --sweep friction-slope-s-per-m=0..1:1 --out o"),
            "--sweep friction-slope=...",
            "--sweep friction-slope-s-per-m=...",
        )
        .exits(2),
    ];
    pairs
}

#[test]
fn old_spellings_work_as_the_new_ones_with_one_note() {
    let base = std::env::temp_dir().join(format!("squeal-deprecated-{}", std::process::id()));
    let pairs = pairs();
    let mut failures = Vec::new();
    for (k, p) in pairs.iter().enumerate() {
        let old_dir = fresh(&base.join(format!("{k}-old")));
        let new_dir = fresh(&base.join(format!("{k}-new")));
        let old = squeal(&p.old, &old_dir);
        let new = squeal(&p.new, &new_dir);
        let (old_err, new_err) = (text(&old.stderr), text(&new.stderr));
        let mut problems = Vec::new();
        if old.status.code() != Some(p.code) || new.status.code() != Some(p.code) {
            problems.push(format!(
                "exit {:?}, the new spelling's {:?}, expected {}",
                old.status.code(),
                new.status.code(),
                p.code
            ));
        }
        let notes: Vec<&str> = old_err.lines().filter(|l| l.contains(NOTE)).collect();
        match notes.as_slice() {
            [line] => {
                if !line.contains(&format!("{} {NOTE} {}", p.old_name, p.new_name)) {
                    problems.push(format!(
                        "the note `{line}` does not say `{} {NOTE} {}`",
                        p.old_name, p.new_name
                    ));
                }
            }
            _ => problems.push(format!("{} deprecation notes, not one", notes.len())),
        }
        if new_err.contains(NOTE) {
            problems.push("the new spelling printed a deprecation note".into());
        }
        // The rest of standard error (an error message, warnings) is the same.
        if without_notes(&old_err) != without_notes(&new_err) {
            problems.push(format!(
                "other standard error differs:\n  old: {:?}\n  new: {:?}",
                without_notes(&old_err),
                without_notes(&new_err)
            ));
        }
        if !p.timed && old.stdout != new.stdout {
            problems.push(format!(
                "standard output differs:\n  old: {}\n  new: {}",
                text(&old.stdout),
                text(&new.stdout)
            ));
        }
        let (old_files, new_files) = (files_below(&old_dir), files_below(&new_dir));
        let files_agree = match p.files {
            Files::Same => old_files == new_files,
            Files::OldAmongNew => {
                !old_files.is_empty() && old_files.iter().all(|f| new_files.contains(f))
            }
        };
        // A command told where to write that succeeded wrote something there.
        if p.code == 0 && p.new.iter().any(|w| w == "--out") && new_files.is_empty() {
            problems.push("wrote nothing".into());
        }
        if !files_agree {
            problems.push(format!(
                "files: old {old_files:?}, new {new_files:?} ({:?})",
                p.files
            ));
        }
        if old_err.contains("panicked") || new_err.contains("panicked") {
            problems.push("panicked".into());
        }
        if !problems.is_empty() {
            failures.push(format!(
                "{:?}\n  vs {:?}:\n  {}\n  old stderr: {}",
                p.old,
                p.new,
                problems.join("\n  "),
                old_err.trim()
            ));
        }
    }
    let _ = std::fs::remove_dir_all(&base);
    assert!(
        failures.is_empty(),
        "{} of {} deprecated spellings misbehaved:\n{}",
        failures.len(),
        pairs.len(),
        failures.join("\n\n")
    );
}

/// Every row of `RENAMED` (src/cli/grammar.rs, one row a line) has a pair above that uses its
/// old spelling in its command.
#[test]
fn every_renamed_option_has_a_pair() {
    let grammar = std::fs::read_to_string(repo("src/cli/grammar.rs")).expect("grammar.rs");
    let pairs = pairs();
    let quoted = |s: &str| -> Vec<String> {
        s.split('"')
            .skip(1)
            .step_by(2)
            .map(str::to_string)
            .collect()
    };
    let mut rows = 0;
    let mut missing = Vec::new();
    for line in grammar
        .lines()
        .filter(|l| l.trim_start().starts_with("Renamed { command: &["))
    {
        rows += 1;
        let (command, rest) = line.split_once("old:").expect("old:");
        let command = quoted(command);
        let old = quoted(rest.split_once("new:").expect("new:").0)
            .pop()
            .expect("old spelling");
        let covered = pairs.iter().any(|p| {
            p.old.starts_with(&command)
                && p.old
                    .iter()
                    .any(|w| *w == old || w.starts_with(&format!("{old}=")))
        });
        if !covered {
            missing.push(format!("{command:?} {old}"));
        }
    }
    assert!(rows >= 28, "RENAMED rows found: {rows}");
    assert!(missing.is_empty(), "no pair for {missing:?}");
}

/// The deprecated `--name` still refuses a name that would leave its reports folder, and a
/// refused report writes nothing.
#[test]
fn deprecated_report_name_stays_a_plain_name() {
    let dir =
        fresh(&std::env::temp_dir().join(format!("squeal-deprecated-name-{}", std::process::id())));
    let run = repo("data/runs/case3-paper");
    for name in ["../escape", "a/b", "..", ".hidden", ""] {
        let args = words(&format!("report {run} --reports r --name"));
        let out = Command::new(env!("CARGO_BIN_EXE_squeal"))
            .args(&args)
            .arg(name)
            .current_dir(&dir)
            .output()
            .expect("run");
        let err = text(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name:?}: {err}");
        assert!(
            err.contains("--name") && err.contains(NOTE),
            "{name:?}: {err}"
        );
        assert!(files_below(&dir).is_empty(), "{name:?} wrote files");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A reader that stops early (`squeal profile s1002 --csv - | head -1`) ends the program
/// quietly: no panic on the closed standard output.
#[test]
fn a_closed_pipe_ends_the_program_without_a_panic() {
    // About 65 000 rows (1.5 MB): far more than a pipe holds, so the writer meets the closed
    // pipe.
    let mut child = Command::new(env!("CARGO_BIN_EXE_squeal"))
        .args(["profile", "s1002", "--csv", "-", "--step-mm", "0.002"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn squeal");
    let stdout = child.stdout.take().expect("stdout");
    let mut first = String::new();
    std::io::BufReader::new(stdout)
        .read_line(&mut first)
        .expect("first line");
    assert_eq!(first.trim_end(), "s_mm,f_mm");
    // The reader is dropped here: the pipe is closed.
    let out = child.wait_with_output().expect("wait");
    let err = text(&out.stderr);
    assert_ne!(out.status.code(), Some(101), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}
