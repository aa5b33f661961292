//! Measurements: images and their comparison (PSNR, SSIM; FLIP and an eccentricity-aware FLIP
//! with the `flip` feature) over the pixels the lens shows, temporal stability, timing
//! statistics.

pub mod display;
#[cfg(feature = "flip")]
pub mod flip;
mod image;
#[cfg(feature = "flip")]
pub mod perceptual;
mod summary;
pub mod temporal;
mod timing;

pub use display::{EyePixels, Region};
pub use image::{ImageError, RgbaImage};
pub use summary::ErrorSummary;
pub use timing::Stats;
