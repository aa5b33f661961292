//! What can stop `foveate xr`, each error naming what is missing.

use openxr as xr;

use crate::gpu::GpuError;
use crate::plan::ConfigError;

/// Everything that can stop `foveate xr`, each naming what is missing.
#[derive(Debug, thiserror::Error)]
pub enum XrError {
    #[error("no OpenXR loader ({0}): install `libopenxr-loader1` and a runtime (`scripts/xr-test.sh` runs Monado)")]
    NoLoader(String),
    #[error("no OpenXR runtime answered xrCreateInstance ({0}): install one and make it active (Monado: `monado-service` must be running)")]
    NoRuntime(xr::sys::Result),
    #[error("the OpenXR runtime does not offer XR_KHR_vulkan_enable2, and foveate renders with Vulkan only")]
    NoVulkan,
    #[error("the runtime has no head-mounted display ({0})")]
    NoHeadset(xr::sys::Result),
    #[error("the runtime offers no PRIMARY_STEREO view configuration (it offers {0})")]
    NoStereo(String),
    #[error("the runtime wants Vulkan {min}..={max}; foveate makes Vulkan 1.1 instances")]
    VulkanVersion { min: String, max: String },
    #[error("the runtime's swapchains offer no format foveate renders its output to (R8G8B8A8_SRGB, Vulkan format 43); offered: {0:?}")]
    NoSwapchainFormat(Vec<u32>),
    #[error("{call} failed: {result}")]
    Call {
        call: &'static str,
        result: xr::sys::Result,
    },
    #[error("foveate cannot render into the runtime's swapchain: {0}")]
    OutputMismatch(String),
    #[error(transparent)]
    Gpu(#[from] GpuError),
    #[error("the frame's configuration: {0}")]
    Config(#[from] ConfigError),
    #[error("the runtime's visibility mask: {0}")]
    Mask(String),
}

pub(super) trait XrResultExt<T> {
    fn xr(self, call: &'static str) -> Result<T, XrError>;
}

impl<T> XrResultExt<T> for Result<T, xr::sys::Result> {
    fn xr(self, call: &'static str) -> Result<T, XrError> {
        self.map_err(|result| XrError::Call { call, result })
    }
}
