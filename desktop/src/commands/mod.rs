//! One file (or folder) per command of the CLI; `cli.rs` dispatches to them.

pub mod bench;
pub mod compare;
pub mod cull;
pub mod flicker;
pub mod judge;
pub mod latency;
pub mod mask;
pub mod mffr;
mod motion_frontier;
pub mod pixels;
pub mod render;
pub mod view;
pub mod xr;
