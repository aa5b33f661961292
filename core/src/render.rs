//! Rendering frames: the [`FoveationLayer`] (views, masks, output stage and frame slots around
//! the scene steps, whoever draws them) and foveate's own scene [`Renderer`] on it.
//!
//! The two live in folders of their own inside the crate, the layer knowing nothing of the
//! renderer; this module is their one public path.

pub(crate) use crate::foveation_layer::OutputTexels;
pub use crate::foveation_layer::{
    output_image_desc, view_images, DrawContext, DrawPass, FoveationLayer, FrameInput, FrameRecord,
    FrameStats, FrameViewSet, HandedImage, HistoryOutcome, HistoryOutcomes, PassStatistics,
    StepFragments, StepShaders, StereoImage, View, ViewImage, ViewKind, MAX_OUTPUT_IMAGES,
};
internal_use!(crate::foveation_layer::{Command, CommandLog});
internal_use!(crate::foveation_layer::record_frame);
internal_use!(crate::foveation_layer::{FrameDraws, Recorder, Rect});
pub use crate::scene_renderer::{counting_frame, BegunFrame, FramesInFlight, Renderer};
