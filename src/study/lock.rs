//! The lock of a study folder while `study run` works on it: a file `.lock` in the folder
//! holding the process id of its holder, created exclusively (`O_EXCL`), removed when the
//! run ends. A second `study run` of the same folder is refused naming the holder's pid;
//! a lock whose holder no longer runs (killed: Linux `/proc/PID` is gone) is taken over.
//! Two runs on one folder would both start the same runs and move their folders into
//! place over each other.
use std::io::Write;
use std::path::{Path, PathBuf};

/// The lock file's name in the study folder.
pub const LOCK_FILE: &str = ".lock";

/// A held lock; dropping it removes the lock file.
#[derive(Debug)]
pub struct StudyLock {
    path: PathBuf,
    /// The lock file, removed by the interrupt handler (crate::output::interrupt).
    _registered: crate::output::interrupt::Registered<'static>,
}

/// Why the lock cannot be had.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LockError {
    /// Another process that still runs holds it.
    #[error(
        "study folder {} is in use by another `study run` (process {pid}, lock file {}); \
         wait for it to end, or stop it",
        dir.display(),
        lock.display()
    )]
    Held {
        /// The study folder.
        dir: PathBuf,
        /// The lock file.
        lock: PathBuf,
        /// The holder's process id.
        pid: u32,
    },
    /// The lock file cannot be created, read or removed.
    #[error("cannot lock study folder {}: {error}", dir.display())]
    Io {
        /// The study folder.
        dir: PathBuf,
        /// The error.
        error: std::io::Error,
    },
}

/// Whether process `pid` runs (Linux `/proc`; elsewhere every holder counts as running).
fn runs(pid: u32) -> bool {
    if !Path::new("/proc/self").exists() {
        return true;
    }
    Path::new(&format!("/proc/{pid}")).exists()
}

impl StudyLock {
    /// Takes the lock of study folder `dir` (created if missing) for this process.
    pub fn acquire(dir: &Path) -> Result<StudyLock, LockError> {
        let io = |error| LockError::Io {
            dir: dir.to_path_buf(),
            error,
        };
        std::fs::create_dir_all(dir).map_err(io)?;
        let path = dir.join(LOCK_FILE);
        // Twice at most: once more after removing a stale lock.
        for _ in 0..2 {
            match std::fs::OpenOptions::new()
                .write(true)
                .create_new(true)
                .open(&path)
            {
                Ok(mut f) => {
                    let registered = crate::output::interrupt::temporary(&path);
                    writeln!(f, "{}", std::process::id()).map_err(io)?;
                    return Ok(StudyLock {
                        path,
                        _registered: registered,
                    });
                }
                Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => {
                    let text = crate::model::limits::read_regular_file(&path).unwrap_or_default();
                    match text.trim().parse::<u32>() {
                        Ok(pid) if pid != std::process::id() && runs(pid) => {
                            return Err(LockError::Held {
                                dir: dir.to_path_buf(),
                                lock: path,
                                pid,
                            })
                        }
                        // A dead holder, or a file cut short by a kill: stale.
                        _ => match std::fs::remove_file(&path) {
                            Ok(()) => {}
                            Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                            Err(e) => return Err(io(e)),
                        },
                    }
                }
                Err(e) => return Err(io(e)),
            }
        }
        let pid = crate::model::limits::read_regular_file(&path)
            .ok()
            .and_then(|t| t.trim().parse().ok())
            .unwrap_or(0);
        Err(LockError::Held {
            dir: dir.to_path_buf(),
            lock: path,
            pid,
        })
    }
}

impl Drop for StudyLock {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.path);
    }
}
