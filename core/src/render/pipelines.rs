use std::ffi::CStr;

use ash::vk;

use crate::gpu::{
    Buffer, DescriptorPool, DescriptorSetLayout, Gpu, GpuError, Pipeline, PipelineLayout,
    ShaderModule, VkResultExt,
};
use crate::plan::{FramePlan, PassPlan, Submission};
use crate::scene::Vertex;
use crate::shaders::{
    ShaderBinary, COMPOSITE_FRAG, COMPOSITE_VERT, COVERAGE_FRAG, COVERAGE_VERT, MASK_FRAG,
    MASK_VERT, SCENE_FRAG, SCENE_FRAG_COUNTING, SCENE_VERT,
};

const ENTRY: &CStr = c"main";

/// The scene shaders' resources: views (binding 0), instances (1) and, only when fragment
/// counting is on, the counter (2).
pub(crate) struct SceneBindings {
    pub layout: PipelineLayout,
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
    ) -> Result<Self, GpuError> {
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
        ]
        .into_iter()
        .flatten()
        .collect();
        let bindings: Vec<vk::DescriptorSetLayoutBinding> = resources
            .iter()
            .map(|&(binding, ty, stages, _)| {
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
                descriptor_count: 2,
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
        Ok(SceneBindings {
            layout,
            _set_layout: set_layout,
            _pool: pool,
            set,
        })
    }
}

fn shader_module(gpu: &Gpu, shader: &ShaderBinary) -> Result<ShaderModule, GpuError> {
    let words = shader.words();
    let info = vk::ShaderModuleCreateInfo::default().code(&words);
    let raw =
        unsafe { gpu.device().create_shader_module(&info, None) }.vk("vkCreateShaderModule")?;
    Ok(ShaderModule::from_raw(&gpu.dev, raw))
}

/// The vertex shader's `VIEW_SOURCE` for a submission (see `shaders/scene.vert`).
fn view_source(submission: Submission) -> u32 {
    match submission {
        Submission::Multiview => 0,
        Submission::SingleEye(_) | Submission::PerObject => 1,
        Submission::Instanced => 2,
    }
}

/// What a pipeline of a scene pass draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum PipelineKind {
    /// The scene's meshes: depth tested and written, stencil tested when the pass has masks.
    Scene,
    /// Stencil mask fans: stencil written (reference set per draw), nothing else.
    Mask,
    /// The coverage probe: a full-view triangle, stencil tested, counted, nothing written.
    Coverage,
    /// Composition of a foveated frame: a full-view triangle sampling the views (single-sampled,
    /// no depth).
    Composite,
}

/// A pipeline for one pass of the plan.
pub(crate) fn pass_pipeline(
    gpu: &Gpu,
    plan: &FramePlan,
    pass: &PassPlan,
    kind: PipelineKind,
    render_pass: vk::RenderPass,
    layout: &PipelineLayout,
) -> Result<Pipeline, GpuError> {
    let (vert, frag) = match kind {
        PipelineKind::Scene => (
            &SCENE_VERT,
            if plan.count_fragments() {
                &SCENE_FRAG_COUNTING
            } else {
                &SCENE_FRAG
            },
        ),
        PipelineKind::Mask => (&MASK_VERT, &MASK_FRAG),
        PipelineKind::Coverage => (&COVERAGE_VERT, &COVERAGE_FRAG),
        PipelineKind::Composite => (&COMPOSITE_VERT, &COMPOSITE_FRAG),
    };
    let vert = shader_module(gpu, vert)?;
    let frag = shader_module(gpu, frag)?;
    let mut spec_data = view_source(pass.submission).to_le_bytes().to_vec();
    spec_data.extend_from_slice(&(1.0 / pass.guard_band as f32).to_le_bytes());
    let spec_entries = [
        vk::SpecializationMapEntry {
            constant_id: 0,
            offset: 0,
            size: 4,
        },
        vk::SpecializationMapEntry {
            constant_id: 1,
            offset: 4,
            size: 4,
        },
    ];
    // The mask and coverage shaders only declare constant 1.
    let spec_entries = if kind == PipelineKind::Scene {
        &spec_entries[..]
    } else {
        &spec_entries[1..]
    };
    let spec = vk::SpecializationInfo::default()
        .map_entries(spec_entries)
        .data(&spec_data);
    let stages = [
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::VERTEX)
            .module(vert.raw)
            .name(ENTRY)
            .specialization_info(&spec),
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::FRAGMENT)
            .module(frag.raw)
            .name(ENTRY),
    ];
    let bindings = [vk::VertexInputBindingDescription {
        binding: 0,
        stride: std::mem::size_of::<Vertex>() as u32,
        input_rate: vk::VertexInputRate::VERTEX,
    }];
    let attributes = [
        vk::VertexInputAttributeDescription {
            location: 0,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: 0,
        },
        vk::VertexInputAttributeDescription {
            location: 1,
            binding: 0,
            format: vk::Format::R32G32B32_SFLOAT,
            offset: 12,
        },
    ];
    let vertex_input = if kind == PipelineKind::Scene {
        vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(&bindings)
            .vertex_attribute_descriptions(&attributes)
    } else {
        vk::PipelineVertexInputStateCreateInfo::default()
    };
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    let raster = vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        // The projections keep the image upright (Vulkan NDC y down), so on-screen winding is
        // the geometry's own: counter-clockwise faces the viewer. Masks and the probe are 2D.
        .cull_mode(if kind == PipelineKind::Scene {
            vk::CullModeFlags::BACK
        } else {
            vk::CullModeFlags::NONE
        })
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0);
    let samples = if kind == PipelineKind::Composite {
        1
    } else {
        plan.samples
    };
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(vk::SampleCountFlags::from_raw(samples));
    let stencil_op = |compare, pass_op, write_mask| vk::StencilOpState {
        fail_op: vk::StencilOp::KEEP,
        pass_op,
        depth_fail_op: vk::StencilOp::KEEP,
        compare_op: compare,
        compare_mask: 0xff,
        write_mask,
        reference: 0,
    };
    let stencil = match kind {
        PipelineKind::Mask => stencil_op(vk::CompareOp::ALWAYS, vk::StencilOp::REPLACE, 0xff),
        // Scene draws and the probe test the masks and never write them.
        _ => stencil_op(vk::CompareOp::EQUAL, vk::StencilOp::KEEP, 0),
    };
    let depth = vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(kind == PipelineKind::Scene)
        .depth_write_enable(kind == PipelineKind::Scene)
        // Reverse-Z: nearer is greater.
        .depth_compare_op(vk::CompareOp::GREATER)
        .stencil_test_enable(pass.stencil_masks)
        .front(stencil)
        .back(stencil);
    let writes_colour = matches!(kind, PipelineKind::Scene | PipelineKind::Composite);
    let write = if writes_colour {
        vk::ColorComponentFlags::RGBA
    } else {
        vk::ColorComponentFlags::empty()
    };
    let blend_attachments =
        [vk::PipelineColorBlendAttachmentState::default().color_write_mask(write)];
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
    let mut dynamic_states = vec![vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    if pass.stencil_masks {
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
        .render_pass(render_pass)
        .subpass(0);
    // SAFETY: all referenced state lives on this stack frame for the call.
    let pipelines = unsafe {
        gpu.device()
            .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
    }
    .map_err(|(_, e)| e)
    .vk("vkCreateGraphicsPipelines")?;
    Ok(Pipeline::from_raw(&gpu.dev, pipelines[0]))
}
