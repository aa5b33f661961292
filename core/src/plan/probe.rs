//! The coverage probe: last in a scene pass, a full-view draw counted per view under the pass's
//! masks (`foveate pixels` measures with it). Executor: `foveation_layer/probe.rs`.

use super::model::PassPlan;
use super::pipeline::{PipelineDesc, StepContext};
use super::steps::Step;
use crate::shaders::{COVERAGE_FRAG, COVERAGE_VERT};

pub(super) fn add_probe(pass: &mut PassPlan) {
    pass.steps.push(Step::Probe { stencil: None });
}

/// The probe counts in every frame (its fragment shader always has the counter) and writes
/// nothing.
pub(super) fn probe_pipeline(ctx: &StepContext) -> PipelineDesc {
    PipelineDesc {
        writes_colour: false,
        ..ctx.pipeline(&COVERAGE_VERT, &COVERAGE_FRAG, &COVERAGE_FRAG)
    }
}
