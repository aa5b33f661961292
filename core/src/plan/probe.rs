//! The coverage probe: last in a scene pass, a full-view draw counted per view under the pass's
//! masks (`foveate pixels` measures with it). Executor: `render/probe.rs`.

use super::model::PassPlan;
use super::steps::Step;

pub(super) fn add_probe(pass: &mut PassPlan) {
    pass.steps.push(Step::Probe { stencil: None });
}
