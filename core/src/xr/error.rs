//! What can stop `foveate xr`, each error naming what is missing.

use openxr as xr;

use crate::gpu::GpuError;
use crate::metrics::JudgeError;
use crate::plan::ConfigError;

/// Everything that can stop `foveate xr`, each naming what is missing.
#[derive(Debug, thiserror::Error)]
pub enum XrError {
    #[error("no OpenXR loader ({0}): install `libopenxr-loader1` and a runtime (`scripts/xr-test.sh` runs Monado)")]
    /// The OpenXR loader could not be opened.
    NoLoader(String),
    #[error("no OpenXR runtime answered xrCreateInstance ({0}): install one and make it active (Monado: `monado-service` must be running)")]
    /// No runtime answered.
    NoRuntime(xr::sys::Result),
    #[error("the OpenXR runtime does not offer XR_KHR_vulkan_enable2, and foveate renders with Vulkan only")]
    /// The runtime cannot render with Vulkan.
    NoVulkan,
    #[error("the runtime has no head-mounted display ({0})")]
    /// The runtime has no headset.
    NoHeadset(xr::sys::Result),
    #[error("the runtime offers no PRIMARY_STEREO view configuration (it offers {0})")]
    /// The runtime offers no stereo view configuration.
    NoStereo(String),
    #[error("the runtime wants Vulkan {min}..={max}; foveate makes Vulkan 1.1 instances")]
    /// The runtime's Vulkan versions exclude 1.1.
    VulkanVersion {
        /** The lowest it takes. */
        min: String,
        /** The highest it takes. */
        max: String,
    },
    #[error("the runtime's swapchains offer no format foveate renders its output to (R8G8B8A8_SRGB, Vulkan format 43); offered: {0:?}")]
    /// No swapchain format foveate renders to (the Vulkan formats offered).
    NoSwapchainFormat(Vec<u32>),
    #[error("{call} failed: {result}")]
    /// An OpenXR call failed.
    Call {
        /// The call, as OpenXR names it.
        call: &'static str,
        /// What it returned.
        result: xr::sys::Result,
    },
    #[error("foveate cannot render into the runtime's swapchain: {0}")]
    /// The runtime's swapchain images cannot be rendered into.
    OutputMismatch(String),
    #[error(transparent)]
    /// A Vulkan error.
    Gpu(#[from] GpuError),
    #[error("the frame's configuration: {0}")]
    /// The frame's configuration was refused.
    Config(#[from] ConfigError),
    #[error("the runtime's visibility mask: {0}")]
    /// The runtime's visibility mask could not be used.
    Mask(String),
    #[error("judging a frame: {0}")]
    /// A frame could not be judged (`--judge`).
    Judge(#[from] JudgeError),
}

pub(super) trait XrResultExt<T> {
    fn xr(self, call: &'static str) -> Result<T, XrError>;
}

impl<T> XrResultExt<T> for Result<T, xr::sys::Result> {
    fn xr(self, call: &'static str) -> Result<T, XrError> {
        self.map_err(|result| XrError::Call { call, result })
    }
}
