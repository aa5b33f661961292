//! The output stage (Di Donato 2017 §3.3–3.4, §3.6.1): what the display shows, per eye — for the
//! lens, each pixel undistorted then fetched; for a foveated frame, the periphery upscaled
//! bilinearly and the fovea blended over it with smoothstep across the band: its descriptor set,
//! sampler and uniforms (its pipeline is its step's, like every other).

use glam::Vec4;

use super::descriptors::DescriptorSet;
use super::executor::{Executor, FrameContext};
use super::recorder::{Recorder, Rect};
use super::sampled_set::SampledSet;
use crate::gpu::{Buffer, Gpu, GpuError, Image};
use crate::plan::{PassPlan, Step};
use crate::view::{Eye, FovTangents};

/// The output stage's uniform block (`Output` in `shaders/output.frag`, std140).
#[repr(C)]
#[derive(Clone, Copy)]
struct OutputBlock {
    periphery: [Vec4; 2],
    fovea: [Vec4; 2],
    display: [Vec4; 2],
    params: Vec4,
    screen: Vec4,
}

pub(crate) struct OutputStage {
    /// One per frame slot.
    sets: Vec<SampledSet>,
}

impl OutputStage {
    /// Sets up sampling of the images the output pass reads (its `samples`, in order),
    /// counting into each frame slot's counter (`counters`) in counting frames.
    pub fn new(
        gpu: &Gpu,
        images: &[&Image],
        counters: &[Option<&Buffer>],
    ) -> Result<Self, GpuError> {
        let bytes = std::mem::size_of::<OutputBlock>() as u64;
        Ok(OutputStage {
            sets: SampledSet::per_slot(gpu, images, true, bytes, 0, counters)?,
        })
    }
}

impl Executor for OutputStage {
    /// Writes this frame's fields: each eye's rendered and display tangents, and with
    /// foveation its (gaze-dependent) fovea tangents.
    fn update(&mut self, slot: usize, frame: &FrameContext) {
        let (plan, fovea) = (frame.plan, frame.fovea);
        let tangents = |f: FovTangents| Vec4::from_array(f.as_array());
        let periphery = Eye::BOTH.map(|e| tangents(plan.eyes.fov(e)));
        let (k1, k2) = plan
            .lens
            .map_or((0.0, 0.0), |l| (l.distortion.k1, l.distortion.k2));
        let block = OutputBlock {
            periphery,
            fovea: fovea.map_or(periphery, |f| f.map(tangents)),
            display: plan.lens.map_or(periphery, |l| l.display.map(tangents)),
            params: plan.foveation.map_or(Vec4::ZERO, |g| {
                Vec4::new(
                    g.fovea_screen_px,
                    g.blend_band_px,
                    g.debug_tint as u32 as f32,
                    g.periphery_sharpen,
                )
            }),
            screen: Vec4::new(
                plan.eye_resolution.width as f32,
                plan.eye_resolution.height as f32,
                k1,
                k2,
            ),
        };
        self.sets[slot].uniforms.write(&[block]);
    }

    fn descriptors(&self, step: &Step, slot: usize) -> Option<&DescriptorSet> {
        matches!(step, Step::Output(_)).then_some(&self.sets[slot].descriptors)
    }
}

/// The output step: one full-view triangle per eye (multiview).
pub(super) fn record_output(pass: &PassPlan, area: Rect, rec: &mut dyn Recorder) {
    rec.set_viewport(area, pass.guard_band);
    rec.draw(3);
}
