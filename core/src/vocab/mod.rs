//! The words every module shares: configuration errors, resolutions, what the device can do and
//! what its driver gets wrong. A leaf: it imports nothing of ours, so any module may import it
//! without a cycle (`tests/module_graph.rs` checks that, and that no two modules import each
//! other).

mod caps;
mod error;
mod files;
mod image;
mod named_enum;
mod resolution;

pub use caps::{DeviceCaps, DriverQuirks};

/// The views a frame's shaders know: the periphery, fovea and parafoveal ring pairs (the ring
/// in the fovea's pass, so no pass has more than four). The MFFR far view comes after them.
pub const FRAME_VIEWS: u32 = 6;
pub use error::ConfigError;
pub use files::{check_writable, read_bounded, write_atomic, write_atomic_with, FileError};
pub use image::{ImageError, RgbaImage};
pub(crate) use named_enum::named_enum;
pub use resolution::Resolution;
