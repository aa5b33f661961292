use std::ffi::CStr;
use std::sync::Arc;

use ash::vk;

use super::descriptors::{Binding, DescriptorSet, Resource};
use super::targets::CompiledPass;
use crate::gpu::{
    Buffer, Gpu, GpuError, ImageView, Pipeline, PipelineKey, PipelineLayout, VkResultExt,
};
use crate::plan::{CompareOp, PipelineDesc, StencilOp, StencilState, VertexInput};
use crate::scene::Vertex;
use crate::shaders::ShaderBinary;

const ENTRY: &CStr = c"main";

/// A lit scene's resources, as the scene shaders bind them: its three texture arrays (5–7)
/// and their sampler, its materials (8) and its lights (9).
#[derive(Clone, Copy)]
pub(crate) struct LitBindings<'a> {
    pub textures: &'a [ImageView; 3],
    pub sampler: vk::Sampler,
    pub materials: &'a Buffer,
    pub lighting: &'a Buffer,
}

/// The scene shaders' resources: views (binding 0), instances (1: foveate's scene's, none when
/// an engine draws) and, only when their effect is on, the fragment counter (2), the stencil
/// mask shapes (3), culled instance ids (4) and a lit scene's textures (5–7), materials (8)
/// and lights (9); the view index or mask shape set as a vertex push constant.
pub(crate) fn scene_bindings(
    gpu: &Gpu,
    views: &Buffer,
    instances: Option<&Buffer>,
    counter: Option<&Buffer>,
    masks: Option<&Buffer>,
    instance_ids: Option<&Buffer>,
    lit: Option<LitBindings>,
) -> Result<DescriptorSet, GpuError> {
    use vk::ShaderStageFlags as Stage;
    let binding = |binding, stages, resource| Binding {
        binding,
        stages,
        resource,
    };
    let mut bindings = vec![binding(
        0,
        Stage::VERTEX | Stage::FRAGMENT,
        Resource::Uniform(views),
    )];
    bindings.extend(instances.map(|b| binding(1, Stage::VERTEX, Resource::Storage(b))));
    bindings.extend(counter.map(|b| binding(2, Stage::FRAGMENT, Resource::Storage(b))));
    bindings.extend(masks.map(|b| binding(3, Stage::VERTEX, Resource::Uniform(b))));
    bindings.extend(instance_ids.map(|b| binding(4, Stage::VERTEX, Resource::Storage(b))));
    if let Some(m) = lit {
        let textures = (5..).zip(m.textures);
        bindings.extend(
            textures
                .map(|(i, view)| binding(i, Stage::FRAGMENT, Resource::Sampled(view, m.sampler))),
        );
        bindings.push(binding(8, Stage::FRAGMENT, Resource::Storage(m.materials)));
        bindings.push(binding(9, Stage::FRAGMENT, Resource::Uniform(m.lighting)));
    }
    let push = vk::PushConstantRange {
        stage_flags: Stage::VERTEX,
        offset: 0,
        size: 4,
    };
    DescriptorSet::new(gpu, &bindings, Some(push))
}

/// The plan's stencil state in Vulkan's terms (failing fragments keep the value).
pub(super) fn vk_stencil(s: StencilState) -> vk::StencilOpState {
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
        let vert = gpu.shader_module(desc.vertex)?;
        let frag = gpu.shader_module(desc.fragment)?;
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
        // One state per colour attachment of the subpass (a second: the next history).
        let blend_attachments = vec![
            vk::PipelineColorBlendAttachmentState::default()
                .color_write_mask(write);
            compiled.colour_attachments as usize
        ];
        let blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let mut dynamic_states = vec![vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        if desc.dynamic_stencil_reference {
            dynamic_states.push(vk::DynamicState::STENCIL_REFERENCE);
        }
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        // Where the device reports its compiler's statistics, every pipeline captures them.
        let info = vk::GraphicsPipelineCreateInfo::default()
            .flags(gpu.statistics_flags())
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
                .create_graphics_pipelines(gpu.pipeline_cache.cache.raw, &[info], None)
        }
        .map_err(|(_, e)| e)
        .vk("vkCreateGraphicsPipelines")?;
        gpu.pipeline_with_statistics(pipelines[0])
    })
}
