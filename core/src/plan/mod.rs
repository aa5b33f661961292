//! From a [`RenderConfig`], a scene and the device's capabilities to a [`FramePlan`]: which
//! passes and attachments a frame has and what happens to each attachment's contents.
//!
//! Pure: no Vulkan objects are created here, so every rule is unit-tested without a GPU and
//! `foveate plan` prints exactly what the renderer will build.

mod attachments;
mod barriers;
mod build;
mod config;
mod counting;
mod derive;
mod engine;
mod masks;
mod mffr;
mod model;
mod ops;
mod output;
mod pipeline;
mod print;
mod print_attachments;
mod probe;
mod radial_density;
mod scene_sizes;
mod split_views;
mod steps;
mod stereo_scene;
mod temporal;
mod validate;
mod workload;

pub use crate::vocab::{ConfigError, DeviceCaps, DriverQuirks, Resolution, FRAME_VIEWS};
pub use attachments::{AttachmentPlan, AttachmentRole, Format, Use};
pub use build::plan;
pub use config::{
    CullConfig, FoveaLayout, OutputFormat, OutputStage, RadialDensity, RadialDensityGeometry,
    RenderConfig, StereoMode, MAX_FRAMES_IN_FLIGHT, MAX_SPARE_INSTANCES, MAX_VIEWS,
};
pub use engine::plan_for_engine;
pub use model::{
    BufferPlan, ClusterPlan, CountedSlot, FoveaLayoutChoice, FramePlan, HistoryPair, LensOutput,
    LodPlan, PassKind, PassPlan, Submission, TargetLayout, COUNTER_SLOTS_PER_STEP,
    HISTORY_OUTCOME_SLOTS, SKY,
};
pub use ops::{
    Access, AttachmentId, Barrier, ClearValue, Layout, LoadOp, PassBarriers, StoreOp, Touch,
};
pub use pipeline::{Constant, ConstantKind, PipelineDesc, VertexInput};
pub(crate) use scene_sizes::cluster_plan;
pub use steps::{
    CompareOp, CountedStep, DrawSet, OutputSource, OutputStep, StencilOp, StencilState, Step,
    MASK_BIT, NEAR_BIT, SKIP_BIT,
};
pub use workload::AttachmentTraffic;

#[cfg(test)]
mod default_tests;
#[cfg(test)]
mod depth_resolve_tests;
#[cfg(test)]
mod effect_tests;
#[cfg(test)]
mod history_at_tests;
#[cfg(test)]
mod pipeline_tests;
#[cfg(test)]
mod ring_tests;
#[cfg(test)]
mod robustness_tests;
#[cfg(test)]
mod step_tests;
#[cfg(test)]
mod tests;
