//! The 8-bit RGBA image every module passes around (the GPU reads frames back into it, metrics
//! compare them), with its reading and writing; the comparisons live in `metrics`.

use std::path::{Path, PathBuf};

/// Why an image could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    #[error("cannot read image {path}: {source}")]
    Read {
        path: PathBuf,
        source: image::ImageError,
    },
    #[error("cannot write PNG {path}: {source}")]
    Write {
        path: PathBuf,
        source: image::ImageError,
    },
    #[error("images differ in size: {a:?} vs {b:?}")]
    SizeMismatch { a: (u32, u32), b: (u32, u32) },
}

/// An 8-bit sRGB RGBA image, rows top to bottom.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbaImage {
    pub width: u32,
    pub height: u32,
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
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            data: vec![0; width as usize * height as usize * 4],
        }
    }

    pub fn pixel(&self, x: u32, y: u32) -> [u8; 4] {
        let i = (y as usize * self.width as usize + x as usize) * 4;
        [
            self.data[i],
            self.data[i + 1],
            self.data[i + 2],
            self.data[i + 3],
        ]
    }

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

    /// Writes an 8-bit RGBA PNG.
    pub fn save_png(&self, path: &Path) -> Result<(), ImageError> {
        image::save_buffer_with_format(
            path,
            &self.data,
            self.width,
            self.height,
            image::ExtendedColorType::Rgba8,
            image::ImageFormat::Png,
        )
        .map_err(|source| ImageError::Write {
            path: path.into(),
            source,
        })
    }

    /// Reads an image (PNG or JPEG, any channel layout or depth), converted to 8-bit RGBA.
    pub fn load_png(path: &Path) -> Result<RgbaImage, ImageError> {
        let img = image::open(path).map_err(|source| ImageError::Read {
            path: path.into(),
            source,
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
