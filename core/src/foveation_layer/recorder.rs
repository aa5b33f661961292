//! The one narrow interface recording goes through ([`Recorder`]), implemented by Vulkan
//! (`vulkan_recorder.rs`) and by a command log (`command_log.rs`) that tests read without a GPU,
//! and the small types it speaks in.

use crate::plan::{Barrier, ClearValue};
use crate::scene::Draw;

/// A rectangle of a pass's render area: x, y, width, height in pixels.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    pub x: u32,
    pub y: u32,
    pub width: u32,
    pub height: u32,
}

/// What recording a frame does, in the renderer's own terms.
pub trait Recorder {
    /// Before the frame: reset `count` timestamp queries (the whole pool, spare slots too).
    fn reset_queries(&mut self, count: u32);
    /// A timestamp after everything recorded so far.
    fn timestamp(&mut self, index: u32);
    /// Counting frames: zero the fragment counters, visible to the fragment shaders, and reset
    /// `statistics` pipeline-statistics queries.
    fn clear_counters(&mut self, statistics: u32);
    /// Counting frames: a pipeline-statistics query around pass `pass` (outside the render
    /// pass, so a multiview pass's views land in one query).
    fn begin_statistics(&mut self, pass: usize);
    fn end_statistics(&mut self, pass: usize);
    /// Counting frames: one pass's counting atomics before the next pass's.
    fn counters_barrier(&mut self);
    /// Counting frames: the counters, visible to the host.
    fn counters_to_host(&mut self);
    /// Pass `pass` begins, clearing as `clears` says, once what it waits on is done (`wait`:
    /// the plan's barriers, which Vulkan executes as the render pass's external dependency).
    fn begin_pass(&mut self, pass: usize, clears: &[ClearValue], wait: &[Barrier]);
    /// Pass `pass` ends; later work that touches its images waits for it as `signal` says.
    fn end_pass(&mut self, pass: usize, signal: &[Barrier]);
    /// Step `step` of pass `pass`: its pipeline and the resources it reads.
    fn bind_step(&mut self, pass: usize, step: usize);
    /// The scene's vertex and index buffers.
    fn bind_geometry(&mut self);
    /// Viewport `guard_band` times larger than `area`, centred on it, scissored to it.
    fn set_viewport(&mut self, area: Rect, guard_band: u32);
    /// The vertex stage's push constant: the view index or the mask fans' shape set.
    fn push_vertex(&mut self, value: u32);
    /// The fragment stage's push constant (the far composite's view in a single-eye pass).
    fn push_fragment(&mut self, value: u32);
    fn stencil_reference(&mut self, reference: u32);
    /// `vertices` generated vertices (full-view triangles, mask fans).
    fn draw(&mut self, vertices: u32);
    /// Mesh `mesh` for `instance_count` instances from `first_instance`.
    fn draw_indexed(&mut self, mesh: usize, instance_count: u32, first_instance: u32);
    /// Step `step` of pass `pass` is the engine's: it draws its own world into the pass's
    /// views, with its own pipelines and resources.
    fn engine_draws(&mut self, pass: usize, step: usize);
}

/// Who draws a frame's scene steps.
pub enum FrameDraws<'a> {
    /// foveate's scene: every instance, and each cull slot's culled draws.
    Scene {
        all: &'a [Draw],
        culled: &'a [Vec<Draw>],
    },
    /// An engine, its own draws (a `FoveationLayer`'s frame).
    Engine,
}

impl FrameDraws<'_> {
    /// The draws of a scene step of foveate's scene culled into `cull_slot` (every instance
    /// when none); `None` when the engine draws.
    pub(super) fn of(&self, cull_slot: Option<usize>) -> Option<&[Draw]> {
        match self {
            FrameDraws::Scene { all, culled } => {
                Some(cull_slot.map_or(*all, |slot| &culled[slot][..]))
            }
            FrameDraws::Engine => None,
        }
    }
}
