//! The output stage (Di Donato 2017 §3.3–3.4, §3.6.1): what the display shows, per eye — for the
//! lens, each pixel undistorted then fetched; for a foveated frame, the periphery upscaled
//! bilinearly (or accumulated over frames: `temporal.rs`) and the fovea blended over it with
//! smoothstep across the band: its descriptor sets, sampler and uniforms (its pipeline is its
//! step's, like every other). A periphery accumulated at its own texels runs the same stage
//! once more before the output pass, at the periphery's size with no fovea and no lens: one
//! `OutputStage` per output step.

use glam::Vec4;

use super::descriptors::DescriptorSet;
use super::executor::{Executor, FrameContext};
use super::recorder::{Recorder, Rect};
use super::sampled_set::SampledSet;
use super::temporal::{tangents, AccumulateBlock, TemporalAccumulation};
use crate::foveation::TemporalConfig;
use crate::gpu::{Buffer, Gpu, GpuError, Image};
use crate::plan::{FramePlan, OutputStep, PassPlan, Step};
use crate::view::Eye;

/// The output stage's uniform block (`Output` in `shaders/output.frag`, std140).
#[repr(C)]
#[derive(Clone, Copy)]
struct OutputBlock {
    periphery: [Vec4; 2],
    fovea: [Vec4; 2],
    display: [Vec4; 2],
    params: Vec4,
    screen: Vec4,
    accumulate: AccumulateBlock,
    /// The parafoveal ring's tangents per eye.
    ring: [Vec4; 2],
    /// The ring's diameter and band (screen pixels).
    ring_params: Vec4,
}

pub(crate) struct OutputStage {
    /// The step it serves: the output pass's, or the periphery's accumulation at its own
    /// texels before it.
    step: OutputStep,
    /// The size of each eye's image the pass writes (pixels).
    screen: [u32; 2],
    /// One per frame parity (the images of a history pair swap roles), one per frame slot.
    sets: [Vec<SampledSet>; 2],
    temporal: Option<TemporalAccumulation>,
}

impl OutputStage {
    /// Sets up sampling of the images the pass of `step` reads, as even and odd frames find
    /// them (`images`: its two sources, then with accumulation the history and the periphery's
    /// depths, this frame's and the frame before's), counting into each frame slot's counter
    /// (`counters`) in counting frames. `screen`: the size of each eye's image it writes.
    pub fn new(
        gpu: &Gpu,
        plan: &FramePlan,
        (step, screen): (OutputStep, [u32; 2]),
        images: [Vec<&Image>; 2],
        temporal: Option<TemporalConfig>,
        counters: &[Option<&Buffer>],
    ) -> Result<Self, GpuError> {
        let bytes = std::mem::size_of::<OutputBlock>() as u64;
        let set =
            |parity: usize| SampledSet::per_slot(gpu, &images[parity], true, bytes, 0, counters);
        // Without a history both parities bind the same: one set each slot serves both.
        let odd = if temporal.is_some() {
            set(1)?
        } else {
            Vec::new()
        };
        Ok(OutputStage {
            step,
            screen,
            sets: [set(0)?, odd],
            temporal: temporal.map(|t| TemporalAccumulation::new(plan, t)),
        })
    }

    /// Which parity's sets frames of `parity` use.
    fn of(&self, parity: usize) -> usize {
        if self.sets[1].is_empty() {
            0
        } else {
            parity
        }
    }
}

impl Executor for OutputStage {
    /// Writes this frame's fields: each eye's rendered and display tangents, with foveation
    /// its (gaze-dependent) fovea tangents, and with accumulation the reprojection.
    fn update(&mut self, slot: usize, frame: &FrameContext) {
        let (plan, fovea) = (frame.plan, frame.fovea);
        let periphery = Eye::BOTH.map(|e| tangents(plan.eyes.fov(e)));
        let (k1, k2) = plan
            .lens
            .map_or((0.0, 0.0), |l| (l.distortion.k1, l.distortion.k2));
        // The periphery accumulated at its own texels measures the fovea, the band and the
        // hole in its texels.
        let texels_per_px = self.screen[0] as f32 / plan.eye_resolution.width as f32;
        let params = match plan.foveation {
            // The fovea's place and band in the periphery's texels; no tint, no sharpening.
            Some(g) if self.step.periphery_only => Vec4::new(
                g.fovea_screen_px * texels_per_px,
                g.blend_band_px * texels_per_px,
                0.0,
                0.0,
            ),
            Some(g) => Vec4::new(
                g.fovea_screen_px,
                g.blend_band_px,
                g.debug_tint as u32 as f32,
                g.periphery_sharpen,
            ),
            None => Vec4::ZERO,
        };
        let ring_params = plan
            .foveation
            .and_then(|g| g.ring)
            .map_or(Vec4::ZERO, |r| Vec4::new(r.screen_px, r.band_px, 0.0, 0.0));
        let block = OutputBlock {
            periphery,
            fovea: fovea.map_or(periphery, |f| f.map(tangents)),
            ring: frame.views.ring.map_or(periphery, |r| r.map(tangents)),
            ring_params,
            display: plan.lens.map_or(periphery, |l| l.display.map(tangents)),
            params,
            screen: Vec4::new(self.screen[0] as f32, self.screen[1] as f32, k1, k2),
            accumulate: self
                .temporal
                .as_mut()
                .map_or_else(AccumulateBlock::default, |t| {
                    t.next_block(frame, texels_per_px)
                }),
        };
        let parity = self.of(frame.parity);
        self.sets[parity][slot].uniforms.write(&[block]);
    }

    fn descriptors(&self, step: &Step, slot: usize, parity: usize) -> Option<&DescriptorSet> {
        matches!(step, Step::Output(o) if *o == self.step)
            .then_some(&self.sets[self.of(parity)][slot].descriptors)
    }
}

/// The output step: one full-view triangle per eye (multiview).
pub(super) fn record_output(pass: &PassPlan, area: Rect, rec: &mut dyn Recorder) {
    rec.set_viewport(area, pass.guard_band);
    rec.draw(3);
}
