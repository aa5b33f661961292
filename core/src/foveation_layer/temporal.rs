//! Temporal accumulation of the periphery, the output stage's share of it (builder:
//! `plan/temporal.rs`; maths: `foveation/temporal.rs`; shader: `accumulate.glsl`): the state
//! the output stage keeps across frames. It keeps the previous frame's eye poses, from which
//! each frame it writes the reprojection into the previous frame's clip space, and decides when
//! the history is dropped whole (the first frame, a cut).

use glam::{Mat4, Vec2, Vec4};

use super::executor::FrameContext;
use crate::foveation::{HistoryClip, TemporalConfig};
use crate::plan::FramePlan;
use crate::view::{reverse_z_projection, Eye, FovTangents};

/// The accumulation's share of the output stage's uniform block (`Output` in
/// `shaders/output.frag`, std140, after the composition's fields).
#[repr(C)]
#[derive(Clone, Copy, Default)]
pub(super) struct AccumulateBlock {
    previous_from_view: [Mat4; 2],
    jitter: Vec4,
    depth: Vec4,
    clip: Vec4,
    still: Vec4,
}

pub(super) struct TemporalAccumulation {
    config: TemporalConfig,
    /// Each eye's unjittered projection (the plan's field and depth range: fixed).
    projection: [Mat4; 2],
    /// Each eye's clip space from world space (unjittered) and the left eye's pose, of the
    /// frame before; `None` until a frame was rendered.
    previous: Option<([Mat4; 2], Mat4)>,
    /// Frames rendered since the history was last dropped whole.
    frames_accumulated: u64,
    /// The frame before's jitter: where its periphery's depth was sampled.
    previous_jitter: Vec2,
}

impl TemporalAccumulation {
    pub fn new(plan: &FramePlan, config: TemporalConfig) -> Self {
        TemporalAccumulation {
            config,
            projection: Eye::BOTH
                .map(|e| reverse_z_projection(plan.eyes.fov(e), plan.near, plan.far)),
            previous: None,
            frames_accumulated: 0,
            previous_jitter: Vec2::ZERO,
        }
    }

    /// This frame's block: the reprojection from its eyes into the previous frame's clip
    /// space, the jitter, and a reset on the first frame and at a cut. Advances the state.
    /// `texels_per_px`: the history's pixels per output pixel (1, or the periphery's density
    /// where it accumulates at its own texels).
    pub fn next_block(&mut self, frame: &FrameContext, texels_per_px: f32) -> AccumulateBlock {
        let plan = frame.plan;
        let hole_px = plan.foveation.map_or(0.0, |g| g.accumulated_hole_px) * texels_per_px;
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
        // Where an instance was taken out, nothing marks its pixels: `moved` clips everywhere
        // for this one frame, as the range clip does.
        let clip = match self.config.clip {
            HistoryClip::Moved if frame.instance_removed => HistoryClip::Range,
            clip => clip,
        };
        let block = AccumulateBlock {
            previous_from_view: Eye::BOTH
                .map(|e| previous_clip[e.index()] * world_from_eye[e.index()]),
            jitter: Vec4::new(jitter.x, jitter.y, self.config.blend, reset as u32 as f32),
            depth: Vec4::new(a, b, hole_px * 0.5, 1.0 / self.frames_accumulated as f32),
            clip: Vec4::new(
                clip.spread(),
                clip.depth_test(),
                self.previous_jitter.x,
                self.previous_jitter.y,
            ),
            still: {
                let (end, fade) = self.config.reach_cosines();
                Vec4::new(self.config.still_blend, end, fade, 0.0)
            },
        };
        self.previous_jitter = jitter;
        self.previous = Some((
            Eye::BOTH.map(|e| self.projection[e.index()] * world_from_eye[e.index()].inverse()),
            world_from_eye[0],
        ));
        block
    }
}

/// A field of view as the shaders take it: tangents left, right, up, down.
pub(super) fn tangents(f: FovTangents) -> Vec4 {
    Vec4::from_array(f.as_array())
}
