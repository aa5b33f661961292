//! Radial density masking (Preißner 2020 §4.4.2, after Vlachos, GDC 2016): in the scene pass, a
//! stencil mask skips 2×2 pixel quads in the periphery — every other quad past `inner`, three in
//! four past `outer`, distances in units of the lens ellipse — and a reconstruction pass fills the
//! skipped quads from their kept neighbours. Shaders: `radial_density.glsl`, `radial_mask.frag`,
//! `reconstruct.frag`; executor: `foveation_layer/radial_density.rs`.

use super::config::RadialDensityGeometry;
use super::model::{AttachmentPlan, PassKind, PassPlan};
use super::output::sampling_pass;
use super::pipeline::{Constant, PipelineDesc, StepContext};
use super::steps::{stencil_placeholder, Step};
use super::Resolution;
use crate::shaders::{
    COMPOSITE_VERT, RADIAL_MASK_FRAG, RADIAL_MASK_FRAG_COUNTING, RECONSTRUCT_FRAG,
    RECONSTRUCT_FRAG_COUNTING,
};

/// Adds the mask step to the scene pass — after any mask fans, before the scene; the scene and
/// probe skip what it marks (`steps::assign_stencil_states`) — then the reconstruction pass.
pub(super) fn add_radial_density(
    passes: &mut Vec<PassPlan>,
    attachments: &mut Vec<AttachmentPlan>,
    eye: Resolution,
) {
    let Some(scene) = passes.iter_mut().find(|p| p.kind == PassKind::Scene) else {
        return;
    };
    let at = scene
        .steps
        .iter()
        .position(|s| !matches!(s, Step::MaskFans { .. }))
        .unwrap_or(0);
    scene.steps.insert(
        at,
        Step::RadialMask {
            stencil: stencil_placeholder(),
        },
    );
    let scene = scene.clone();
    let views = scene.resolve.unwrap_or(scene.color).attachment;
    attachments[views].name = "masked stereo colour";
    let reconstruct = sampling_pass(
        vec![views],
        eye,
        attachments,
        "reconstruct (radial density)",
        PassKind::Reconstruct,
        Step::Reconstruct,
    );
    passes.push(reconstruct);
}

/// The mask's full-view draw writes stencil only.
pub(super) fn radial_mask_pipeline(ctx: &StepContext, r: &RadialDensityGeometry) -> PipelineDesc {
    let desc = ctx.pipeline(
        &COMPOSITE_VERT,
        &RADIAL_MASK_FRAG,
        &RADIAL_MASK_FRAG_COUNTING,
    );
    PipelineDesc {
        writes_colour: false,
        ..with_lens(desc, r)
    }
}

pub(super) fn reconstruct_pipeline(ctx: &StepContext, r: &RadialDensityGeometry) -> PipelineDesc {
    let desc = ctx.pipeline(
        &COMPOSITE_VERT,
        &RECONSTRUCT_FRAG,
        &RECONSTRUCT_FRAG_COUNTING,
    );
    with_lens(desc, r)
}

/// The view's size, the radii and each eye's lens ellipse (`shaders/radial_density.glsl`).
fn with_lens(desc: PipelineDesc, r: &RadialDensityGeometry) -> PipelineDesc {
    use Constant::*;
    let values = [
        r.view.width as f32,
        r.view.height as f32,
        r.config.inner,
        r.config.outer,
    ]
    .into_iter()
    .chain(r.lens.iter().flat_map(|l| l.to_array()));
    let names = [
        ViewWidth, ViewHeight, Inner, Outer, LeftCx, LeftCy, LeftRx, LeftRy, RightCx, RightCy,
        RightRx, RightRy,
    ];
    names
        .into_iter()
        .zip(values)
        .fold(desc, |desc, (name, value)| desc.float(name, value))
}
