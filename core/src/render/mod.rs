//! The renderer: compiles a [`FramePlan`](crate::plan::FramePlan) into Vulkan objects and
//! records, submits and measures frames.

mod cluster_cull;
mod command_log;
mod counting;
mod cull_slots;
mod culling;
mod descriptors;
mod engine_views;
mod executor;
mod far_view;
mod frame_input;
mod frame_slot;
mod frames_in_flight;
mod history_outcomes;
mod instances;
mod layer;
mod layer_engine;
mod lod_select;
mod masks;
mod materials;
mod mffr;
mod moving;
mod output;
mod output_pixels;
mod output_targets;
mod pipelines;
mod probe;
mod radial_density;
mod readback;
mod record;
mod recorder;
mod renderer;
mod sampled_set;
mod scene_buffers;
mod setup;
mod stats;
mod stereo_scene;
mod targets;
mod temporal;
mod view_images;
mod views;
mod vulkan_recorder;

internal_use!(command_log::{Command, CommandLog});
pub use engine_views::{DrawContext, DrawPass, FrameViewSet, View, ViewKind};
pub use frame_input::{FrameInput, FrameRecord};
pub use frames_in_flight::{BegunFrame, FramesInFlight};
pub use history_outcomes::{HistoryOutcome, HistoryOutcomes};
pub use layer::FoveationLayer;
pub use output_targets::MAX_OUTPUT_IMAGES;
pub(crate) use readback::OutputTexels;
pub use readback::StereoImage;
internal_use!(record::record_frame);
internal_use!(recorder::{FrameDraws, Recorder, Rect});
pub use renderer::{counting_frame, Renderer};
pub use stats::{FrameStats, PassStatistics, StepFragments};
pub use view_images::{view_images, HandedImage, ViewImage};

/// How the image a plan's frames end in is made; an output handed in per frame (an OpenXR
/// swapchain's, [`crate::plan::RenderConfig::external_output`]) must be made the same way.
pub fn output_image_desc(plan: &crate::plan::FramePlan) -> crate::gpu::ImageDesc<'static> {
    targets::image_desc(plan, plan.outputs()[0])
}
