//! Measurements: images and their comparison (PSNR, SSIM; FLIP and an eccentricity-aware FLIP
//! with the `flip` feature), timing statistics.

#[cfg(feature = "flip")]
pub mod flip;
mod image;
mod timing;

pub use image::{ImageError, RgbaImage};
pub use timing::Stats;
