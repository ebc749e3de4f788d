//! Where outputs go: the output location is checked before any work, and an output
//! folder is replaced as a whole.
//!
//! * [`check_output_dir`] / [`check_output_file`] run before a command computes anything:
//!   the path must not be empty, a folder must not be a file (and a file not a folder),
//!   and the nearest existing folder must accept a new file (a probe file is created and
//!   removed), so a read-only location fails in milliseconds, not after the simulation.
//! * [`replace_dir`] writes an output folder (a run folder, `fe --out`, the frames of
//!   `export vtk`) **beside** the target as `.NAME.tmp-PID`, then swaps it in: the old
//!   folder is renamed to `.NAME.old-PID`, the new one to `NAME`, and the old one removed.
//!   A reader sees the old folder or the new one, never a mix; a failure at any point
//!   leaves the old folder as it was and nothing else. Everything in the old folder goes
//!   (also files another command put there, such as `plots/` or `vtk/`, which described
//!   the old run). So that this never removes a user's own files, an existing non-empty
//!   folder is replaced only if it holds one of the files its writer owns (a run folder's
//!   `summary.json`, `fe`'s `fe_summary.json`, `step_*.vtu` frames); otherwise the
//!   command refuses before any work.
//! * Temporary names carry the process id. A process killed mid-write (SIGKILL, power
//!   loss) leaves its `.NAME.tmp-PID` behind; the next write of the same target removes
//!   the temporaries of processes that no longer run ([`sweep_stale`], Linux `/proc`).
use super::error::{OutputError, Result};

macro_rules! bail {
    ($($t:tt)*) => {
        return Err(OutputError::Location(format!($($t)*)))
    };
}
use std::fs;
use std::path::{Path, PathBuf};

/// The folder that holds `p` (`.` for a bare name).
fn parent_of(p: &Path) -> PathBuf {
    match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// Creates and removes a probe file in the existing folder `dir`.
fn probe(dir: &Path, what: &str, target: &Path) -> Result<()> {
    let p = dir.join(format!(".fem2rbd-probe-{}", std::process::id()));
    match fs::OpenOptions::new().write(true).create_new(true).open(&p) {
        Ok(_) => {
            let _ = fs::remove_file(&p);
            Ok(())
        }
        Err(e) => Err(OutputError::Location(format!(
            "{what} {}: cannot write in {} ({e})",
            target.display(),
            dir.display()
        ))),
    }
}

/// The nearest existing ancestor of `p` (itself included); it must be a folder.
fn existing_ancestor(p: &Path, what: &str) -> Result<PathBuf> {
    let mut cur = p.to_path_buf();
    loop {
        if cur.exists() {
            if !cur.is_dir() {
                bail!(
                    "{what} {}: {} is a file, not a folder",
                    p.display(),
                    cur.display()
                );
            }
            return Ok(cur);
        }
        cur = parent_of(&cur);
    }
}

/// Checks an output folder before any work (module docs). `what` names it in errors
/// (`"output folder"`, `"--out"`).
pub fn check_output_dir(dir: &Path, what: &str) -> Result<()> {
    if dir.as_os_str().is_empty() {
        bail!("{what} is empty: give a folder name");
    }
    if dir.exists() && !dir.is_dir() {
        bail!("{what} {} exists and is not a folder", dir.display());
    }
    let base = existing_ancestor(dir, what)?;
    // The folder is built beside the target, so its parent must take new entries; an
    // existing target must take them too.
    probe(&base, what, dir)?;
    if dir.exists() {
        probe(&parent_of(dir), what, dir)?;
    }
    Ok(())
}

/// Checks an output file path before any work: not empty, not a folder, its folder
/// exists and accepts a new file.
pub fn check_output_file(path: &Path, what: &str) -> Result<()> {
    if path.as_os_str().is_empty() {
        bail!("{what} is empty: give a file name");
    }
    if path.is_dir() {
        bail!("{what} {} is a folder, not a file", path.display());
    }
    if path.file_name().is_none() {
        bail!("{what} {} has no file name", path.display());
    }
    let dir = parent_of(path);
    if !dir.is_dir() {
        bail!(
            "{what} {}: folder {} does not exist",
            path.display(),
            dir.display()
        );
    }
    probe(&dir, what, path)
}

/// Whether the existing folder `dir` may be replaced: empty, or holding one of `owned`
/// (file names; a trailing `*` matches a prefix).
fn replaceable(dir: &Path, owned: &[&str]) -> Result<bool> {
    let mut empty = true;
    for e in fs::read_dir(dir).map_err(OutputError::io("cannot list", dir))? {
        let name = e
            .map_err(OutputError::io("cannot list", dir))?
            .file_name()
            .to_string_lossy()
            .into_owned();
        empty = false;
        let hit = owned.iter().any(|o| match o.strip_suffix('*') {
            Some(prefix) => name.starts_with(prefix),
            None => name == *o,
        });
        if hit {
            return Ok(true);
        }
    }
    Ok(empty)
}

/// Refuses before any work when `dir` exists, is not empty and holds none of `owned`
/// (module docs).
pub fn check_replaceable(dir: &Path, owned: &[&str], what: &str) -> Result<()> {
    if dir.is_dir() && !replaceable(dir, owned)? {
        bail!(
            "{what} {} exists and holds files fem2rbd did not write (none of {}); \
             give a new or empty folder: the output folder is replaced as a whole",
            dir.display(),
            owned.join(", ")
        );
    }
    Ok(())
}

/// `.NAME.<kind>-PID` beside `target`.
fn sibling(target: &Path, kind: &str) -> Result<PathBuf> {
    let name = target
        .file_name()
        .ok_or_else(|| {
            OutputError::Location(format!("output path {} has no name", target.display()))
        })?
        .to_string_lossy()
        .into_owned();
    Ok(parent_of(target).join(format!(".{name}.{kind}-{}", std::process::id())))
}

/// Removes `.NAME.tmp-PID` and `.NAME.old-PID` beside `target` left by processes that no
/// longer run (Linux: no `/proc/PID`). Elsewhere it does nothing.
pub(crate) fn sweep_stale(target: &Path) {
    if !cfg!(target_os = "linux") || !Path::new("/proc/self").exists() {
        return;
    }
    let Some(name) = target.file_name().map(|n| n.to_string_lossy().into_owned()) else {
        return;
    };
    let Ok(entries) = fs::read_dir(parent_of(target)) else {
        return;
    };
    for e in entries.flatten() {
        let f = e.file_name().to_string_lossy().into_owned();
        let Some(rest) = f.strip_prefix(&format!(".{name}.")) else {
            continue;
        };
        let pid = rest
            .strip_prefix("tmp-")
            .or_else(|| rest.strip_prefix("old-"))
            .and_then(|p| p.parse::<u32>().ok());
        if let Some(pid) = pid {
            if pid != std::process::id() && !Path::new(&format!("/proc/{pid}")).exists() {
                let p = e.path();
                let _ = if p.is_dir() {
                    fs::remove_dir_all(&p)
                } else {
                    fs::remove_file(&p)
                };
            }
        }
    }
}

/// A folder being built beside its target; dropped without [`StagedDir::swap_in`], it is
/// removed.
pub(crate) struct StagedDir {
    target: PathBuf,
    stage: PathBuf,
    done: bool,
}

impl StagedDir {
    /// Starts building `target` (module docs): sweeps stale temporaries, refuses a
    /// non-empty folder holding none of `owned`, creates `.NAME.tmp-PID`.
    pub fn new(target: &Path, owned: &[&str]) -> Result<StagedDir> {
        check_output_dir(target, "output folder")?;
        check_replaceable(target, owned, "output folder")?;
        sweep_stale(target);
        let parent = parent_of(target);
        fs::create_dir_all(&parent).map_err(OutputError::io("cannot create", &parent))?;
        let stage = sibling(target, "tmp")?;
        if stage.exists() {
            fs::remove_dir_all(&stage).map_err(OutputError::io("cannot remove", &stage))?;
        }
        fs::create_dir(&stage).map_err(OutputError::io("cannot create", &stage))?;
        Ok(StagedDir {
            target: target.to_path_buf(),
            stage,
            done: false,
        })
    }

    /// Writes one file into the staged folder (synced, so the swap publishes whole files).
    pub fn write(&self, name: &str, bytes: &[u8]) -> Result<()> {
        use std::io::Write;
        let p = self.stage.join(name);
        let mut f = fs::File::create(&p).map_err(OutputError::io("cannot create", &p))?;
        f.write_all(bytes)
            .and_then(|_| f.sync_all())
            .map_err(OutputError::io("cannot write", &p))
    }

    /// Swaps the staged folder in for the target (module docs).
    pub fn swap_in(mut self) -> Result<()> {
        let old = sibling(&self.target, "old")?;
        let had_old = self.target.exists();
        if had_old {
            if old.exists() {
                let _ = fs::remove_dir_all(&old);
            }
            fs::rename(&self.target, &old).map_err(|error| OutputError::Io {
                action: "cannot move aside the old",
                path: self.target.clone(),
                error: std::io::Error::new(error.kind(), format!("to {}: {error}", old.display())),
            })?;
        }
        if let Err(e) = fs::rename(&self.stage, &self.target) {
            if had_old {
                // Put the old folder back: the target is as it was.
                let _ = fs::rename(&old, &self.target);
            }
            return Err(OutputError::Io {
                action: "cannot rename",
                path: self.stage.clone(),
                error: std::io::Error::new(e.kind(), format!("to {}: {e}", self.target.display())),
            });
        }
        self.done = true;
        if had_old {
            fs::remove_dir_all(&old)
                .map_err(OutputError::io("cannot remove the old folder", &old))?;
        }
        Ok(())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.done {
            let _ = fs::remove_dir_all(&self.stage);
        }
    }
}

/// Writes `files` (name, bytes) as the whole content of folder `dir`, replacing any
/// previous content at once (module docs). Returns the paths written.
pub fn replace_dir(dir: &Path, owned: &[&str], files: &[(&str, &[u8])]) -> Result<Vec<PathBuf>> {
    let staged = StagedDir::new(dir, owned)?;
    for (name, bytes) in files {
        staged.write(name, bytes)?;
    }
    staged.swap_in()?;
    Ok(files.iter().map(|(n, _)| dir.join(n)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    #[test]
    fn a_folder_is_replaced_as_a_whole() {
        let t = tempfile::tempdir().unwrap();
        let run = t.path().join("run");
        replace_dir(
            &run,
            &["summary.json"],
            &[("a.csv", b"1"), ("summary.json", b"{}")],
        )
        .unwrap();
        assert_eq!(names(&run), ["a.csv", "summary.json"]);
        // A second, smaller run leaves nothing of the first.
        replace_dir(&run, &["summary.json"], &[("summary.json", b"{\"x\":1}")]).unwrap();
        assert_eq!(names(&run), ["summary.json"]);
        assert_eq!(fs::read(run.join("summary.json")).unwrap(), b"{\"x\":1}");
        assert_eq!(names(t.path()), ["run"]);
    }

    #[test]
    fn a_foreign_folder_is_refused_and_left_alone() {
        let t = tempfile::tempdir().unwrap();
        let dir = t.path().join("mine");
        fs::create_dir(&dir).unwrap();
        fs::write(dir.join("thesis.tex"), "x").unwrap();
        let e = replace_dir(&dir, &["summary.json"], &[("summary.json", b"{}")]).unwrap_err();
        assert!(e.to_string().contains("did not write"), "{e}");
        assert_eq!(names(&dir), ["thesis.tex"]);
        assert_eq!(names(t.path()), ["mine"]);
    }

    #[test]
    fn bad_locations_are_named() {
        let t = tempfile::tempdir().unwrap();
        let f = t.path().join("file");
        fs::write(&f, "x").unwrap();
        let e = check_output_dir(Path::new(""), "output")
            .unwrap_err()
            .to_string();
        assert!(e.contains("empty"), "{e}");
        let e = check_output_dir(&f, "output").unwrap_err().to_string();
        assert!(e.contains("not a folder"), "{e}");
        let e = check_output_dir(&f.join("sub"), "output")
            .unwrap_err()
            .to_string();
        assert!(e.contains("is a file"), "{e}");
        let e = check_output_file(t.path(), "-o").unwrap_err().to_string();
        assert!(e.contains("is a folder"), "{e}");
        let e = check_output_file(&t.path().join("no/x.py"), "-o")
            .unwrap_err()
            .to_string();
        assert!(e.contains("does not exist"), "{e}");
        assert_eq!(names(t.path()), ["file"]);
    }

    #[test]
    fn stale_temporaries_of_dead_processes_are_swept() {
        let t = tempfile::tempdir().unwrap();
        let target = t.path().join("run");
        // PID 0x7fff_fff0 does not run; our own PID does.
        fs::create_dir(t.path().join(".run.tmp-2147483632")).unwrap();
        fs::write(t.path().join(".run.old-2147483632"), "x").unwrap();
        let mine = t.path().join(format!(".run.tmp-{}", std::process::id()));
        fs::write(&mine, "x").unwrap();
        sweep_stale(&target);
        assert_eq!(
            names(t.path()),
            [format!(".run.tmp-{}", std::process::id())]
        );
    }
}
