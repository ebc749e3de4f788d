//! Atomic file output: write to `.<name>.tmp-<pid>` beside the target, then rename.
use super::error::{OutputError, Result};
use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// A file being written; it appears under its final name only when [`AtomicFile::commit`]
/// succeeds. Dropped without commit, the temporary file is removed.
pub struct AtomicFile {
    target: PathBuf,
    tmp: PathBuf,
    writer: Option<BufWriter<File>>,
    /// The temporary file, removed by the interrupt handler ([`super::interrupt`]).
    _registered: super::interrupt::Registered<'static>,
}

impl AtomicFile {
    /// Starts writing `target` (its parent folder must exist).
    pub fn create(target: impl AsRef<Path>) -> Result<Self> {
        let target = target.as_ref().to_path_buf();
        let name = target
            .file_name()
            .ok_or_else(|| {
                OutputError::Location(format!("output path {} has no file name", target.display()))
            })?
            .to_string_lossy()
            .into_owned();
        if target.is_dir() {
            return Err(OutputError::Location(format!(
                "output {} is a folder, not a file",
                target.display()
            )));
        }
        super::location::sweep_stale(&target);
        let tmp = target.with_file_name(format!(".{name}.tmp-{}", std::process::id()));
        let registered = super::interrupt::temporary(&tmp);
        let file =
            File::create(&tmp).map_err(OutputError::io("cannot create temporary file", &tmp))?;
        Ok(Self {
            target,
            tmp,
            writer: Some(BufWriter::new(file)),
            _registered: registered,
        })
    }

    /// Flushes, syncs and renames the temporary file onto the target. On any failure
    /// (a full disk, a target that is a folder) the temporary file is removed.
    pub fn commit(mut self) -> Result<()> {
        let writer = self.writer.take().expect("writer present until commit");
        let result = (|| {
            let file = writer
                .into_inner()
                .map_err(|e| e.into_error())
                .map_err(OutputError::io("cannot write", &self.tmp))?;
            file.sync_all()
                .map_err(OutputError::io("cannot sync", &self.tmp))?;
            drop(file);
            super::interrupt::critical(|| fs::rename(&self.tmp, &self.target)).map_err(|error| {
                OutputError::Io {
                    action: "cannot rename",
                    path: self.tmp.clone(),
                    error: std::io::Error::new(
                        error.kind(),
                        format!("to {}: {error}", self.target.display()),
                    ),
                }
            })
        })();
        if result.is_err() {
            let _ = fs::remove_file(&self.tmp);
        }
        result
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.writer
            .as_mut()
            .expect("writer present until commit")
            .write(buf)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.writer
            .as_mut()
            .expect("writer present until commit")
            .flush()
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.writer.take().is_some() {
            let _ = fs::remove_file(&self.tmp);
        }
    }
}

/// Writes `bytes` to `target` atomically.
pub fn write_atomic(target: impl AsRef<Path>, bytes: &[u8]) -> Result<()> {
    let target = target.as_ref();
    let mut f = AtomicFile::create(target)?;
    f.write_all(bytes)
        .map_err(OutputError::io("cannot write", target))?;
    f.commit()
}

/// Writes every `(target, bytes)` of `files` all or nothing: each is written to its
/// temporary file before the first is renamed into place, so a failure while writing (a
/// full disk, a target that is a folder) leaves none of them new and no temporary file.
/// Parent folders must exist.
pub fn write_all_atomic(files: &[(PathBuf, Vec<u8>)]) -> Result<()> {
    let mut pending = Vec::with_capacity(files.len());
    for (p, bytes) in files {
        let mut f = AtomicFile::create(p)?;
        f.write_all(bytes)
            .map_err(OutputError::io("cannot write", p))?;
        pending.push(f);
    }
    for f in pending {
        f.commit()?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_set_with_one_bad_target_writes_none_of_it() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a.csv");
        fs::write(&a, b"old").unwrap();
        let folder = dir.path().join("folder");
        fs::create_dir(&folder).unwrap();
        let files = vec![
            (a.clone(), b"new".to_vec()),
            (folder.join("no/b.csv"), b"x".to_vec()),
        ];
        assert!(write_all_atomic(&files).is_err());
        assert_eq!(fs::read(&a).unwrap(), b"old");
        let mut names: Vec<_> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        names.sort();
        assert_eq!(
            names,
            vec![std::ffi::OsString::from("a.csv"), "folder".into()]
        );
        write_all_atomic(&files[..1]).unwrap();
        assert_eq!(fs::read(&a).unwrap(), b"new");
    }

    #[test]
    fn committed_file_appears_and_uncommitted_leaves_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.csv");
        write_atomic(&p, b"x,y\n1,2\n").unwrap();
        assert_eq!(fs::read(&p).unwrap(), b"x,y\n1,2\n");
        {
            let mut f = AtomicFile::create(dir.path().join("b.csv")).unwrap();
            f.write_all(b"half").unwrap();
        }
        let names: Vec<_> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("a.csv")]);
    }

    #[test]
    fn a_failed_rename_leaves_no_temporary_file() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("t");
        let mut f = AtomicFile::create(&target).unwrap();
        f.write_all(b"x").unwrap();
        // The target becomes a non-empty folder between create and commit: rename fails.
        fs::create_dir(&target).unwrap();
        fs::write(target.join("inside"), "y").unwrap();
        assert!(f.commit().is_err());
        let names: Vec<_> = fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("t")]);
    }
}
