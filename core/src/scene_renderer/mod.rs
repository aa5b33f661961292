//! foveate's scene renderer, on the foveation layer: the scene's buffers and materials,
//! per-frame culling into the plan's cull slots, levels of detail and moving instances. It
//! hands the layer its scene steps as an engine would (the geometry to draw, the bindings its
//! shaders read), and the layer records the rest of the frame. Its public items are reached
//! through the `render` module.

mod cluster_cull;
mod cull_slots;
mod culling;
mod frames_in_flight;
mod instances;
mod lod_select;
mod materials;
mod moving;
mod renderer;
mod scene_buffers;

pub use frames_in_flight::{BegunFrame, FramesInFlight};
pub use renderer::{counting_frame, Renderer};
