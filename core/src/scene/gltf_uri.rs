//! The files a glTF scene names, read only where the scene owns them: a URI resolves inside the
//! scene file's folder (no absolute paths, no `..` out of it, no symbolic link that leads out),
//! names a regular file (no device, pipe or folder), and is read no further than its limit (a
//! buffer's declared size, foveate's cap for an image) — so a buffer at `/dev/zero`, or a
//! sparse 4 GB file declared as 36 bytes, is an error, not a read until memory runs out.

use std::path::{Path, PathBuf};

use base64::Engine;

use crate::vocab::read_bounded;

/// The bytes a URI names: a base64 `data:` URI, or a file inside `base` (the scene's folder)
/// of at most `limit` bytes; `limit_is` says in errors what sets the limit.
pub(super) fn read_uri(
    uri: &str,
    base: Option<&Path>,
    limit: u64,
    limit_is: &str,
) -> Result<Vec<u8>, String> {
    if let Some(rest) = uri.strip_prefix("data:") {
        let (_, data) = rest
            .split_once(";base64,")
            .ok_or("a data URI that is not base64")?;
        let bytes = base64::engine::general_purpose::STANDARD
            .decode(data)
            .map_err(|e| format!("bad base64 in its data URI: {e}"))?;
        if bytes.len() as u64 > limit {
            return Err(format!(
                "its data URI holds {} bytes, more than the {limit} {limit_is}",
                bytes.len()
            ));
        }
        return Ok(bytes);
    }
    if uri.contains("://") {
        return Err(format!("{uri} is not a local file"));
    }
    let base = base.ok_or(format!(
        "names file {uri}, but there is no folder to look in"
    ))?;
    let path = inside(base, &percent_decode(uri))?;
    read_bounded(&path, limit, limit_is)
}

/// A buffer's bytes: the GLB binary chunk, or its URI's, bounded by its declared length.
pub(super) fn load_buffer(
    buffer: &gltf::Buffer,
    base: Option<&Path>,
    blob: Option<&[u8]>,
) -> Result<Vec<u8>, String> {
    let what = format!("buffer {}", buffer.index());
    let data = match buffer.source() {
        gltf::buffer::Source::Bin => blob
            .ok_or(format!("{what} is the GLB binary chunk, which is missing"))?
            .to_vec(),
        // Bounded by the declared length (a file may pad it to 4 bytes, as GLB chunks are).
        gltf::buffer::Source::Uri(uri) => {
            let limit = (buffer.length() as u64).next_multiple_of(4);
            read_uri(uri, base, limit, "the scene declares for it")
                .map_err(|e| format!("{what}: {e}"))?
        }
    };
    if data.len() < buffer.length() {
        return Err(format!(
            "{what} holds {} bytes, fewer than the {} it declares",
            data.len(),
            buffer.length()
        ));
    }
    Ok(data)
}

/// `relative` resolved inside `base`: absolute paths are refused, and the resolved path (links
/// followed) must lie inside the resolved folder.
fn inside(base: &Path, relative: &str) -> Result<PathBuf, String> {
    let named = Path::new(relative);
    if named.is_absolute() {
        return Err(format!(
            "names {relative}, an absolute path: a scene reads only files in its own folder"
        ));
    }
    let base = if base.as_os_str().is_empty() {
        Path::new(".")
    } else {
        base
    };
    let folder = base
        .canonicalize()
        .map_err(|e| format!("its folder {}: {e}", base.display()))?;
    let joined = base.join(named);
    let resolved = joined
        .canonicalize()
        .map_err(|e| format!("cannot read {}: {e}", joined.display()))?;
    if !resolved.starts_with(&folder) {
        return Err(format!(
            "names {relative}, which resolves to {} outside the scene's folder {}: a scene reads only files in its own folder",
            resolved.display(),
            folder.display()
        ));
    }
    Ok(resolved)
}

/// `%XX` escapes decoded (glTF URIs are URI-encoded: a space is `%20`).
fn percent_decode(uri: &str) -> String {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        let hex = (bytes[i] == b'%')
            .then(|| uri.get(i + 1..i + 3))
            .flatten()
            .and_then(|h| u8::from_str_radix(h, 16).ok());
        match hex {
            Some(b) => {
                out.push(b);
                i += 3;
            }
            None => {
                out.push(bytes[i]);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
}
