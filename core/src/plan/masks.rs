//! Stencil masks (the HMD mask's lens ellipse, foveation's inset and outset circles): mask fans
//! first in a scene pass. Shapes per frame: `render/masks.rs`; shaders: `mask.vert`, `mask.frag`.

use super::model::PassPlan;
use super::steps::{stencil_placeholder, Step};

pub(super) fn add_mask_fans(pass: &mut PassPlan) {
    pass.steps.insert(
        0,
        Step::MaskFans {
            stencil: stencil_placeholder(),
        },
    );
}
