//! Writing result files: models in the format their extension names, and
//! atomic writes, so an interrupted run never leaves a half-written file
//! where a good one was.

use anyhow::{Context, Result};
use genform_core::Scene;
use genform_export::{ExportOptions, Format};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The export format `path`'s extension names.
pub fn output_format(path: &Path) -> Result<Format> {
    Format::from_path(path).ok_or_else(|| unknown_format(path, &[]))
}

/// The error for an output path whose format is unknown: it lists the
/// export formats and `extra` (extensions, with the dot, that the caller
/// writes itself).
pub fn unknown_format(path: &Path, extra: &[&str]) -> anyhow::Error {
    let known = Format::extensions().iter().map(|e| format!(".{e}"));
    let all: Vec<String> = known.chain(extra.iter().map(|e| e.to_string())).collect();
    anyhow::anyhow!("cannot tell the output format of {}; use one of the extensions: {}", path.display(), all.join(" "))
}

/// Exports `scene` to `path` in the format its extension names; returns
/// the files written (an OBJ brings its material library).
pub fn write_model(scene: &Scene, path: &Path) -> Result<Vec<PathBuf>> {
    write_model_with(scene, path, &ExportOptions::default())
}

/// [`write_model`] with explicit export options.
///
/// An OBJ gets its materials (the tag colours) in a `.mtl` file of the
/// same stem beside it, named relative in its `mtllib` line, and the
/// images of textured tags beside it too (`STEM.TEXTURE.png`, named by
/// the library's `map_Kd`); all go through [`write_atomic`], the images
/// and the library first, so the OBJ never names a file that is not
/// there.
pub fn write_model_with(scene: &Scene, path: &Path, options: &ExportOptions) -> Result<Vec<PathBuf>> {
    let format = output_format(path)?;
    let context = || format!("cannot export {}", path.display());
    if format == Format::Obj {
        let mtl = path.with_extension("mtl");
        let name = mtl.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let (obj, library) = genform_export::export_obj_with_mtl(scene, options, &name).with_context(context)?;
        // The images its materials name, beside it (each through the gate:
        // none may replace a file the command read).
        let mut images = Vec::new();
        for (file, png) in genform_export::obj_texture_files(scene, &name) {
            let image = path.with_file_name(file);
            write_atomic(&image, png)?;
            images.push(image);
        }
        write_atomic(&mtl, &library)?;
        write_atomic(path, &obj)?;
        let mut written = vec![path.to_path_buf(), mtl];
        written.extend(images);
        return Ok(written);
    }
    // Straight into the file: a large drawing is never held whole.
    let mut refused = None;
    let written = write_atomic_with(path, |w| {
        genform_export::export_to(scene, format, options, w).map_err(|e| match e {
            genform_export::ExportError::Io(text) => std::io::Error::other(text),
            e => {
                refused = Some(e);
                std::io::Error::other("refused")
            }
        })
    });
    if let Some(e) = refused {
        return Err(e).with_context(context);
    }
    written?;
    Ok(vec![path.to_path_buf()])
}

/// Writes `bytes` to `path` through a temporary file in the same folder
/// (`.NAME.PID-N.tmp`, unique within the process, so two threads saving
/// the same file never share one) and a rename: killed at any moment, the
/// command leaves at `path` either the old file, nothing, or the complete
/// new one — never a partial file (at worst a hidden temporary file stays
/// behind). Nothing is synced to the disk: a kill leaves the page cache
/// intact, and waiting for the disk cost most of a whole `sample` (7 ms of
/// work, 25 ms of wall time for a 1.8 MB string on a busy disk); against a
/// power cut, replacing a file by rename is what ext4 and others flush
/// first.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic_via(path, |f| f.write_all(bytes))
}

/// [`write_atomic`] for output made piece by piece: `fill` writes the
/// whole content to the temporary file, so a large output is never held in
/// memory at once. The file is written by a thread of its own, a few
/// hundred kilobytes at a time, so that the kernel's copy of one piece
/// overlaps the making of the next (a large drawing is tens of megabytes).
pub fn write_atomic_with(path: &Path, fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<()> {
    write_atomic_via(path, |f| write_behind(f, fill))
}

/// Bytes handed to the writing thread at a time.
const BEHIND_PIECE: usize = 1 << 18;

/// Runs `fill` on a writer whose full pieces a second thread writes to
/// `file` (through a few recycled buffers); the first error, of either
/// side, is returned.
fn write_behind(
    file: &mut std::fs::File,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    use std::sync::mpsc::{Receiver, SyncSender, sync_channel};
    /// A `Write` that sends full pieces to the writing thread.
    struct Behind {
        piece: Vec<u8>,
        full: SyncSender<Vec<u8>>,
        empty: Receiver<Vec<u8>>,
    }
    impl Behind {
        fn send(&mut self) -> std::io::Result<()> {
            let next = self.empty.recv().unwrap_or_default();
            let piece = std::mem::replace(&mut self.piece, next);
            // A closed channel means the thread stopped at an error, which
            // it returns.
            self.full.send(piece).map_err(|_| std::io::Error::other("the writing thread stopped"))
        }
    }
    impl Write for Behind {
        fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
            self.write_all(buf)?;
            Ok(buf.len())
        }
        fn write_all(&mut self, mut buf: &[u8]) -> std::io::Result<()> {
            while !buf.is_empty() {
                let n = buf.len().min(BEHIND_PIECE - self.piece.len());
                self.piece.extend_from_slice(&buf[..n]);
                buf = &buf[n..];
                if self.piece.len() == BEHIND_PIECE {
                    self.send()?;
                }
            }
            Ok(())
        }
        fn flush(&mut self) -> std::io::Result<()> {
            Ok(())
        }
    }
    std::thread::scope(|scope| {
        let (full, pieces) = sync_channel::<Vec<u8>>(2);
        let (give_back, empty) = sync_channel::<Vec<u8>>(3);
        for _ in 0..2 {
            give_back.send(Vec::with_capacity(BEHIND_PIECE)).expect("room for the spare pieces");
        }
        let writer = scope.spawn(move || -> std::io::Result<()> {
            for mut piece in pieces {
                file.write_all(&piece)?;
                piece.clear();
                // The filler may have finished and stopped taking pieces back.
                let _ = give_back.try_send(piece);
            }
            Ok(())
        });
        let mut w = Behind { piece: Vec::with_capacity(BEHIND_PIECE), full, empty };
        let filled = fill(&mut w).and_then(|()| {
            let rest = std::mem::take(&mut w.piece);
            w.full.send(rest).map_err(|_| std::io::Error::other("the writing thread stopped"))
        });
        drop(w);
        let written = writer.join().unwrap_or_else(|_| Err(std::io::Error::other("the writing thread panicked")));
        // The thread's own error explains a stop that the filler only saw.
        written.and(filled)
    })
}

/// Creates the temporary file beside `path`, has `fill` write it, and
/// renames it over `path` (see [`write_atomic`]).
fn write_atomic_via(path: &Path, fill: impl FnOnce(&mut std::fs::File) -> std::io::Result<()>) -> Result<()> {
    static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    crate::gate::check_write(path)?;
    crate::gate::create_dir(dir)?;
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let tmp = dir.join(format!(".{name}.{}-{n}.tmp", std::process::id()));
    let result = (|| -> std::io::Result<()> {
        fill(&mut std::fs::File::create(&tmp)?)?;
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result.with_context(|| format!("cannot write {}", path.display()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_writes_replace_whole_files_and_leave_no_temporaries() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sub/r.mca");
        write_atomic(&path, b"first").unwrap();
        write_atomic(&path, b"second, longer").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"second, longer");
        // Threads writing one file each finish with one complete version.
        std::thread::scope(|s| {
            for i in 0..8u8 {
                let path = &path;
                s.spawn(move || write_atomic(path, &vec![i; 100_000]).unwrap());
            }
        });
        let bytes = std::fs::read(&path).unwrap();
        assert!(bytes.len() == 100_000 && bytes.iter().all(|&b| b == bytes[0]), "a mixed file");
        let names: Vec<_> =
            std::fs::read_dir(dir.path().join("sub")).unwrap().map(|e| e.unwrap().file_name()).collect();
        assert_eq!(names, ["r.mca"]);
    }

    #[test]
    fn pieces_written_behind_arrive_whole_and_in_order() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.txt");
        // Writes of odd sizes straddling the pieces, over five pieces.
        let want: Vec<u8> = (0..5 * BEHIND_PIECE + 12_345).map(|i| (i * 7 % 251) as u8).collect();
        write_atomic_with(&path, |w| want.chunks(9_973).try_for_each(|c| w.write_all(c))).unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), want);
        // An error of the filler leaves the old file and no temporary.
        let failed = write_atomic_with(&path, |w| {
            w.write_all(&want[..2 * BEHIND_PIECE])?;
            Err(std::io::Error::other("the exporter gave up"))
        });
        assert!(format!("{:#}", failed.unwrap_err()).contains("the exporter gave up"));
        assert_eq!(std::fs::read(&path).unwrap(), want);
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    /// The writing thread's own error (a full disk) is the one reported,
    /// and the filler stops instead of waiting for ever.
    #[cfg(target_os = "linux")]
    #[test]
    fn a_failing_write_behind_reports_the_disks_error() {
        let mut full = std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
        let err = write_behind(&mut full, |w| {
            for _ in 0..64 {
                w.write_all(&[1; BEHIND_PIECE])?;
            }
            Ok(())
        })
        .unwrap_err();
        assert_eq!(err.kind(), std::io::ErrorKind::StorageFull, "{err}");
    }
}
