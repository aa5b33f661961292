//! Composition of a foveated frame (seed 001 §3.3–3.4, §3.6.1): each eye at full resolution,
//! the periphery view upscaled bilinearly and the fovea view blended over it with smoothstep
//! across the band at the fovea's edge. A technique in one place: its descriptor set, sampler,
//! uniforms, pipeline and recording.

use ash::vk;
use glam::Vec4;

use super::pipelines::{pass_pipeline, PipelineKind};
use crate::gpu::{
    Buffer, DescriptorPool, DescriptorSetLayout, Gpu, GpuError, Image, ImageView, MemoryLocation,
    Pipeline, PipelineLayout, Sampler, VkResultExt,
};
use crate::plan::{FramePlan, PassPlan};
use crate::view::{Eye, FovTangents};

/// The composition's uniform block (`Composite` in `shaders/composite.frag`, std140).
#[repr(C)]
#[derive(Clone, Copy)]
struct CompositeBlock {
    periphery: [Vec4; 2],
    fovea: [Vec4; 2],
    params: Vec4,
    screen: Vec4,
}

pub(crate) struct Composite {
    pub pipeline: Pipeline,
    pub layout: PipelineLayout,
    _set_layout: DescriptorSetLayout,
    _pool: DescriptorPool,
    pub set: vk::DescriptorSet,
    _sampler: Sampler,
    _views: ImageView,
    uniforms: Buffer,
}

impl Composite {
    /// Sets up composition for `pass`, sampling `views` (the scene pass's four layers).
    pub fn new(
        gpu: &Gpu,
        plan: &FramePlan,
        pass: &PassPlan,
        render_pass: vk::RenderPass,
        views: &Image,
    ) -> Result<Self, GpuError> {
        let device = gpu.device();
        let bindings = [
            vk::DescriptorSetLayoutBinding::default()
                .binding(0)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::FRAGMENT),
            vk::DescriptorSetLayoutBinding::default()
                .binding(1)
                .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::FRAGMENT),
        ];
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
        let sizes = [
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                descriptor_count: 1,
            },
            vk::DescriptorPoolSize {
                ty: vk::DescriptorType::UNIFORM_BUFFER,
                descriptor_count: 1,
            },
        ];
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
        let view = views.view(0, views.layers, true)?;
        let uniforms = Buffer::new(
            gpu,
            "composite",
            std::mem::size_of::<CompositeBlock>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let image_info = [vk::DescriptorImageInfo {
            sampler: sampler.raw,
            image_view: view.raw,
            image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        }];
        let buffer_info = [vk::DescriptorBufferInfo {
            buffer: uniforms.raw,
            offset: 0,
            range: vk::WHOLE_SIZE,
        }];
        let writes = [
            vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(0)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .image_info(&image_info),
            vk::WriteDescriptorSet::default()
                .dst_set(set)
                .dst_binding(1)
                .descriptor_type(vk::DescriptorType::UNIFORM_BUFFER)
                .buffer_info(&buffer_info),
        ];
        unsafe { device.update_descriptor_sets(&writes, &[]) };
        let layout = PipelineLayout::from_raw(
            &gpu.dev,
            unsafe {
                device.create_pipeline_layout(
                    &vk::PipelineLayoutCreateInfo::default().set_layouts(&layouts),
                    None,
                )
            }
            .vk("vkCreatePipelineLayout")?,
        );
        let pipeline = pass_pipeline(
            gpu,
            plan,
            pass,
            PipelineKind::Composite,
            render_pass,
            &layout,
        )?;
        Ok(Composite {
            pipeline,
            layout,
            _set_layout: set_layout,
            _pool: pool,
            set,
            _sampler: sampler,
            _views: view,
            uniforms,
        })
    }

    /// Writes this frame's windows: each eye's periphery and (gaze-dependent) fovea tangents.
    pub fn update(&mut self, plan: &FramePlan, fovea: &[FovTangents; 2]) {
        let g = plan
            .foveation
            .as_ref()
            .expect("composition is planned only with foveation");
        let tangents = |f: FovTangents| Vec4::from_array(f.as_array());
        let block = CompositeBlock {
            periphery: Eye::BOTH.map(|e| tangents(plan.eyes.fov(e))),
            fovea: fovea.map(tangents),
            params: Vec4::new(
                g.fovea_screen_px,
                g.blend_band_px,
                g.debug_tint as u32 as f32,
                0.0,
            ),
            screen: Vec4::new(
                plan.eye_resolution.width as f32,
                plan.eye_resolution.height as f32,
                0.0,
                0.0,
            ),
        };
        self.uniforms.write(&[block]);
    }
}
