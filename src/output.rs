//! Output folders that are never lost or misplaced.
//!
//! - Output names (a report's `--name`) are plain names: no path separators, no `.` or `..`,
//!   nothing hidden, so that they cannot leave the folder they are meant for.
//! - A command writes into a hidden temporary sibling of its output folder
//!   (`.NAME.partial-PID`) and moves the result into place only when it has succeeded
//!   ([`StagedDir`]): a failure leaves nothing behind, and an existing folder is changed only
//!   by a complete result. Dropping an uncommitted stage removes it, with the parent folders
//!   it created. A process killed before it could (SIGKILL, or a signal to a command without
//!   a handler) leaves its stage; the next command that stages the same output removes the
//!   stages of processes that no longer run ([`sweep_stale_stages`]).
//! - A run claims its run directory while it writes there ([`FolderLock`], `run.lock` with its
//!   process id), so that a second run (a resume started by hand, or by a script, while the
//!   first still goes) is refused instead of writing into the same files.

use std::path::{Path, PathBuf};

use crate::{Error, Result};

/// Checks that `name` is a plain folder or file name: 1 to 100 characters, not `.` or `..`,
/// not starting with `.` or `-`, without `/`, `\`, `:` or control characters.
pub fn check_plain_name(field: &str, name: &str) -> Result<()> {
    let bad = name.is_empty()
        || name.chars().count() > 100
        || name.starts_with('.')
        || name.starts_with('-')
        || name
            .chars()
            .any(|c| c == '/' || c == '\\' || c == ':' || c.is_control());
    if bad {
        return Err(Error::input(
            "command line",
            field,
            format!(
                "{name:?} is not a plain name: 1 to 100 characters, no path separators, \
                 not starting with '.' or '-' (e.g. case3-report)"
            ),
        ));
    }
    Ok(())
}

/// The files and folders the running command reads ([`protect_inputs`]), canonical: no
/// output of the command may be written over one of them or replace a folder holding one.
static PROTECTED_INPUTS: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

/// Declares the paths the command reads (files or folders; those that do not exist are
/// ignored): every output written through this module is checked against them, so that a
/// mistaken `--out` (the input CSV, the run directory a report reads) is refused instead of
/// destroying the input.
pub fn protect_inputs<P: AsRef<Path>>(paths: impl IntoIterator<Item = P>) {
    let mut held = PROTECTED_INPUTS.lock().unwrap_or_else(|e| e.into_inner());
    for p in paths {
        if let Ok(c) = p.as_ref().canonicalize() {
            if !held.contains(&c) {
                held.push(c);
            }
        }
    }
}

/// The canonical form of a path that may not exist yet: its parent's canonical path and its
/// name (the parent may not exist either: then the path as given).
fn canonical_target(path: &Path) -> PathBuf {
    if let Ok(c) = path.canonicalize() {
        return c;
    }
    match (path.parent(), path.file_name()) {
        (Some(parent), Some(name)) => {
            let parent = if parent.as_os_str().is_empty() {
                Path::new(".")
            } else {
                parent
            };
            parent
                .canonicalize()
                .map(|p| p.join(name))
                .unwrap_or_else(|_| path.to_path_buf())
        }
        _ => path.to_path_buf(),
    }
}

/// Refuses to write the file `path` when it is one of the command's inputs.
pub fn check_not_an_input(path: &Path) -> Result<()> {
    let target = canonical_target(path);
    let held = PROTECTED_INPUTS.lock().unwrap_or_else(|e| e.into_inner());
    if held.contains(&target) {
        return Err(Error::input(
            path.display().to_string(),
            "--out",
            "is an input of this command: refusing to write over it; expected another output \
             path",
        ));
    }
    Ok(())
}

/// Checks an output folder's path before anything is written: it may be new or a folder, but
/// not a file (an input file given as the output folder is named as such). An input folder (a
/// run directory) may take outputs beside its files, which a commit checks one by one.
pub fn check_folder_target(dir: &Path) -> Result<()> {
    if dir.is_file() {
        check_not_an_input(dir)?;
        return Err(Error::input(
            dir.display().to_string(),
            "--out",
            "is a file: expected an output folder (new, or one that exists)",
        ));
    }
    Ok(())
}

/// Refuses to replace the folder `dir` whole when it is, or holds, one of the command's inputs.
fn check_holds_no_input(dir: &Path) -> Result<()> {
    let target = canonical_target(dir);
    let held = PROTECTED_INPUTS.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(input) = held.iter().find(|p| p.starts_with(&target)) {
        return Err(Error::input(
            dir.display().to_string(),
            "--out",
            format!(
                "holds {}, an input of this command: refusing to replace it; expected another \
                 output folder",
                input.display()
            ),
        ));
    }
    Ok(())
}

/// The file that marks a folder squeal made and may replace whole (a run directory, a report,
/// an EMA result): `--overwrite` and a report's replacement touch no other folder.
pub const OUTPUT_MARKER: &str = ".squeal-output";

/// Files by which a folder written by an earlier release (before [`OUTPUT_MARKER`]) is known as
/// squeal's: a run directory's record, a report's summary, an EMA's modes.
const EARLIER_OUTPUT_FILES: [&str; 3] = ["run.json", "report.json", "modes.uff"];

/// Checks that the folder `dir` may be deleted and written again whole: it is no folder a
/// user needs (`/`, the home folder, the current folder or one above it), and squeal made it
/// ([`OUTPUT_MARKER`], or a run, report or EMA of an earlier release). `field` names the
/// option that asked for the replacement.
pub fn check_replaceable(dir: &Path, field: &str) -> Result<()> {
    check_holds_no_input(dir)?;
    let shown = dir.display().to_string();
    let refuse = |why: &str| Error::input(&shown, field, why.to_string());
    let Ok(target) = dir.canonicalize() else {
        return Ok(()); // nothing there to lose
    };
    let home = std::env::var_os("HOME").and_then(|h| PathBuf::from(h).canonicalize().ok());
    let cwd = std::env::current_dir().and_then(|c| c.canonicalize()).ok();
    if target.parent().is_none() || home.as_ref() == Some(&target) {
        return Err(refuse(
            "is the root or the home folder: refusing to replace it; give a folder of its own",
        ));
    }
    if cwd.as_ref().is_some_and(|c| c.starts_with(&target)) {
        return Err(refuse(
            "is the current folder or contains it: refusing to replace it; give a folder of its \
             own (e.g. out/case3)",
        ));
    }
    if !target.is_dir() {
        return Err(refuse("is a file, not a folder: expected an output folder"));
    }
    let made_by_squeal = target.join(OUTPUT_MARKER).exists()
        || EARLIER_OUTPUT_FILES.iter().any(|f| target.join(f).exists());
    if has_entries(&target) && !made_by_squeal {
        return Err(refuse(
            "holds files squeal did not write (no run, report or EMA result): refusing to \
             replace them; give a new or empty folder",
        ));
    }
    Ok(())
}

/// Writes [`OUTPUT_MARKER`] into `dir`.
pub fn mark_output(dir: &Path) -> Result<()> {
    let path = dir.join(OUTPUT_MARKER);
    std::fs::write(
        &path,
        "A folder squeal wrote: `--overwrite` and a new report may replace it whole.\n",
    )
    .map_err(|e| Error::io(&path, e))
}

/// An earlier output folder set aside while its replacement is made: renamed to a hidden
/// sibling (`.NAME.replaced-PID`) and an empty folder made in its place. [`SetAside::discard`]
/// deletes the old one once the new one holds a result; dropped before that (the new run
/// failed or was stopped before it wrote anything of its own), the new folder is removed and
/// the old one renamed back, as it was.
#[derive(Debug)]
pub struct SetAside {
    dir: PathBuf,
    aside: PathBuf,
    done: bool,
}

impl SetAside {
    /// Sets `dir` aside (after [`check_replaceable`]) and makes it again, empty.
    pub fn new(dir: &Path, field: &str) -> Result<SetAside> {
        check_replaceable(dir, field)?;
        let name = dir
            .file_name()
            .map(|n| n.to_string_lossy().to_string())
            .unwrap_or_else(|| "output".to_string());
        let parent = match dir.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let aside = parent.join(format!(".{name}.replaced-{}", std::process::id()));
        if aside.exists() {
            std::fs::remove_dir_all(&aside).map_err(|e| Error::io(&aside, e))?;
        }
        std::fs::rename(dir, &aside).map_err(|e| Error::io(dir, e))?;
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        Ok(SetAside {
            dir: dir.to_path_buf(),
            aside,
            done: false,
        })
    }

    /// The replacement holds a result: the old folder goes.
    pub fn discard(mut self) -> Result<()> {
        self.done = true;
        std::fs::remove_dir_all(&self.aside).map_err(|e| Error::io(&self.aside, e))
    }
}

impl Drop for SetAside {
    fn drop(&mut self) {
        if !self.done {
            // Best effort, on the way out of an error: the error itself is reported.
            let _ = std::fs::remove_dir_all(&self.dir);
            let _ = std::fs::rename(&self.aside, &self.dir);
        }
    }
}

/// Whether a folder holds anything.
pub fn has_entries(dir: &Path) -> bool {
    std::fs::read_dir(dir).is_ok_and(|mut entries| entries.next().is_some())
}

/// How a staged result joins an existing output folder.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Commit {
    /// The result replaces the folder whole (a report: stale files of an older one go).
    Replace,
    /// The result's files replace files of the same name; other files stay (an output folder
    /// shared with other commands, e.g. a run directory).
    Merge,
}

/// A temporary sibling of an output folder, moved into place by [`StagedDir::commit`].
#[derive(Debug)]
pub struct StagedDir {
    target: PathBuf,
    staging: PathBuf,
    committed: bool,
    /// The topmost parent folder this stage created (None: they all existed); removed, if
    /// empty, with the stage when the command fails.
    created_parent: Option<PathBuf>,
}

/// The stage name of output `name` for process `pid`.
fn stage_name(name: &str, pid: u32) -> String {
    format!(".{name}.partial-{pid}")
}

/// Removes the stages of output `name` in `parent` left by processes that no longer run
/// (killed while they wrote). A stage of a running squeal process stays, as does anything
/// whose name is not exactly a stage name. Best effort: a stage that cannot be removed stays.
/// Where there is no `/proc` to ask, no other process counts as running (as for stale locks).
pub fn sweep_stale_stages(parent: &Path, name: &str) {
    let Ok(entries) = std::fs::read_dir(parent) else {
        return;
    };
    let prefix = format!(".{name}.partial-");
    for entry in entries.flatten() {
        let file_name = entry.file_name().to_string_lossy().to_string();
        let Some(pid) = file_name
            .strip_prefix(&prefix)
            .and_then(|p| p.parse::<u32>().ok())
        else {
            continue;
        };
        if process_runs_squeal(pid) {
            continue;
        }
        let path = entry.path();
        let _ = if path.is_dir() {
            std::fs::remove_dir_all(&path)
        } else {
            std::fs::remove_file(&path)
        };
    }
}

/// Creates `dir` and its missing parents; returns the topmost folder it created (None when
/// `dir` existed).
pub fn create_dir_recording(dir: &Path) -> Result<Option<PathBuf>> {
    let mut top = None;
    let mut at = Some(dir);
    while let Some(p) = at {
        if p.as_os_str().is_empty() || p.exists() {
            break;
        }
        top = Some(p.to_path_buf());
        at = p.parent();
    }
    std::fs::create_dir_all(dir).map_err(|e| folder_error(dir, e))?;
    Ok(top)
}

/// The error of a folder `dir` that could not be made: when a file stands where one of its
/// folders should be (the OS says "exists" or "not a directory"), that file is named.
fn folder_error(dir: &Path, e: std::io::Error) -> Error {
    use std::io::ErrorKind as K;
    if matches!(e.kind(), K::AlreadyExists | K::NotADirectory) {
        let mut at = Some(dir);
        while let Some(p) = at.filter(|p| !p.as_os_str().is_empty()) {
            if p.is_file() {
                return Error::io(
                    p,
                    std::io::Error::other("is a file, where a folder is needed"),
                );
            }
            at = p.parent();
        }
    }
    Error::io(dir, e)
}

/// Removes the empty folders from `dir` up to `top` (both included), as created by
/// [`create_dir_recording`]; stops at the first that is not empty.
pub fn remove_created(dir: &Path, top: &Path) {
    let mut at = Some(dir);
    while let Some(p) = at {
        if std::fs::remove_dir(p).is_err() || p == top {
            break;
        }
        at = p.parent();
    }
}

impl StagedDir {
    /// Creates the stage for `target` (its parent folders too).
    pub fn new(target: &Path) -> Result<StagedDir> {
        check_folder_target(target)?;
        let name = target
            .file_name()
            .map(|n| n.to_string_lossy().to_string())
            .unwrap_or_else(|| "output".to_string());
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let created_parent = create_dir_recording(&parent)?;
        sweep_stale_stages(&parent, &name);
        let staging = parent.join(stage_name(&name, std::process::id()));
        if staging.exists() {
            std::fs::remove_dir_all(&staging).map_err(|e| Error::io(&staging, e))?;
        }
        std::fs::create_dir(&staging).map_err(|e| Error::io(&staging, e))?;
        Ok(StagedDir {
            target: target.to_path_buf(),
            staging,
            committed: false,
            created_parent,
        })
    }

    /// Where to write.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// The final folder.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// Moves the result into place (renames within one file system).
    pub fn commit(mut self, how: Commit) -> Result<PathBuf> {
        let target = self.target.clone();
        if how == Commit::Replace {
            // Only a folder squeal made is replaced whole; the new one is marked as such.
            check_replaceable(&target, "--out")?;
            mark_output(&self.staging)?;
        }
        if how == Commit::Replace || !target.exists() {
            if target.exists() {
                std::fs::remove_dir_all(&target).map_err(|e| Error::io(&target, e))?;
            }
            std::fs::rename(&self.staging, &target).map_err(|e| Error::io(&target, e))?;
        } else {
            let entries =
                std::fs::read_dir(&self.staging).map_err(|e| Error::io(&self.staging, e))?;
            let mut moves = Vec::new();
            for entry in entries {
                let entry = entry.map_err(|e| Error::io(&self.staging, e))?;
                let to = target.join(entry.file_name());
                // Every file checked before any is moved: a refused merge changes nothing.
                check_not_an_input(&to)?;
                moves.push((entry.path(), to));
            }
            for (from, to) in moves {
                if to.is_dir() {
                    std::fs::remove_dir_all(&to).map_err(|e| Error::io(&to, e))?;
                }
                std::fs::rename(from, &to).map_err(|e| Error::io(&to, e))?;
            }
            std::fs::remove_dir(&self.staging).map_err(|e| Error::io(&self.staging, e))?;
        }
        self.committed = true;
        Ok(target)
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.committed {
            // Best effort: the stage is a hidden temporary folder; a failure to remove it must
            // not hide the error that dropped it.
            let _ = std::fs::remove_dir_all(&self.staging);
            if let (Some(top), Some(parent)) = (&self.created_parent, self.staging.parent()) {
                remove_created(parent, top);
            }
        }
    }
}

/// Writes the file `path` through `write` on a hidden temporary sibling, renamed onto `path`
/// when `write` succeeds and removed when it fails: a failed write leaves no partial file and
/// does not touch an existing one.
pub fn write_file_staged<T>(path: &Path, write: impl FnOnce(&Path) -> Result<T>) -> Result<T> {
    check_not_an_input(path)?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_else(|| "output".to_string());
    let parent = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let created_parent = create_dir_recording(&parent)?;
    sweep_stale_stages(&parent, &name);
    let staging = parent.join(stage_name(&name, std::process::id()));
    match write(&staging) {
        Ok(value) => {
            std::fs::rename(&staging, path).map_err(|e| Error::io(path, e))?;
            Ok(value)
        }
        Err(e) => {
            let _ = std::fs::remove_file(&staging);
            if let Some(top) = &created_parent {
                remove_created(&parent, top);
            }
            Err(e)
        }
    }
}

/// Writes `value` as pretty JSON to `path` through [`write_file_staged`]: a process killed
/// while writing leaves the last whole file (a run's `status.json` and `run.json`, rewritten
/// at each checkpoint).
pub fn write_json_staged(path: &Path, value: &impl serde::Serialize) -> Result<()> {
    let text = serde_json::to_string_pretty(value).map_err(|e| Error::Numerical(e.to_string()))?;
    write_file_staged(path, |staging| {
        std::fs::write(staging, &text).map_err(|e| Error::io(staging, e))
    })
}

/// The file a run holds in its run directory while it writes there.
pub const LOCK_FILE: &str = "run.lock";

/// A run's claim on its run directory: `run.lock` with the process id, removed when the claim
/// is dropped. A lock whose process no longer runs (killed: nothing removed it) is stale and
/// is taken over.
#[derive(Debug)]
pub struct FolderLock {
    path: PathBuf,
}

impl FolderLock {
    /// Claims `dir` (created if missing), or says which live process holds it.
    pub fn acquire(dir: &Path) -> Result<FolderLock> {
        std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
        let path = dir.join(LOCK_FILE);
        // Twice at most: the second attempt follows the removal of a stale lock.
        for _ in 0..2 {
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(mut file) => {
                    use std::io::Write as _;
                    write!(file, "{}", std::process::id()).map_err(|e| Error::io(&path, e))?;
                    return Ok(FolderLock { path });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    if let Some(pid) = FolderLock::holder(dir) {
                        return Err(held_by(dir, pid));
                    }
                    std::fs::remove_file(&path).map_err(|e| Error::io(&path, e))?;
                }
                Err(e) => return Err(Error::io(&path, e)),
            }
        }
        Err(Error::io(
            &path,
            std::io::Error::other("another process claimed the folder at the same moment"),
        ))
    }

    /// The live process holding `dir`'s lock, if any.
    pub fn holder(dir: &Path) -> Option<u32> {
        let text = std::fs::read_to_string(dir.join(LOCK_FILE)).ok()?;
        let pid = text.trim().parse::<u32>().ok()?;
        process_runs_squeal(pid).then_some(pid)
    }

    /// The error for a run refused because `dir` is held (by [`FolderLock::holder`]).
    pub fn refuse_if_held(dir: &Path) -> Result<()> {
        match FolderLock::holder(dir) {
            Some(pid) => Err(held_by(dir, pid)),
            None => Ok(()),
        }
    }
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        // Best effort: a lock left behind is stale once this process has ended.
        let _ = std::fs::remove_file(&self.path);
    }
}

fn held_by(dir: &Path, pid: u32) -> Error {
    Error::input(
        dir.display().to_string(),
        "--out",
        format!(
            "a run (process {pid}) is writing into this folder; wait for it to end, or stop it \
             (SIGTERM or Ctrl-C write a checkpoint) and then resume"
        ),
    )
}

/// Whether process `pid` runs and is a run of this program: this process, one of the same
/// executable, or one whose command line names `squeal` (a pid reused by another program is
/// not a holder). Read from `/proc`; where there is none, no process counts as running and a
/// lock is always taken over.
fn process_runs_squeal(pid: u32) -> bool {
    if pid == std::process::id() {
        return true;
    }
    let proc_dir = Path::new("/proc").join(pid.to_string());
    if !proc_dir.exists() {
        return false;
    }
    let same_exe = match (
        std::fs::read_link(proc_dir.join("exe")),
        std::fs::read_link("/proc/self/exe"),
    ) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    let names_squeal = std::fs::read(proc_dir.join("cmdline"))
        .map(|c| String::from_utf8_lossy(&c).contains("squeal"))
        .unwrap_or(false);
    same_exe || names_squeal
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("squeal_output_{tag}_{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn plain_names_only() {
        for good in ["case3", "report-1", "a b", "x.y"] {
            assert!(check_plain_name("--name", good).is_ok(), "{good}");
        }
        for bad in [
            "",
            ".",
            "..",
            "../escape",
            "a/b",
            "a\\b",
            ".hidden",
            "-x",
            "c:d",
            "a\nb",
        ] {
            let e = check_plain_name("--name", bad).unwrap_err().to_string();
            assert!(
                e.contains("--name") && e.contains("plain name"),
                "{bad}: {e}"
            );
        }
    }

    /// Item 12 of issue 53: a failed command leaves no folder it created, and the stages that
    /// killed processes left behind go with the next command that stages the same output,
    /// while the stage of a process still running (here a shell whose command line names
    /// squeal) and files that only look like stages stay.
    #[cfg(target_os = "linux")]
    #[test]
    fn stale_stages_of_dead_processes_are_swept_and_failures_leave_no_new_folders() {
        let root = temp("sweep");
        // Parents created for a stage that fails go with it.
        {
            let _stage = StagedDir::new(&root.join("a/b/out")).unwrap();
            assert!(root.join("a/b").is_dir());
        }
        assert!(!root.join("a").exists(), "the created parents stayed");
        let failed: Result<()> = write_file_staged(&root.join("c/d/f.txt"), |_| {
            Err(Error::Numerical("writer failed".into()))
        });
        assert!(failed.is_err() && !root.join("c").exists());
        // A dead process: one that has run and been waited for.
        let mut child = std::process::Command::new("true").spawn().unwrap();
        let dead = child.id();
        child.wait().unwrap();
        let mut live = std::process::Command::new("sh")
            // `; true` keeps the shell from handing its process to `sleep`, whose command line
            // would not name squeal.
            .args(["-c", "sleep 30; true", "squeal-test-holder"])
            .spawn()
            .unwrap();
        // The shell's command line is its own once it has started: wait for that (measured: on
        // a loaded machine the sweep below could otherwise read it before it was set).
        let cmdline = format!("/proc/{}/cmdline", live.id());
        for _ in 0..500 {
            if std::fs::read(&cmdline).is_ok_and(|c| String::from_utf8_lossy(&c).contains("squeal"))
            {
                break;
            }
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        let dead_stage = root.join(stage_name("out", dead));
        let live_stage = root.join(stage_name("out", live.id()));
        let dead_file = root.join(stage_name("f.txt", dead));
        let lookalike = root.join(".out.partial-notapid");
        for d in [&dead_stage, &live_stage, &lookalike] {
            std::fs::create_dir_all(d).unwrap();
            std::fs::write(d.join("x"), "x").unwrap();
        }
        std::fs::write(&dead_file, "half").unwrap();
        let stage = StagedDir::new(&root.join("out")).unwrap();
        assert!(!dead_stage.exists(), "a dead process's stage stayed");
        assert!(live_stage.exists() && lookalike.exists());
        stage.commit(Commit::Merge).unwrap();
        write_file_staged(&root.join("f.txt"), |p| {
            std::fs::write(p, "whole").map_err(|e| Error::io(p, e))
        })
        .unwrap();
        assert!(!dead_file.exists(), "a dead process's staged file stayed");
        live.kill().unwrap();
        live.wait().unwrap();
        let _ = std::fs::remove_dir_all(&root);
    }

    #[test]
    fn a_dropped_stage_leaves_nothing_and_a_commit_moves_the_result() {
        let root = temp("stage");
        let target = root.join("out");
        {
            let stage = StagedDir::new(&target).unwrap();
            std::fs::write(stage.path().join("a.txt"), "1").unwrap();
            // Dropped without a commit: as when the command fails.
        }
        assert!(!target.exists());
        assert!(!has_entries(&root), "the stage was not removed");
        // Merge into an existing folder keeps its other files and replaces same-named ones.
        std::fs::create_dir_all(&target).unwrap();
        std::fs::write(target.join("keep.txt"), "old").unwrap();
        std::fs::write(target.join("a.txt"), "old").unwrap();
        let stage = StagedDir::new(&target).unwrap();
        std::fs::write(stage.path().join("a.txt"), "new").unwrap();
        stage.commit(Commit::Merge).unwrap();
        assert_eq!(
            std::fs::read_to_string(target.join("a.txt")).unwrap(),
            "new"
        );
        assert_eq!(
            std::fs::read_to_string(target.join("keep.txt")).unwrap(),
            "old"
        );
        // Replace refuses a folder squeal did not make, and leaves it as it was.
        let stage = StagedDir::new(&target).unwrap();
        std::fs::write(stage.path().join("b.txt"), "b").unwrap();
        assert!(stage.commit(Commit::Replace).is_err());
        assert!(target.join("keep.txt").exists() && !target.join("b.txt").exists());
        // A folder squeal made: Replace drops the old files and marks the new folder.
        mark_output(&target).unwrap();
        let stage = StagedDir::new(&target).unwrap();
        std::fs::write(stage.path().join("b.txt"), "b").unwrap();
        stage.commit(Commit::Replace).unwrap();
        assert!(!target.join("keep.txt").exists() && target.join("b.txt").exists());
        assert!(target.join(OUTPUT_MARKER).exists());
        let names: Vec<_> = std::fs::read_dir(&root).unwrap().collect();
        assert_eq!(names.len(), 1, "only the output folder remains");
        // A staged file: a failing writer leaves the old file as it was and no stage.
        let file = root.join("f.txt");
        std::fs::write(&file, "old").unwrap();
        let failed: Result<()> = write_file_staged(&file, |p| {
            std::fs::write(p, "half").unwrap();
            Err(Error::Numerical("writer failed".into()))
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "old");
        write_file_staged(&file, |p| {
            std::fs::write(p, "new").map_err(|e| Error::io(p, e))
        })
        .unwrap();
        assert_eq!(std::fs::read_to_string(&file).unwrap(), "new");
        assert_eq!(std::fs::read_dir(&root).unwrap().count(), 2);
        let _ = std::fs::remove_dir_all(&root);
    }

    #[test]
    fn a_held_folder_is_refused_and_a_stale_lock_is_taken_over() {
        let dir = temp("lock");
        let lock = FolderLock::acquire(&dir).unwrap();
        assert_eq!(FolderLock::holder(&dir), Some(std::process::id()));
        let refused = FolderLock::acquire(&dir).unwrap_err().to_string();
        assert!(
            refused.contains(&format!("process {}", std::process::id()))
                && refused.contains("--out"),
            "{refused}"
        );
        assert!(FolderLock::refuse_if_held(&dir).is_err());
        drop(lock);
        assert!(!dir.join(LOCK_FILE).exists());
        assert!(FolderLock::refuse_if_held(&dir).is_ok());
        // A lock left by a process that has ended (as after a kill) is taken over.
        let ended = std::process::Command::new("true").spawn().unwrap();
        let ended_pid = ended.id();
        let mut ended = ended;
        ended.wait().unwrap();
        std::fs::write(dir.join(LOCK_FILE), ended_pid.to_string()).unwrap();
        assert_eq!(FolderLock::holder(&dir), None);
        let taken = FolderLock::acquire(&dir).unwrap();
        assert_eq!(
            std::fs::read_to_string(dir.join(LOCK_FILE)).unwrap(),
            std::process::id().to_string()
        );
        drop(taken);
        // So is one that does not hold a process id.
        std::fs::write(dir.join(LOCK_FILE), "not a pid").unwrap();
        drop(FolderLock::acquire(&dir).unwrap());
        let _ = std::fs::remove_dir_all(&dir);
    }
}
