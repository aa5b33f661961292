//! foveate: stereo and foveated VR rendering on Vulkan, where every optimisation is measured.
//!
//! A frame goes `RenderConfig` + scene + device caps → [`plan::plan`] (pure, printable
//! [`plan::FramePlan`]) → [`render::Renderer`] (Vulkan objects compiled from the plan) → frames
//! recorded into the caller's command buffers ([`render::Renderer::record`], frames in flight)
//! or rendered and waited for ([`render::Renderer::render_frame`]), with GPU timestamps and
//! exact per-view fragment counts. The device may be foveate's ([`gpu::Gpu::new`]) or an
//! engine's ([`gpu::Gpu::from_engine`]).
//!
//! The examples in `core/examples/` go from a first headless frame to an engine's frame loop
//! (`headless`, `own_images`, `engine_loop`, `judge`), and `docs/embedding.md` walks through
//! them. Features: `flip` (NVIDIA's FLIP and the eccentricity-aware FLIP in [`metrics`]),
//! `clusters` (meshes split into culled clusters), `xr` (OpenXR).

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

/// The Vulkan bindings the API speaks in (command buffers, images, semaphores): use this one,
/// so the versions match.
pub use ash;
/// The maths types the API speaks in (`Mat4`, `Vec2`, …): use this one, so the versions match.
pub use glam;
