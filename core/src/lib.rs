//! foveate: stereo and foveated VR rendering on Vulkan, where every optimisation is measured.
//!
//! A frame goes `RenderConfig` + scene + device caps → [`plan::plan`] (pure, printable
//! [`plan::FramePlan`]) → [`render::Renderer`] (Vulkan objects compiled from the plan) → frames
//! with GPU timestamps and exact per-view fragment counts. See `DESIGN.md` in the shared folder.

pub mod cull;
pub mod foveation;
pub mod gpu;
pub mod measure;
pub mod metrics;
pub mod mffr;
pub mod plan;
pub mod render;
pub mod scene;
pub mod shaders;
pub mod view;
pub mod vocab;
pub mod xr;

pub use plan::{plan, ConfigError, FramePlan, RenderConfig, StereoMode};
