//! The resources of a full-view pass that samples an earlier pass's image: a descriptor set
//! with the image (bilinear, clamped) and a uniform block, and the pipeline layout around it.
//! Foveated composition and the MFFR far composite each own one.

use ash::vk;

use super::descriptors::{Binding, DescriptorSet, Resource};
use crate::gpu::{Buffer, Gpu, GpuError, Image, ImageView, MemoryLocation, Sampler, VkResultExt};

pub(crate) struct SampledSet {
    /// The set, its layout and the pipeline layout around it.
    pub descriptors: DescriptorSet,
    _sampler: Sampler,
    _views: Vec<ImageView>,
    pub uniforms: Buffer,
}

impl SampledSet {
    /// Binding 0: `images[0]` (every layer: an array view when it has more than one, or when
    /// `arrays` asks for one), binding 3: `images[1]` when there is a second; binding 1: a
    /// uniform block of `uniform_bytes`; binding 2, in counting frames only, the fragment
    /// counter; `push_bytes` of fragment push constants (0 for none).
    pub fn new(
        gpu: &Gpu,
        images: &[&Image],
        arrays: bool,
        uniform_bytes: u64,
        push_bytes: u32,
        counter: Option<&Buffer>,
    ) -> Result<Self, GpuError> {
        let sampler_info = vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(0.0);
        // SAFETY: plain object creation; the sampler is owned by the returned value.
        let sampler = Sampler::from_raw(
            &gpu.dev,
            unsafe { gpu.device().create_sampler(&sampler_info, None) }.vk("vkCreateSampler")?,
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
        let fragment = vk::ShaderStageFlags::FRAGMENT;
        let binding = |binding, resource| Binding {
            binding,
            stages: fragment,
            resource,
        };
        let mut bindings = vec![
            binding(0, Resource::Sampled(&views[0], sampler.raw)),
            binding(1, Resource::Uniform(&uniforms)),
        ];
        bindings.extend(counter.map(|c| binding(2, Resource::Storage(c))));
        bindings.extend(
            views
                .get(1)
                .map(|v| binding(3, Resource::Sampled(v, sampler.raw))),
        );
        let push = (push_bytes > 0).then_some(vk::PushConstantRange {
            stage_flags: fragment,
            offset: 0,
            size: push_bytes,
        });
        let descriptors = DescriptorSet::new(gpu, &bindings, push)?;
        Ok(SampledSet {
            descriptors,
            _sampler: sampler,
            _views: views,
            uniforms,
        })
    }
}
