//! Stencil masks (the HMD mask's lens ellipse, foveation's inset and outset circles): mask fans
//! first in a scene pass. Shapes per frame: `foveation_layer/masks.rs`; shaders: `mask.vert`, `mask.frag`.

use super::model::PassPlan;
use super::pipeline::{PipelineDesc, StepContext};
use super::steps::{stencil_placeholder, Step};
use crate::shaders::{MASK_FRAG, MASK_FRAG_COUNTING, MASK_VERT};

/// The mask fans first in `pass`; with `hidden_area`, they also drop a runtime's hidden-area
/// mesh (handed in per frame) from the eye views.
pub(super) fn add_mask_fans(pass: &mut PassPlan, hidden_area: bool) {
    pass.steps.insert(
        0,
        Step::MaskFans {
            stencil: stencil_placeholder(),
            hidden_area,
        },
    );
}

/// Mask fans write stencil only, their reference set per fan set.
pub(super) fn mask_pipeline(ctx: &StepContext) -> PipelineDesc {
    PipelineDesc {
        writes_colour: false,
        dynamic_stencil_reference: true,
        ..ctx.pipeline(&MASK_VERT, &MASK_FRAG, &MASK_FRAG_COUNTING)
    }
}
