//! foveate: stereo and foveated VR rendering on Vulkan, where every optimisation is measured.
//!
//! foveate renders a stereo frame the ways VR renderers do — multiview, two passes, each object
//! twice, instanced stereo — and the optimisations mobile headsets use: foveated rendering
//! (low-resolution periphery views and gaze-following fovea insets, stencil masks, blending,
//! temporal accumulation), the HMD stencil mask, stereo culling (superfrustum, cones, round
//! robin), monoscopic far-field rendering and radial density masking. Each frame reports what it
//! cost (GPU time per pass, draws, triangles; a counting frame adds exact fragments per view),
//! and [`metrics`] reports what an approximation costs in image accuracy against a
//! full-quality reference.
//!
//! # A frame's pipeline
//!
//! 1. A [`plan::RenderConfig`] (headset, resolution, stereo mode, MSAA, foveation, …; every
//!    field has a default) and a [`scene::Scene`] (built in, or a glTF file:
//!    [`scene::load_gltf`]).
//! 2. [`plan()`]: pure and printable. It checks the configuration against the device — a bad
//!    value is a [`plan::ConfigError`] naming the field, the value and the limit — and decides
//!    every pass, attachment, barrier and load/store op ([`plan::FramePlan`]).
//! 3. [`render::Renderer::new`]: the Vulkan objects the plan calls for, and nothing else.
//! 4. Frames: [`render::Renderer::render`] records, submits and waits;
//!    [`render::Renderer::record`] records into a command buffer the caller began, for the
//!    caller to submit (with [`render::FramesInFlight`], or the engine's own loop). Each returns
//!    its [`render::FrameStats`].
//!
//! An engine that draws its own world takes foveation alone: a [`render::FoveationLayer`]
//! (made from a configuration, no scene) tells it the passes to draw into and each frame's
//! views, records the stencil masks before its draws and the output stage (composition,
//! accumulation, lens) after them, in the engine's command buffer; `Renderer` is foveate's own
//! scene drawn through the same layer. The `bring_your_own_draws` example is such an engine.
//!
//! The device is foveate's own ([`gpu::Gpu::new`]: the best Vulkan 1.1 device with multiview;
//! Mesa's lavapipe will do) or the engine's ([`gpu::Gpu::from_engine`]). The API speaks
//! [`ash`] and [`glam`] types; use the re-exported crates so the versions match.
//!
//! # Example
//!
//! A foveated frame at 256² per eye, its GPU time per pass, and the two eyes' images:
//!
//! ```
//! use foveate::foveation::FoveationConfig;
//! use foveate::gpu::{Gpu, GpuOptions};
//! use foveate::plan::{RenderConfig, Resolution};
//! use foveate::render::{FrameInput, Renderer};
//!
//! # fn main() -> Result<(), Box<dyn std::error::Error>> {
//! let gpu = Gpu::new(&GpuOptions::default())?;
//! let scene = foveate::scene::default_scene();
//! let config = RenderConfig {
//!     resolution: Some(Resolution::square(256)),
//!     foveation: Some(FoveationConfig::default()),
//!     ..RenderConfig::default()
//! };
//! let plan = foveate::plan(&scene, &config, gpu.caps())?;
//! println!("{plan}"); // every pass, attachment and barrier, and why
//! let mut renderer = Renderer::new(&gpu, &plan, &scene)?;
//! let gaze = foveate::glam::Vec2::new(0.2, -0.1); // right of and below the centre
//! let stats = renderer.render(&FrameInput::new(scene.head).with_gaze([gaze; 2]))?;
//! for (pass, ms) in stats.gpu_pass_times() {
//!     println!("{pass}: {ms:.2} ms");
//! }
//! let eyes = renderer.readback()?; // sRGB, left and right
//! assert_eq!((eyes.left.width, eyes.left.height), (256, 256));
//! # Ok(())
//! # }
//! ```
//!
//! More in the crate's `examples/`: `bring_your_own_draws` (an engine's own pipeline drawing a
//! glTF file into a layer's views), `headless` (the above, saved as a PNG), `own_images`
//! (frames into images the program owns), `engine_loop` (the engine's command buffers, frames
//! in flight) and `judge` (a frame judged against its full-quality reference);
//! `docs/embedding.md` in the repository walks through them.
//!
//! # Features
//!
//! - `flip`: NVIDIA's FLIP and an eccentricity-aware FLIP in [`metrics`] (builds C++).
//! - `clusters`: meshes split into clusters culled one by one, and levels of detail
//!   (meshoptimizer; builds C++).
//! - `xr`: an OpenXR session (the `xr` module); the loader is opened at run time.
//!
//! Building needs `glslc` (Debian: `apt-get install glslc`): the shaders are compiled from the
//! GLSL shipped in the package.

// Every public item is documented. `internals` makes undocumented helpers public (hidden from
// the docs), so the lint holds for the library as users get it: without that feature
// (`scripts/test.sh` checks it with warnings denied).
#![cfg_attr(not(feature = "internals"), warn(missing_docs))]
// Without `internals`, what only the CLI and the tests reach for is crate-private, and some of
// it has no caller inside the crate.
#![cfg_attr(not(feature = "internals"), allow(dead_code))]

/// Re-exports items the CLI, the viewer and the tests use but an engine does not need: public
/// and hidden from the docs with the `internals` feature, crate-private without it.
macro_rules! internal_use {
    ($($tree:tt)*) => {
        #[cfg(feature = "internals")]
        #[doc(hidden)]
        pub use $($tree)*;
        #[cfg(not(feature = "internals"))]
        #[allow(unused_imports)]
        pub(crate) use $($tree)*;
    };
}

/// Declares a module that is internal in the sense of [`internal_use`].
macro_rules! internal_mod {
    ($name:ident) => {
        #[cfg(feature = "internals")]
        #[doc(hidden)]
        pub mod $name;
        #[cfg(not(feature = "internals"))]
        pub(crate) mod $name;
    };
}

pub mod cull;
pub mod foveation;
mod foveation_layer;
pub mod gpu;
pub mod judge;
pub mod metrics;
pub mod mffr;
pub mod plan;
pub mod render;
pub mod scene;
mod scene_renderer;
pub mod tile_price;
pub mod view;
pub mod xr;

internal_mod!(measure);
internal_mod!(shaders);
mod vocab;
internal_use!(vocab::{check_writable, read_bounded, write_atomic, write_atomic_with});

pub use plan::plan;

/// The Vulkan bindings the API speaks in (command buffers, images, semaphores): use this one,
/// so the versions match.
pub use ash;
/// The maths types the API speaks in (`Mat4`, `Vec2`, …): use this one, so the versions match.
pub use glam;
