//! The folders the server may touch, and the only way a path a client
//! names becomes a file: [`Roots::resolve`] and [`resolve_in`].
//!
//! A client path is a *root path*, `ROOT/relative/path` with `ROOT` one of
//! `examples`, `scene` (the folder of the file given on the command line)
//! or `runs` (`--out`). It must be relative, `/`-separated, without `.`,
//! `..`, empty or backslash components; the file it names is canonicalized
//! (symbolic links followed) and must still lie inside its root's
//! canonical folder. Nothing else is ever read, served or written.

use std::path::{Component, Path, PathBuf};

use super::api::ApiError;

/// One named folder.
#[derive(Clone, Debug)]
pub struct Root {
    /// The first component of root paths into it.
    pub name: &'static str,
    /// Its canonical path.
    pub dir: PathBuf,
}

/// Every folder the server may touch.
#[derive(Clone, Debug, Default)]
pub struct Roots {
    roots: Vec<Root>,
}

impl Roots {
    /// Adds folder `dir` as root `name` (canonicalized; a folder that does
    /// not exist is skipped, except `runs`, which is created).
    pub fn add(&mut self, name: &'static str, dir: &Path) -> std::io::Result<()> {
        if name == "runs" {
            std::fs::create_dir_all(dir)?;
        }
        if dir.is_dir() {
            self.roots.push(Root { name, dir: dir.canonicalize()? });
        }
        Ok(())
    }

    /// The root called `name`.
    pub fn get(&self, name: &str) -> Option<&Root> {
        self.roots.iter().find(|r| r.name == name)
    }

    /// The existing file or folder a root path names.
    pub fn resolve(&self, path: &str) -> Result<PathBuf, ApiError> {
        let parts = components(path)?;
        let (first, rest) = parts.split_first().ok_or_else(|| ApiError::bad_request("empty path"))?;
        let root = self.get(first).ok_or_else(|| {
            let names: Vec<&str> = self.roots.iter().map(|r| r.name).collect();
            ApiError::bad_request(format!("`{path}`: paths start with one of the roots {}", names.join(", ")))
        })?;
        resolve_parts(&root.dir, rest, path)
    }

    /// Every root, in the order they were added.
    pub fn list(&self) -> &[Root] {
        &self.roots
    }

    /// `file` (canonical) as a root path (`examples/…`), if it lies in a
    /// root; in the innermost one when roots nest (`--out` inside the
    /// scene's folder).
    pub fn display(&self, file: &Path) -> Option<String> {
        let r = self.roots.iter().filter(|r| file.starts_with(&r.dir)).max_by_key(|r| r.dir.components().count())?;
        let rel = file.strip_prefix(&r.dir).ok()?;
        let parts: Vec<String> = rel.components().map(|c| c.as_os_str().to_string_lossy().into_owned()).collect();
        Some(if parts.is_empty() { r.name.to_string() } else { format!("{}/{}", r.name, parts.join("/")) })
    }
}

/// The existing file `rel` (a `/`-separated relative path) inside folder
/// `dir` (canonical), e.g. a file of a run folder.
pub fn resolve_in(dir: &Path, rel: &str) -> Result<PathBuf, ApiError> {
    let parts = components(rel)?;
    resolve_parts(dir, &parts, rel)
}

fn resolve_parts(dir: &Path, parts: &[&str], shown: &str) -> Result<PathBuf, ApiError> {
    let mut path = dir.to_path_buf();
    path.extend(parts);
    let real = path.canonicalize().map_err(|_| ApiError::not_found(format!("`{shown}` does not exist")))?;
    if !real.starts_with(dir) {
        return Err(ApiError::forbidden(format!("`{shown}` leads outside the folders the studio serves")));
    }
    Ok(real)
}

/// The components of a client path, refused when it is absolute or has
/// `.`, `..`, empty, backslash or NUL components.
fn components(path: &str) -> Result<Vec<&str>, ApiError> {
    let refuse = |why: &str| Err(ApiError::forbidden(format!("`{path}`: {why}")));
    if path.starts_with('/') || Path::new(path).is_absolute() {
        return refuse("absolute paths are not served");
    }
    if path.contains('\\') || path.contains('\0') || path.contains(':') {
        return refuse("paths are `/`-separated names without `\\`, `:` or NUL");
    }
    let parts: Vec<&str> = path.split('/').collect();
    for p in &parts {
        if p.is_empty() || *p == "." || *p == ".." {
            return refuse("paths may not have empty, `.` or `..` parts");
        }
        if Path::new(p).components().any(|c| !matches!(c, Component::Normal(_))) {
            return refuse("not a plain name");
        }
    }
    Ok(parts)
}

/// Files below `dir` (recursively, at most `depth` levels and `max`
/// files), sorted, whose canonical path stays inside `dir`; symbolic
/// links that lead out are left out.
pub fn walk(dir: &Path, depth: usize, max: usize) -> Vec<PathBuf> {
    let mut out = Vec::new();
    walk_into(dir, dir, depth, max, &mut out);
    out.sort();
    out
}

fn walk_into(root: &Path, dir: &Path, depth: usize, max: usize, out: &mut Vec<PathBuf>) {
    let Ok(entries) = std::fs::read_dir(dir) else { return };
    let mut entries: Vec<_> = entries.flatten().collect();
    entries.sort_by_key(|e| e.file_name());
    for e in entries {
        if out.len() >= max {
            return;
        }
        if e.file_name().to_string_lossy().starts_with('.') {
            continue;
        }
        let Ok(real) = e.path().canonicalize() else { continue };
        if !real.starts_with(root) {
            continue;
        }
        if real.is_dir() {
            if depth > 0 && real != dir {
                walk_into(root, &real, depth - 1, max, out);
            }
        } else if real.is_file() {
            out.push(real);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn roots(dir: &Path) -> Roots {
        std::fs::create_dir_all(dir.join("ex/shape")).unwrap();
        std::fs::write(dir.join("ex/shape/a.sg"), "x").unwrap();
        std::fs::write(dir.join("secret.txt"), "x").unwrap();
        let mut r = Roots::default();
        r.add("examples", &dir.join("ex")).unwrap();
        r.add("runs", &dir.join("out")).unwrap();
        r
    }

    #[test]
    fn root_paths_resolve_inside_their_root_only() {
        let dir = tempfile::tempdir().unwrap();
        let r = roots(dir.path());
        let a = r.resolve("examples/shape/a.sg").unwrap();
        assert!(a.ends_with("ex/shape/a.sg"));
        assert_eq!(r.display(&a).unwrap(), "examples/shape/a.sg");
        for bad in
            ["examples/../secret.txt", "/etc/passwd", "examples/./shape/a.sg", "examples//shape", "examples\\..\\x"]
        {
            assert_eq!(r.resolve(bad).unwrap_err().status.as_u16(), 403, "{bad}");
        }
        assert_eq!(r.resolve("examples/shape/none.sg").unwrap_err().status.as_u16(), 404);
        assert_eq!(r.resolve("elsewhere/a.sg").unwrap_err().status.as_u16(), 400);
        assert!(r.get("runs").is_some() && dir.path().join("out").is_dir(), "runs is created");
    }

    #[cfg(unix)]
    #[test]
    fn symbolic_links_out_of_a_root_are_refused_and_not_listed() {
        let dir = tempfile::tempdir().unwrap();
        let r = roots(dir.path());
        std::os::unix::fs::symlink(dir.path().join("secret.txt"), dir.path().join("ex/leak.txt")).unwrap();
        std::os::unix::fs::symlink(dir.path().join("ex/shape/a.sg"), dir.path().join("ex/inside.sg")).unwrap();
        assert_eq!(r.resolve("examples/leak.txt").unwrap_err().status.as_u16(), 403);
        assert!(r.resolve("examples/inside.sg").is_ok());
        let listed = walk(&r.get("examples").unwrap().dir, 4, 100);
        assert!(listed.iter().all(|p| !p.ends_with("secret.txt")), "{listed:?}");
    }
}
