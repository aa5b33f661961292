//! Radial density masking in the renderer (builder: `plan/radial_density.rs`; shaders:
//! `radial_density.glsl`, `radial_mask.frag`, `reconstruct.frag`): recording the mask and the
//! reconstruction, and the reconstruction's sampled views. Every parameter is a
//! specialisation constant of the pipelines, so there is nothing to update per frame.

use super::descriptors::DescriptorSet;
use super::executor::{Executor, FrameContext};
use super::recorder::{Recorder, Rect};
use super::sampled_set::SampledSet;
use crate::gpu::{Buffer, Gpu, GpuError, Image};
use crate::plan::{PassPlan, Step};

/// The reconstruction's resources: the masked views, sampled.
pub(crate) struct Reconstruction {
    /// One per frame slot.
    sets: Vec<SampledSet>,
}

impl Reconstruction {
    /// Sets up sampling of `views` (the scene pass's two layers), counting into `counter` in
    /// counting frames (`counters`: each frame slot's).
    pub fn new(gpu: &Gpu, views: &Image, counters: &[Option<&Buffer>]) -> Result<Self, GpuError> {
        // The shader reads no uniforms: the smallest block the sampled set allows.
        Ok(Reconstruction {
            sets: SampledSet::per_slot(gpu, &[views], false, 16, 0, counters)?,
        })
    }
}

impl Executor for Reconstruction {
    fn update(&mut self, _slot: usize, _frame: &FrameContext) {}

    fn descriptors(&self, step: &Step, slot: usize, _parity: usize) -> Option<&DescriptorSet> {
        (*step == Step::Reconstruct).then_some(&self.sets[slot].descriptors)
    }
}

/// The mask step: one full-view triangle per view; its shader keeps the skipped quads, whose
/// stencil it marks.
pub(super) fn record_radial_mask(pass: &PassPlan, area: Rect, rec: &mut dyn Recorder) {
    rec.set_viewport(area, pass.guard_band);
    rec.draw(3);
}

/// The reconstruction step: one full-view triangle per eye.
pub(super) fn record_reconstruction(pass: &PassPlan, area: Rect, rec: &mut dyn Recorder) {
    rec.set_viewport(area, pass.guard_band);
    rec.draw(3);
}
