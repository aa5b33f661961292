//! OpenXR: foveate on a headset runtime. The session's lifecycle and the conversion of the
//! runtime's views are pure and tested on every host; the runtime itself (instance, Vulkan
//! through the runtime, swapchains the output stage renders into, the frame loop) needs the
//! `xr` feature (the `openxr` crate, its loader opened at run time).

#[cfg(feature = "xr")]
mod error;
mod gaze;
mod lifecycle;
#[cfg(feature = "xr")]
mod pixels;
#[cfg(feature = "xr")]
mod runtime;
#[cfg(feature = "xr")]
mod session;
#[cfg(feature = "xr")]
mod summary;
#[cfg(feature = "xr")]
mod tracker;
mod views;
#[cfg(feature = "xr")]
mod visibility;
mod watchdog;

#[cfg(feature = "xr")]
pub use error::XrError;
pub use gaze::eye_gazes;
pub use lifecycle::{Ended, FrameOutcome, Lifecycle, RuntimeEvent, SessionBackend, SessionState};
#[cfg(feature = "xr")]
pub use pixels::PixelCheck;
#[cfg(feature = "xr")]
pub use runtime::{Platform, RuntimeReport, XrRuntime};
#[cfg(feature = "xr")]
pub use session::{GazeSource, XrSession, XrSettings};
#[cfg(feature = "xr")]
pub use summary::{Judged, Pacing, XrSummary};
pub use views::{fit_eyes, fov_tangents, FittedEyes, Pose};
#[cfg(feature = "xr")]
pub use visibility::MaskFractions;
pub use watchdog::{Stall, Watchdog};
