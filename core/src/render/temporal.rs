//! Temporal accumulation of the periphery in the renderer (builder: `plan/temporal.rs`; maths:
//! `foveation/temporal.rs`; shaders: `accumulate.frag`, `store_history.frag`): the first
//! executor with state across frames. It keeps the previous frame's eye poses, from which each
//! frame it writes the reprojection into the previous frame's clip space, and decides when the
//! history is dropped whole (the first frame, a cut).

use glam::{Mat4, Vec2, Vec4};

use super::descriptors::DescriptorSet;
use super::executor::{Executor, FrameContext};
use super::recorder::{Recorder, Rect};
use super::sampled_set::SampledSet;
use crate::foveation::TemporalConfig;
use crate::gpu::{Buffer, Gpu, GpuError, Image};
use crate::plan::{FramePlan, PassPlan, Step};
use crate::view::{reverse_z_projection, Eye, FovTangents};

/// The accumulate pass's uniform block (`Accumulate` in `shaders/accumulate.frag`, std140).
#[repr(C)]
#[derive(Clone, Copy)]
struct AccumulateBlock {
    previous_from_view: [Mat4; 2],
    field: [Vec4; 2],
    fovea: [Vec4; 2],
    jitter: Vec4,
    depth: Vec4,
}

/// The images the accumulation reads and writes, as the plan's passes name them.
pub(crate) struct TemporalImages<'a> {
    pub periphery: &'a Image,
    pub history: &'a Image,
    pub periphery_depth: &'a Image,
    pub accumulated: &'a Image,
}

pub(crate) struct TemporalAccumulation {
    config: TemporalConfig,
    /// Each eye's unjittered projection (the plan's field and depth range: fixed).
    projection: [Mat4; 2],
    /// Each eye's rendered field as tangents (left, right, up, down): fixed by the plan.
    field: [Vec4; 2],
    /// The accumulate and store-history steps' sets, one of each per frame slot.
    accumulate: Vec<SampledSet>,
    store: Vec<SampledSet>,
    /// Each eye's clip space from world space (unjittered) and the left eye's pose, of the
    /// frame before; `None` until a frame was rendered.
    previous: Option<([Mat4; 2], Mat4)>,
    /// Frames rendered since the history was last dropped whole.
    frames_accumulated: u64,
}

impl TemporalAccumulation {
    pub fn new(
        gpu: &Gpu,
        plan: &FramePlan,
        config: TemporalConfig,
        images: TemporalImages,
        counters: &[Option<&Buffer>],
    ) -> Result<Self, GpuError> {
        let bytes = std::mem::size_of::<AccumulateBlock>() as u64;
        let field = Eye::BOTH.map(|e| tangents(plan.eyes.fov(e)));
        let sources = [images.periphery, images.history, images.periphery_depth];
        Ok(TemporalAccumulation {
            config,
            field,
            projection: Eye::BOTH
                .map(|e| reverse_z_projection(plan.eyes.fov(e), plan.near, plan.far)),
            accumulate: SampledSet::per_slot(gpu, &sources, true, bytes, 0, counters)?,
            // The copy reads no uniforms: the smallest block the sampled set allows.
            store: SampledSet::per_slot(gpu, &[images.accumulated], true, 16, 0, counters)?,
            previous: None,
            frames_accumulated: 0,
        })
    }
}

impl Executor for TemporalAccumulation {
    /// Writes the reprojection from this frame's eyes into the previous frame's clip space, and
    /// drops the history on the first frame and at a cut.
    fn update(&mut self, slot: usize, frame: &FrameContext) {
        let plan = frame.plan;
        let Some(g) = plan.foveation else { return };
        let world_from_eye = Eye::BOTH.map(|e| frame.views.views[e.index()].0);
        let reset = self
            .previous
            .is_none_or(|(_, left)| self.config.is_cut(left, world_from_eye[0]));
        let previous_clip = self.previous.map_or([Mat4::IDENTITY; 2], |(clip, _)| clip);
        let jitter = frame.jitter.unwrap_or(Vec2::ZERO);
        // depth = b / distance − a, from the projection's third row.
        let (a, b) = (self.projection[0].z_axis.z, self.projection[0].w_axis.z);
        self.frames_accumulated = if reset {
            1
        } else {
            self.frames_accumulated + 1
        };
        let block = AccumulateBlock {
            previous_from_view: Eye::BOTH
                .map(|e| previous_clip[e.index()] * world_from_eye[e.index()]),
            field: self.field,
            fovea: frame.fovea.map_or(self.field, |f| f.map(tangents)),
            jitter: Vec4::new(jitter.x, jitter.y, self.config.blend, reset as u32 as f32),
            depth: Vec4::new(
                a,
                b,
                g.accumulated_hole_px * 0.5,
                1.0 / self.frames_accumulated as f32,
            ),
        };
        self.accumulate[slot].uniforms.write(&[block]);
        self.previous = Some((
            Eye::BOTH.map(|e| self.projection[e.index()] * world_from_eye[e.index()].inverse()),
            world_from_eye[0],
        ));
    }

    fn descriptors(&self, step: &Step, slot: usize) -> Option<&DescriptorSet> {
        match step {
            Step::Accumulate => Some(&self.accumulate[slot].descriptors),
            Step::StoreHistory => Some(&self.store[slot].descriptors),
            _ => None,
        }
    }
}

fn tangents(f: FovTangents) -> Vec4 {
    Vec4::from_array(f.as_array())
}

/// The accumulate and store-history steps: one full-view triangle per eye each.
pub(super) fn record_temporal(pass: &PassPlan, area: Rect, rec: &mut dyn Recorder) {
    rec.set_viewport(area, pass.guard_band);
    rec.draw(3);
}
