//! What a frame cost, as measured: CPU and GPU times, per-pass pipeline statistics, and the
//! counting frame's per-step, per-view fragments.

use ash::vk;

use super::history_outcomes::HistoryOutcomes;
use crate::mffr::FAR_VIEW_INDEX;
use crate::plan::{CountedStep, COUNTER_SLOTS_PER_STEP};

/// What one frame cost, measured.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FrameStats {
    /// CPU time recording the command buffer.
    pub cpu_record_ms: f64,
    /// CPU time of the `vkQueueSubmit` call.
    pub cpu_submit_ms: f64,
    /// Wall time from the start of recording to the frame's fence signalling.
    pub frame_ms: f64,
    /// GPU time between the frame's first and last timestamp (when timestamps are planned).
    pub gpu_ms: Option<f64>,
    /// GPU time of each planned pass, in plan order (when timestamps are planned); named by
    /// [`FrameStats::gpu_pass_times`].
    pub gpu_pass_ms: Vec<f64>,
    /// Each planned pass's name, in plan order, as the plan prints it.
    pub pass_names: Vec<&'static str>,
    /// Fragments the scene draws shaded per eye view, over every eye pass (when fragment
    /// counting is planned; empty otherwise). Masks, composites and probes are in
    /// [`FrameStats::steps`].
    pub fragments: Vec<u64>,
    /// Fragments the MFFR far pass's scene draws shaded (when both are planned).
    pub far_fragments: Option<u64>,
    /// Every counted step's fragments, per view, in recording order (counting frames only).
    pub steps: Vec<StepFragments>,
    /// What became of each accumulated pixel's history (counting frames whose output
    /// accumulates the periphery; `None` otherwise).
    pub history: Option<HistoryOutcomes>,
    /// CPU time splitting the instances into the MFFR near and far sets (0 without MFFR).
    pub cpu_cull_ms: f64,
    /// Instances drawn by each scene pass, in plan order (every instance without culling).
    pub instances_drawn: Vec<u64>,
    /// Draw commands the frame recorded (scene draws, masks, composites).
    pub draw_calls: u64,
    /// Triangles those draw commands submitted (per draw: triangles × instances).
    pub triangles: u64,
    /// Of those, the triangles each pass submitted, in plan order.
    pub pass_triangles: Vec<u64>,
    /// Primitives and fragment-shader invocations each pass's pipelines processed, measured by
    /// pipeline-statistics queries (counting frames on devices that have them; empty
    /// otherwise), in plan order.
    pub pass_statistics: Vec<PassStatistics>,
}

/// A pass's work as pipeline-statistics queries measure it, summed over its views. Lavapipe
/// runs a multiview pass's views one after another and counts each view's primitives; a tile
/// GPU may count a multiview draw once. Full-view passes count their one triangle per view.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PassStatistics {
    /// Primitives input assembly produced.
    pub assembled: u64,
    /// Primitives that reached the clipper.
    pub clipped_in: u64,
    /// Primitives the clipper passed on to rasterisation (culled and degenerate ones gone).
    pub rasterised: u64,
    /// Fragment shader invocations as the driver counts them: helper invocations may or may
    /// not count, and lavapipe 22.3 counts whole raster blocks, so the exact per-view figures
    /// are the counting frame's atomics ([`FrameStats::steps`]).
    pub fragment_invocations: u64,
}

/// The pipeline statistics counting frames query, in the order Vulkan returns them.
pub(super) const PASS_STATISTICS: vk::QueryPipelineStatisticFlags =
    vk::QueryPipelineStatisticFlags::from_raw(
        vk::QueryPipelineStatisticFlags::INPUT_ASSEMBLY_PRIMITIVES.as_raw()
            | vk::QueryPipelineStatisticFlags::CLIPPING_INVOCATIONS.as_raw()
            | vk::QueryPipelineStatisticFlags::CLIPPING_PRIMITIVES.as_raw()
            | vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS.as_raw(),
    );

/// Fragments one step of a pass shaded, measured by the counting frame's atomics.
#[derive(Clone, Debug, PartialEq)]
pub struct StepFragments {
    /// The pass's name, as the plan prints it.
    pub pass: &'static str,
    /// What the step draws.
    pub step: CountedStep,
    /// Per view: views 0–3, then the MFFR far view.
    pub views: [u64; COUNTER_SLOTS_PER_STEP as usize],
}

impl StepFragments {
    /// Fragments over every view.
    pub fn total(&self) -> u64 {
        self.views.iter().sum()
    }
}

impl FrameStats {
    /// Each pass's GPU time with its name, in plan order (none without timestamps).
    pub fn gpu_pass_times(&self) -> impl Iterator<Item = (&'static str, f64)> + '_ {
        self.pass_names
            .iter()
            .copied()
            .zip(self.gpu_pass_ms.iter().copied())
    }

    /// The GPU time of the pass named `name` (as the plan prints it), when timed.
    pub fn gpu_pass_ms_of(&self, name: &str) -> Option<f64> {
        self.gpu_pass_times()
            .find(|(n, _)| *n == name)
            .map(|(_, ms)| ms)
    }

    /// A counting frame: the scene's fragments per eye view (`views` of them) and, with MFFR,
    /// the far view's, from the per-step counts.
    pub(super) fn split_scene_fragments(&mut self, views: u32, mffr: bool) {
        let scene = self.per_view(CountedStep::Scene);
        self.fragments = scene[..views as usize].to_vec();
        self.far_fragments = mffr.then_some(scene[FAR_VIEW_INDEX as usize]);
    }

    /// Fragments every counted step shaded: the frame's whole fragment work.
    pub fn total_fragments(&self) -> u64 {
        self.steps.iter().map(StepFragments::total).sum()
    }

    /// Fragments the scene draws shaded, eye views and MFFR far view together.
    pub fn scene_fragments(&self) -> u64 {
        self.fragments_of(CountedStep::Scene)
    }

    /// Fragments the steps of one kind shaded, over passes and views.
    pub fn fragments_of(&self, step: CountedStep) -> u64 {
        self.per_view(step).iter().sum()
    }

    /// Fragments the steps of one kind shaded per view (0–3, then the far view), over passes.
    pub fn per_view(&self, step: CountedStep) -> [u64; COUNTER_SLOTS_PER_STEP as usize] {
        let mut views = [0; COUNTER_SLOTS_PER_STEP as usize];
        for s in self.steps.iter().filter(|s| s.step == step) {
            for (sum, n) in views.iter_mut().zip(s.views) {
                *sum += n;
            }
        }
        views
    }
}

/// Draw commands and triangles recorded into the current frame.
#[derive(Clone, Copy, Debug, Default)]
pub(super) struct DrawTally {
    pub calls: u64,
    pub triangles: u64,
}
