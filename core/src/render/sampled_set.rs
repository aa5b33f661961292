//! The resources of a full-view pass that samples an earlier pass's image: a descriptor set
//! with the image (bilinear, clamped) and a uniform block, and the pipeline layout around it.
//! Foveated composition and the MFFR far composite each own one.

use ash::vk;

use crate::gpu::{
    Buffer, Description, DescriptorPool, DescriptorSetLayout, Gpu, GpuError, Image, ImageView,
    MemoryLocation, PipelineLayout, Sampler, VkResultExt,
};

pub(crate) struct SampledSet {
    pub layout: PipelineLayout,
    /// What the layout is made of (see `SceneBindings::layout_description`).
    pub layout_description: Description,
    _set_layout: DescriptorSetLayout,
    _pool: DescriptorPool,
    pub set: vk::DescriptorSet,
    _sampler: Sampler,
    _views: Vec<ImageView>,
    pub uniforms: Buffer,
}

impl SampledSet {
    /// Binding 0: `images[0]` (every layer: an array view when it has more than one, or when
    /// `arrays` asks for one), binding 3: `images[1]` when there is a second; binding 1: a uniform block of `uniform_bytes`;
    /// binding 2, in counting frames only, the fragment counter; `push_bytes` of fragment push
    /// constants (0 for none).
    pub fn new(
        gpu: &Gpu,
        images: &[&Image],
        arrays: bool,
        uniform_bytes: u64,
        push_bytes: u32,
        counter: Option<&Buffer>,
    ) -> Result<Self, GpuError> {
        let device = gpu.device();
        let counter_binding = vk::DescriptorSetLayoutBinding::default()
            .binding(2)
            .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
            .descriptor_count(1)
            .stage_flags(vk::ShaderStageFlags::FRAGMENT);
        let image_binding = |binding| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::FRAGMENT)
        };
        let image_bindings = [0, 3];
        let mut bindings = vec![
            image_binding(0),
            vk::DescriptorSetLayoutBinding::default()
                .binding(1)
                .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::FRAGMENT),
        ];
        bindings.extend(counter.map(|_| counter_binding));
        bindings.extend(
            image_bindings[1..images.len()]
                .iter()
                .map(|&b| image_binding(b)),
        );
        // SAFETY: plain object creation; every handle is owned by the returned value.
        let set_layout = DescriptorSetLayout::from_raw(
            &gpu.dev,
            unsafe {
                device.create_descriptor_set_layout(
                    &vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings),
                    None,
                )
            }
            .vk("vkCreateDescriptorSetLayout")?,
        );
        let sizes: Vec<vk::DescriptorPoolSize> = bindings
            .iter()
            .map(|b| vk::DescriptorPoolSize {
                ty: b.descriptor_type,
                descriptor_count: 1,
            })
            .collect();
        let pool = DescriptorPool::from_raw(
            &gpu.dev,
            unsafe {
                device.create_descriptor_pool(
                    &vk::DescriptorPoolCreateInfo::default()
                        .max_sets(1)
                        .pool_sizes(&sizes),
                    None,
                )
            }
            .vk("vkCreateDescriptorPool")?,
        );
        let layouts = [set_layout.raw];
        let set = unsafe {
            device.allocate_descriptor_sets(
                &vk::DescriptorSetAllocateInfo::default()
                    .descriptor_pool(pool.raw)
                    .set_layouts(&layouts),
            )
        }
        .vk("vkAllocateDescriptorSets")?[0];
        let sampler_info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(0.0);
        let sampler = Sampler::from_raw(
            &gpu.dev,
            unsafe { device.create_sampler(&sampler_info, None) }.vk("vkCreateSampler")?,
        );
        let views = images
            .iter()
            .map(|image| image.view(0, image.layers, arrays || image.layers > 1))
            .collect::<Result<Vec<_>, _>>()?;
        let uniforms = Buffer::new(
            gpu,
            "sampled pass uniforms",
            uniform_bytes,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let image_infos: Vec<[vk::DescriptorImageInfo; 1]> = views
            .iter()
            .map(|view| {
                [vk::DescriptorImageInfo {
                    sampler: sampler.raw,
                    image_view: view.raw,
                    image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                }]
            })
            .collect();
        let buffer_info = [vk::DescriptorBufferInfo {
            buffer: uniforms.raw,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let counter_info = counter.map(|c| {
            [vk::DescriptorBufferInfo {
                buffer: c.raw,
                offset: 0,
                range: vk::WHOLE_SIZE,
            }]
        });
        let mut writes: Vec<vk::WriteDescriptorSet> = image_bindings
            .iter()
            .zip(&image_infos)
            .map(|(&binding, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(binding)
                    .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                    .image_info(info)
            })
            .collect();
        writes.push(
            vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(1)
                .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                .buffer_info(&buffer_info),
        );
        if let Some(info) = &counter_info {
            writes.push(
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(2)
                    .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                    .buffer_info(info),
            );
        }
        unsafe { device.update_descriptor_sets(&writes, &[]) };
        let push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::FRAGMENT,
            offset: 0,
            size: push_bytes,
        }];
        let info = vk::PipelineLayoutCreateInfo::default().set_layouts(&layouts);
        let info = if push_bytes > 0 {
            info.push_constant_ranges(&push)
        } else {
            info
        };
        let layout = PipelineLayout::from_raw(
            &gpu.dev,
            unsafe { device.create_pipeline_layout(&info, None) }.vk("vkCreatePipelineLayout")?,
        );
        let layout_description = super::pipelines::describe_layout(&bindings, push_bytes);
        Ok(SampledSet {
            layout,
            layout_description,
            _set_layout: set_layout,
            _pool: pool,
            set,
            _sampler: sampler,
            _views: views,
            uniforms,
        })
    }
}
