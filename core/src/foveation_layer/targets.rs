//! The frame's images, render passes and framebuffers, built straight from the plan: every
//! load/store op, layout and usage flag here comes from a plan decision.

use ash::vk;

use std::sync::Arc;

use crate::gpu::{
    Description, Framebuffer, Gpu, GpuError, Image, ImageDesc, ImageView, RenderPass, VkResultExt,
};
use crate::plan::{
    AttachmentId, AttachmentPlan, Barrier, Format, FramePlan, Layout, LoadOp, StoreOp, Touch, Use,
};

pub(crate) fn vk_format(format: Format) -> vk::Format {
    match format {
        Format::Rgba8Srgb => vk::Format::R8G8B8A8_SRGB,
        Format::Rgba8Unorm => vk::Format::R8G8B8A8_UNORM,
        Format::Rgba16F => vk::Format::R16G16B16A16_SFLOAT,
        Format::Rgb10A2 => vk::Format::A2B10G10R10_UNORM_PACK32,
        Format::R8 => vk::Format::R8_UNORM,
        Format::D32 => vk::Format::D32_SFLOAT,
        Format::D32S8 => vk::Format::D32_SFLOAT_S8_UINT,
    }
}

fn usage(a: &AttachmentPlan) -> vk::ImageUsageFlags {
    let mut usage = if a.format.is_depth() {
        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
    } else {
        vk::ImageUsageFlags::COLOR_ATTACHMENT
    };
    if a.transient {
        usage |= vk::ImageUsageFlags::TRANSIENT_ATTACHMENT;
    }
    if a.read_after_frame {
        usage |= vk::ImageUsageFlags::TRANSFER_SRC;
    }
    if a.sampled {
        usage |= vk::ImageUsageFlags::SAMPLED;
    }
    usage
}

/// What the image of `attachment` is made as: an external output image (an OpenXR swapchain's)
/// must be made the same way.
pub(crate) fn image_desc(plan: &FramePlan, id: AttachmentId) -> ImageDesc<'static> {
    let a = &plan.attachments[id];
    // A history the first frame samples before any pass wrote it is cleared once at creation.
    let cleared = if plan.sampled_before_written().contains(&id) {
        vk::ImageUsageFlags::TRANSFER_DST
    } else {
        vk::ImageUsageFlags::empty()
    };
    ImageDesc {
        name: a.name,
        format: vk_format(a.format),
        width: a.width,
        height: a.height,
        layers: a.layers,
        samples: a.samples,
        mip_levels: 1,
        usage: usage(a) | cleared,
    }
}

/// One image per planned attachment; an external output borrows `external[0]`, and the
/// attachments `handed` names borrow an engine's images (each made as [`image_desc`] says).
pub(crate) fn create_images(
    gpu: &Gpu,
    plan: &FramePlan,
    external: &[vk::Image],
    handed: &[(AttachmentId, vk::Image)],
) -> Result<Vec<Image>, GpuError> {
    let outputs = plan.outputs();
    (0..plan.attachments.len())
        .map(|id| {
            let desc = image_desc(plan, id);
            if let Some(&(_, raw)) = handed.iter().find(|(a, _)| *a == id) {
                // SAFETY: the engine made `raw` as `desc` says (checked against its own
                // description), for this device.
                return Ok(unsafe { Image::borrowed(gpu, raw, &desc) });
            }
            // An output handed in stands in for the renderer's own; without one the renderer
            // makes its own, which frames render into when none is handed in.
            if let (true, true, Some(&raw)) = (
                plan.external_output,
                outputs.contains(&id),
                external.first(),
            ) {
                // SAFETY: the caller made `raw` as `desc` says, for this device.
                Ok(unsafe { Image::borrowed(gpu, raw, &desc) })
            } else {
                Image::new(gpu, &desc)
            }
        })
        .collect()
}

/// A render pass of the plan made concrete.
pub(crate) struct CompiledPass {
    /// Shared with every other live pass of the same description (see `gpu::ObjectCache`).
    pub render_pass: Arc<RenderPass>,
    /// That description: pipelines made for this render pass carry it in theirs.
    pub description: Description,
    pub framebuffer: Framebuffer,
    _views: Vec<ImageView>,
    pub extent: vk::Extent2D,
    /// Colour attachments of its subpass: 1, or 2 with the next history.
    pub colour_attachments: u32,
}

pub(crate) fn vk_layout(layout: Layout) -> vk::ImageLayout {
    match layout {
        Layout::Undefined => vk::ImageLayout::UNDEFINED,
        Layout::ColorAttachment => vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        Layout::DepthStencilAttachment => vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL,
        Layout::TransferSrc => vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        Layout::ShaderReadOnly => vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    }
}

/// The attachment description of a use: every op and layout as the plan derived it.
fn description(plan: &FramePlan, u: &Use) -> vk::AttachmentDescription {
    let a = &plan.attachments[u.attachment];
    let load = match u.load {
        LoadOp::Clear => vk::AttachmentLoadOp::CLEAR,
        LoadOp::Load => vk::AttachmentLoadOp::LOAD,
        LoadOp::DontCare => vk::AttachmentLoadOp::DONT_CARE,
    };
    let store = match u.store {
        StoreOp::Store => vk::AttachmentStoreOp::STORE,
        StoreOp::DontCare => vk::AttachmentStoreOp::DONT_CARE,
    };
    let stencil = a.format == Format::D32S8;
    vk::AttachmentDescription::default()
        .format(vk_format(a.format))
        .samples(vk::SampleCountFlags::from_raw(a.samples))
        .load_op(load)
        .store_op(store)
        .stencil_load_op(if stencil {
            load
        } else {
            vk::AttachmentLoadOp::DONT_CARE
        })
        .stencil_store_op(match u.stencil_store {
            StoreOp::Store => vk::AttachmentStoreOp::STORE,
            StoreOp::DontCare => vk::AttachmentStoreOp::DONT_CARE,
        })
        .initial_layout(vk_layout(u.initial_layout))
        .final_layout(vk_layout(u.final_layout))
}

/// Where a touch happens, what it makes available when it comes first (its writes) and what it
/// needs visible when it comes second.
fn synchronisation(touch: Touch) -> (vk::PipelineStageFlags, vk::AccessFlags, vk::AccessFlags) {
    match touch {
        Touch::ColourAttachment => (
            vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
            vk::AccessFlags::COLOR_ATTACHMENT_READ | vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
        ),
        Touch::DepthAttachment => (
            vk::PipelineStageFlags::EARLY_FRAGMENT_TESTS
                | vk::PipelineStageFlags::LATE_FRAGMENT_TESTS,
            vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
            vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_READ
                | vk::AccessFlags::DEPTH_STENCIL_ATTACHMENT_WRITE,
        ),
        Touch::Sampled => (
            vk::PipelineStageFlags::FRAGMENT_SHADER,
            vk::AccessFlags::empty(),
            vk::AccessFlags::SHADER_READ,
        ),
        Touch::ReadAfterFrame => (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::empty(),
            vk::AccessFlags::TRANSFER_READ,
        ),
    }
}

/// One subpass dependency covering `barriers` (none when there are none).
fn dependency(barriers: &[Barrier], src: u32, dst: u32) -> Option<vk::SubpassDependency> {
    barriers
        .iter()
        .fold(None, |d: Option<vk::SubpassDependency>, b| {
            let (src_stage, src_access, _) = synchronisation(b.from);
            let (dst_stage, _, dst_access) = synchronisation(b.to);
            let d = d.unwrap_or_else(|| {
                vk::SubpassDependency::default()
                    .src_subpass(src)
                    .dst_subpass(dst)
            });
            Some(
                d.src_stage_mask(d.src_stage_mask | src_stage)
                    .dst_stage_mask(d.dst_stage_mask | dst_stage)
                    .src_access_mask(d.src_access_mask | src_access)
                    .dst_access_mask(d.dst_access_mask | dst_access),
            )
        })
}

/// Pass `pass_index` of the plan as a render pass and a framebuffer of the images `image`
/// gives for each attachment.
pub(crate) fn compile_pass<'i>(
    gpu: &Gpu,
    plan: &FramePlan,
    pass_index: usize,
    image: &dyn Fn(AttachmentId) -> &'i Image,
) -> Result<CompiledPass, GpuError> {
    let pass = &plan.passes[pass_index];
    let uses: Vec<&Use> = pass.uses().collect();
    let descriptions: Vec<vk::AttachmentDescription> =
        uses.iter().map(|u| description(plan, u)).collect();
    // The plan's barriers, as the render pass's external dependencies: what the pass waits
    // on before its first subpass, and what later work waits on after it.
    let dependencies: Vec<vk::SubpassDependency> = [
        dependency(&pass.barriers.wait, vk::SUBPASS_EXTERNAL, 0),
        dependency(&pass.barriers.signal, 0, vk::SUBPASS_EXTERNAL),
    ]
    .into_iter()
    .flatten()
    .collect();
    // Everything the render pass's create info depends on.
    let mut description: Description = vec![
        pass.view_mask as u64,
        pass.depth.is_some() as u64,
        pass.resolve.is_some() as u64,
        pass.history.is_some() as u64,
        pass.depth_resolve.is_some() as u64,
    ];
    for d in &dependencies {
        description.extend([
            d.src_subpass as u64,
            d.src_stage_mask.as_raw() as u64,
            d.dst_stage_mask.as_raw() as u64,
            d.src_access_mask.as_raw() as u64,
            d.dst_access_mask.as_raw() as u64,
        ]);
    }
    for d in &descriptions {
        description.extend([
            d.format.as_raw() as u64,
            d.samples.as_raw() as u64,
            d.load_op.as_raw() as u64,
            d.store_op.as_raw() as u64,
            d.stencil_load_op.as_raw() as u64,
            d.stencil_store_op.as_raw() as u64,
            d.initial_layout.as_raw() as u64,
            d.final_layout.as_raw() as u64,
        ]);
    }
    let parts = PassParts {
        view_mask: pass.view_mask,
        refs: SubpassRefs::of(pass),
        descriptions: &descriptions,
        dependencies: &dependencies,
    };
    let render_pass = gpu.render_passes.get_or_create(description.clone(), || {
        let raw = match parts.refs.depth_resolve {
            None => create_render_pass(gpu, &parts)?,
            Some(_) => create_render_pass2(gpu, &parts)?,
        };
        Ok::<_, GpuError>(RenderPass::from_raw(&gpu.dev, raw))
    })?;

    // Multiview framebuffers have one layer and array views holding every view's layer.
    let array = pass.view_mask != 0;
    let views = uses
        .iter()
        .map(|u| image(u.attachment).view(u.base_layer, u.layer_count, array))
        .collect::<Result<Vec<_>, _>>()?;
    let raw_views: Vec<vk::ImageView> = views.iter().map(|v| v.raw).collect();
    let color = &plan.attachments[pass.color.attachment];
    let extent = vk::Extent2D {
        width: color.width,
        height: color.height,
    };
    let fb_info = vk::FramebufferCreateInfo::default()
        .render_pass(render_pass.raw)
        .attachments(&raw_views)
        .width(extent.width)
        .height(extent.height)
        .layers(1);
    let raw =
        unsafe { gpu.device().create_framebuffer(&fb_info, None) }.vk("vkCreateFramebuffer")?;
    Ok(CompiledPass {
        framebuffer: Framebuffer::from_raw(&gpu.dev, raw),
        render_pass,
        description,
        _views: views,
        extent,
        colour_attachments: parts.refs.colour.len() as u32,
    })
}

/// Where each of a pass's attachments sits in its render pass (the order of
/// [`PassPlan::uses`](crate::plan::PassPlan::uses)) as its subpass refers to them.
struct SubpassRefs {
    /// Colour attachments: the output, then the next history if the pass writes it
    /// (location 1).
    colour: Vec<u32>,
    depth: Option<u32>,
    /// One per colour attachment where the pass resolves (the history is not resolved).
    resolve: Option<Vec<u32>>,
    depth_resolve: Option<u32>,
}

impl SubpassRefs {
    fn of(pass: &crate::plan::PassPlan) -> Self {
        let mut next = 0;
        let mut index = |present: bool| {
            present.then(|| {
                next += 1;
                next - 1
            })
        };
        let colour = index(true);
        let depth = index(pass.depth.is_some());
        let resolve = index(pass.resolve.is_some());
        let history = index(pass.history.is_some());
        let depth_resolve = index(pass.depth_resolve.is_some());
        SubpassRefs {
            colour: colour.into_iter().chain(history).collect(),
            depth,
            resolve: resolve.map(|r| {
                std::iter::once(r)
                    .chain(history.map(|_| vk::ATTACHMENT_UNUSED))
                    .collect()
            }),
            depth_resolve,
        }
    }

    /// The references as `make` builds them (either render pass version's struct): colour,
    /// resolve, depth and depth resolve.
    fn made<R>(&self, make: impl Fn(u32, vk::ImageLayout) -> R) -> MadeRefs<R> {
        let colour = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
        let depth = vk::ImageLayout::DEPTH_STENCIL_ATTACHMENT_OPTIMAL;
        MadeRefs {
            colour: self.colour.iter().map(|&a| make(a, colour)).collect(),
            resolve: self
                .resolve
                .iter()
                .flatten()
                .map(|&a| make(a, colour))
                .collect(),
            depth: self.depth.map(|a| make(a, depth)),
            depth_resolve: self.depth_resolve.map(|a| make(a, depth)),
        }
    }
}

/// What either version of `vkCreateRenderPass` makes a pass from.
struct PassParts<'a> {
    view_mask: u32,
    refs: SubpassRefs,
    descriptions: &'a [vk::AttachmentDescription],
    dependencies: &'a [vk::SubpassDependency],
}

/// A subpass's references, made.
struct MadeRefs<R> {
    colour: Vec<R>,
    resolve: Vec<R>,
    depth: Option<R>,
    depth_resolve: Option<R>,
}

/// The render pass with `vkCreateRenderPass` (Vulkan 1.0 with multiview).
fn create_render_pass(gpu: &Gpu, parts: &PassParts) -> Result<vk::RenderPass, GpuError> {
    let made = parts
        .refs
        .made(|attachment, layout| vk::AttachmentReference { attachment, layout });
    let mut subpass = vk::SubpassDescription::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .color_attachments(&made.colour);
    if let Some(depth) = &made.depth {
        subpass = subpass.depth_stencil_attachment(depth);
    }
    if parts.refs.resolve.is_some() {
        subpass = subpass.resolve_attachments(&made.resolve);
    }
    let subpasses = [subpass];
    let masks = [parts.view_mask];
    let mut multiview = vk::RenderPassMultiviewCreateInfo::default()
        .view_masks(&masks)
        .correlation_masks(&masks);
    let mut info = vk::RenderPassCreateInfo::default()
        .attachments(parts.descriptions)
        .subpasses(&subpasses)
        .dependencies(parts.dependencies);
    if parts.view_mask != 0 {
        info = info.push_next(&mut multiview);
    }
    // SAFETY: the create info points at locals alive for the call.
    unsafe { gpu.device().create_render_pass(&info, None) }.vk("vkCreateRenderPass")
}

/// The render pass with `vkCreateRenderPass2KHR`: the same attachments, subpass and
/// dependencies, and the depth resolved to one sample in the pass (sample 0, the depth at
/// the pixel's centre; every device that resolves depth offers it). The stencil is not
/// resolved: the resolved image has none.
fn create_render_pass2(gpu: &Gpu, parts: &PassParts) -> Result<vk::RenderPass, GpuError> {
    let Some(loader) = &gpu.render_pass2 else {
        return Err(GpuError::Unusable {
            name: gpu.caps().device_name.clone(),
            why: "a pass resolves depth, and VK_KHR_depth_stencil_resolve is not enabled".into(),
        });
    };
    let made = parts.refs.made(|attachment, layout| {
        vk::AttachmentReference2::default()
            .attachment(attachment)
            .layout(layout)
    });
    let attachments: Vec<vk::AttachmentDescription2> = parts
        .descriptions
        .iter()
        .map(|d| {
            vk::AttachmentDescription2::default()
                .format(d.format)
                .samples(d.samples)
                .load_op(d.load_op)
                .store_op(d.store_op)
                .stencil_load_op(d.stencil_load_op)
                .stencil_store_op(d.stencil_store_op)
                .initial_layout(d.initial_layout)
                .final_layout(d.final_layout)
        })
        .collect();
    // Sample 0 for both aspects: a device without independent resolve modes needs them equal,
    // and the stencil has nowhere to go.
    let mut resolve = vk::SubpassDescriptionDepthStencilResolve::default()
        .depth_resolve_mode(vk::ResolveModeFlags::SAMPLE_ZERO)
        .stencil_resolve_mode(vk::ResolveModeFlags::SAMPLE_ZERO);
    if let Some(r) = &made.depth_resolve {
        resolve = resolve.depth_stencil_resolve_attachment(r);
    }
    let mut subpass = vk::SubpassDescription2::default()
        .pipeline_bind_point(vk::PipelineBindPoint::GRAPHICS)
        .view_mask(parts.view_mask)
        .color_attachments(&made.colour)
        .push_next(&mut resolve);
    if let Some(depth) = &made.depth {
        subpass = subpass.depth_stencil_attachment(depth);
    }
    if parts.refs.resolve.is_some() {
        subpass = subpass.resolve_attachments(&made.resolve);
    }
    let dependencies: Vec<vk::SubpassDependency2> = parts
        .dependencies
        .iter()
        .map(|d| {
            vk::SubpassDependency2::default()
                .src_subpass(d.src_subpass)
                .dst_subpass(d.dst_subpass)
                .src_stage_mask(d.src_stage_mask)
                .dst_stage_mask(d.dst_stage_mask)
                .src_access_mask(d.src_access_mask)
                .dst_access_mask(d.dst_access_mask)
        })
        .collect();
    let subpasses = [subpass];
    let masks = [parts.view_mask];
    let info = vk::RenderPassCreateInfo2::default()
        .attachments(&attachments)
        .subpasses(&subpasses)
        .dependencies(&dependencies)
        .correlated_view_masks(if parts.view_mask != 0 { &masks } else { &[] });
    // SAFETY: the create info points at locals alive for the call.
    unsafe { loader.create_render_pass2(&info, None) }.vk("vkCreateRenderPass2KHR")
}
