//! Judging frames on the device that rendered them: FLIP (Andersson et al. 2020) and the
//! eccentricity-aware FLIP of [`crate::metrics`] as compute passes, so that judging a frame
//! costs about as much as rendering it. `metrics::flip` (NVIDIA's reference C++, feature
//! `flip`) stays the oracle the tests hold this to. Flicker ([`crate::metrics::temporal`]) is
//! measured here too, on the renderers' outputs where they lie ([`GpuFlicker`]).

mod filters;
mod flicker;
mod flip;
mod geometry;
mod gpu_flip;
mod images;
mod live;
mod outputs;
mod reduce;
mod vulkan;

pub use flicker::GpuFlicker;
pub use flip::FlipJudge;
pub use gpu_flip::GpuFlip;
pub use images::{EyeLayers, JudgedImage};
pub use live::{reference_config, LiveJudge, LiveJudgement, MAX_JUDGE_INTERVAL};
pub use outputs::Capture;
