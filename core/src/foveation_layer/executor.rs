//! A technique's executor: made from the plan, it owns its technique's resources (images,
//! buffers, descriptor sets, per-frame uniforms), writes its uniforms each frame and records its
//! steps (each executor's file has its `record_…` functions). The renderer keeps its executors
//! in a list and loops over them; it computes none of their maths.

use super::descriptors::DescriptorSet;
use super::views::FrameViews;
use crate::plan::{FramePlan, Step};
use crate::view::{FovTangents, HiddenArea};

/// What every executor sees of a frame before it is recorded.
pub(super) struct FrameContext<'a> {
    pub plan: &'a FramePlan,
    /// Each eye's fovea window around its gaze, when foveated.
    pub fovea: Option<&'a [FovTangents; 2]>,
    /// Every view of the frame, the MFFR far view included.
    pub views: &'a FrameViews,
    /// The periphery views' sub-pixel offset this frame (periphery pixels, x right, y down),
    /// when temporal accumulation jitters them.
    pub jitter: Option<glam::Vec2>,
    /// Each eye's hidden-area mesh, when the plan's HMD mask takes one and one was handed in.
    pub hidden_area: Option<&'a [HiddenArea; 2]>,
    /// Whether an instance was taken out of the scene since the frame before.
    pub instance_removed: bool,
    /// 0 on even frames (counted from the renderer's first), 1 on odd: which image of each
    /// history pair the frame reads and which it writes, and which descriptor sets it binds.
    pub parity: usize,
}

/// One technique's per-frame work. One that keeps state across frames (the periphery's
/// temporal history) owns it and says in `update` when it resets.
///
/// Its per-frame resources (uniforms, descriptor sets) come one per frame slot, so a frame
/// records while an earlier one runs: `slot` says whose. State across frames (the previous
/// poses) is the executor's own, shared by every slot.
pub(super) trait Executor: Send {
    /// Writes this frame's uniforms, those of frame slot `slot`.
    fn update(&mut self, slot: usize, frame: &FrameContext);
    /// The descriptor set `step` binds in frame slot `slot` on frames of `parity` (0 even, 1
    /// odd: a history pair's images swap roles), when it is one of this executor's steps that
    /// reads the executor's own resources (others bind the scene's).
    fn descriptors(&self, step: &Step, slot: usize, parity: usize) -> Option<&DescriptorSet>;
}
