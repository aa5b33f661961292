//! Files foveate writes and reads on a user's word. Writes are whole or not at all: every output
//! (images, CSV tables, plots, the pipeline cache, saved frames) is written to a temporary file
//! beside its destination and renamed over it, so a failed write — a full disk, a killed
//! process — leaves the earlier file byte for byte as it was; output paths are checked before
//! the work that fills them, so a long run does not end by finding it cannot write its result.
//! Reads (scenes, gaze traces, the pipeline cache) take regular files of bounded size only.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// A file that could not be written (or will not be writable), naming it and why.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {}: {why}", path.display())]
pub struct FileError {
    /// The file.
    pub path: PathBuf,
    /// What went wrong.
    pub why: String,
}

impl FileError {
    fn new(path: &Path, why: impl ToString) -> Self {
        FileError {
            path: path.to_path_buf(),
            why: why.to_string(),
        }
    }
}

/// The folder a file lands in (`.` for a bare file name).
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    }
}

/// Where a write of `path` lands: a symbolic link's target (the link stays a link), and only
/// where there is nothing yet or a regular file — never over a device, pipe, socket or folder
/// (renaming over `/dev/zero` would replace the device node).
fn destination(path: &Path) -> Result<PathBuf, FileError> {
    let target = match std::fs::symlink_metadata(path) {
        Ok(meta) if meta.file_type().is_symlink() => {
            std::fs::canonicalize(path).map_err(|e| FileError::new(path, e))?
        }
        _ => path.to_path_buf(),
    };
    match std::fs::metadata(&target) {
        Ok(meta) if meta.is_dir() => Err(FileError::new(path, "it is a folder")),
        Ok(meta) if !meta.is_file() => Err(FileError::new(
            path,
            "it is not a regular file (a device, pipe or socket): foveate replaces only files",
        )),
        _ => Ok(target),
    }
}

/// Checks, before any work, that `path` can be written: it names a file (not a folder, a
/// device or a pipe), its folder exists, and a file can be created there (which `/proc`, a
/// read-only mount or a folder without write permission refuse). Nothing is left behind.
pub fn check_writable(path: &Path) -> Result<(), FileError> {
    let path = &destination(path)?;
    if path.file_name().is_none() {
        return Err(FileError::new(path, "it names no file"));
    }
    let folder = folder_of(path);
    if !folder.is_dir() {
        let why = if folder.exists() {
            format!("{} is not a folder", folder.display())
        } else {
            format!("its folder {} does not exist", folder.display())
        };
        return Err(FileError::new(path, why));
    }
    let probe = temporary_beside(path);
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .map_err(|e| FileError::new(path, e))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// The temporary file a write of `path` goes through: hidden, beside it (a rename within one
/// folder is atomic), named by process so parallel runs never share one.
fn temporary_beside(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map_or_else(|| "output".into(), |n| n.to_string_lossy().into_owned());
    folder_of(path).join(format!(".{name}.{}.tmp", std::process::id()))
}

/// Writes `bytes` to `path` atomically: into a temporary file beside it, flushed to disk, then
/// renamed over `path`. On failure the temporary file is removed and `path` is untouched.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), FileError> {
    write_atomic_with(path, |file| file.write_all(bytes))
}

/// As [`write_atomic`], the contents written by `fill` (which may fail part-way: the earlier
/// file then stays).
pub fn write_atomic_with(
    path: &Path,
    fill: impl FnOnce(&mut std::fs::File) -> std::io::Result<()>,
) -> Result<(), FileError> {
    let shown = path;
    let path = &destination(path)?;
    let temporary = temporary_beside(path);
    let written = (|| {
        let mut file = std::fs::OpenOptions::new()
            .write(true)
            .create_new(true)
            .open(&temporary)?;
        fill(&mut file)?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&temporary, path)
    })();
    written.map_err(|e| {
        let _ = std::fs::remove_file(&temporary);
        FileError::new(shown, e)
    })
}

/// A regular file's bytes, at most `limit` of them (`limit_is` says what sets it, for the
/// error: "the scene declares for it"). Anything else is refused: a device (`/dev/zero`
/// would be read until memory runs out), a folder, or a named pipe, which is looked at before
/// it is opened (opening one waits for a writer, for ever). The size is checked before a byte
/// is read, and the read stops one byte past the limit (a file that grows meanwhile is caught).
pub fn read_bounded(path: &Path, limit: u64, limit_is: &str) -> Result<Vec<u8>, String> {
    let shown = path.display();
    let regular = |meta: std::io::Result<std::fs::Metadata>| {
        let meta = meta.map_err(|e| format!("cannot read {shown}: {e}"))?;
        if !meta.is_file() {
            return Err(format!(
                "{shown} is not a regular file (a device, pipe or folder)"
            ));
        }
        Ok(meta)
    };
    let within = |bytes: u64| {
        if bytes > limit {
            return Err(format!(
                "{shown} holds {bytes} bytes, more than the {limit} {limit_is}"
            ));
        }
        Ok(())
    };
    regular(std::fs::metadata(path))?;
    let file = std::fs::File::open(path).map_err(|e| format!("cannot read {shown}: {e}"))?;
    let meta = regular(file.metadata())?;
    within(meta.len())?;
    let mut bytes = Vec::with_capacity(meta.len() as usize);
    file.take(limit.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read {shown}: {e}"))?;
    within(bytes.len() as u64)?;
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("foveate-files-{name}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    fn entries(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    /// A write that fails half-way (the injected writer errs after writing part of the new
    /// contents) keeps the earlier file byte for byte and leaves no temporary file. Negative
    /// control: writing in place (`std::fs::write` semantics) would leave the half-written file.
    #[test]
    fn a_write_failing_part_way_keeps_the_earlier_file() {
        let dir = scratch("partial");
        let path = dir.join("frame.png");
        write_atomic(&path, b"the earlier, good file").unwrap();
        let failed = write_atomic_with(&path, |f| {
            f.write_all(b"half of the new")?;
            Err(std::io::Error::other("disk full (injected)"))
        });
        let err = failed.unwrap_err().to_string();
        assert!(
            err.contains("frame.png") && err.contains("disk full"),
            "{err}"
        );
        assert_eq!(std::fs::read(&path).unwrap(), b"the earlier, good file");
        assert_eq!(entries(&dir), ["frame.png"]);
        // The negative control: the same failure written in place truncates the good file.
        let mut in_place = std::fs::File::create(&path).unwrap();
        in_place.write_all(b"half of the new").unwrap();
        assert_ne!(std::fs::read(&path).unwrap(), b"the earlier, good file");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A symbolic link is written through: its target gets the file, the link stays a link.
    #[test]
    fn a_link_is_written_through() {
        let dir = scratch("link");
        std::fs::write(dir.join("target.png"), b"old").unwrap();
        std::os::unix::fs::symlink(dir.join("target.png"), dir.join("link.png")).unwrap();
        write_atomic(&dir.join("link.png"), b"new").unwrap();
        assert_eq!(std::fs::read(dir.join("target.png")).unwrap(), b"new");
        let link = std::fs::symlink_metadata(dir.join("link.png")).unwrap();
        assert!(link.file_type().is_symlink());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn a_successful_write_replaces_the_file_and_leaves_nothing_else() {
        let dir = scratch("replace");
        let path = dir.join("table.csv");
        write_atomic(&path, b"old").unwrap();
        write_atomic(&path, b"new").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"new");
        assert_eq!(entries(&dir), ["table.csv"]);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Paths that cannot be written are refused before any work, naming why, and the check
    /// leaves nothing behind; a folder as the destination of a write leaves no temporary file.
    #[test]
    fn unwritable_paths_are_refused_up_front() {
        let dir = scratch("unwritable");
        let file = dir.join("a-file");
        std::fs::write(&file, b"x").unwrap();
        for (path, why) in [
            (dir.clone(), "it is a folder"),
            (file.join("x.png"), "is not a folder"),
            (dir.join("missing").join("x.png"), "does not exist"),
            (
                PathBuf::from("/proc/foveate-x.png"),
                "cannot write /proc/foveate-x.png",
            ),
        ] {
            let err = check_writable(&path).unwrap_err().to_string();
            assert!(err.contains(why), "{}: {err}", path.display());
        }
        check_writable(&dir.join("fine.png")).unwrap();
        let err = write_atomic(&dir, b"x").unwrap_err().to_string();
        assert!(err.contains("it is a folder"), "{err}");
        assert_eq!(entries(&dir), ["a-file"]);
        // Only regular files are replaced: a pipe here stands for any special file (renaming
        // over /dev/zero would swap the device node for a file; the test leaves real devices be).
        let pipe = dir.join("pipe.png");
        let made = std::process::Command::new("mkfifo").arg(&pipe).status();
        assert!(made.unwrap().success());
        let err = write_atomic(&pipe, b"x").unwrap_err().to_string();
        assert!(err.contains("not a regular file"), "{err}");
        assert!(check_writable(&pipe).is_err());
        use std::os::unix::fs::FileTypeExt;
        assert!(
            std::fs::metadata(&pipe).unwrap().file_type().is_fifo(),
            "still a pipe"
        );
        std::fs::remove_file(&pipe).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
