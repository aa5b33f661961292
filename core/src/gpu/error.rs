use ash::vk;

use crate::vocab::ConfigError;

/// Everything that can go wrong talking to Vulkan, with what to do about it where we know.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error("cannot load the Vulkan loader ({0}); install `libvulkan1` and a driver (`mesa-vulkan-drivers` provides lavapipe)")]
    Loader(String),
    #[error("{call} failed: {result}")]
    Vk {
        call: &'static str,
        result: vk::Result,
    },
    #[error("no usable Vulkan device (Vulkan 1.1 with a graphics queue and multiview); install `mesa-vulkan-drivers` for lavapipe")]
    NoDevice,
    #[error("the Vulkan device {name} cannot run foveate: {why}")]
    Unusable { name: String, why: String },
    #[error("the OpenXR runtime could not make Vulkan objects: {0}")]
    Runtime(String),
    #[error("no Vulkan device matches `{wanted}`; available: {available}")]
    DeviceNotFound { wanted: String, available: String },
    #[error("validation was requested but VK_LAYER_KHRONOS_validation is not installed (`apt-get install vulkan-validationlayers`)")]
    NoValidationLayer,
    #[error("GPU memory: {0}")]
    Memory(#[from] gpu_allocator::AllocationError),
    #[error(transparent)]
    Config(#[from] ConfigError),
    #[error("pipeline cache {path}: {error}")]
    PipelineCache { path: String, error: String },
    #[error("cannot present to the window: {0}")]
    NoPresentation(String),
    #[error("the plan renders into output images handed in per frame (an OpenXR swapchain's), but none were given")]
    NoOutputImages,
    #[error("output image {index} asked for, but {count} were handed in")]
    NoSuchOutputImage { index: usize, count: usize },
    #[error("more than {limit} distinct output images handed in to one renderer: reuse images (a swapchain's), or make a new renderer")]
    TooManyOutputImages { limit: usize },
    #[error("readback asked for before any frame was rendered")]
    NoFrameRendered,
    #[error("the figures of frame {frame} were asked for after its frame slot {slot} was recorded into again: read a frame's figures before the renderer cycles back to its slot")]
    FrameSlotReused { frame: u64, slot: usize },
    #[error("frames in flight: {0}")]
    FramesInFlight(String),
    #[error("Vulkan validation reported {} message(s):\n{}", .0.len(), .0.join("\n"))]
    Validation(Vec<String>),
}

/// Converts `vk::Result` at the boundary, naming the call that failed.
pub trait VkResultExt<T> {
    fn vk(self, call: &'static str) -> Result<T, GpuError>;
}

impl<T> VkResultExt<T> for Result<T, vk::Result> {
    fn vk(self, call: &'static str) -> Result<T, GpuError> {
        self.map_err(|result| GpuError::Vk { call, result })
    }
}
