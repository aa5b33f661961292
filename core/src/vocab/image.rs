//! The 8-bit RGBA image every module passes around (the GPU reads frames back into it, metrics
//! compare them), with its reading and writing; the comparisons live in `metrics`.

use std::path::{Path, PathBuf};

use super::files::{check_writable, write_atomic, FileError};

/// Why an image could not be read or written. Each message names the file and the cause once
/// (the cause is part of the message, not a separate source, so `{:#}` chains do not repeat it).
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    #[error("cannot read image {}: {why}", path.display())]
    /// The file could not be read or decoded.
    Read {
        /** The file. */
        path: PathBuf,
        /** What went wrong. */
        why: String,
    },
    #[error("cannot write image {}: {why}", path.display())]
    /// The image could not be encoded.
    Encode {
        /** The file. */
        path: PathBuf,
        /** What went wrong. */
        why: String,
    },
    #[error("{0}")]
    /// The file could not be written.
    Write(FileError),
    #[error("cannot write image {}: its extension names no format foveate writes ({}); use .png, or .jpg/.jpeg", path.display(), if extension.is_empty() { "none" } else { extension })]
    /// The file's extension names no format foveate writes.
    UnknownFormat {
        /** The file. */
        path: PathBuf,
        /** Its extension (empty: none). */
        extension: String,
    },
    #[error("images differ in size: {a:?} vs {b:?}")]
    /// Two images compared differ in size.
    SizeMismatch {
        /** The first's width and height. */
        a: (u32, u32),
        /** The second's width and height. */
        b: (u32, u32),
    },
}

/// An 8-bit sRGB RGBA image, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbaImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width × height` pixels of 4 bytes, row after row.
    pub data: Vec<u8>,
}

impl From<image::RgbaImage> for RgbaImage {
    fn from(img: image::RgbaImage) -> Self {
        RgbaImage {
            width: img.width(),
            height: img.height(),
            data: img.into_raw(),
        }
    }
}

impl RgbaImage {
    /// A `width` × `height` image, transparent black.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            data: vec![0; width as usize * height as usize * 4],
        }
    }

    /// The pixel at column `x`, row `y` (panics outside the image, as indexing does).
    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = (y as usize * self.width as usize + x as usize) * 4;
        [
            self.data[i],
            self.data[i + 1],
            self.data[i + 2],
            self.data[i + 3],
        ]
    }

    /// Sets the pixel at column `x`, row `y` (panics outside the image, as indexing does).
    pub fn set_pixel(&mut self, x: u32, y: u32, p: [u8; 4]) {
        let i = (y as usize * self.width as usize + x as usize) * 4;
        self.data[i..i + 4].copy_from_slice(&p);
    }

    /// The `w`×`h` region at (`x`, `y`).
    pub fn crop(&self, x: u32, y: u32, w: u32, h: u32) -> RgbaImage {
        let mut out = RgbaImage::new(w, h);
        for row in 0..h {
            let src = ((y + row) as usize * self.width as usize + x as usize) * 4;
            let dst = row as usize * w as usize * 4;
            out.data[dst..dst + w as usize * 4]
                .copy_from_slice(&self.data[src..src + w as usize * 4]);
        }
        out
    }

    /// Places `a` and `b` side by side (same height).
    pub fn side_by_side(a: &RgbaImage, b: &RgbaImage) -> RgbaImage {
        let mut out = RgbaImage::new(a.width + b.width, a.height.max(b.height));
        for (img, x0) in [(a, 0), (b, a.width)] {
            for y in 0..img.height {
                let src = (y * img.width * 4) as usize;
                let dst = ((y * out.width + x0) * 4) as usize;
                out.data[dst..dst + (img.width * 4) as usize]
                    .copy_from_slice(&img.data[src..src + (img.width * 4) as usize]);
            }
        }
        out
    }

    /// Places `a` above `b` (same width).
    pub fn stacked(a: &RgbaImage, b: &RgbaImage) -> RgbaImage {
        let mut out = RgbaImage::new(a.width.max(b.width), a.height + b.height);
        for (img, y0) in [(a, 0), (b, a.height)] {
            for y in 0..img.height {
                let src = (y * img.width * 4) as usize;
                let dst = ((y + y0) * out.width * 4) as usize;
                out.data[dst..dst + (img.width * 4) as usize]
                    .copy_from_slice(&img.data[src..src + (img.width * 4) as usize]);
            }
        }
        out
    }

    /// The format a path's extension names: `.png` (8-bit RGBA) or `.jpg`/`.jpeg` (RGB,
    /// quality 95, alpha dropped); anything else is an error naming the extension.
    pub fn format_for(path: &Path) -> Result<image::ImageFormat, ImageError> {
        let extension = path
            .extension()
            .map(|e| e.to_string_lossy().to_ascii_lowercase())
            .unwrap_or_default();
        match extension.as_str() {
            "png" => Ok(image::ImageFormat::Png),
            "jpg" | "jpeg" => Ok(image::ImageFormat::Jpeg),
            _ => Err(ImageError::UnknownFormat {
                path: path.into(),
                extension,
            }),
        }
    }

    /// Checks, before the work that makes the image, that `path` names a format foveate writes
    /// and can be written: its folder exists and a file can be made there.
    pub fn check_output(path: &Path) -> Result<(), ImageError> {
        check_writable(path).map_err(ImageError::Write)?;
        Self::format_for(path).map(|_| ())
    }

    /// Writes the image in the format its extension names ([`RgbaImage::format_for`]),
    /// atomically: a failed write leaves an earlier file at `path` as it was.
    pub fn save(&self, path: &Path) -> Result<(), ImageError> {
        let format = Self::format_for(path)?;
        let mut bytes = std::io::Cursor::new(Vec::new());
        let fail = |why: String| ImageError::Encode {
            path: path.into(),
            why,
        };
        let encoded = match format {
            image::ImageFormat::Jpeg => {
                let rgba = image::RgbaImage::from_raw(self.width, self.height, self.data.clone())
                    .ok_or_else(|| {
                    fail(format!(
                        "{} bytes do not hold {}x{} RGBA pixels",
                        self.data.len(),
                        self.width,
                        self.height
                    ))
                })?;
                image::codecs::jpeg::JpegEncoder::new_with_quality(&mut bytes, 95)
                    .encode_image(&image::DynamicImage::from(rgba).to_rgb8())
            }
            _ => image::write_buffer_with_format(
                &mut bytes,
                &self.data,
                self.width,
                self.height,
                image::ExtendedColorType::Rgba8,
                format,
            ),
        };
        encoded.map_err(|e| fail(e.to_string()))?;
        write_atomic(path, bytes.get_ref()).map_err(ImageError::Write)
    }

    /// Reads an image (PNG or JPEG, any channel layout or depth), converted to 8-bit RGBA.
    pub fn load_png(path: &Path) -> Result<RgbaImage, ImageError> {
        let img = image::open(path).map_err(|e| ImageError::Read {
            path: path.into(),
            why: e.to_string(),
        })?;
        Ok(RgbaImage::from(img.to_rgba8()))
    }

    /// `SizeMismatch` unless `other` has this image's size.
    pub fn check_size(&self, other: &RgbaImage) -> Result<(), ImageError> {
        if (self.width, self.height) != (other.width, other.height) {
            return Err(ImageError::SizeMismatch {
                a: (self.width, self.height),
                b: (other.width, other.height),
            });
        }
        Ok(())
    }
}
