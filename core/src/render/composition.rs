//! Composition of a foveated frame (seed 001 §3.3–3.4, §3.6.1): each eye at full resolution,
//! the periphery view upscaled bilinearly and the fovea view blended over it with smoothstep
//! across the band at the fovea's edge: its descriptor set, sampler and uniforms (its pipeline is
//! its step's, like every other).

use glam::Vec4;

use super::record::{Recorder, Rect};
use super::sampled_set::SampledSet;
use crate::gpu::{Buffer, Gpu, GpuError, Image};
use crate::plan::{FramePlan, PassPlan};
use crate::view::{Eye, FovTangents};

/// The composition's uniform block (`Composite` in `shaders/composite.frag`, std140).
#[repr(C)]
#[derive(Clone, Copy)]
struct CompositeBlock {
    periphery: [Vec4; 2],
    fovea: [Vec4; 2],
    params: Vec4,
    screen: Vec4,
}

pub(crate) struct Composite {
    pub set: SampledSet,
}

impl Composite {
    /// Sets up sampling of `views` (the scene pass's four layers), counting into `counter` in
    /// counting frames.
    pub fn new(gpu: &Gpu, views: &Image, counter: Option<&Buffer>) -> Result<Self, GpuError> {
        let bytes = std::mem::size_of::<CompositeBlock>() as u64;
        Ok(Composite {
            set: SampledSet::new(gpu, views, bytes, 0, counter)?,
        })
    }

    /// Writes this frame's windows: each eye's periphery and (gaze-dependent) fovea tangents.
    pub fn update(&mut self, plan: &FramePlan, fovea: &[FovTangents; 2]) {
        let g = plan
            .foveation
            .as_ref()
            .expect("composition is planned only with foveation");
        let tangents = |f: FovTangents| Vec4::from_array(f.as_array());
        let block = CompositeBlock {
            periphery: Eye::BOTH.map(|e| tangents(plan.eyes.fov(e))),
            fovea: fovea.map(tangents),
            params: Vec4::new(
                g.fovea_screen_px,
                g.blend_band_px,
                g.debug_tint as u32 as f32,
                0.0,
            ),
            screen: Vec4::new(
                plan.eye_resolution.width as f32,
                plan.eye_resolution.height as f32,
                0.0,
                0.0,
            ),
        };
        self.set.uniforms.write(&[block]);
    }
}

/// The composition step: one full-view triangle per eye (multiview) sampling the views.
pub(super) fn record_composition(pass: &PassPlan, area: Rect, rec: &mut dyn Recorder) {
    rec.set_viewport(area, pass.guard_band);
    rec.draw(3);
}
