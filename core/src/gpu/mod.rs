//! Vulkan through `ash`: the context (instance, device, queue, validation), memory through
//! `gpu-allocator`, and RAII wrappers so each Vulkan object is owned by exactly one Rust value.

mod cache;
mod context;
mod error;
mod handles;
mod memory;
mod submit;

pub use context::{DeviceInfo, Gpu, GpuOptions};
pub use error::{GpuError, VkResultExt};
pub use handles::{
    CommandPool, DescriptorPool, DescriptorSetLayout, Fence, Framebuffer, ImageView, Pipeline,
    PipelineCache, PipelineLayout, QueryPool, RenderPass, Sampler, ShaderModule,
};
pub(crate) use memory::pod_bytes;
pub use memory::{Buffer, Image, ImageDesc, MemoryLocation};

pub(crate) use cache::{hash_word, name_word, Description, ObjectCache};
pub(crate) use context::DeviceOwner;
