//! One descriptor set and the pipeline layout around it, made from what each binding holds:
//! the scene's bindings and every sampled set are made here.

use ash::vk;

use crate::gpu::{
    Buffer, Description, DescriptorPool, DescriptorSetLayout, Gpu, GpuError, ImageView,
    PipelineLayout, VkResultExt,
};

/// What one binding holds.
pub(crate) enum Resource<'a> {
    Uniform(&'a Buffer),
    Storage(&'a Buffer),
    /// An image view sampled through `sampler`, in `SHADER_READ_ONLY_OPTIMAL`.
    Sampled(&'a ImageView, vk::Sampler),
}

pub(crate) struct Binding<'a> {
    pub binding: u32,
    pub stages: vk::ShaderStageFlags,
    pub resource: Resource<'a>,
}

impl Resource<'_> {
    fn descriptor_type(&self) -> vk::DescriptorType {
        match self {
            Resource::Uniform(_) => vk::DescriptorType::UNIFORM_BUFFER,
            Resource::Storage(_) => vk::DescriptorType::STORAGE_BUFFER,
            Resource::Sampled(..) => vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
        }
    }
}

/// A descriptor set with its layout, pool and pipeline layout, all owned.
pub(crate) struct DescriptorSet {
    pub layout: PipelineLayout,
    /// What the pipeline layout is made of: pipelines for identically described (compatible)
    /// layouts are shared (see `gpu::ObjectCache`).
    pub layout_description: Description,
    _set_layout: DescriptorSetLayout,
    _pool: DescriptorPool,
    pub set: vk::DescriptorSet,
}

impl DescriptorSet {
    /// A set holding `bindings`, written, in a pipeline layout with `push` constants (if any).
    pub fn new(
        gpu: &Gpu,
        bindings: &[Binding],
        push: Option<vk::PushConstantRange>,
    ) -> Result<Self, GpuError> {
        let device = gpu.device();
        let layout_bindings: Vec<vk::DescriptorSetLayoutBinding> = bindings
            .iter()
            .map(|b| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(b.binding)
                    .descriptor_type(b.resource.descriptor_type())
                    .descriptor_count(1)
                    .stage_flags(b.stages)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&layout_bindings);
        // SAFETY (every call): plain object creation and a descriptor update with locals alive
        // for the call; every handle is owned by the returned value.
        let set_layout = DescriptorSetLayout::from_raw(
            &gpu.dev,
            unsafe { device.create_descriptor_set_layout(&info, None) }
                .vk("vkCreateDescriptorSetLayout")?,
        );
        let sizes: Vec<vk::DescriptorPoolSize> = layout_bindings
            .iter()
            .map(|b| vk::DescriptorPoolSize {
                ty: b.descriptor_type,
                descriptor_count: 1,
            })
            .collect();
        let pool_info = vk::DescriptorPoolCreateInfo::default()
            .max_sets(1)
            .pool_sizes(&sizes);
        let pool = DescriptorPool::from_raw(
            &gpu.dev,
            unsafe { device.create_descriptor_pool(&pool_info, None) }
                .vk("vkCreateDescriptorPool")?,
        );
        let layouts = [set_layout.raw];
        let alloc = vk::DescriptorSetAllocateInfo::default()
            .descriptor_pool(pool.raw)
            .set_layouts(&layouts);
        let set =
            unsafe { device.allocate_descriptor_sets(&alloc) }.vk("vkAllocateDescriptorSets")?[0];
        write(device, set, bindings);
        let pushes: Vec<vk::PushConstantRange> = push.into_iter().collect();
        let layout_info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&layouts)
            .push_constant_ranges(&pushes);
        let layout = PipelineLayout::from_raw(
            &gpu.dev,
            unsafe { device.create_pipeline_layout(&layout_info, None) }
                .vk("vkCreatePipelineLayout")?,
        );
        Ok(DescriptorSet {
            layout,
            layout_description: describe_layout(&layout_bindings, push),
            _set_layout: set_layout,
            _pool: pool,
            set,
        })
    }
}

/// One binding's descriptor info, kept alive for the update.
enum Info {
    Buffer([vk::DescriptorBufferInfo; 1]),
    Image([vk::DescriptorImageInfo; 1]),
}

/// Points every binding of `set` at its resource.
fn write(device: &ash::Device, set: vk::DescriptorSet, bindings: &[Binding]) {
    let infos: Vec<Info> = bindings
        .iter()
        .map(|b| match b.resource {
            Resource::Uniform(buffer) | Resource::Storage(buffer) => {
                Info::Buffer([vk::DescriptorBufferInfo {
                    buffer: buffer.raw,
                    offset: 0,
                    range: vk::WHOLE_SIZE,
                }])
            }
            Resource::Sampled(view, sampler) => Info::Image([vk::DescriptorImageInfo {
                sampler,
                image_view: view.raw,
                image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            }]),
        })
        .collect();
    let writes: Vec<vk::WriteDescriptorSet> = bindings
        .iter()
        .zip(&infos)
        .map(|(b, info)| {
            let write = vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(b.binding)
                .descriptor_type(b.resource.descriptor_type());
            match info {
                Info::Buffer(buffer) => write.buffer_info(buffer),
                Info::Image(image) => write.image_info(image),
            }
        })
        .collect();
    // SAFETY: the set is idle (just allocated) and every info outlives the call.
    unsafe { device.update_descriptor_sets(&writes, &[]) };
}

/// A pipeline layout's description: its bindings and push-constant range.
fn describe_layout(
    bindings: &[vk::DescriptorSetLayoutBinding],
    push: Option<vk::PushConstantRange>,
) -> Description {
    bindings
        .iter()
        .flat_map(|b| {
            [
                b.binding as u64,
                b.descriptor_type.as_raw() as u64,
                b.stage_flags.as_raw() as u64,
            ]
        })
        .chain(push.map_or([0, 0], |p| [p.stage_flags.as_raw() as u64, p.size as u64]))
        .collect()
}
