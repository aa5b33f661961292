//! The foveation layer: compiles a [`FramePlan`](crate::plan::FramePlan) into Vulkan objects
//! and records a frame around its scene steps — the views placed, the stencil masks, the output
//! stage (composition, accumulation, lens), the frame slots and their queries — with the
//! engine's draws, or foveate's scene renderer's, at each scene step. It imports nothing of the
//! renderer's (`core/tests/module_graph.rs`): the renderer hands it its scene as an engine
//! would. The `render` module re-exports its public items.

mod command_log;
mod counting;
mod descriptors;
mod engine_views;
mod executor;
pub(crate) mod far_view;
pub(crate) mod frame_input;
pub(crate) mod frame_slot;
mod history_outcomes;
pub(crate) mod layer;
mod layer_copy;
mod layer_engine;
mod masks;
mod mffr;
mod output;
mod output_pixels;
mod output_targets;
pub(crate) mod pipelines;
mod probe;
mod radial_density;
mod readback;
mod record;
pub(crate) mod recorder;
mod sampled_set;
pub(crate) mod setup;
mod shader_report;
pub(crate) mod stats;
mod stereo_scene;
mod targets;
mod temporal;
mod view_images;
pub(crate) mod views;
pub(crate) mod vulkan_recorder;

internal_use!(command_log::{Command, CommandLog});
pub use engine_views::{DrawContext, DrawPass, FrameViewSet, View, ViewKind};
pub use frame_input::{FrameInput, FrameRecord};
pub use history_outcomes::{HistoryOutcome, HistoryOutcomes};
pub use layer::FoveationLayer;
pub use output_targets::MAX_OUTPUT_IMAGES;
pub(crate) use readback::OutputTexels;
pub use readback::StereoImage;
internal_use!(record::record_frame);
internal_use!(recorder::{FrameDraws, Recorder, Rect});
pub use shader_report::StepShaders;
pub use stats::{FrameStats, PassStatistics, StepFragments};
pub use view_images::{view_images, HandedImage, ViewImage};

/// How the image a plan's frames end in is made; an output handed in per frame (an OpenXR
/// swapchain's, [`crate::plan::RenderConfig::external_output`]) must be made the same way.
pub fn output_image_desc(plan: &crate::plan::FramePlan) -> crate::gpu::ImageDesc<'static> {
    targets::image_desc(plan, plan.outputs()[0])
}
