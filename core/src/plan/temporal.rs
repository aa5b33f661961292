//! Temporal accumulation of the periphery (maths: `foveation/temporal.rs`; executor:
//! `render/temporal.rs`; shaders: `accumulate.frag`, `store_history.frag`). Two full-view
//! passes at the screen's density join a foveated frame: before the output stage, `accumulate`
//! gathers the jittered periphery into the history reprojected by depth; after it,
//! `store history` keeps the result for the next frame (a pass cannot sample the image it
//! writes). The output stage samples the accumulated periphery in place of the periphery view.

use super::model::{AttachmentPlan, AttachmentRole, Format, PassKind, PassPlan};
use super::ops::AttachmentId;
use super::output::full_view_pass;
use super::pipeline::{PipelineDesc, StepContext};
use super::steps::Step;
use super::Resolution;
use crate::shaders::{
    ACCUMULATE_FRAG, ACCUMULATE_FRAG_COUNTING, COMPOSITE_VERT, STORE_HISTORY_FRAG,
    STORE_HISTORY_FRAG_COUNTING,
};

/// The accumulation added to a frame whose scene passes are planned.
pub(super) struct Accumulation {
    /// The accumulated periphery, which the output stage samples.
    pub accumulated: AttachmentId,
    /// The pass that keeps it for the next frame, to follow the output stage.
    pub store: PassPlan,
}

/// Adds the accumulate pass, reading the periphery pass's colour and depth (views 0 and 1) and
/// the history; returns the accumulated image and the pass that stores it. `None` without a
/// periphery pass.
pub(super) fn add_accumulation(
    passes: &mut Vec<PassPlan>,
    attachments: &mut Vec<AttachmentPlan>,
    eye: Resolution,
) -> Option<Accumulation> {
    let periphery = passes
        .iter()
        .find(|p| p.kind == PassKind::Scene && p.first_view == 0)?;
    let colour = periphery.resolve.unwrap_or(periphery.color).attachment;
    let depth = periphery.depth?.attachment;
    let image = |name| AttachmentPlan {
        name,
        role: AttachmentRole::Color,
        format: Format::Rgba16F,
        samples: 1,
        width: eye.width,
        height: eye.height,
        layers: 2,
        read_after_frame: false,
        sampled: false,
        transient: false,
    };
    attachments.push(image("periphery history"));
    let history = attachments.len() - 1;
    attachments.push(image("accumulated periphery"));
    let accumulated = attachments.len() - 1;
    // The order of `samples` is the executor's binding order.
    passes.push(full_view_pass(
        vec![colour, history, depth],
        accumulated,
        attachments,
        "accumulate (periphery over its history)",
        PassKind::Accumulate,
        Step::Accumulate,
    ));
    let store = full_view_pass(
        vec![accumulated],
        history,
        attachments,
        "store history",
        PassKind::StoreHistory,
        Step::StoreHistory,
    );
    Some(Accumulation { accumulated, store })
}

pub(super) fn accumulate_pipeline(ctx: &StepContext) -> PipelineDesc {
    ctx.pipeline(&COMPOSITE_VERT, &ACCUMULATE_FRAG, &ACCUMULATE_FRAG_COUNTING)
}

pub(super) fn store_history_pipeline(ctx: &StepContext) -> PipelineDesc {
    ctx.pipeline(
        &COMPOSITE_VERT,
        &STORE_HISTORY_FRAG,
        &STORE_HISTORY_FRAG_COUNTING,
    )
}
