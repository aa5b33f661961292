//! Composition of a foveated frame (seed 001 §3.3–3.4, §3.6.1): each eye at full resolution,
//! the periphery view upscaled bilinearly and the fovea view blended over it with smoothstep
//! across the band at the fovea's edge. A technique in one place: its descriptor set, sampler,
//! uniforms, pipeline and recording.

use glam::Vec4;

use std::sync::Arc;

use super::pipelines::{pass_pipeline, PipelineKind};
use super::sampled_set::SampledSet;
use super::targets::CompiledPass;
use crate::gpu::{Buffer, Gpu, GpuError, Image, Pipeline};
use crate::plan::FramePlan;
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
    pub pipeline: Arc<Pipeline>,
    pub set: SampledSet,
}

impl Composite {
    /// Sets up composition for pass `pass`, sampling `views` (the scene pass's four layers) and
    /// counting into `counter` in counting frames.
    pub fn new(
        gpu: &Gpu,
        plan: &FramePlan,
        pass: usize,
        compiled: &CompiledPass,
        views: &Image,
        counter: Option<&Buffer>,
    ) -> Result<Self, GpuError> {
        let bytes = std::mem::size_of::<CompositeBlock>() as u64;
        let set = SampledSet::new(gpu, views, bytes, 0, counter)?;
        let pipeline = pass_pipeline(
            gpu,
            plan,
            pass,
            PipelineKind::Composite,
            compiled,
            &set.layout,
            &set.layout_description,
        )?;
        Ok(Composite { pipeline, set })
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
