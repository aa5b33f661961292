//! Measurements: images and their comparison, timing statistics.

mod image;
mod timing;

pub use image::{ImageError, RgbaImage};
pub use timing::Stats;
