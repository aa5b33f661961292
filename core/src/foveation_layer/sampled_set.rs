//! The resources of a full-view pass that samples an earlier pass's image: a descriptor set
//! with the image (bilinear, clamped) and a uniform block, and the pipeline layout around it.
//! Foveated composition and the MFFR far composite each own one.

use ash::vk;

use super::descriptors::{Binding, DescriptorSet, Resource};
use crate::gpu::{Buffer, Gpu, GpuError, Image, ImageView, MemoryLocation, Sampler, VkResultExt};

pub(crate) struct SampledSet {
    /// The set, its layout and the pipeline layout around it.
    pub descriptors: DescriptorSet,
    _samplers: Vec<Sampler>,
    _views: Vec<ImageView>,
    pub uniforms: Buffer,
}

impl SampledSet {
    /// One set per frame slot, each counting into its slot's counter (`counters`: one entry a
    /// slot), all sampling the same images.
    pub fn per_slot(
        gpu: &Gpu,
        images: &[&Image],
        arrays: bool,
        uniform_bytes: u64,
        push_bytes: u32,
        counters: &[Option<&Buffer>],
    ) -> Result<Vec<Self>, GpuError> {
        counters
            .iter()
            .map(|&counter| Self::new(gpu, images, arrays, uniform_bytes, push_bytes, counter))
            .collect()
    }

    /// Binding 0: `images[0]` (every layer: an array view when it has more than one, or when
    /// `arrays` asks for one; a depth image's depth), binding 3: `images[1]` when there is a
    /// second, binding 4: `images[2]` when there is a third, binding 5: `images[3]` when
    /// there is a fourth, binding 6: `images[4]` when there is a fifth; binding 1: a
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
        // Depth is read texel by texel: its formats need not filter linearly.
        let sampler = |filter| {
            let info = vk::SamplerCreateInfo::default()
                .mag_filter(filter)
                .min_filter(filter)
                .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
                .address_mode_u(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
                .max_lod(0.0);
            // SAFETY: plain object creation; the sampler is owned by the returned value.
            unsafe { gpu.device().create_sampler(&info, None) }
                .vk("vkCreateSampler")
                .map(|raw| Sampler::from_raw(&gpu.dev, raw))
        };
        let is_depth = |image: &Image| image.aspect.contains(vk::ImageAspectFlags::DEPTH);
        let samplers = images
            .iter()
            .map(|&image| {
                sampler(if is_depth(image) {
                    vk::Filter::NEAREST
                } else {
                    vk::Filter::LINEAR
                })
            })
            .collect::<Result<Vec<_>, _>>()?;
        let views = images
            .iter()
            .map(|image| image.sampled_view(0, image.layers, arrays || image.layers > 1))
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
            binding(0, Resource::Sampled(&views[0], samplers[0].raw)),
            binding(1, Resource::Uniform(&uniforms)),
        ];
        bindings.extend(counter.map(|c| binding(2, Resource::Storage(c))));
        for (b, (view, sampler)) in [3, 4, 5, 6]
            .into_iter()
            .zip(views.iter().zip(&samplers).skip(1))
        {
            bindings.push(binding(b, Resource::Sampled(view, sampler.raw)));
        }
        let push = (push_bytes > 0).then_some(vk::PushConstantRange {
            stage_flags: fragment,
            offset: 0,
            size: push_bytes,
        });
        let descriptors = DescriptorSet::new(gpu, &bindings, push)?;
        Ok(SampledSet {
            descriptors,
            _samplers: samplers,
            _views: views,
            uniforms,
        })
    }
}
