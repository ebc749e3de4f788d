//! What an interrupted process leaves behind: nothing of its own.
//!
//! Every writer that builds an output beside its target ([`super::AtomicFile`]'s
//! `.NAME.tmp-PID`, a staged folder's `.NAME.tmp-PID` and the `.NAME.old-PID` it moves the
//! old folder to, a study's `runs/.tmp-ID-PID`, the study lock) registers it here while it
//! exists. When SIGINT or SIGTERM arrives, the binary's handler (`fem2rbd`'s `main`) calls
//! [`clean_up`]: every registered temporary is removed, a folder moved aside for a swap is
//! put back where its new content has not yet taken its place (or removed where it has), and
//! the process exits with 128 + the signal's number. An output is therefore always either
//! its old content or its new one, with no temporary beside it.
//!
//! The renames that publish an output run inside [`critical`], which holds the same lock
//! as [`clean_up`]: the handler never sees a swap half done. [`clean_up`] keeps the lock
//! until the process exits, so nothing is published after it has cleaned up.
//!
//! A library user that installs no handler pays one mutex per output file.
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};

/// Something on disk that belongs to a write in progress.
#[derive(Debug, Clone)]
enum Pending {
    /// A temporary file or folder: removed.
    Temporary(PathBuf),
    /// `old` holds the previous content of `target`, moved aside for a swap: put back if
    /// `target` is missing, removed otherwise.
    MovedAside { old: PathBuf, target: PathBuf },
}

/// The writes in progress of one process (one global [`REGISTRY`]; tests make their own).
#[derive(Default)]
pub(crate) struct Registry {
    entries: Mutex<Entries>,
}

#[derive(Default)]
pub(crate) struct Entries {
    next: u64,
    open: Vec<(u64, Pending)>,
}

/// The process's writes in progress.
static REGISTRY: Registry = Registry {
    entries: Mutex::new(Entries {
        next: 0,
        open: Vec::new(),
    }),
};

/// A registration; dropping it (the write committed or abandoned) forgets the entry.
#[must_use = "the entry is forgotten when this is dropped"]
pub struct Registered<'a> {
    registry: &'a Registry,
    id: u64,
}

impl std::fmt::Debug for Registered<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_tuple("Registered").field(&self.id).finish()
    }
}

impl Drop for Registered<'_> {
    fn drop(&mut self) {
        self.registry.lock().open.retain(|(id, _)| *id != self.id);
    }
}

impl Registry {
    fn lock(&self) -> MutexGuard<'_, Entries> {
        // A panic while holding the lock leaves the list itself valid.
        self.entries.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn add(&self, p: Pending) -> Registered<'_> {
        let mut e = self.lock();
        e.next += 1;
        let id = e.next;
        e.open.push((id, p));
        Registered { registry: self, id }
    }

    /// Registers a temporary file or folder.
    pub(crate) fn temporary(&self, path: &Path) -> Registered<'_> {
        self.add(Pending::Temporary(path.to_path_buf()))
    }

    /// Registers `old`, the previous content of `target` moved aside for a swap.
    pub(crate) fn moved_aside(&self, old: &Path, target: &Path) -> Registered<'_> {
        self.add(Pending::MovedAside {
            old: old.to_path_buf(),
            target: target.to_path_buf(),
        })
    }

    /// Runs `f` (a rename that publishes an output) so that no clean-up interleaves with it.
    pub(crate) fn critical<T>(&self, f: impl FnOnce() -> T) -> T {
        let _guard = self.lock();
        f()
    }

    /// Removes every registered temporary (newest first) and puts back or removes every
    /// folder moved aside (module docs); returns the paths removed or restored and the
    /// lock, which the caller holds until the process exits.
    pub(crate) fn clean_up(&self) -> (Vec<PathBuf>, MutexGuard<'_, Entries>) {
        let mut guard = self.lock();
        let mut touched = Vec::new();
        for (_, p) in guard.open.drain(..).rev() {
            match p {
                Pending::Temporary(path) => {
                    if remove(&path) {
                        touched.push(path);
                    }
                }
                Pending::MovedAside { old, target } => {
                    if !old.exists() {
                        continue;
                    }
                    if target.exists() {
                        if remove(&old) {
                            touched.push(old);
                        }
                    } else if fs::rename(&old, &target).is_ok() {
                        touched.push(target);
                    }
                }
            }
        }
        (touched, guard)
    }
}

/// Removes a file or a folder with its content; whether there was one.
///
/// Another thread of the process may still be writing files into a staged folder (the
/// clean-up does not stop it): a file created while the folder is being emptied makes
/// the removal fail, so it is tried again until the folder is gone. The writer creates
/// its files by path in the folder and never the folder itself, so once the folder is
/// gone nothing brings it back.
fn remove(path: &Path) -> bool {
    match fs::symlink_metadata(path) {
        Ok(m) if m.is_dir() => {
            (0..1000).any(|_| fs::remove_dir_all(path).is_ok() || !path.exists())
        }
        Ok(_) => fs::remove_file(path).is_ok(),
        Err(_) => false,
    }
}

/// Registers a temporary file or folder of this process.
pub fn temporary(path: &Path) -> Registered<'static> {
    REGISTRY.temporary(path)
}

/// Registers the previous content of `target`, moved aside to `old` for a swap.
pub fn moved_aside(old: &Path, target: &Path) -> Registered<'static> {
    REGISTRY.moved_aside(old, target)
}

/// Runs a publishing rename so that the interrupt handler's clean-up never interleaves.
pub fn critical<T>(f: impl FnOnce() -> T) -> T {
    REGISTRY.critical(f)
}

/// The interrupt handler's clean-up of this process (module docs): the paths removed or
/// restored. Nothing is registered or published afterwards: the registry stays locked for
/// the rest of the process's life.
pub fn clean_up() -> Vec<PathBuf> {
    let (touched, guard) = REGISTRY.clean_up();
    std::mem::forget(guard);
    touched
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::location::tests::names;

    #[test]
    fn clean_up_removes_temporaries_and_keeps_what_was_committed() {
        let t = tempfile::tempdir().unwrap();
        let r = Registry::default();
        let file = t.path().join(".a.csv.tmp-1");
        let folder = t.path().join(".run.tmp-1");
        fs::write(&file, "half").unwrap();
        fs::create_dir(&folder).unwrap();
        fs::write(folder.join("bodies.csv"), "x").unwrap();
        let committed = t.path().join(".b.csv.tmp-1");
        fs::write(&committed, "whole").unwrap();
        let _f = r.temporary(&file);
        let _d = r.temporary(&folder);
        {
            let _c = r.temporary(&committed);
            fs::rename(&committed, t.path().join("b.csv")).unwrap();
        }
        let (touched, _guard) = r.clean_up();
        assert_eq!(touched, vec![folder, file]);
        assert_eq!(names(t.path()), ["b.csv"]);
    }

    #[test]
    fn a_folder_moved_aside_is_put_back_until_its_replacement_is_in_place() {
        let t = tempfile::tempdir().unwrap();
        let r = Registry::default();
        // Interrupted between the two renames of a swap: the old folder comes back.
        let target = t.path().join("run");
        let old = t.path().join(".run.old-1");
        let stage = t.path().join(".run.tmp-1");
        fs::create_dir(&old).unwrap();
        fs::write(old.join("summary.json"), "old").unwrap();
        fs::create_dir(&stage).unwrap();
        let _s = r.temporary(&stage);
        let _o = r.moved_aside(&old, &target);
        let (touched, guard) = r.clean_up();
        drop(guard);
        assert_eq!(touched, vec![target.clone(), stage]);
        assert_eq!(names(t.path()), ["run"]);
        assert_eq!(
            fs::read_to_string(target.join("summary.json")).unwrap(),
            "old"
        );
        // Interrupted after the new folder took its place: the old one goes.
        fs::rename(&target, &old).unwrap();
        fs::create_dir(&target).unwrap();
        fs::write(target.join("summary.json"), "new").unwrap();
        let _o = r.moved_aside(&old, &target);
        let (touched, _guard) = r.clean_up();
        assert_eq!(touched, vec![old]);
        assert_eq!(names(t.path()), ["run"]);
        assert_eq!(
            fs::read_to_string(target.join("summary.json")).unwrap(),
            "new"
        );
    }
}
