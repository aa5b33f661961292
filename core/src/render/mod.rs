//! The renderer: compiles a [`FramePlan`](crate::plan::FramePlan) into Vulkan objects and
//! records, submits and measures frames.

mod command_log;
mod counting;
mod culling;
mod masks;
mod materials;
mod mffr;
mod output;
mod pipelines;
mod probe;
mod radial_density;
mod record;
mod renderer;
mod sampled_set;
mod scene_buffers;
mod stereo_scene;
mod targets;

pub use crate::plan::SKY;
pub use command_log::{Command, CommandLog};
pub use record::{record_frame, FrameDraws, Recorder, Rect};
pub use renderer::{
    counting_frame, FrameStats, PassStatistics, Renderer, StepFragments, StereoImage,
};
