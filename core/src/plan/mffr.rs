//! MFFR's far field: one mono pass from the far view into an image the eye passes composite,
//! before their scene step (far-first) or after it (near-first).

use super::model::*;
use super::ops::Access;
use super::pipeline::{Constant, PipelineDesc, StepContext};
use super::steps::{DrawSet, Step};
use super::stereo_scene::view_source;
use super::{RenderConfig, Resolution};
use crate::mffr::{MffrOrder, MffrVariant};
use crate::shaders::{COMPOSITE_VERT, FAR_COMPOSITE_FRAG, FAR_COMPOSITE_FRAG_COUNTING};

/// The MFFR far pass: the far field once, from one view, resolved into an image every eye
/// pass samples (and which is therefore stored).
pub(super) fn far_pass(
    config: &RenderConfig,
    size: Resolution,
    attachments: &mut Vec<AttachmentPlan>,
) -> PassPlan {
    let mut add = |name, role, format, samples| {
        attachments.push(AttachmentPlan {
            name,
            role,
            format,
            samples,
            width: size.width,
            height: size.height,
            layers: 1,
            read_after_frame: false,
            sampled: false,
            transient: false,
        });
        attachments.len() - 1
    };
    let samples = far_samples(config);
    let msaa = samples > 1;
    let color = msaa.then(|| {
        add(
            "far colour (MSAA)",
            AttachmentRole::Color,
            Format::Rgba8Srgb,
            samples,
        )
    });
    let depth = add("far depth", AttachmentRole::Depth, Format::D32, samples);
    let output_role = if msaa {
        AttachmentRole::Resolve
    } else {
        AttachmentRole::Color
    };
    let output = add("far field colour", output_role, Format::Rgba8Srgb, 1);
    let whole = |id, access| Use::new(id, 0, 1, access);
    PassPlan {
        depth: Some(whole(depth, Access::Clear)),
        resolve: color.map(|_| whole(output, Access::Overwrite)),
        steps: vec![Step::scene(DrawSet::FarField)],
        ..PassPlan::new(
            "far field (mono)",
            PassKind::FarField,
            0,
            Submission::FarView,
            whole(color.unwrap_or(output), Access::Clear),
        )
    }
}

/// The far pass's MSAA samples: MFFR's own, or the frame's.
pub(super) fn far_samples(config: &RenderConfig) -> u32 {
    config.mffr.and_then(|m| m.far_msaa).unwrap_or(config.msaa)
}

/// The far composite step of an eye pass, on the side of its scene step the order says.
pub(super) fn add_far_composite(pass: &mut PassPlan, order: MffrOrder) {
    let scene = pass
        .steps
        .iter()
        .position(|s| matches!(s, Step::Scene { .. }))
        .unwrap_or(0);
    let at = match order {
        MffrOrder::FarFirst => scene,
        MffrOrder::NearFirst => scene + 1,
    };
    pass.steps.insert(at, Step::FarComposite { stencil: None });
}

/// The far composite: a full-view draw per view reprojecting the far image (its view from the
/// pass's submission), with the split's depth where the variant shifts depth.
pub(super) fn far_composite_pipeline(
    ctx: &StepContext,
    plan: &FramePlan,
    pass: &PassPlan,
) -> PipelineDesc {
    let depth_shift = plan
        .mffr
        .is_some_and(|m| m.config.variant == MffrVariant::DepthShift);
    ctx.pipeline(
        &COMPOSITE_VERT,
        &FAR_COMPOSITE_FRAG,
        &FAR_COMPOSITE_FRAG_COUNTING,
    )
    .constant(Constant::ViewSource, view_source(pass.submission))
    .flag(Constant::DepthShift, depth_shift)
}
