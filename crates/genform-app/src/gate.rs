//! The file gate: every file a command reads and every file it writes
//! passes here, so the rules hold for every path, not only for the ones a
//! check happens to list.
//!
//! - **Reads are recorded** in the command's [`Session`] by identity (device
//!   and inode after following links): the grammar, its meshes, context and
//!   footprints, worlds, environments and their meshes, targets, genomes,
//!   steering logs. An output that would replace any of them is refused,
//!   naming both — up front where a command knows its outputs
//!   ([`refuse_outputs`]) and, as the net under every write, in
//!   [`check_write`] (which [`crate::files::write_atomic`] calls).
//! - **A confined process** (the studio, [`confine`]) reads only below its
//!   read roots and writes only below its write root: a path outside them,
//!   absolute or through `..` or a symbolic link, is refused with one
//!   message whether or not the file exists, and no folder below the write
//!   root may be a symbolic link (a planted link is never followed).
//!
//! A session belongs to the thread that began it ([`session`]); work
//! handed to other threads carries it with [`within`].

use anyhow::{Context, Result, bail};
use std::cell::RefCell;
use std::path::{Component, Path, PathBuf};
use std::sync::{Arc, Mutex, RwLock};

/// A file's identity: device and inode after following links (on other
/// systems than Unix, the canonical path).
#[derive(Clone, Debug, PartialEq, Eq)]
struct FileId(#[cfg(unix)] (u64, u64), #[cfg(not(unix))] PathBuf);

/// The identity of the existing file at `path`, following links.
fn identity(path: &Path) -> Option<FileId> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        let m = std::fs::metadata(path).ok()?;
        Some(FileId((m.dev(), m.ino())))
    }
    #[cfg(not(unix))]
    {
        path.canonicalize().ok().map(FileId)
    }
}

/// Whether `a` and `b` are the same existing file (links followed, any
/// spelling).
pub(crate) fn same_file(a: &Path, b: &Path) -> bool {
    identity(a).is_some_and(|id| identity(b) == Some(id))
}

/// One file a command read.
#[derive(Clone, Debug)]
struct Input {
    path: PathBuf,
    what: String,
    id: FileId,
}

/// The files one command has read so far.
#[derive(Debug, Default)]
pub struct Session {
    inputs: Mutex<Vec<Input>>,
}

impl Session {
    fn record(&self, path: &Path, what: &str) {
        if let Some(id) = identity(path) {
            let mut inputs = self.inputs.lock().unwrap_or_else(|e| e.into_inner());
            if !inputs.iter().any(|i| i.id == id) {
                inputs.push(Input { path: path.to_path_buf(), what: what.to_string(), id });
            }
        }
    }

    /// The input that `path` (an existing file) is, if it is one.
    fn input_at(&self, path: &Path) -> Option<Input> {
        let id = identity(path)?;
        self.inputs.lock().unwrap_or_else(|e| e.into_inner()).iter().find(|i| i.id == id).cloned()
    }

    /// The paths of the files read so far, in order (for tests and notes).
    pub fn inputs(&self) -> Vec<PathBuf> {
        self.inputs.lock().unwrap_or_else(|e| e.into_inner()).iter().map(|i| i.path.clone()).collect()
    }
}

thread_local! {
    static CURRENT: RefCell<Option<Arc<Session>>> = const { RefCell::new(None) };
}

/// Keeps a session in force on this thread; the one before comes back
/// when it is dropped.
pub struct SessionGuard {
    _restore: Restore,
    session: Arc<Session>,
}

impl SessionGuard {
    /// The session in force.
    pub fn session(&self) -> &Arc<Session> {
        &self.session
    }
}

/// Puts the session that was in force back when dropped (`None`: a
/// joined session, nothing to put back).
struct Restore(Option<Option<Arc<Session>>>);

impl Drop for Restore {
    fn drop(&mut self) {
        if let Some(previous) = self.0.take() {
            CURRENT.with(|c| *c.borrow_mut() = previous);
        }
    }
}

/// The session of the command running on this thread: the one in force,
/// or a new one for as long as the guard lives. A door that runs one
/// command per process (the CLI) begins it first, so that everything the
/// command reads is in it; requests of genform-app begin or join one.
pub fn session() -> SessionGuard {
    CURRENT.with(|c| {
        let mut current = c.borrow_mut();
        match &*current {
            Some(s) => SessionGuard { _restore: Restore(None), session: s.clone() },
            None => {
                let s = Arc::new(Session::default());
                *current = Some(s.clone());
                SessionGuard { _restore: Restore(Some(None)), session: s }
            }
        }
    })
}

/// A new session in force on this thread for as long as the guard lives,
/// whatever was in force (a handle that keeps what its grammar read).
pub fn fresh_session() -> SessionGuard {
    let session = Arc::new(Session::default());
    let previous = CURRENT.with(|c| c.borrow_mut().replace(session.clone()));
    SessionGuard { _restore: Restore(Some(previous)), session }
}

/// The session in force on this thread, to hand to worker threads.
pub fn current() -> Option<Arc<Session>> {
    CURRENT.with(|c| c.borrow().clone())
}

/// Runs `f` with `session` in force on this thread (a worker's share of a
/// command).
pub fn within<T>(session: &Option<Arc<Session>>, f: impl FnOnce() -> T) -> T {
    let previous = CURRENT.with(|c| std::mem::replace(&mut *c.borrow_mut(), session.clone()));
    let _restore = Restore(Some(previous));
    f()
}

/// Where a confined process may read and write.
#[derive(Clone, Debug)]
struct Confinement {
    /// Canonical folders below which files are read.
    read: Vec<PathBuf>,
    /// The canonical folder below which files are written.
    write: PathBuf,
    /// How the roots are named in refusals, e.g. "examples/, scene/ and runs/".
    shown: String,
}

static CONFINED: RwLock<Option<Confinement>> = RwLock::new(None);

/// Confines this process: from now on files are read only below `read`
/// (and `write`) and written only below `write`; `shown` names the roots
/// in refusals (never the server's paths). The studio calls it at start.
pub fn confine(read: &[PathBuf], write: &Path, shown: &str) -> Result<()> {
    let canon = |p: &Path| p.canonicalize().with_context(|| format!("cannot open {}", p.display()));
    let write = canon(write)?;
    let mut roots: Vec<PathBuf> = read.iter().filter(|p| p.exists()).map(|p| canon(p)).collect::<Result<_>>()?;
    roots.push(write.clone());
    *CONFINED.write().unwrap_or_else(|e| e.into_inner()) =
        Some(Confinement { read: roots, write, shown: shown.into() });
    Ok(())
}

/// The confinement in force, if any.
fn confinement() -> Option<Confinement> {
    CONFINED.read().unwrap_or_else(|e| e.into_inner()).clone()
}

/// `path` made absolute and with `.`/`..` taken lexically, then its longest
/// existing prefix canonicalized (links followed), so a file that does not
/// exist yet resolves where it would be created.
fn resolved(path: &Path) -> PathBuf {
    let absolute =
        if path.is_absolute() { path.to_path_buf() } else { std::env::current_dir().unwrap_or_default().join(path) };
    let mut clean = PathBuf::new();
    for c in absolute.components() {
        match c {
            Component::ParentDir => {
                clean.pop();
            }
            Component::CurDir => {}
            c => clean.push(c),
        }
    }
    let mut rest = Vec::new();
    let mut head = clean.as_path();
    loop {
        if let Ok(real) = head.canonicalize() {
            let mut out = real;
            out.extend(rest.iter().rev());
            return out;
        }
        match (head.parent(), head.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_os_string());
                head = parent;
            }
            _ => return clean,
        }
    }
}

/// A path a confined process may not touch (outside its roots, or a
/// symbolic link below its write root): doors answer it as forbidden.
#[derive(Debug)]
pub struct Refused(pub String);

impl std::fmt::Display for Refused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Refused {}

/// The refusal of a path outside the confinement: the same words whether
/// or not the file exists, naming the path as it was given.
fn outside(path: &Path, c: &Confinement, verb: &str) -> anyhow::Error {
    let message = format!(
        "`{}` is outside the folders this studio may {verb} ({}): name a file inside them, relative to the scene \
         or grammar",
        path.display(),
        c.shown
    );
    LAST_REFUSAL.with(|r| *r.borrow_mut() = Some(message.clone()));
    anyhow::Error::new(Refused(message))
}

thread_local! {
    /// The last refusal on this thread, for readers whose errors become
    /// text (a grammar's assets become compile diagnostics).
    static LAST_REFUSAL: RefCell<Option<String>> = const { RefCell::new(None) };
}

/// Takes the last refusal made on this thread, if any: a compile that
/// failed over a refused asset is refused as a whole ([`Refused`]).
pub(crate) fn take_refusal() -> Option<String> {
    LAST_REFUSAL.with(|r| r.borrow_mut().take())
}

/// Admits a read of `path` (a `what`, e.g. "mesh"): refused outside a
/// confinement's roots; recorded in the session in force.
pub fn admit_read(path: &Path, what: &str) -> Result<()> {
    admit_path(path)?;
    if let Some(s) = current() {
        s.record(path, what);
    }
    Ok(())
}

/// Refuses a path a confined process may not read, without reading it or
/// recording it (a scene names its files long before a run reads them).
pub fn admit_path(path: &Path) -> Result<()> {
    match confinement() {
        Some(c) if !c.read.iter().any(|r| resolved(path).starts_with(r)) => Err(outside(path, &c, "read")),
        _ => Ok(()),
    }
}

/// `e` placed at `place` (a scene's `file:line:col`), still a [`Refused`]
/// when it was one.
pub(crate) fn placed(place: String, e: anyhow::Error) -> anyhow::Error {
    match e.downcast::<Refused>() {
        Ok(r) => anyhow::Error::new(Refused(format!("{place}: {}", r.0))),
        Err(e) => anyhow::anyhow!("{place}: {e:#}"),
    }
}

/// Reads the file `path`, a `what` the user named, through the gate.
pub fn read_bytes(path: &Path, what: &str) -> Result<Vec<u8>> {
    admit_read(path, what)?;
    std::fs::read(path).with_context(|| format!("cannot read {what} {}", path.display()))
}

/// Reads a mesh file (OBJ, STL, GLB by extension) through the gate.
pub fn read_mesh(path: &Path) -> Result<genform_core::Mesh> {
    admit_read(path, "mesh")?;
    Ok(genform_export::read_mesh_file(path)?)
}

/// Admits a write of `path`: refused when it would replace a file the
/// command read, and, in a confined process, outside the write root or
/// through a symbolic link below it.
pub fn check_write(path: &Path) -> Result<()> {
    check_confined_write(path)?;
    if let Some(s) = current()
        && let Some(input) = s.input_at(path)
    {
        bail!(
            "writing {} would replace the {} {}, an input of this command: choose another output",
            path.display(),
            input.what,
            input.path.display()
        );
    }
    Ok(())
}

/// In a confined process, refuses a write outside the write root or
/// through a symbolic link below it.
fn check_confined_write(path: &Path) -> Result<()> {
    if let Some(c) = confinement() {
        // Walk the path as written below the write root: no part of it
        // may be a symbolic link (a planted link would lead elsewhere).
        let absolute = if path.is_absolute() {
            path.to_path_buf()
        } else {
            std::env::current_dir().unwrap_or_default().join(path)
        };
        let mut at = PathBuf::new();
        for part in absolute.components() {
            let parent_below = at.canonicalize().is_ok_and(|r| r.starts_with(&c.write));
            at.push(part);
            if parent_below && std::fs::symlink_metadata(&at).is_ok_and(|m| m.file_type().is_symlink()) {
                return Err(anyhow::Error::new(Refused(format!(
                    "`{}` is a symbolic link in the studio's folder; the studio never writes through one (remove it)",
                    shown_below(&at, &c.write)
                ))));
            }
        }
        if !resolved(path).starts_with(&c.write) {
            return Err(outside(path, &c, "write"));
        }
    }
    Ok(())
}

/// `path` relative to the write root, for messages.
fn shown_below(path: &Path, root: &Path) -> String {
    let real = resolved(path.parent().unwrap_or(path)).join(path.file_name().unwrap_or_default());
    real.strip_prefix(root).map_or_else(|_| path.display().to_string(), |r| r.display().to_string())
}

/// Creates the folder `dir` (and its parents) through the gate.
pub fn create_dir(dir: &Path) -> Result<()> {
    // A folder that is an input (a world folder) may take new files.
    check_confined_write(dir)?;
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create folder {}", dir.display()))
}

/// Refuses a command whose outputs (flag or name, path) would replace one
/// of the files it read so far, before it runs: compared by identity, so
/// two spellings of one file, or a link to it, count.
pub fn refuse_outputs(outputs: &[(&str, &Path)]) -> Result<()> {
    let Some(s) = current() else { return Ok(()) };
    for &(flag, out) in outputs {
        if let Some(input) = s.input_at(out) {
            bail!(
                "{flag} {} is the {} {}, an input of this command; writing it would destroy it: choose another \
                 output",
                out.display(),
                input.what,
                input.path.display()
            );
        }
    }
    Ok(())
}

/// [`refuse_outputs`] for a command that writes a folder: refuses when a
/// file it read lies in `folder` under a name `writes` says the command
/// writes there (`flag` names the folder's option in the refusal).
pub fn refuse_folder(flag: &str, folder: &Path, writes: impl Fn(&str) -> bool) -> Result<()> {
    let Some(s) = current() else { return Ok(()) };
    let given = folder;
    let folder = resolved(folder);
    let inputs = s.inputs.lock().unwrap_or_else(|e| e.into_inner()).clone();
    for input in inputs {
        let real = resolved(&input.path);
        let name = real.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        if real.parent() == Some(folder.as_path()) && writes(&name) {
            bail!(
                "{flag} {} would replace its {name}, which is the {} {} this command reads: choose another folder",
                given.display(),
                input.what,
                input.path.display()
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_are_recorded_by_identity_and_outputs_over_them_refused() {
        let dir = tempfile::tempdir().unwrap();
        let mesh = dir.path().join("trunk.obj");
        std::fs::write(&mesh, "v 0 0 0\n").unwrap();
        let guard = session();
        read_bytes(&mesh, "mesh").unwrap();
        // Another spelling of the same file.
        let other = dir.path().join(".").join("trunk.obj");
        let e = refuse_outputs(&[("--out", &other)]).unwrap_err().to_string();
        assert!(e.contains("is the mesh") && e.contains("trunk.obj"), "{e}");
        let e = check_write(&other).unwrap_err().to_string();
        assert!(e.contains("would replace the mesh"), "{e}");
        check_write(&dir.path().join("new.obj")).unwrap();
        assert_eq!(guard.session().inputs(), vec![mesh.clone()]);
        drop(guard);
        // Without a session nothing is recorded.
        check_write(&mesh).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn a_link_to_an_input_is_that_input() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("target.obj");
        std::fs::write(&target, "v 0 0 0\n").unwrap();
        std::os::unix::fs::symlink(&target, dir.path().join("best.obj")).unwrap();
        let _guard = session();
        admit_read(&target, "target").unwrap();
        let e = refuse_outputs(&[("--out", &dir.path().join("best.obj"))]).unwrap_err().to_string();
        assert!(e.contains("is the target"), "{e}");
    }

    #[test]
    fn workers_share_the_session_they_are_handed() {
        let dir = tempfile::tempdir().unwrap();
        let file = dir.path().join("a.txt");
        std::fs::write(&file, "x").unwrap();
        let guard = session();
        let s = current();
        std::thread::scope(|scope| {
            scope.spawn(|| within(&s, || read_bytes(&file, "text").unwrap()));
        });
        assert_eq!(guard.session().inputs(), vec![file]);
    }

    #[test]
    fn paths_resolve_where_they_would_be_created() {
        let dir = tempfile::tempdir().unwrap();
        let real = dir.path().canonicalize().unwrap();
        assert_eq!(resolved(&dir.path().join("a/../b/c.txt")), real.join("b/c.txt"));
        assert_eq!(resolved(&dir.path().join("x/y")), real.join("x/y"));
    }
}
