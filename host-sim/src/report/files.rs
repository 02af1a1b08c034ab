//! The files a command writes, all or none: each output is first written
//! into a hidden staging folder beside its final place
//! (`.deploywatch-partial-PID/` in the output's folder, so that the final
//! move is a rename on one file system), and moved into place only when
//! every output of the command is written ([`Outputs::commit`]). A command
//! that fails or is interrupted half-way leaves the old outputs as they
//! were: never a new JSON and new plots beside an old report. A failure
//! removes the staging folder; an interrupt (Ctrl-C, a kill) may leave it,
//! hidden, to be deleted by hand.
//!
//! Every command writes through it: `--out`, `--json`, `--plot`, the
//! diagnosis report and its plots (`docs/spec/formats.md` names them).
//!
//! An output named by a symbolic link is written to the file the link
//! points to (the link stays); one that is a device or a pipe
//! (`/dev/null`, `/dev/stdout`, a FIFO) is written through, into it, at
//! the commit, never replaced by a file. The commands refuse an output
//! that is one of their inputs before they start ([`is_input`]).

use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Why an output could not be written or moved into place.
#[derive(Debug, thiserror::Error)]
#[error("{path}: cannot write: {message}")]
pub struct FileError {
    /// The output (its final path).
    pub path: String,
    /// What failed.
    pub message: String,
}

impl FileError {
    fn new(path: &Path, message: impl std::fmt::Display) -> Self {
        FileError {
            path: path.display().to_string(),
            message: message.to_string(),
        }
    }
}

/// The outputs of one command, staged until [`Outputs::commit`]. Dropped
/// without a commit, it removes what it staged.
#[derive(Debug, Default)]
pub struct Outputs {
    /// Final folder → its staging folder.
    staging: BTreeMap<PathBuf, PathBuf>,
    /// Outputs written through into a device or a pipe at the commit:
    /// (staged file, final path).
    through: Vec<(PathBuf, PathBuf)>,
    /// The staging folder of `through`, in the system's temporary folder
    /// (a device's folder, `/dev`, is no place for it).
    through_dir: Option<PathBuf>,
}

/// True when `path` names the same file as one of `inputs` (by whatever
/// path: links and `.` resolved).
pub fn is_input(path: &Path, inputs: &[&Path]) -> bool {
    let Ok(real) = std::fs::canonicalize(path) else {
        return false;
    };
    inputs
        .iter()
        .any(|i| std::fs::canonicalize(i).is_ok_and(|r| r == real))
}

/// Symbolic links followed to the path they name at last (at most 40, as
/// the kernel does; a link to nothing yet names the file it would be).
fn link_target(path: &Path) -> PathBuf {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        let Ok(meta) = std::fs::symlink_metadata(&p) else {
            break;
        };
        if !meta.file_type().is_symlink() {
            break;
        }
        let Ok(to) = std::fs::read_link(&p) else {
            break;
        };
        p = match p.parent() {
            Some(dir) if to.is_relative() => dir.join(to),
            _ => to,
        };
    }
    p
}

/// True when `path` is something other than a file or a folder that
/// exists: a device, a pipe or a socket (links followed).
pub fn is_special(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|m| !m.file_type().is_file() && !m.is_dir())
}

/// The name of the staging folder in an output folder.
fn staging_name() -> String {
    format!(".deploywatch-partial-{}", std::process::id())
}

impl Outputs {
    /// No output staged yet.
    pub fn new() -> Self {
        Outputs::default()
    }

    /// Where to write the output whose final path is `path`: the same file
    /// name in the staging folder of `path`'s folder (created on first
    /// use). Files written beside it in that folder (a report's plots) are
    /// staged too.
    pub fn path(&mut self, path: &Path) -> Result<PathBuf, FileError> {
        let name = path
            .file_name()
            .ok_or_else(|| FileError::new(path, "expected a file name"))?;
        if is_special(path) {
            return self.through(path, name);
        }
        let path = &link_target(path);
        let name = path.file_name().unwrap_or(name);
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        if !self.staging.contains_key(&dir) {
            let stage = dir.join(staging_name());
            std::fs::create_dir_all(&stage).map_err(|e| FileError::new(path, e))?;
            self.staging.insert(dir.clone(), stage);
        }
        Ok(self.staging[&dir].join(name))
    }

    /// Where to stage the output `path`, a device or a pipe written
    /// through at the commit: a folder of its own (files written beside it
    /// are dropped) in the system's temporary folder.
    fn through(&mut self, path: &Path, name: &std::ffi::OsStr) -> Result<PathBuf, FileError> {
        let root = match &self.through_dir {
            Some(d) => d.clone(),
            None => {
                // One folder per set of outputs: two sets of one process
                // (the Python package's threads) never share it.
                static SETS: std::sync::atomic::AtomicUsize =
                    std::sync::atomic::AtomicUsize::new(0);
                let set = SETS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let d = std::env::temp_dir().join(format!("{}-{set}", staging_name()));
                self.through_dir = Some(d.clone());
                d
            }
        };
        let dir = root.join(self.through.len().to_string());
        std::fs::create_dir_all(&dir).map_err(|e| FileError::new(path, e))?;
        let staged = dir.join(name);
        self.through.push((staged.clone(), path.to_path_buf()));
        Ok(staged)
    }

    /// Writes `bytes` as the output `path` (staged).
    pub fn write(&mut self, path: &Path, bytes: impl AsRef<[u8]>) -> Result<(), FileError> {
        let staged = self.path(path)?;
        std::fs::write(&staged, bytes).map_err(|e| FileError::new(path, e))
    }

    /// Moves every staged file to its final place, then removes the
    /// staging folders. Nothing is moved when a final place is taken by a
    /// folder; Markdown files (a report) are moved last, after the files
    /// they link.
    pub fn commit(mut self) -> Result<(), FileError> {
        // Devices and pipes first: a full device fails before any file
        // is moved.
        for (staged, to) in &self.through {
            let bytes = std::fs::read(staged).map_err(|e| FileError::new(to, e))?;
            std::fs::OpenOptions::new()
                .write(true)
                .open(to)
                .and_then(|mut f| f.write_all(&bytes))
                .map_err(|e| FileError::new(to, e))?;
        }
        let mut moves = Vec::new();
        for (dir, stage) in &self.staging {
            let entries = std::fs::read_dir(stage).map_err(|e| FileError::new(stage, e))?;
            for entry in entries {
                let from = entry.map_err(|e| FileError::new(stage, e))?.path();
                let to = dir.join(from.file_name().unwrap_or_default());
                if to.is_dir() {
                    return Err(FileError::new(&to, "is a folder; expected a file name"));
                }
                moves.push((from, to));
            }
        }
        let is_md = |p: &Path| p.extension().is_some_and(|e| e == "md");
        moves.sort_by_key(|(_, to)| (is_md(to), to.clone()));
        for (from, to) in &moves {
            std::fs::rename(from, to).map_err(|e| FileError::new(to, e))?;
        }
        for stage in std::mem::take(&mut self.staging).values() {
            let _ = std::fs::remove_dir_all(stage);
        }
        Ok(())
    }
}

impl Drop for Outputs {
    fn drop(&mut self) {
        for stage in self.staging.values().chain(&self.through_dir) {
            let _ = std::fs::remove_dir_all(stage);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn temp_dir(name: &str) -> PathBuf {
        let d =
            std::env::temp_dir().join(format!("deploywatch-files-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    #[test]
    fn nothing_appears_before_the_commit_and_everything_after() {
        let d = temp_dir("commit");
        let mut o = Outputs::new();
        o.write(&d.join("a.json"), "new").unwrap();
        std::fs::write(
            o.path(&d.join("r.md")).unwrap().with_file_name("p.png"),
            "png",
        )
        .unwrap();
        o.write(&d.join("r.md"), "report").unwrap();
        assert!(!d.join("a.json").exists() && !d.join("p.png").exists());
        o.commit().unwrap();
        assert_eq!(std::fs::read_to_string(d.join("a.json")).unwrap(), "new");
        assert_eq!(std::fs::read_to_string(d.join("p.png")).unwrap(), "png");
        assert_eq!(std::fs::read_to_string(d.join("r.md")).unwrap(), "report");
        let left: Vec<_> = std::fs::read_dir(&d).unwrap().collect();
        assert_eq!(left.len(), 3, "the staging folder is removed");
    }

    #[test]
    fn a_dropped_or_failed_set_leaves_the_old_files_untouched() {
        let d = temp_dir("drop");
        std::fs::write(d.join("a.json"), "old").unwrap();
        let mut o = Outputs::new();
        o.write(&d.join("a.json"), "new").unwrap();
        drop(o);
        assert_eq!(std::fs::read_to_string(d.join("a.json")).unwrap(), "old");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 1);

        std::fs::create_dir(d.join("b.png")).unwrap();
        let mut o = Outputs::new();
        o.write(&d.join("a.json"), "new").unwrap();
        o.write(&d.join("b.png"), "png").unwrap();
        let e = o.commit().unwrap_err();
        assert!(e.to_string().contains("b.png"), "{e}");
        assert_eq!(std::fs::read_to_string(d.join("a.json")).unwrap(), "old");
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 2);
    }

    #[test]
    fn a_link_is_written_through_to_its_file_and_stays_a_link() {
        let d = temp_dir("link");
        std::fs::write(d.join("target.csv"), "old").unwrap();
        std::os::unix::fs::symlink("target.csv", d.join("link.csv")).unwrap();
        let mut o = Outputs::new();
        o.write(&d.join("link.csv"), "new").unwrap();
        o.commit().unwrap();
        let link = std::fs::symlink_metadata(d.join("link.csv")).unwrap();
        assert!(link.file_type().is_symlink(), "the link stays a link");
        assert_eq!(
            std::fs::read_to_string(d.join("target.csv")).unwrap(),
            "new"
        );
        assert_eq!(std::fs::read_dir(&d).unwrap().count(), 2);
    }

    #[test]
    fn a_pipe_is_written_into_never_replaced() {
        let d = temp_dir("fifo");
        let fifo = d.join("out.csv");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            eprintln!("skipped: no mkfifo on this machine");
            return;
        }
        let reader = {
            let fifo = fifo.clone();
            std::thread::spawn(move || std::fs::read_to_string(fifo).unwrap())
        };
        let mut o = Outputs::new();
        o.write(&fifo, "through the pipe").unwrap();
        o.commit().unwrap();
        assert_eq!(reader.join().unwrap(), "through the pipe");
        let meta = std::fs::symlink_metadata(&fifo).unwrap();
        assert!(!meta.is_file(), "the pipe was replaced by a file");
        assert_eq!(
            std::fs::read_dir(&d).unwrap().count(),
            1,
            "nothing staged beside it"
        );
    }

    #[test]
    fn an_input_is_known_by_any_of_its_paths() {
        let d = temp_dir("input");
        std::fs::write(d.join("wing.toml"), "mechanism").unwrap();
        std::os::unix::fs::symlink("wing.toml", d.join("link.toml")).unwrap();
        let input = d.join("wing.toml");
        assert!(is_input(&d.join(".").join("wing.toml"), &[&input]));
        assert!(is_input(&d.join("link.toml"), &[&input]));
        assert!(!is_input(&d.join("run.csv"), &[&input]));
        assert!(!is_input(&input, &[]));
    }
}
