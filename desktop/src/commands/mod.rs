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
pub mod price;
pub mod render;
pub mod results;
pub mod shaders;
pub mod soak;
pub mod view;
pub mod xr;

/// The width of a table's configuration column: its longest name, and at least the header
/// ("configuration"), so the figures after a long name stay under their headings.
fn name_column_width<'a>(names: impl Iterator<Item = &'a str>) -> usize {
    names
        .map(str::len)
        .max()
        .unwrap_or(0)
        .max("configuration".len())
}
