//! Owned Vulkan handles: each wrapper destroys its handle on drop and keeps the device alive
//! until then.

use std::sync::Arc;

use ash::vk;

use super::DeviceOwner;

macro_rules! owned_handle {
    ($(#[$doc:meta])* $name:ident, $raw:ty, $destroy:ident) => {
        $(#[$doc])*
        pub struct $name {
            dev: Arc<DeviceOwner>,
            pub raw: $raw,
        }

        impl $name {
            /// Takes ownership of `raw`, which must have been created on `dev`'s device.
            pub(crate) fn from_raw(dev: &Arc<DeviceOwner>, raw: $raw) -> Self {
                dev.created(stringify!($name));
                Self { dev: dev.clone(), raw }
            }

            /// The device the handle was made on.
            #[allow(dead_code)]
            pub(crate) fn device(&self) -> &ash::Device {
                &self.dev.device
            }
        }

        impl Drop for $name {
            fn drop(&mut self) {
                // SAFETY: the handle was created on this device and is owned only here; users
                // keep it alive until the GPU work using it has completed (fence waited).
                unsafe { self.dev.device.$destroy(self.raw, None) }
                self.dev.destroyed(stringify!($name));
            }
        }
    };
}

owned_handle!(RenderPass, vk::RenderPass, destroy_render_pass);
owned_handle!(Framebuffer, vk::Framebuffer, destroy_framebuffer);
owned_handle!(PipelineLayout, vk::PipelineLayout, destroy_pipeline_layout);
owned_handle!(
    DescriptorSetLayout,
    vk::DescriptorSetLayout,
    destroy_descriptor_set_layout
);
owned_handle!(
    /// Descriptor sets allocated from the pool die with it.
    DescriptorPool,
    vk::DescriptorPool,
    destroy_descriptor_pool
);
owned_handle!(ShaderModule, vk::ShaderModule, destroy_shader_module);
owned_handle!(
    /// Command buffers allocated from the pool die with it.
    CommandPool,
    vk::CommandPool,
    destroy_command_pool
);
owned_handle!(Fence, vk::Fence, destroy_fence);
owned_handle!(Semaphore, vk::Semaphore, destroy_semaphore);
owned_handle!(
    /// Set by the GPU, read by the host: whether the work before it has finished.
    Event,
    vk::Event,
    destroy_event
);
owned_handle!(QueryPool, vk::QueryPool, destroy_query_pool);
owned_handle!(PipelineCache, vk::PipelineCache, destroy_pipeline_cache);
owned_handle!(ImageView, vk::ImageView, destroy_image_view);
owned_handle!(Sampler, vk::Sampler, destroy_sampler);

/// A pipeline, with what its driver's compiler reported of it where the device reports that.
pub struct Pipeline {
    dev: Arc<DeviceOwner>,
    pub raw: vk::Pipeline,
    /// Its executables' statistics, captured as it was created: none where the device does not
    /// report them (`VK_KHR_pipeline_executable_properties`).
    pub statistics: Option<Vec<super::ShaderExecutable>>,
}

impl Pipeline {
    /// Takes ownership of `raw`, which must have been created on `dev`'s device.
    pub(crate) fn from_raw(dev: &Arc<DeviceOwner>, raw: vk::Pipeline) -> Self {
        dev.created("Pipeline");
        Self {
            dev: dev.clone(),
            raw,
            statistics: None,
        }
    }
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        // SAFETY: as for every owned handle: created on this device, owned only here, kept
        // alive until the GPU work using it has completed.
        unsafe { self.dev.device.destroy_pipeline(self.raw, None) }
        self.dev.destroyed("Pipeline");
    }
}
