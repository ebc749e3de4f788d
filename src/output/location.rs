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
//!   folder is replaced only if fem2rbd wrote it and it holds nothing else: it carries
//!   the marker file [`MARKER`] of the same [`FolderKind`] (written into every folder
//!   [`replace_dir`] builds), and every other entry is a name that kind owns (a run
//!   folder's tables, `plots/`, `vtk/`, …). A folder without the marker, with another
//!   kind's marker, or holding anything else (the user's scenario, model or record, say)
//!   is refused before any work, naming what it holds.
//! * [`check_holds_no_input`] and [`check_not_an_input`] refuse an output folder that
//!   contains an input of the command, and an output file that is an input (the same
//!   file, however it is named), before any work.
//! * Temporary names carry the process id. SIGINT and SIGTERM remove a process's
//!   temporaries and put back a folder moved aside ([`super::interrupt`]); a process killed
//!   mid-write otherwise (SIGKILL, power loss) leaves its `.NAME.tmp-PID` behind; the next write of the same target removes
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

/// The marker file fem2rbd writes into every folder it replaces as a whole
/// ([`replace_dir`]); its first line names the folder's [`FolderKind`].
pub const MARKER: &str = ".fem2rbd";

/// A kind of output folder that fem2rbd replaces as a whole: its name (the marker's first
/// line) and the entries it may hold besides the marker (file or folder names; a trailing
/// `*` matches a prefix). Entries that other commands add to such a folder (`plot`'s
/// `plots/`, `export vtk`'s `vtk/`) are among them, so that a rerun replaces them too.
#[derive(Debug, Clone, Copy)]
pub struct FolderKind {
    /// The kind's name, e.g. `"run"`.
    pub name: &'static str,
    /// What the folder may hold besides [`MARKER`].
    pub owns: &'static [&'static str],
}

impl FolderKind {
    /// The marker file's content.
    pub fn marker_text(&self) -> String {
        format!(
            "{}\nThis folder was written by fem2rbd ({} folder). The next write to it replaces it \
             as a whole: keep no files of your own here.\n",
            self.name, self.name
        )
    }

    fn owns(&self, entry: &str) -> bool {
        self.owns.iter().any(|o| match o.strip_suffix('*') {
            Some(prefix) => entry.starts_with(prefix),
            None => entry == *o,
        })
    }
}

/// Why the existing folder `dir` may not be replaced by a folder of `kind`, or `None`
/// when it may (module docs).
fn not_replaceable(dir: &Path, kind: &FolderKind) -> Result<Option<String>> {
    let mut names = Vec::new();
    for e in fs::read_dir(dir).map_err(OutputError::io("cannot list", dir))? {
        let e = e.map_err(OutputError::io("cannot list", dir))?;
        names.push(e.file_name().to_string_lossy().into_owned());
    }
    if names.is_empty() {
        return Ok(None);
    }
    names.sort();
    let marker = dir.join(MARKER);
    if !marker.is_file() {
        return Ok(Some(format!(
            "is not empty and fem2rbd did not write it (no {MARKER} marker; it holds {})",
            listing(&names)
        )));
    }
    let text = fs::read_to_string(&marker).unwrap_or_default();
    let found = text.lines().next().unwrap_or("").trim();
    if found != kind.name {
        return Ok(Some(format!(
            "is a fem2rbd {} folder, not a {} folder",
            if found.is_empty() { "(unknown)" } else { found },
            kind.name
        )));
    }
    let foreign: Vec<String> = names
        .into_iter()
        .filter(|n| n != MARKER && !kind.owns(n))
        .collect();
    if !foreign.is_empty() {
        return Ok(Some(format!(
            "holds {}, which fem2rbd did not write there",
            listing(&foreign)
        )));
    }
    Ok(None)
}

/// Up to five names, quoted, and how many more.
fn listing(names: &[String]) -> String {
    let shown: Vec<String> = names.iter().take(5).map(|n| format!("{n:?}")).collect();
    match names.len() {
        n if n > 5 => format!("{} and {} more", shown.join(", "), n - 5),
        _ => shown.join(", "),
    }
}

/// Refuses before any work when `dir` exists and may not be replaced by a folder of
/// `kind` (module docs).
pub fn check_replaceable(dir: &Path, kind: &FolderKind, what: &str) -> Result<()> {
    if dir.is_dir() {
        if let Some(why) = not_replaceable(dir, kind)? {
            bail!(
                "{what} {} {why}; the output folder is replaced as a whole, so give a new or \
                 empty folder",
                dir.display()
            );
        }
    }
    Ok(())
}

/// `p` made absolute and free of `.`/`..` and links where it exists; where it does not,
/// its nearest existing ancestor is resolved and the rest appended.
fn resolved(p: &Path) -> PathBuf {
    let abs = std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
    let mut tail = Vec::new();
    let mut cur = abs.as_path();
    loop {
        if let Ok(c) = fs::canonicalize(cur) {
            let mut out = c;
            for t in tail.iter().rev() {
                out.push(t);
            }
            return out;
        }
        match (cur.parent(), cur.file_name()) {
            (Some(parent), Some(name)) => {
                tail.push(name.to_os_string());
                cur = parent;
            }
            _ => return abs,
        }
    }
}

/// Whether `a` and `b` are the same existing file (the same device and inode: also through
/// a link or another name).
fn same_file(a: &Path, b: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let (Ok(x), Ok(y)) = (fs::metadata(a), fs::metadata(b)) {
            return x.dev() == y.dev() && x.ino() == y.ino();
        }
    }
    a.exists() && resolved(a) == resolved(b)
}

/// Refuses an output file that is one of the command's `inputs` (module docs).
pub fn check_not_an_input<P: AsRef<Path>>(out: &Path, inputs: &[P], what: &str) -> Result<()> {
    for input in inputs {
        let input = input.as_ref();
        if same_file(out, input) {
            bail!(
                "{what} {} is the input {}: writing it would destroy the input; give another \
                 file name",
                out.display(),
                input.display()
            );
        }
    }
    Ok(())
}

/// Refuses an output folder (replaced as a whole) that is or contains one of the
/// command's `inputs` (module docs).
pub fn check_holds_no_input<P: AsRef<Path>>(dir: &Path, inputs: &[P], what: &str) -> Result<()> {
    let d = resolved(dir);
    for input in inputs {
        let input = input.as_ref();
        if resolved(input).starts_with(&d) {
            bail!(
                "{what} {} holds the input {}: the output folder is replaced as a whole, so \
                 give a folder that holds none of the inputs",
                dir.display(),
                input.display()
            );
        }
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
    /// The staged folder, removed by the interrupt handler ([`super::interrupt`]).
    _registered: super::interrupt::Registered<'static>,
}

impl StagedDir {
    /// Starts building `target` (module docs): sweeps stale temporaries, refuses a
    /// folder that a folder of `kind` may not replace, creates `.NAME.tmp-PID` holding the
    /// marker of `kind`.
    pub fn new(target: &Path, kind: &FolderKind) -> Result<StagedDir> {
        check_output_dir(target, "output folder")?;
        check_replaceable(target, kind, "output folder")?;
        sweep_stale(target);
        let parent = parent_of(target);
        fs::create_dir_all(&parent).map_err(OutputError::io("cannot create", &parent))?;
        let stage = sibling(target, "tmp")?;
        if stage.exists() {
            fs::remove_dir_all(&stage).map_err(OutputError::io("cannot remove", &stage))?;
        }
        let registered = super::interrupt::temporary(&stage);
        fs::create_dir(&stage).map_err(OutputError::io("cannot create", &stage))?;
        let staged = StagedDir {
            target: target.to_path_buf(),
            stage,
            done: false,
            _registered: registered,
        };
        staged.write(MARKER, kind.marker_text().as_bytes())?;
        Ok(staged)
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
        if had_old && old.exists() {
            let _ = fs::remove_dir_all(&old);
        }
        // Until the old folder is gone, an interrupt puts it back or removes it
        // ([`super::interrupt`]); both renames run without an interrupt between them.
        let _aside = had_old.then(|| super::interrupt::moved_aside(&old, &self.target));
        super::interrupt::critical(|| {
            if had_old {
                fs::rename(&self.target, &old).map_err(|error| OutputError::Io {
                    action: "cannot move aside the old",
                    path: self.target.clone(),
                    error: std::io::Error::new(
                        error.kind(),
                        format!("to {}: {error}", old.display()),
                    ),
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
                    error: std::io::Error::new(
                        e.kind(),
                        format!("to {}: {e}", self.target.display()),
                    ),
                });
            }
            Ok(())
        })?;
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
pub fn replace_dir(dir: &Path, kind: &FolderKind, files: &[(&str, &[u8])]) -> Result<Vec<PathBuf>> {
    let staged = StagedDir::new(dir, kind)?;
    for (name, bytes) in files {
        staged.write(name, bytes)?;
    }
    staged.swap_in()?;
    Ok(files.iter().map(|(n, _)| dir.join(n)).collect())
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// The sorted names of the entries of `dir`.
    pub(crate) fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    }

    const RUN: FolderKind = FolderKind {
        name: "run",
        owns: &["a.csv", "summary.json", "plots"],
    };

    #[test]
    fn a_folder_is_replaced_as_a_whole() {
        let t = tempfile::tempdir().unwrap();
        let run = t.path().join("run");
        replace_dir(&run, &RUN, &[("a.csv", b"1"), ("summary.json", b"{}")]).unwrap();
        assert_eq!(names(&run), [MARKER, "a.csv", "summary.json"]);
        assert!(fs::read_to_string(run.join(MARKER))
            .unwrap()
            .starts_with("run\n"));
        // What another command added to it (plots/) is replaced too.
        fs::create_dir(run.join("plots")).unwrap();
        // A second, smaller run leaves nothing of the first.
        replace_dir(&run, &RUN, &[("summary.json", b"{\"x\":1}")]).unwrap();
        assert_eq!(names(&run), [MARKER, "summary.json"]);
        assert_eq!(fs::read(run.join("summary.json")).unwrap(), b"{\"x\":1}");
        assert_eq!(names(t.path()), ["run"]);
    }

    #[test]
    fn a_foreign_folder_is_refused_and_left_alone() {
        let t = tempfile::tempdir().unwrap();
        let dir = t.path().join("mine");
        fs::create_dir(&dir).unwrap();
        fs::write(dir.join("thesis.tex"), "x").unwrap();
        let e = replace_dir(&dir, &RUN, &[("summary.json", b"{}")]).unwrap_err();
        let e = e.to_string();
        assert!(
            e.contains("did not write") && e.contains("thesis.tex"),
            "{e}"
        );
        assert_eq!(names(&dir), ["thesis.tex"]);
        assert_eq!(names(t.path()), ["mine"]);
    }

    #[test]
    fn a_file_of_ones_own_among_a_run_s_files_is_never_deleted() {
        // The user's scenario beside an old run's summary.json: the summary alone does not
        // make it fem2rbd's folder.
        let t = tempfile::tempdir().unwrap();
        let dir = t.path().join("in");
        fs::create_dir(&dir).unwrap();
        fs::write(dir.join("summary.json"), "{}").unwrap();
        fs::write(dir.join("s.toml"), "x").unwrap();
        let e = replace_dir(&dir, &RUN, &[("summary.json", b"{}")])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no .fem2rbd marker") && e.contains("s.toml"),
            "{e}"
        );
        // A folder fem2rbd wrote, to which the user then added a file.
        let run = t.path().join("run");
        replace_dir(&run, &RUN, &[("a.csv", b"1")]).unwrap();
        fs::write(run.join("notes.txt"), "mine").unwrap();
        let e = replace_dir(&run, &RUN, &[("a.csv", b"2")])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("\"notes.txt\", which fem2rbd did not write"),
            "{e}"
        );
        assert_eq!(names(&run), [MARKER, "a.csv", "notes.txt"]);
        assert_eq!(fs::read(run.join("a.csv")).unwrap(), b"1");
        // Another kind's folder is not this kind's.
        let fe = FolderKind {
            name: "fe",
            owns: &["a.csv"],
        };
        let e = replace_dir(&t.path().join("in2"), &fe, &[("a.csv", b"1")]).map(|_| ());
        assert!(e.is_ok());
        let e = replace_dir(&t.path().join("in2"), &RUN, &[("a.csv", b"1")])
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("is a fem2rbd fe folder, not a run folder"),
            "{e}"
        );
    }

    #[test]
    fn outputs_that_are_inputs_are_refused() {
        let t = tempfile::tempdir().unwrap();
        let dir = t.path().join("in");
        fs::create_dir_all(dir.join("sub")).unwrap();
        let model = dir.join("sub").join("model.toml");
        fs::write(&model, "x").unwrap();
        // The folder, or one above it, holds the input.
        for out in [dir.clone(), t.path().to_path_buf(), dir.join("sub/../sub")] {
            let e = check_holds_no_input(&out, &[&model], "output folder")
                .unwrap_err()
                .to_string();
            assert!(e.contains("holds the input"), "{e}");
        }
        check_holds_no_input(&dir.join("out"), &[&model], "output folder").unwrap();
        check_holds_no_input(&t.path().join("in-out"), &[&model], "output folder").unwrap();
        // The same file under another name, or through a hard link.
        let e = check_not_an_input(&dir.join("./sub/model.toml"), &[&model], "--output")
            .unwrap_err()
            .to_string();
        assert!(e.contains("is the input"), "{e}");
        let link = t.path().join("link.toml");
        fs::hard_link(&model, &link).unwrap();
        assert!(check_not_an_input(&link, &[&model], "--output").is_err());
        check_not_an_input(&dir.join("model.toml"), &[&model], "--output").unwrap();
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
