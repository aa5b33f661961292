//! Output paths checked before the work that fills them: a run of minutes or hours must not end
//! by finding that it cannot write its result. (The writes themselves are atomic:
//! `foveate::write_atomic`.)

use std::path::{Path, PathBuf};

use anyhow::Result;
use foveate::check_writable;
use foveate::metrics::RgbaImage;

/// Files given by path (`-` is standard output, always writable).
pub fn files(paths: &[Option<&Path>]) -> Result<()> {
    for path in paths.iter().flatten() {
        if *path != Path::new("-") {
            check_writable(path)?;
        }
    }
    Ok(())
}

/// An image: its extension names a format foveate writes, and it can be written.
pub fn image(path: &Path) -> Result<()> {
    Ok(RgbaImage::check_output(path)?)
}

/// A plot written as `<stem>.png` and `<stem>.svg` (appended: a stem may hold a dot).
pub fn plot(stem: &Path) -> Result<()> {
    for extension in ["png", "svg"] {
        check_writable(&plot_file(stem, extension))?;
    }
    Ok(())
}

/// The file `<stem>.<extension>` of a plot. Appended, never `Path::with_extension`: that
/// replaces whatever follows a stem's last dot (`frontier-0.6-still` would become
/// `frontier-0.png`, and every motion's plot the same file).
pub fn plot_file(stem: &Path, extension: &str) -> PathBuf {
    let mut name = stem.as_os_str().to_owned();
    name.push(".");
    name.push(extension);
    PathBuf::from(name)
}

/// A folder that receives files: made if missing, and a file can be written in it.
pub fn folder(dir: &Path) -> Result<()> {
    if dir.exists() && !dir.is_dir() {
        anyhow::bail!("cannot write into {}: it is not a folder", dir.display());
    }
    std::fs::create_dir_all(dir)
        .map_err(|e| anyhow::anyhow!("cannot make the folder {}: {e}", dir.display()))?;
    Ok(check_writable(&dir.join("foveate-output"))?)
}
