//! The one option grammar of every command (docs/cli.md): where a command writes when `--out`
//! is left out, and the deprecated spellings of the previous release with their one-line note.

use std::ffi::OsString;
use std::path::{Path, PathBuf};

/// The folder every command writes below when `--out` is left out (`out/<command>/<name>`).
pub const OUT_ROOT: &str = "out";
/// The folder reports are written below (`reports/<name>`): the repository keeps its reports
/// there, and the default job (`squeal` alone) writes `reports/default`.
pub const REPORTS_ROOT: &str = "reports";

/// The folder a command writes into: `--out DIR` when given, else `out/<command>/<name>`, where
/// `command` is the command path (`kalker/solve`) and `name` names the main input (empty for a
/// command without an input file: `out/<command>`).
pub fn out_dir(out: Option<PathBuf>, command: &str, name: &str) -> PathBuf {
    out.unwrap_or_else(|| {
        let dir = Path::new(OUT_ROOT).join(command);
        if name.is_empty() {
            dir
        } else {
            dir.join(name)
        }
    })
}

/// The name of an input for a default output folder: a file's name without its extension, a
/// folder's own name (`data/runs/case3-paper/` -> `case3-paper`).
pub fn input_name(path: &Path) -> String {
    let name = if path.is_dir() {
        path.file_name()
    } else {
        path.file_stem()
    };
    name.map(|n| n.to_string_lossy().into_owned())
        .filter(|n| !n.is_empty() && n != "." && n != "..")
        .unwrap_or_else(|| "input".to_string())
}

/// A renamed option: `old` still works in `command` for this release and prints a note.
pub struct Renamed {
    /// The command path (`["kalker", "solve"]`); an empty second word matches any subcommand.
    pub command: &'static [&'static str],
    /// The old spelling.
    pub old: &'static str,
    /// The new spelling.
    pub new: &'static str,
}

/// Every option renamed by the grammar (issue 52). Clap accepts the old names as hidden
/// aliases; this table makes them print their note. Remove both in the next release.
#[rustfmt::skip]
pub const RENAMED: &[Renamed] = &[
    Renamed { command: &["simulate"], old: "--scenario", new: "--case" },
    Renamed { command: &["bench", "rolling"], old: "--scenario", new: "--case" },
    Renamed { command: &["bench", "preload"], old: "--scenario", new: "--case" },
    Renamed { command: &["mesh"], old: "--scenario", new: "--model" },
    Renamed { command: &["identify"], old: "--fmin", new: "--fmin-hz" },
    Renamed { command: &["identify"], old: "--fmax", new: "--fmax-hz" },
    Renamed { command: &["check-modes"], old: "--fmin", new: "--fmin-hz" },
    Renamed { command: &["check-modes"], old: "--fmax", new: "--fmax-hz" },
    Renamed { command: &["growth"], old: "--signal", new: "--column" },
    Renamed { command: &["psd"], old: "--peak-fmin", new: "--fmin-hz" },
    Renamed { command: &["psd"], old: "--peak-fmax", new: "--fmax-hz" },
    Renamed { command: &["cwt"], old: "--fmin", new: "--fmin-hz" },
    Renamed { command: &["cwt"], old: "--fmax", new: "--fmax-hz" },
    Renamed { command: &["wav"], old: "--rate", new: "--sample-rate-hz" },
    Renamed { command: &["kalker"], old: "--fn", new: "--normal-force-n" },
    Renamed { command: &["kalker"], old: "--fx", new: "--force-x-n" },
    Renamed { command: &["kalker"], old: "--fy", new: "--force-y-n" },
    Renamed { command: &["kalker"], old: "--wheel-radius", new: "--wheel-radius-m" },
    Renamed { command: &["kalker"], old: "--rail-radius", new: "--rail-radius-m" },
    Renamed { command: &["kalker"], old: "--wheel-y", new: "--wheel-y-m" },
    Renamed { command: &["kalker"], old: "--e", new: "--youngs-modulus-pa" },
    Renamed { command: &["kalker"], old: "--nu", new: "--poisson-ratio" },
    Renamed { command: &["kalker"], old: "--phi", new: "--phi-per-m" },
    Renamed { command: &["stability"], old: "--fn", new: "--normal-force-n" },
    Renamed { command: &["stability"], old: "--fx", new: "--force-x-n" },
    Renamed { command: &["stability"], old: "--fy", new: "--force-y-n" },
    Renamed { command: &["stability"], old: "--friction-slope", new: "--friction-slope-s-per-m" },
    Renamed { command: &["bench", "modal"], old: "--fmax", new: "--fmax-hz" },
];

/// The note printed for a deprecated spelling (one line on standard error).
pub fn note(old: &str, new: &str) {
    eprintln!("warning: {old} is deprecated, use {new}; the old spelling goes in the next release");
}

/// The command path of a command line: the first word that is not an option, and for
/// `kalker` and `bench` the second when it names a subcommand.
fn command_path(args: &[String]) -> Vec<String> {
    let words: Vec<&String> = args
        .iter()
        .skip(1)
        .filter(|a| !a.starts_with('-'))
        .collect();
    let mut path = Vec::new();
    if let Some(first) = words.first() {
        path.push(first.to_string());
        if let Some(second) = words.get(1) {
            let subcommands: &[&str] = match first.as_str() {
                "kalker" => &["hertz", "solve", "creep", "compare"],
                "bench" => &["explicit", "modal", "stability", "rolling", "preload"],
                _ => &[],
            };
            if subcommands.contains(&second.as_str()) {
                path.push(second.to_string());
            }
        }
    }
    path
}

/// The renamed options a command line uses, as (old, new) pairs, each once.
pub fn deprecated_in(args: &[String]) -> Vec<(&'static str, &'static str)> {
    let path = command_path(args);
    let mut found: Vec<(&str, &str)> = Vec::new();
    for r in RENAMED {
        let applies =
            r.command.iter().zip(path.iter()).all(|(a, b)| a == b) && path.len() >= r.command.len();
        if !applies {
            continue;
        }
        let used = args
            .iter()
            .skip(1)
            .take_while(|a| a.as_str() != "--")
            .any(|a| a == r.old || a.starts_with(&format!("{}=", r.old)));
        if used && !found.contains(&(r.old, r.new)) {
            found.push((r.old, r.new));
        }
    }
    found
}

/// Print the note of every renamed option in the command line (before clap parses it).
pub fn warn_deprecated(args: &[OsString]) {
    let args: Vec<String> = args
        .iter()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    for (old, new) in deprecated_in(&args) {
        note(old, new);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(line: &str) -> Vec<String> {
        line.split_whitespace().map(String::from).collect()
    }

    #[test]
    fn renamed_options_are_found_in_their_command_only() {
        let old = deprecated_in(&words("squeal simulate --scenario c.json --out o"));
        assert_eq!(old, [("--scenario", "--case")]);
        let old = deprecated_in(&words("squeal mesh --scenario m.json"));
        assert_eq!(old, [("--scenario", "--model")]);
        // The same spelling in a command that never had it is clap's business, not a note.
        assert!(deprecated_in(&words("squeal identify run --fn 3")).is_empty());
        // `--old=value`, a subcommand path, and nothing after `--`.
        let old = deprecated_in(&words("squeal kalker solve --fn=1e5 --fx 3 -- --fy"));
        assert_eq!(old, [("--fn", "--normal-force-n"), ("--fx", "--force-x-n")]);
        assert_eq!(
            deprecated_in(&words("squeal bench modal --mtx d --fmax 5")),
            [("--fmax", "--fmax-hz")]
        );
        // New spellings print nothing.
        assert!(deprecated_in(&words("squeal simulate --case c.json")).is_empty());
    }

    #[test]
    fn default_folders_follow_one_rule() {
        assert_eq!(
            out_dir(None, "kalker/solve", "x"),
            Path::new("out/kalker/solve/x")
        );
        assert_eq!(out_dir(Some("o".into()), "psd", "x"), Path::new("o"));
        assert_eq!(
            out_dir(None, "kalker/creep", "").to_str(),
            Some("out/kalker/creep")
        );
        assert_eq!(
            input_name(Path::new("data/cases/case3-demo.json")),
            "case3-demo"
        );
        assert_eq!(input_name(Path::new("src")), "src");
        assert_eq!(input_name(Path::new(".")), "input");
    }
}
