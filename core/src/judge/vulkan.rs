//! The Vulkan objects the judge's passes share: one descriptor set of storage buffers, push
//! constants, and a compute pipeline per pass.

use ash::vk;

use crate::gpu::{
    access, memory_barrier, Buffer, DescriptorPool, DescriptorSetLayout, Gpu, GpuError, Pipeline,
    PipelineLayout, VkResultExt,
};
use crate::shaders::{
    ShaderBinary, FLIP_COMBINE_COMP, FLIP_GATHER_COMP, FLIP_HISTOGRAM_COMP, FLIP_HORIZONTAL_COMP,
    FLIP_PREPARE_COMP, FLIP_REDUCE_COMP, FLIP_RESAMPLE_COMP, FLIP_VERTICAL_COMP,
};

/// One descriptor set of storage buffers and a pipeline layout with push constants, which every
/// pass of a judge shares.
pub(super) struct SharedSet {
    pub(super) set: vk::DescriptorSet,
    pub(super) layout: PipelineLayout,
    _pool: DescriptorPool,
    _set_layout: DescriptorSetLayout,
}

impl SharedSet {
    /// A set of `bindings` storage buffers, passes with `push_bytes` of push constants.
    pub(super) fn new(gpu: &Gpu, bindings: u32, push_bytes: u32) -> Result<Self, GpuError> {
        let (set_layout, layout) = layouts(gpu, bindings, push_bytes)?;
        let pool = descriptor_pool(gpu, bindings)?;
        let layouts = [set_layout.raw];
        let info = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool.raw)
            .set_layouts(&layouts);
        // SAFETY: the pool has room for this one set of this layout.
        let set = unsafe { gpu.device().allocate_descriptor_sets(&info) }
            .vk("vkAllocateDescriptorSets")?[0];
        Ok(SharedSet {
            set,
            layout,
            _pool: pool,
            _set_layout: set_layout,
        })
    }

    /// Points binding i at `buffers[i]`; the set must not be in use (every judgement waits
    /// for its submission).
    pub(super) fn bind(&self, gpu: &Gpu, buffers: &[&Buffer]) {
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = buffers
            .iter()
            .map(|b| {
                [vk::DescriptorBufferInfo::default()
                    .buffer(b.raw)
                    .range(vk::WHOLE_SIZE)]
            })
            .collect();
        let writes: Vec<_> = infos
            .iter()
            .enumerate()
            .map(|(binding, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(self.set)
                    .dst_binding(binding as u32)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(info)
            })
            .collect();
        // SAFETY: the set is not in use (see above); the buffers are live.
        unsafe { gpu.device().update_descriptor_sets(&writes, &[]) };
    }

    /// Records `pipeline` over `groups` workgroups with `push` as its push constants, after
    /// everything the compute passes recorded before it.
    pub(super) fn dispatch(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        pipeline: &Pipeline,
        push: &[u8],
        groups: [u32; 3],
    ) {
        // SAFETY: `cmd` is recording; the pipeline, layout and set outlive the submission
        // (`one_shot` waits for it); the push constants match the layout's range.
        unsafe {
            let rw = access::COMPUTE_READ_WRITE;
            memory_barrier(device, cmd, rw, rw);
            device.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw);
            device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::COMPUTE,
                self.layout.raw,
                0,
                &[self.set],
                &[],
            );
            device.cmd_push_constants(cmd, self.layout.raw, vk::ShaderStageFlags::COMPUTE, 0, push);
            device.cmd_dispatch(cmd, groups[0], groups[1], groups[2]);
        }
    }
}

/// The descriptor set layout (every binding a storage buffer) and the pipeline layout with
/// `push_bytes` of push constants.
fn layouts(
    gpu: &Gpu,
    bindings: u32,
    push_bytes: u32,
) -> Result<(DescriptorSetLayout, PipelineLayout), GpuError> {
    let device = gpu.device();
    let bindings: Vec<_> = (0..bindings)
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
fn descriptor_pool(gpu: &Gpu, bindings: u32) -> Result<DescriptorPool, GpuError> {
    let sizes = [vk::DescriptorPoolSize::default()
        .ty(vk::DescriptorType::STORAGE_BUFFER)
        .descriptor_count(bindings)];
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
        .flags(gpu.statistics_flags())
        .stage(stage)
        .layout(layout.raw)];
    // SAFETY: valid create info; the module lives until the call returns.
    let raw = unsafe {
        gpu.device()
            .create_compute_pipelines(vk::PipelineCache::null(), &info, None)
    }
    .map_err(|(_, e)| e)
    .vk("vkCreateComputePipelines")?;
    gpu.pipeline_with_statistics(raw[0])
}

/// Each pipeline's shader and what the driver's compiler reported of it (empty where the
/// device does not report statistics).
pub(super) fn statistics<'p>(
    pipelines: impl IntoIterator<Item = (&'p Pipeline, &'static ShaderBinary)>,
) -> Vec<(&'static str, &'p [crate::gpu::ShaderExecutable])> {
    pipelines
        .into_iter()
        .map(|(p, shader)| (shader.name, p.statistics.as_deref().unwrap_or(&[])))
        .collect()
}

/// FLIP's compute shaders, one pipeline each, in the order `FlipJudge` holds them.
pub(super) const FLIP_SHADERS: [&ShaderBinary; 8] = [
    &FLIP_PREPARE_COMP,
    &FLIP_REDUCE_COMP,
    &FLIP_HORIZONTAL_COMP,
    &FLIP_VERTICAL_COMP,
    &FLIP_COMBINE_COMP,
    &FLIP_RESAMPLE_COMP,
    &FLIP_HISTOGRAM_COMP,
    &FLIP_GATHER_COMP,
];

impl super::FlipJudge {
    /// Each compute pipeline's shader and what the driver's compiler reported of it (empty
    /// where the device does not report statistics: `FoveationLayer::shader_statistics`).
    pub fn shader_statistics(&self) -> Vec<(&'static str, &[crate::gpu::ShaderExecutable])> {
        statistics(self.pipelines.iter().zip(FLIP_SHADERS))
    }
}
