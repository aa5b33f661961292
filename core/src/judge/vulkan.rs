//! The Vulkan objects the judge's passes share: one descriptor set of storage buffers, push
//! constants, and a compute pipeline per pass.

use ash::vk;

use crate::gpu::{
    DescriptorPool, DescriptorSetLayout, Gpu, GpuError, Pipeline, PipelineLayout, VkResultExt,
};
use crate::shaders::ShaderBinary;

/// The storage buffers the passes share, by binding (see `shaders/flip_common.glsl`).
pub(super) const BINDINGS: u32 = 9;

/// The descriptor set layout (every binding a storage buffer) and the pipeline layout with
/// `push_bytes` of push constants, which every pass shares.
pub(super) fn layouts(
    gpu: &Gpu,
    push_bytes: u32,
) -> Result<(DescriptorSetLayout, PipelineLayout), GpuError> {
    let device = gpu.device();
    let bindings: Vec<_> = (0..BINDINGS)
        .map(|b| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(b)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE)
        })
        .collect();
    let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
    // SAFETY: valid create infos; each handle is owned by the value returned.
    let raw = unsafe { device.create_descriptor_set_layout(&info, None) }
        .vk("vkCreateDescriptorSetLayout")?;
    let set_layout = DescriptorSetLayout::from_raw(&gpu.dev, raw);
    let ranges = [vk::PushConstantRange::default()
        .stage_flags(vk::ShaderStageFlags::COMPUTE)
        .size(push_bytes)];
    let set_layouts = [set_layout.raw];
    let info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(&set_layouts)
        .push_constant_ranges(&ranges);
    let raw = unsafe { device.create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")?;
    Ok((set_layout, PipelineLayout::from_raw(&gpu.dev, raw)))
}

/// A pool for the one descriptor set.
pub(super) fn descriptor_pool(gpu: &Gpu) -> Result<DescriptorPool, GpuError> {
    let sizes = [vk::DescriptorPoolSize::default()
        .ty(vk::DescriptorType::STORAGE_BUFFER)
        .descriptor_count(BINDINGS)];
    let info = vk::DescriptorPoolCreateInfo::default()
        .max_sets(1)
        .pool_sizes(&sizes);
    // SAFETY: valid create info; the pool is owned by the value returned.
    let raw =
        unsafe { gpu.device().create_descriptor_pool(&info, None) }.vk("vkCreateDescriptorPool")?;
    Ok(DescriptorPool::from_raw(&gpu.dev, raw))
}

/// The compute pipeline of `shader` in `layout`.
pub(super) fn compute_pipeline(
    gpu: &Gpu,
    layout: &PipelineLayout,
    shader: &ShaderBinary,
) -> Result<Pipeline, GpuError> {
    let module = gpu.shader_module(shader)?;
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module.raw)
        .name(c"main");
    let info = [vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout.raw)];
    // SAFETY: valid create info; the module lives until the call returns.
    let raw = unsafe {
        gpu.device()
            .create_compute_pipelines(vk::PipelineCache::null(), &info, None)
    }
    .map_err(|(_, e)| e)
    .vk("vkCreateComputePipelines")?;
    Ok(Pipeline::from_raw(&gpu.dev, raw[0]))
}
