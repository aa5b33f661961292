//! Measurements: images and their comparison (PSNR, SSIM; FLIP and an eccentricity-aware FLIP,
//! judged on the GPU by the `judge` module or by NVIDIA's reference with the `flip` feature)
//! over the pixels the lens shows, temporal stability, timing statistics.

pub(crate) mod acuity;
pub mod display;
#[cfg(feature = "flip")]
pub mod flip;
mod histogram;
mod image;
mod per_second;
pub mod perceptual;
mod summary;
pub mod temporal;
mod timing;

pub use acuity::{Acuity, EyeFlipErrors, FlipMapper, FlipMaps, JudgeError};
pub use display::{EyePixels, PixelsKey, Region};
pub use histogram::{ErrorHistogram, HISTOGRAM_BINS};
pub use image::{FileError, ImageError, RgbaImage};
pub use per_second::{PerSecond, SecondSummary};
pub use summary::ErrorSummary;
pub use timing::Stats;
