use ash::vk;

use crate::vocab::ConfigError;

/// Everything that can go wrong talking to Vulkan, with what to do about it where we know.
#[derive(Debug, thiserror::Error)]
pub enum GpuError {
    #[error("cannot load the Vulkan loader ({0}); install `libvulkan1` and a driver (`mesa-vulkan-drivers` provides lavapipe)")]
    /// The Vulkan loader could not be opened.
    Loader(String),
    #[error("{call} failed: {result}")]
    /// A Vulkan call failed.
    Vk {
        /// The call, as Vulkan names it.
        call: &'static str,
        /// What it returned.
        result: vk::Result,
    },
    #[error("the device never wrote the frame's queries ({call} waited and gave up: {result}); a device that executes nothing, such as Mesa's turnip on the drm-shim, never does: plan its frames without timestamps (RenderConfig::timestamps; `foveate shaders --frames N` records frames so)")]
    /// A frame finished (its fence signalled) but its queries were never written: the device
    /// executes nothing.
    QueriesNeverWritten {
        /// The call, as Vulkan names it.
        call: &'static str,
        /// What it returned.
        result: vk::Result,
    },
    #[error("no usable Vulkan device (Vulkan 1.1 with a graphics queue and multiview); install `mesa-vulkan-drivers` for lavapipe")]
    /// No device has what foveate needs.
    NoDevice,
    #[error("the Vulkan device {name} cannot run foveate: {why}")]
    /// The chosen device lacks something foveate needs.
    Unusable {
        /** The device's name. */
        name: String,
        /** What it lacks. */
        why: String,
    },
    #[error("the OpenXR runtime could not make Vulkan objects: {0}")]
    /// The OpenXR runtime failed to make the Vulkan instance or device.
    Runtime(String),
    #[error("no Vulkan device matches `{wanted}`; available: {available}")]
    /// `GpuOptions::device` matched no device.
    DeviceNotFound {
        /** What was asked for. */
        wanted: String,
        /** The devices there are. */
        available: String,
    },
    #[error("validation was requested but VK_LAYER_KHRONOS_validation is not installed (`apt-get install vulkan-validationlayers`)")]
    /// Validation was asked for and the layer is missing.
    NoValidationLayer,
    #[error("GPU memory: {0}")]
    /// An allocation failed.
    Memory(#[from] gpu_allocator::AllocationError),
    #[error(transparent)]
    /// A configuration value was refused.
    Config(#[from] ConfigError),
    #[error("pipeline cache {path}: {error}")]
    /// The pipeline cache file could not be read or written.
    PipelineCache {
        /** The file. */
        path: String,
        /** What went wrong. */
        error: String,
    },
    #[error("cannot present to the window: {0}")]
    /// The window's surface cannot be presented to.
    NoPresentation(String),
    #[error("the plan renders into output images handed in per frame (an OpenXR swapchain's), but none were given")]
    /// The plan renders into handed-in images and the frame had none.
    NoOutputImages,
    #[error("output image {index} asked for, but {count} were handed in")]
    /// An output image index past those handed in.
    NoSuchOutputImage {
        /** The index asked for. */
        index: usize,
        /** How many were handed in. */
        count: usize,
    },
    #[error("more than {limit} distinct output images handed in to one renderer: reuse images (a swapchain's), or make a new renderer")]
    /// More distinct output images than a renderer keeps framebuffers for.
    TooManyOutputImages {
        /** The most it keeps (`render::MAX_OUTPUT_IMAGES`). */
        limit: usize,
    },
    #[error("readback asked for before any frame was rendered")]
    /// Readback before any frame.
    NoFrameRendered,
    #[error("the figures of frame {frame} were asked for after its frame slot {slot} was recorded into again: read a frame's figures before the renderer cycles back to its slot")]
    /// A frame's figures asked for after its slot was reused.
    FrameSlotReused {
        /** The frame's number. */
        frame: u64,
        /** Its slot. */
        slot: usize,
    },
    #[error("frame {frame} has not finished on the GPU and its frame slot {slot} is asked for again: wait for that frame's fence before recording the next frame into slot {slot} (and submit every frame recorded)")]
    /// A frame recorded into a slot whose previous frame has not run to its end.
    SlotInFlight {
        /** The frame still in the slot. */
        frame: u64,
        /** The slot. */
        slot: usize,
    },
    #[error("the Vulkan device is lost ({call} reported VK_ERROR_DEVICE_LOST): every later call on it fails; make a new Gpu, and a new renderer or layer on it")]
    /// The device was lost: every call after that on it is this error.
    DeviceLost {
        /** The call that found it lost. */
        call: &'static str,
    },
    #[error("frames in flight: {0}")]
    /// A frame loop misused (a slot begun twice, a frame from another loop).
    FramesInFlight(String),
    #[error("Vulkan validation reported {} message(s):\n{}", .0.len(), .0.join("\n"))]
    /// Validation messages (only with validation on).
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
