//! A view's resolve copied into its layer (builder: `plan/split_views.rs`; shader:
//! `layer_copy.frag`), where the driver resolves into layer 0 whatever the target's base layer:
//! each copy pass's one sampled image. Nothing to update per frame.

use super::descriptors::DescriptorSet;
use super::executor::{Executor, FrameContext};
use super::recorder::{Recorder, Rect};
use super::sampled_set::SampledSet;
use crate::gpu::{Buffer, Gpu, GpuError, Image};
use crate::plan::{AttachmentId, FramePlan, PassPlan, Step};

/// The images the plan's copy passes read, sampled: per image, one set per frame slot.
pub(crate) struct LayerCopies {
    sets: Vec<(AttachmentId, Vec<SampledSet>)>,
}

impl LayerCopies {
    /// The copies `plan` has (`None` without any), sampling `images`, counting into each
    /// frame slot's counter in counting frames (`counters`).
    pub fn new(
        gpu: &Gpu,
        plan: &FramePlan,
        images: &[Image],
        counters: &[Option<&Buffer>],
    ) -> Result<Option<Self>, GpuError> {
        let mut sets = Vec::new();
        for step in plan.passes.iter().flat_map(|p| &p.steps) {
            if let Step::LayerCopy { from } = *step {
                // The shader reads no uniforms: the smallest block the sampled set allows.
                let image = [&images[from]];
                sets.push((
                    from,
                    SampledSet::per_slot(gpu, &image, true, 16, 0, counters)?,
                ));
            }
        }
        Ok((!sets.is_empty()).then_some(LayerCopies { sets }))
    }
}

impl Executor for LayerCopies {
    fn update(&mut self, _slot: usize, _frame: &FrameContext) {}

    fn descriptors(&self, step: &Step, slot: usize, _parity: usize) -> Option<&DescriptorSet> {
        let Step::LayerCopy { from } = *step else {
            return None;
        };
        let (_, sets) = self.sets.iter().find(|(id, _)| *id == from)?;
        Some(&sets[slot].descriptors)
    }
}

/// The copy step: one full-view triangle.
pub(super) fn record_layer_copy(pass: &PassPlan, area: Rect, rec: &mut dyn Recorder) {
    rec.set_viewport(area, pass.guard_band);
    rec.draw(3);
}
