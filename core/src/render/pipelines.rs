use std::ffi::CStr;
use std::sync::Arc;

use ash::vk;

use super::materials::MaterialSet;
use super::targets::CompiledPass;
use crate::gpu::{
    hash_word, name_word, Buffer, Description, DescriptorPool, DescriptorSetLayout, Gpu, GpuError,
    ImageView, Pipeline, PipelineLayout, ShaderModule, VkResultExt,
};
use crate::mffr::MffrVariant;
use crate::plan::{
    CompareOp, DrawSet, FramePlan, OutputSource, PassKind, StencilOp, StencilState, Step,
    Submission,
};
use crate::scene::Vertex;
use crate::shaders::{
    ShaderBinary, COMPOSITE_VERT, COVERAGE_FRAG, COVERAGE_VERT, FAR_COMPOSITE_FRAG,
    FAR_COMPOSITE_FRAG_COUNTING, MASK_FRAG, MASK_FRAG_COUNTING, MASK_VERT, OUTPUT_FRAG,
    OUTPUT_FRAG_COUNTING, RADIAL_MASK_FRAG, RADIAL_MASK_FRAG_COUNTING, RECONSTRUCT_FRAG,
    RECONSTRUCT_FRAG_COUNTING, SCENE_FRAG, SCENE_FRAG_COUNTING, SCENE_LIT_FRAG,
    SCENE_LIT_FRAG_COUNTING, SCENE_MASKED_FRAG, SCENE_MASKED_FRAG_COUNTING, SCENE_VERT,
    SCENE_VERT_INDIRECT,
};

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

/// The vertex shader's `VIEW_SOURCE` for a submission (see `shaders/scene.vert`).
fn view_source(submission: Submission) -> u32 {
    match submission {
        Submission::Multiview => 0,
        Submission::SingleEye(_) | Submission::PerObject | Submission::FarView => 1,
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
    /// The output stage: a full-view triangle sampling what the frame rendered (single-sampled,
    /// no depth).
    Output,
    /// MFFR: a full-view triangle sampling the far image, under the pass's stencil.
    FarComposite,
    /// Radial density masking: a full-view triangle marking skipped quads in stencil.
    RadialMask,
    /// Radial density reconstruction: a full-view triangle sampling the masked views
    /// (single-sampled, no depth).
    Reconstruct,
}

impl PipelineKind {
    /// The pipeline a step draws with.
    pub fn of(step: &Step) -> PipelineKind {
        match step {
            Step::MaskFans { .. } => PipelineKind::Mask,
            Step::FarComposite { .. } => PipelineKind::FarComposite,
            Step::Scene { .. } => PipelineKind::Scene,
            Step::Probe { .. } => PipelineKind::Coverage,
            Step::Output(_) => PipelineKind::Output,
            Step::RadialMask { .. } => PipelineKind::RadialMask,
            Step::Reconstruct => PipelineKind::Reconstruct,
        }
    }
}

/// The pipeline of step `step` of pass `pass_index`, compiled as `compiled`, with `layout`
/// (made as `layout_description` says). Shared with any live pipeline of the same description.
pub(crate) fn step_pipeline(
    gpu: &Gpu,
    plan: &FramePlan,
    pass_index: usize,
    step: &Step,
    compiled: &CompiledPass,
    layout: &PipelineLayout,
    layout_description: &[u64],
) -> Result<Arc<Pipeline>, GpuError> {
    let pass = &plan.passes[pass_index];
    let kind = PipelineKind::of(step);
    // Counting frames use the counting variant of every fragment shader (the probe always
    // counts); timed frames never carry the counter.
    let counter_base = plan.counter_base(pass_index, step.counted());
    let pick_frag = |plain, counting| {
        if counter_base.is_some() {
            counting
        } else {
            plain
        }
    };
    let (vert, frag) = match kind {
        PipelineKind::Scene => (
            if matches!(
                step,
                Step::Scene {
                    draw_set: DrawSet::All,
                    ..
                }
            ) {
                &SCENE_VERT
            } else {
                &SCENE_VERT_INDIRECT
            },
            if plan.alpha_mask {
                pick_frag(&SCENE_MASKED_FRAG, &SCENE_MASKED_FRAG_COUNTING)
            } else if plan.lit {
                pick_frag(&SCENE_LIT_FRAG, &SCENE_LIT_FRAG_COUNTING)
            } else {
                pick_frag(&SCENE_FRAG, &SCENE_FRAG_COUNTING)
            },
        ),
        PipelineKind::Mask => (&MASK_VERT, pick_frag(&MASK_FRAG, &MASK_FRAG_COUNTING)),
        PipelineKind::Coverage => (&COVERAGE_VERT, &COVERAGE_FRAG),
        PipelineKind::Output => (
            &COMPOSITE_VERT,
            pick_frag(&OUTPUT_FRAG, &OUTPUT_FRAG_COUNTING),
        ),
        PipelineKind::FarComposite => (
            &COMPOSITE_VERT,
            pick_frag(&FAR_COMPOSITE_FRAG, &FAR_COMPOSITE_FRAG_COUNTING),
        ),
        PipelineKind::RadialMask => (
            &COMPOSITE_VERT,
            pick_frag(&RADIAL_MASK_FRAG, &RADIAL_MASK_FRAG_COUNTING),
        ),
        PipelineKind::Reconstruct => (
            &COMPOSITE_VERT,
            pick_frag(&RECONSTRUCT_FRAG, &RECONSTRUCT_FRAG_COUNTING),
        ),
    };
    let (vert_binary, frag_binary) = (vert, frag);
    // Specialisation constants, by id: 0 where the view index comes from, 1 the guard band's
    // clip scale, 2 depth shift (the far composite), 3 depth into alpha (the far pass), 4 the
    // step's first counter slot (counting frames), 5 the pass's first view, 6 fovea tags (the
    // one-pass fovea layout), 10–21 radial density's view size, radii and lens ellipses
    // (`shaders/radial_density.glsl`), 30–33 the output stage's lens, source, fovea layer and
    // periphery sharpening.
    // Every stage gets the ones it declares.
    let far_pass = pass.kind == PassKind::FarField;
    let depth_shift = plan
        .mffr
        .is_some_and(|m| m.config.variant == MffrVariant::DepthShift);
    let mut constants: Vec<(u32, [u8; 4])> = vec![
        (0, view_source(pass.submission).to_le_bytes()),
        (1, (1.0 / pass.guard_band as f32).to_le_bytes()),
        (2, (depth_shift as u32).to_le_bytes()),
        (3, (far_pass as u32).to_le_bytes()),
        (4, counter_base.unwrap_or(0).to_le_bytes()),
        (5, pass.first_view.to_le_bytes()),
        (
            6,
            (matches!(
                step,
                Step::Scene {
                    draw_set: DrawSet::FoveaTagged,
                    ..
                }
            ) as u32)
                .to_le_bytes(),
        ),
    ];
    if let Step::Output(o) = step {
        let (fovea_layer, sharpen) = match o.source {
            OutputSource::Foveated {
                fovea_layer,
                sharpen,
            } => (fovea_layer, sharpen),
            _ => (0, false),
        };
        constants.extend([
            (30, (o.lens as u32).to_le_bytes()),
            (31, o.source.code().to_le_bytes()),
            (32, fovea_layer.to_le_bytes()),
            (33, (sharpen as u32).to_le_bytes()),
        ]);
    }
    if let Some(r) = &plan.radial_density {
        let values = [
            r.view.width as f32,
            r.view.height as f32,
            r.config.inner,
            r.config.outer,
        ]
        .into_iter()
        .chain(r.lens.iter().flat_map(|l| l.to_array()));
        constants.extend((10..).zip(values.map(f32::to_le_bytes)));
    }
    const RADIAL: [u32; 12] = [10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21];
    let radial_and_counter: Vec<u32> = RADIAL.iter().copied().chain([4]).collect();
    let spec_data: Vec<u8> = constants.iter().flat_map(|c| c.1).collect();
    let entries: Vec<vk::SpecializationMapEntry> = constants
        .iter()
        .enumerate()
        .map(|(i, c)| vk::SpecializationMapEntry {
            constant_id: c.0,
            offset: 4 * i as u32,
            size: 4,
        })
        .collect();
    let pick = |ids: &[u32]| -> Vec<vk::SpecializationMapEntry> {
        entries
            .iter()
            .copied()
            .filter(|e| ids.contains(&e.constant_id))
            .collect()
    };
    let (vert_ids, frag_ids): (&[u32], &[u32]) = match kind {
        PipelineKind::Scene => (&[0, 1, 5, 6], &[3, 4]),
        PipelineKind::Mask => (&[1, 5], &[4, 5]),
        PipelineKind::Coverage => (&[1], &[4, 5]),
        PipelineKind::FarComposite => (&[1], &[0, 2, 4, 5]),
        PipelineKind::Output => (&[1], &[4, 30, 31, 32, 33]),
        PipelineKind::RadialMask | PipelineKind::Reconstruct => (&[1], &radial_and_counter),
    };
    let (vert_entries, frag_entries) = (pick(vert_ids), pick(frag_ids));
    let vert_spec = vk::SpecializationInfo::default()
        .map_entries(&vert_entries)
        .data(&spec_data);
    let frag_spec = vk::SpecializationInfo::default()
        .map_entries(&frag_entries)
        .data(&spec_data);
    let samples = if matches!(kind, PipelineKind::Output | PipelineKind::Reconstruct) {
        1
    } else {
        plan.samples
    };
    let stencil = step.stencil().map(vk_stencil);
    // Everything the create info below depends on: the shaders and their constants, the fixed
    // state the kind and the pass decide, the render pass's and the layout's descriptions.
    let mut description: Description = vec![
        kind as u64,
        name_word(vert_binary.name),
        name_word(frag_binary.name),
        samples as u64,
        (pass.depth_clamp && kind == PipelineKind::Scene) as u64,
        hash_word(&stencil.map(|s| {
            (
                s.fail_op.as_raw(),
                s.pass_op.as_raw(),
                s.depth_fail_op.as_raw(),
                s.compare_op.as_raw(),
                s.compare_mask,
                s.write_mask,
                s.reference,
            )
        })),
    ];
    description.extend(constants.iter().map(|c| u32::from_le_bytes(c.1) as u64));
    description.extend(vert_ids.iter().chain(frag_ids).map(|&i| i as u64 + 100));
    description.push(compiled.description.len() as u64);
    description.extend(&compiled.description);
    description.extend(layout_description);
    gpu.pipelines.get_or_create(description, || {
        let vert = shader_module(gpu, vert_binary)?;
        let frag = shader_module(gpu, frag_binary)?;
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
            vk::VertexInputAttributeDescription {
                location: 2,
                binding: 0,
                format: vk::Format::R32G32_SFLOAT,
                offset: 24,
            },
            vk::VertexInputAttributeDescription {
                location: 3,
                binding: 0,
                format: vk::Format::R32G32B32A32_SFLOAT,
                offset: 32,
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
            .depth_clamp_enable(pass.depth_clamp && kind == PipelineKind::Scene)
            // The projections keep the image upright (Vulkan NDC y down), so on-screen winding is
            // the geometry's own: counter-clockwise faces the viewer. Masks and the probe are 2D.
            .cull_mode(if kind == PipelineKind::Scene {
                vk::CullModeFlags::BACK
            } else {
                vk::CullModeFlags::NONE
            })
            .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::from_raw(samples));
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(kind == PipelineKind::Scene)
            .depth_write_enable(kind == PipelineKind::Scene)
            // Reverse-Z: nearer is greater.
            .depth_compare_op(vk::CompareOp::GREATER)
            .stencil_test_enable(stencil.is_some())
            .front(stencil.unwrap_or_default())
            .back(stencil.unwrap_or_default());
        let writes_colour = matches!(
            kind,
            PipelineKind::Scene
                | PipelineKind::Output
                | PipelineKind::FarComposite
                | PipelineKind::Reconstruct
        );
        let write = if writes_colour {
            vk::ColorComponentFlags::RGBA
        } else {
            vk::ColorComponentFlags::empty()
        };
        let blend_attachments =
            [vk::PipelineColorBlendAttachmentState::default().color_write_mask(write)];
        let blend =
            vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
        let mut dynamic_states = vec![vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        if kind == PipelineKind::Mask {
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
