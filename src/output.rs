//! Output folders that are never lost or misplaced.
//!
//! - Output names (a report's `--name`) are plain names: no path separators, no `.` or `..`,
//!   nothing hidden, so that they cannot leave the folder they are meant for.
//! - A command writes into a hidden temporary sibling of its output folder
//!   (`.NAME.partial-PID`) and moves the result into place only when it has succeeded
//!   ([`StagedDir`]): a failure leaves nothing behind, and an existing folder is changed only
//!   by a complete result. Dropping an uncommitted stage removes it.

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
}

impl StagedDir {
    /// Creates the stage for `target` (its parent folders too).
    pub fn new(target: &Path) -> Result<StagedDir> {
        let name = target
            .file_name()
            .map(|n| n.to_string_lossy().to_string())
            .unwrap_or_else(|| "output".to_string());
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        std::fs::create_dir_all(&parent).map_err(|e| Error::io(&parent, e))?;
        let staging = parent.join(format!(".{name}.partial-{}", std::process::id()));
        if staging.exists() {
            std::fs::remove_dir_all(&staging).map_err(|e| Error::io(&staging, e))?;
        }
        std::fs::create_dir(&staging).map_err(|e| Error::io(&staging, e))?;
        Ok(StagedDir {
            target: target.to_path_buf(),
            staging,
            committed: false,
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
        if how == Commit::Replace || !target.exists() {
            if target.exists() {
                std::fs::remove_dir_all(&target).map_err(|e| Error::io(&target, e))?;
            }
            std::fs::rename(&self.staging, &target).map_err(|e| Error::io(&target, e))?;
        } else {
            let entries =
                std::fs::read_dir(&self.staging).map_err(|e| Error::io(&self.staging, e))?;
            for entry in entries {
                let entry = entry.map_err(|e| Error::io(&self.staging, e))?;
                let to = target.join(entry.file_name());
                if to.is_dir() {
                    std::fs::remove_dir_all(&to).map_err(|e| Error::io(&to, e))?;
                }
                std::fs::rename(entry.path(), &to).map_err(|e| Error::io(&to, e))?;
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
        }
    }
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
        // Replace drops the old files.
        let stage = StagedDir::new(&target).unwrap();
        std::fs::write(stage.path().join("b.txt"), "b").unwrap();
        stage.commit(Commit::Replace).unwrap();
        assert!(!target.join("keep.txt").exists() && target.join("b.txt").exists());
        let names: Vec<_> = std::fs::read_dir(&root).unwrap().collect();
        assert_eq!(names.len(), 1, "only the output folder remains");
        let _ = std::fs::remove_dir_all(&root);
    }
}
