//! Setting a renderer up from its plan: the executors of the steps that sample earlier
//! passes, images cleared for the frames that sample them before writing them, the checks that
//! the scene is the plan's, the buffers and query pools effects ask for, and every pass
//! compiled with its steps bound. Run once per renderer, never per frame.

use ash::vk;

use super::descriptors::DescriptorSet;
use super::executor::Executor;
use super::layer_copy::LayerCopies;
use super::mffr::FarComposite;
use super::output::OutputStage;
use super::pipelines::compile_pipeline;
use super::radial_density::Reconstruction;
use super::stats::PASS_STATISTICS;
use super::targets::{compile_pass, CompiledPass};
use super::vulkan_recorder::BoundStep;
use crate::gpu::{Buffer, Gpu, GpuError, Image, MemoryLocation, QueryPool, VkResultExt};
use crate::plan::{AttachmentId, BufferPlan, FramePlan, Step};

/// The executors of the steps that sample earlier passes' images, each when planned: the output
/// stage (a foveated frame's composition, lens distortion), the MFFR far composite and radial
/// density's reconstruction.
///
/// `counters`: each frame slot's fragment counter (one entry a slot, `None` without counting).
pub(super) fn sampling_executors(
    gpu: &Gpu,
    plan: &FramePlan,
    images: &[Image],
    counters: &[Option<&Buffer>],
) -> Result<Vec<Box<dyn Executor>>, GpuError> {
    let mut executors: Vec<Box<dyn Executor>> = Vec::new();
    // The output pass, and before it the periphery's accumulation at its own texels when
    // planned: each an output step with its own sampled sets.
    for p in &plan.passes {
        let Some(&Step::Output(step)) = p.steps.first() else {
            continue;
        };
        // With accumulation the history and the periphery's depths (this frame's, the frame
        // before's) follow the pass's sources.
        let temporal = plan
            .foveation
            .and_then(|f| f.temporal)
            .filter(|_| step.temporal);
        let sources = p.samples.len() - 3 * temporal.is_some() as usize;
        // Two images always: the shader declares both (a one-image source twice); then the
        // accumulation's, as frames of each parity find them.
        let of_frame = |frame| {
            let id = |i: usize| plan.in_frame(p.samples[i], frame);
            let mut ids = vec![id(0), id(sources - 1)];
            ids.extend((sources..p.samples.len()).map(id));
            ids.into_iter().map(|i| &images[i]).collect::<Vec<_>>()
        };
        let target = &plan.attachments[p.color.attachment];
        executors.push(Box::new(OutputStage::new(
            gpu,
            plan,
            (step, [target.width, target.height]),
            [of_frame(0), of_frame(1)],
            temporal,
            counters,
        )?));
    }
    if let Some(p) = plan.far_pass() {
        let far_image = &images[p.resolve.unwrap_or(p.color).attachment];
        executors.push(Box::new(FarComposite::new(gpu, far_image, counters)?));
    }
    let reconstruct = plan
        .passes
        .iter()
        .find(|p| p.steps.contains(&Step::Reconstruct));
    if let Some(p) = reconstruct {
        let views = &images[p.samples[0]];
        executors.push(Box::new(Reconstruction::new(gpu, views, counters)?));
    }
    if let Some(copies) = LayerCopies::new(gpu, plan, images, counters)? {
        executors.push(Box::new(copies));
    }
    Ok(executors)
}

/// Images a frame samples before writing them (a history the previous frame leaves) start
/// cleared to zero — a history with nothing in it — and in the layout sampling expects.
pub(super) fn make_sampleable(
    gpu: &Gpu,
    plan: &FramePlan,
    images: &[Image],
) -> Result<(), GpuError> {
    let ids = plan.sampled_before_written();
    if ids.is_empty() {
        return Ok(());
    }
    // Every such image from one layout to another, `src` done before `dst`.
    let transition = |from, to, src, dst| -> Vec<vk::ImageMemoryBarrier> {
        ids.iter()
            .map(|&id| {
                vk::ImageMemoryBarrier::default()
                    .old_layout(from)
                    .new_layout(to)
                    .src_access_mask(src)
                    .dst_access_mask(dst)
                    .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                    .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                    .image(images[id].raw)
                    .subresource_range(images[id].range(0, images[id].layers))
            })
            .collect()
    };
    let to_clear = transition(
        vk::ImageLayout::UNDEFINED,
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        vk::AccessFlags::empty(),
        vk::AccessFlags::TRANSFER_WRITE,
    );
    let to_sample = transition(
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        vk::AccessFlags::TRANSFER_WRITE,
        vk::AccessFlags::SHADER_READ,
    );
    let device = gpu.device();
    gpu.one_shot(|cmd| {
        // SAFETY: the images are alive and idle; recorded into the one-shot buffer.
        unsafe {
            device.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TOP_OF_PIPE,
                vk::PipelineStageFlags::TRANSFER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &to_clear,
            );
            for &id in &ids {
                let image = &images[id];
                let range = [image.range(0, image.layers)];
                let dst = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
                if image.aspect.contains(vk::ImageAspectFlags::DEPTH) {
                    // Reverse-Z's far plane: a depth with nothing in front.
                    let clear = vk::ClearDepthStencilValue::default();
                    device.cmd_clear_depth_stencil_image(cmd, image.raw, dst, &clear, &range);
                } else {
                    let clear = vk::ClearColorValue::default();
                    device.cmd_clear_color_image(cmd, image.raw, dst, &clear, &range);
                }
            }
            device.cmd_pipeline_barrier(
                cmd,
                vk::PipelineStageFlags::TRANSFER,
                vk::PipelineStageFlags::FRAGMENT_SHADER,
                vk::DependencyFlags::empty(),
                &[],
                &[],
                &to_sample,
            );
        }
    })
}

/// A buffer that exists only because an effect asked for it.
pub(super) fn effect_buffer(
    gpu: &Gpu,
    planned: Option<&BufferPlan>,
    usage: vk::BufferUsageFlags,
    location: MemoryLocation,
) -> Result<Option<Buffer>, GpuError> {
    planned
        .map(|b| Buffer::new(gpu, b.name, b.bytes, usage, location))
        .transpose()
}

/// A query pool of `slots` (none when 0); pipeline statistics count what `PASS_STATISTICS` says.
pub(super) fn query_pool(
    gpu: &Gpu,
    ty: vk::QueryType,
    slots: u32,
) -> Result<Option<QueryPool>, GpuError> {
    if slots == 0 {
        return Ok(None);
    }
    let mut info = vk::QueryPoolCreateInfo::default()
        .query_type(ty)
        .query_count(slots);
    if ty == vk::QueryType::PIPELINE_STATISTICS {
        info = info.pipeline_statistics(PASS_STATISTICS);
    }
    // SAFETY: plain object creation.
    let raw = unsafe { gpu.device().create_query_pool(&info, None) }.vk("vkCreateQueryPool")?;
    Ok(Some(QueryPool::from_raw(&gpu.dev, raw)))
}

/// Each pass compiled, and each of its steps bound: its pipeline, with the resources it reads
/// in each frame slot and on frames of each parity — its technique's sampled set (`sets`), or
/// the slot's scene bindings (`bindings`, one a slot). A slot's sets are laid out as the first
/// slot's, whose layout the pipelines are made with.
pub(super) fn compile_passes<'s>(
    gpu: &Gpu,
    plan: &FramePlan,
    images: &[Image],
    bindings: &'s [&'s DescriptorSet],
    sets: impl Fn(&Step, usize, usize) -> Option<&'s DescriptorSet>,
) -> Result<CompiledFrame, GpuError> {
    let mut passes = Vec::with_capacity(plan.passes.len());
    let mut steps = Vec::with_capacity(plan.passes.len());
    for (i, p) in plan.passes.iter().enumerate() {
        let compiled = compile_pass(gpu, plan, i, &|id| &images[id])?;
        let samples = plan.attachments[p.color.attachment].samples;
        let bound = p
            .steps
            .iter()
            .zip(&p.pipelines)
            .map(|(step, desc)| {
                let of = |slot: usize, parity| sets(step, slot, parity).unwrap_or(bindings[slot]);
                let d = of(0, 0);
                let (layout, description) = (&d.layout, &d.layout_description);
                // An engine's scene step is drawn with the engine's own pipelines.
                let engine = plan.engine_draws && matches!(step, Step::Scene { .. });
                Ok(BoundStep {
                    pipeline: (!engine)
                        .then(|| {
                            compile_pipeline(gpu, desc, samples, &compiled, layout, description)
                        })
                        .transpose()?,
                    layout: layout.raw,
                    sets: (0..bindings.len())
                        .map(|s| [of(s, 0).set, of(s, 1).set])
                        .collect(),
                })
            })
            .collect::<Result<Vec<_>, GpuError>>()?;
        passes.push(compiled);
        steps.push(bound);
    }
    Ok(CompiledFrame {
        passes,
        odd_frames: odd_frame_passes(gpu, plan, 0..plan.passes.len(), &|id| &images[id])?,
        steps,
    })
}

/// A frame's passes compiled, and their steps bound.
pub(super) struct CompiledFrame {
    pub passes: Vec<CompiledPass>,
    /// The passes that touch the history pair, compiled with its images' roles swapped:
    /// odd frames record these in place of the plan's (`(pass index, pass)`).
    pub odd_frames: Vec<(usize, CompiledPass)>,
    pub steps: Vec<Vec<BoundStep>>,
}

/// The passes touching a history pair compiled for odd frames, each pair swapped in the
/// images `image` gives; none without a pair.
pub(super) fn odd_frame_passes<'i>(
    gpu: &Gpu,
    plan: &FramePlan,
    indices: impl IntoIterator<Item = usize>,
    image: &dyn Fn(AttachmentId) -> &'i Image,
) -> Result<Vec<(usize, CompiledPass)>, GpuError> {
    let swapped = |id: AttachmentId| image(plan.in_frame(id, 1));
    let paired = |id| plan.history_pairs().any(|h| h.contains(id));
    indices
        .into_iter()
        .filter(|&i| plan.passes[i].uses().any(|u| paired(u.attachment)))
        .map(|i| Ok((i, compile_pass(gpu, plan, i, &swapped)?)))
        .collect()
}
