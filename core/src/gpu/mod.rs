//! Vulkan through `ash`: the context (instance, device, queue, validation), memory through
//! `gpu-allocator`, RAII wrappers so each Vulkan object is owned by exactly one Rust value, and
//! presentation to a window's swapchain.

mod blit_layout;
mod cache;
mod context;
mod device_choice;
mod error;
mod handles;
mod lost;
mod memory;
mod open;
mod pipeline_cache;
mod present_copy;
mod shader_statistics;
mod submit;
mod swapchain;

pub use blit_layout::BlitSource;
pub use context::{
    DeviceInfo, Gpu, GpuOptions, RawHandles, VulkanCreator, DEPTH_RESOLVE_EXTENSIONS,
};
pub use error::GpuError;
internal_use!(error::VkResultExt);
internal_use!(handles::{
    CommandPool, DescriptorPool, DescriptorSetLayout, Event, Fence, Framebuffer, ImageView, Pipeline,
    PipelineCache, PipelineLayout, QueryPool, RenderPass, Sampler, Semaphore, ShaderModule,
});
pub(crate) use memory::pod_bytes;
pub use memory::{Image, ImageDesc};
internal_use!(memory::{Buffer, MemoryLocation});
pub use open::EngineDevice;
pub use shader_statistics::{ShaderExecutable, ShaderStatistic, StatisticValue};
pub use swapchain::{Acquired, Presented, Swapchain, SwapchainImage};

pub(crate) use cache::{Description, ObjectCache, PipelineKey};
pub(crate) use context::DeviceOwner;
pub(crate) use submit::{access, memory_barrier, transition_image, ImageState};
