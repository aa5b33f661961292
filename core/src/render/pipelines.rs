use std::ffi::CStr;
use std::sync::Arc;

use ash::vk;

use super::materials::MaterialSet;
use super::targets::CompiledPass;
use crate::gpu::{
    Buffer, Description, DescriptorPool, DescriptorSetLayout, Gpu, GpuError, ImageView, Pipeline,
    PipelineKey, PipelineLayout, ShaderModule, VkResultExt,
};
use crate::plan::{CompareOp, PipelineDesc, StencilOp, StencilState, VertexInput};
use crate::scene::Vertex;
use crate::shaders::ShaderBinary;

const ENTRY: &CStr = c"main";

/// The scene shaders' resources: views (binding 0), instances (1) and, only when their effect
/// is on, the fragment counter (2), the stencil mask shapes (3), culled instance ids (4) and a
/// lit scene's textures (5–7), materials (8) and lights (9).
pub(crate) struct SceneBindings {
    pub layout: PipelineLayout,
    /// What the layout is made of: pipelines for identically described (compatible) layouts
    /// are shared.
    pub layout_description: Description,
    _set_layout: DescriptorSetLayout,
    _pool: DescriptorPool,
    pub set: vk::DescriptorSet,
}

impl SceneBindings {
    pub fn new(
        gpu: &Gpu,
        views: &Buffer,
        instances: &Buffer,
        counter: Option<&Buffer>,
        masks: Option<&Buffer>,
        instance_ids: Option<&Buffer>,
        lit: Option<&MaterialSet>,
    ) -> Result<Self, GpuError> {
        let fragment = vk::ShaderStageFlags::FRAGMENT;
        let device = gpu.device();
        // (binding, type, stages, buffer): only what this plan uses exists.
        let uniform = vk::DescriptorType::UNIFORM_BUFFER;
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        let resources: Vec<(u32, vk::DescriptorType, vk::ShaderStageFlags, &Buffer)> = [
            Some((
                0,
                uniform,
                vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                views,
            )),
            Some((1, storage, vk::ShaderStageFlags::VERTEX, instances)),
            counter.map(|b| (2, storage, vk::ShaderStageFlags::FRAGMENT, b)),
            masks.map(|b| (3, uniform, vk::ShaderStageFlags::VERTEX, b)),
            instance_ids.map(|b| (4, storage, vk::ShaderStageFlags::VERTEX, b)),
            lit.map(|m| (8, storage, fragment, &m.materials)),
            lit.map(|m| (9, uniform, fragment, &m.lighting)),
        ]
        .into_iter()
        .flatten()
        .collect();
        let sampled = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        let textures: Vec<(u32, &ImageView)> = lit
            .map(|m| (5..).zip(m.views.iter()).collect())
            .unwrap_or_default();
        let bindings: Vec<vk::DescriptorSetLayoutBinding> = resources
            .iter()
            .map(|&(binding, ty, stages, _)| (binding, ty, stages))
            .chain(
                textures
                    .iter()
                    .map(|&(binding, _)| (binding, sampled, fragment)),
            )
            .map(|(binding, ty, stages)| {
                vk::DescriptorSetLayoutBinding::default()
                    .binding(binding)
                    .descriptor_type(ty)
                    .descriptor_count(1)
                    .stage_flags(stages)
            })
            .collect();
        let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings);
        // SAFETY: plain object creation with locals alive for each call.
        let set_layout = DescriptorSetLayout::from_raw(
            &gpu.dev,
            unsafe { device.create_descriptor_set_layout(&info, None) }
                .vk("vkCreateDescriptorSetLayout")?,
        );
        let sizes = [
            vk::DescriptorPoolSize {
                ty: uniform,
                descriptor_count: 2,
            },
            vk::DescriptorPoolSize {
                ty: storage,
                descriptor_count: 4,
            },
            vk::DescriptorPoolSize {
                ty: sampled,
                descriptor_count: 3,
            },
        ];
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

        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = resources
            .iter()
            .map(|r| {
                [vk::DescriptorBufferInfo {
                    buffer: r.3.raw,
                    offset: 0,
                    range: vk::WHOLE_SIZE,
                }]
            })
            .collect();
        let image_infos: Vec<[vk::DescriptorImageInfo; 1]> = textures
            .iter()
            .map(|&(_, view)| {
                [vk::DescriptorImageInfo {
                    sampler: lit.expect("textures only when lit").sampler.raw,
                    image_view: view.raw,
                    image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                }]
            })
            .collect();
        let writes: Vec<vk::WriteDescriptorSet> = resources
            .iter()
            .zip(&infos)
            .map(|(r, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(r.0)
                    .descriptor_type(r.1)
                    .buffer_info(info)
            })
            .chain(textures.iter().zip(&image_infos).map(|(t, info)| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(t.0)
                    .descriptor_type(sampled)
                    .image_info(info)
            }))
            .collect();
        unsafe { device.update_descriptor_sets(&writes, &[]) };

        let push = [vk::PushConstantRange {
            stage_flags: vk::ShaderStageFlags::VERTEX,
            offset: 0,
            size: 4,
        }];
        let layout_info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&layouts)
            .push_constant_ranges(&push);
        let layout = PipelineLayout::from_raw(
            &gpu.dev,
            unsafe { device.create_pipeline_layout(&layout_info, None) }
                .vk("vkCreatePipelineLayout")?,
        );
        let layout_description = describe_layout(&bindings, push[0].size);
        Ok(SceneBindings {
            layout,
            layout_description,
            _set_layout: set_layout,
            _pool: pool,
            set,
        })
    }
}

/// A pipeline layout's description: its bindings and push-constant bytes. Pipelines made with
/// identically described layouts are compatible, so they are shared (see `gpu::ObjectCache`).
pub(crate) fn describe_layout(
    bindings: &[vk::DescriptorSetLayoutBinding],
    push_bytes: u32,
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
        .chain([push_bytes as u64])
        .collect()
}

/// The plan's stencil state in Vulkan's terms (failing fragments keep the value).
fn vk_stencil(s: StencilState) -> vk::StencilOpState {
    vk::StencilOpState {
        fail_op: vk::StencilOp::KEEP,
        pass_op: match s.pass {
            StencilOp::Keep => vk::StencilOp::KEEP,
            StencilOp::Replace => vk::StencilOp::REPLACE,
        },
        depth_fail_op: vk::StencilOp::KEEP,
        compare_op: match s.compare {
            CompareOp::Always => vk::CompareOp::ALWAYS,
            CompareOp::Equal => vk::CompareOp::EQUAL,
        },
        compare_mask: s.compare_mask,
        write_mask: s.write_mask,
        reference: s.reference,
    }
}

fn shader_module(gpu: &Gpu, shader: &ShaderBinary) -> Result<ShaderModule, GpuError> {
    let words = shader.words();
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    let raw =
        unsafe { gpu.device().create_shader_module(&info, None) }.vk("vkCreateShaderModule")?;
    Ok(ShaderModule::from_raw(&gpu.dev, raw))
}

/// The specialisation info of one stage: the constants its shader declares, from `desc`.
struct StageConstants {
    entries: Vec<vk::SpecializationMapEntry>,
    data: Vec<u8>,
}

impl StageConstants {
    fn new(desc: &PipelineDesc, shader: &ShaderBinary) -> Self {
        let constants = desc.stage_constants(shader);
        StageConstants {
            entries: (0..)
                .zip(&constants)
                .map(|(i, &(id, _))| vk::SpecializationMapEntry {
                    constant_id: id,
                    offset: 4 * i,
                    size: 4,
                })
                .collect(),
            data: constants.iter().flat_map(|c| c.1.to_le_bytes()).collect(),
        }
    }

    fn info(&self) -> vk::SpecializationInfo<'_> {
        vk::SpecializationInfo::default()
            .map_entries(&self.entries)
            .data(&self.data)
    }
}

/// The scene's vertex layout (`scene::Vertex`): position, normal, uv, tangent.
fn scene_vertex_attributes() -> [vk::VertexInputAttributeDescription; 4] {
    let attribute = |location, format, offset| vk::VertexInputAttributeDescription {
        location,
        binding: 0,
        format,
        offset,
    };
    [
        attribute(0, vk::Format::R32G32B32_SFLOAT, 0),
        attribute(1, vk::Format::R32G32B32_SFLOAT, 12),
        attribute(2, vk::Format::R32G32_SFLOAT, 24),
        attribute(3, vk::Format::R32G32B32A32_SFLOAT, 32),
    ]
}

/// The pipeline `desc` states, for a pass with `samples` compiled as `compiled`, with `layout`
/// (made as `layout_description` says). Shared with any live pipeline of the same key.
pub(crate) fn compile_pipeline(
    gpu: &Gpu,
    desc: &PipelineDesc,
    samples: u32,
    compiled: &CompiledPass,
    layout: &PipelineLayout,
    layout_description: &[u64],
) -> Result<Arc<Pipeline>, GpuError> {
    let key = PipelineKey {
        desc: desc.clone(),
        samples,
        render_pass: compiled.description.clone(),
        layout: layout_description.to_vec(),
    };
    gpu.pipelines.get_or_create(key, || {
        let vert = shader_module(gpu, desc.vertex)?;
        let frag = shader_module(gpu, desc.fragment)?;
        let (vert_constants, frag_constants) = (
            StageConstants::new(desc, desc.vertex),
            StageConstants::new(desc, desc.fragment),
        );
        let (vert_spec, frag_spec) = (vert_constants.info(), frag_constants.info());
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(vert.raw)
                .name(ENTRY)
                .specialization_info(&vert_spec),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(frag.raw)
                .name(ENTRY)
                .specialization_info(&frag_spec),
        ];
        let bindings = [vk::VertexInputBindingDescription {
            binding: 0,
            stride: std::mem::size_of::<Vertex>() as u32,
            input_rate: vk::VertexInputRate::VERTEX,
        }];
        let attributes = scene_vertex_attributes();
        let vertex_input = match desc.vertex_input {
            VertexInput::SceneVertices => vk::PipelineVertexInputStateCreateInfo::default()
                .vertex_binding_descriptions(&bindings)
                .vertex_attribute_descriptions(&attributes),
            VertexInput::Generated => vk::PipelineVertexInputStateCreateInfo::default(),
        };
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .depth_clamp_enable(desc.depth_clamp)
            // The projections keep the image upright (Vulkan NDC y down), so on-screen winding is
            // the geometry's own: counter-clockwise faces the viewer.
            .cull_mode(if desc.cull_back_faces {
                vk::CullModeFlags::BACK
            } else {
                vk::CullModeFlags::NONE
            })
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::from_raw(samples));
        let stencil = desc.stencil.map(vk_stencil);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(desc.depth_test)
            .depth_write_enable(desc.depth_test)
            // Reverse-Z: nearer is greater.
            .depth_compare_op(vk::CompareOp::GREATER)
            .stencil_test_enable(stencil.is_some())
            .front(stencil.unwrap_or_default())
            .back(stencil.unwrap_or_default());
        let write = if desc.writes_colour {
            vk::ColorComponentFlags::RGBA
        } else {
            vk::ColorComponentFlags::empty()
        };
        let blend_attachments =
            [vk::PipelineColorBlendAttachmentState::default().color_write_mask(write)];
        let blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let mut dynamic_states = vec![vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        if desc.dynamic_stencil_reference {
            dynamic_states.push(vk::DynamicState::STENCIL_REFERENCE);
        }
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(layout.raw)
            .render_pass(compiled.render_pass.raw)
            .subpass(0);
        // SAFETY: all referenced state lives on this stack frame for the call.
        let pipelines = unsafe {
            gpu.device()
                .create_graphics_pipelines(gpu.pipeline_cache.raw, &[info], None)
        }
        .map_err(|(_, e)| e)
        .vk("vkCreateGraphicsPipelines")?;
        Ok(Pipeline::from_raw(&gpu.dev, pipelines[0]))
    })
}
