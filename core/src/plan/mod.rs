//! From a [`RenderConfig`], a scene and the device's capabilities to a [`FramePlan`]: which
//! passes and attachments a frame has and what happens to each attachment's contents.
//!
//! Pure: no Vulkan objects are created here, so every rule is unit-tested without a GPU and
//! `foveate plan` prints exactly what the renderer will build.

mod barriers;
mod build;
mod config;
mod counting;
mod derive;
mod masks;
mod mffr;
mod model;
mod output;
mod pipeline;
mod print;
mod probe;
mod radial_density;
mod steps;
mod stereo_scene;
mod validate;

pub use crate::vocab::{ConfigError, DeviceCaps, DriverQuirks, Resolution};
pub use barriers::{Barrier, PassBarriers, Touch};
pub use build::plan;
pub use config::{CullConfig, FoveaLayout, OutputStage, RenderConfig, StereoMode, MAX_VIEWS};
pub use derive::{Access, ClearValue, Layout, LoadOp, StoreOp};
pub use model::{
    AttachmentId, AttachmentPlan, AttachmentRole, BufferPlan, CountedSlot, CountedStep, DrawSet,
    Format, FoveaLayoutChoice, FramePlan, LensOutput, PassKind, PassPlan, Submission, TargetLayout,
    Use, COUNTER_SLOTS_PER_STEP, SKY,
};
pub use pipeline::{Constant, ConstantKind, PipelineDesc, VertexInput};
pub use radial_density::{RadialDensity, RadialDensityGeometry};
pub use steps::{
    CompareOp, OutputSource, OutputStep, StencilOp, StencilState, Step, MASK_BIT, NEAR_BIT,
    SKIP_BIT,
};

#[cfg(test)]
mod pipeline_tests;
#[cfg(test)]
mod tests;
