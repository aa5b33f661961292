//! A [`FoveationLayer`] for an engine's draws: made from a configuration and the device, it
//! tells the engine the passes it draws into and each frame's views, and records whole frames —
//! per pass the stencil masks, then the engine's draws, then the output stage — into the
//! engine's command buffer.

use std::borrow::Cow;

use ash::vk;

use super::engine_views::{
    draw_passes, engine_views, superfrustum_of, DrawContext, DrawPass, FrameViewSet,
};
use super::frame_input::{eyes_fit, head_is_a_pose, FrameInput, FrameRecord};
use super::frame_slot::SharedBindings;
use super::layer::{FoveationLayer, SceneFigures};
use super::recorder::FrameDraws;
use super::stats::FrameStats;
use super::view_images::{check_handed, HandedImage};
use super::vulkan_recorder::SceneSteps;
use crate::gpu::{Gpu, GpuError};
use crate::plan::{ConfigError, FramePlan, PassKind, RenderConfig};

impl FoveationLayer {
    /// The layer for an engine's draws: `config` planned for the engine
    /// ([`crate::plan::plan_for_engine`]: what needs foveate's own scene is refused by name)
    /// and built on `gpu` (foveate's device, or the engine's: [`Gpu::from_engine`]).
    pub fn new(gpu: &Gpu, config: &RenderConfig) -> Result<Self, GpuError> {
        let plan = crate::plan::plan_for_engine(config, gpu.caps())?;
        Self::for_plan(gpu, &plan, &[])
    }

    /// The layer for an engine's draws from a plan made by
    /// [`crate::plan::plan_for_engine`], its frames ending in one of `output_images` when
    /// some are handed in (an OpenXR runtime's swapchain images, each made as
    /// [`super::output_image_desc`] says; the plan must have
    /// [`RenderConfig::external_output`]).
    pub fn for_plan(
        gpu: &Gpu,
        plan: &FramePlan,
        output_images: &[vk::Image],
    ) -> Result<Self, GpuError> {
        // SAFETY: no image of the engine's is handed in.
        unsafe { Self::with_images(gpu, plan, output_images, &[]) }
    }

    /// The layer for an engine's draws into images the engine made itself, each as one of
    /// [`view_images`](super::view_images) describes (all of them, or none: foveate's own);
    /// otherwise as [`FoveationLayer::for_plan`]. An image made otherwise than the plan needs
    /// (format, extent, samples, layers, usage), one missing, or one for another attachment
    /// is an error naming it.
    ///
    /// # Safety
    /// Each handed image is of `gpu`'s device, made as its description says, and alive as
    /// long as the layer; nothing else uses it while the layer's frames run.
    pub unsafe fn with_images(
        gpu: &Gpu,
        plan: &FramePlan,
        output_images: &[vk::Image],
        view_images: &[HandedImage],
    ) -> Result<Self, GpuError> {
        if !plan.engine_draws {
            return Err(ConfigError::new(
                "plan",
                "planned for foveate's scene",
                "a plan for an engine's draws (plan::plan_for_engine); foveate's scene is a Renderer's",
            )
            .into());
        }
        let handed = check_handed(plan, view_images)?;
        let multiview_scene =
            (plan.passes.iter()).any(|p| p.kind == PassKind::Scene && p.view_mask.count_ones() > 1);
        if multiview_scene && gpu.caps().quirks.multiview_clipping_drops_views {
            // A plan made for another device's caps: planned for this one, each scene pass
            // would draw one view (`plan/split_views.rs`).
            log::warn!(
                "this driver ({}) draws a primitive a multiview pass clips with the first view's \
                 data into the first view's layer, and the plan has multiview scene passes: plan \
                 the frame for this device (plan_for_engine with its caps), which draws an \
                 engine's views one pass each here",
                gpu.info().driver
            );
        }
        Self::build(gpu, plan, SharedBindings::default(), output_images, &handed)
    }

    /// The passes the engine draws into, in the order a frame records them, with what its
    /// pipelines must match in each (render pass, samples, formats, the stencil test).
    pub fn draw_passes(&self) -> Vec<DrawPass> {
        draw_passes(&self.plan, &self.passes)
    }

    /// The views of the frame `input` describes, for the engine's per-frame uniforms, without
    /// recording anything or keeping anything of `input`: hand the set to
    /// [`FoveationLayer::record`], which records the frame these are the views of. A bad input
    /// is an error naming it, and so is a device found lost.
    pub fn views(&self, input: &FrameInput) -> Result<FrameViewSet, GpuError> {
        self.gpu().check_alive()?;
        self.check_input(input)?;
        let eyes = input.eyes.unwrap_or(self.plan.eyes);
        let plan = match input.eyes {
            Some(eyes) => Cow::Owned(FramePlan {
                eyes,
                ..self.plan.clone()
            }),
            None => Cow::Borrowed(&self.plan),
        };
        let gaze = input.gaze.unwrap_or(self.gaze());
        let (_, views) = self.place_views_for(&plan, gaze, input.world_from_head);
        Ok(FrameViewSet {
            slot: self.next_slot(),
            frame: self.frames_rendered,
            views: engine_views(&plan, &views, &self.draw_passes()),
            input: *input,
            gaze,
            eyes,
        })
    }

    /// Records the frame whose views `frame` holds ([`FoveationLayer::views`], for this very
    /// frame) into `cmd`, using only the resources of the next frame slot: every pass of the
    /// plan, in each pass the engine draws into the stencil masks first, then `draw` with the
    /// pass's [`DrawContext`] (the engine's draws, inside the pass), then the output stage.
    /// The caller submits `cmd` and reads the frame's figures with
    /// [`FoveationLayer::frame_stats`] once it has run.
    ///
    /// An error, with nothing recorded and nothing changed: a set of views of another frame
    /// (one recorded already, or an earlier one) or slot, or placed with another gaze or other
    /// eyes than the layer now has (`set_gaze` or `set_eyes` since [`FoveationLayer::views`]);
    /// a bad input; a slot whose last frame has not finished on the GPU
    /// ([`GpuError::SlotInFlight`]).
    ///
    /// # Safety
    /// `cmd` is a primary command buffer of this layer's device, recording (outside a render
    /// pass), to be submitted to a queue of the layer's queue family: Vulkan gives the layer
    /// no way to check that it was begun. `draw` records only what a subpass allows, with
    /// pipelines made for the pass's render pass, and leaves the pass open. Each frame
    /// recorded is submitted (until then its slot is in flight). Dropping the layer while
    /// frames run waits for the device to go idle: no other thread submits to it meanwhile.
    pub unsafe fn record(
        &mut self,
        cmd: vk::CommandBuffer,
        frame: &FrameViewSet,
        draw: &mut dyn FnMut(&DrawContext),
    ) -> Result<FrameRecord, GpuError> {
        self.check_view_set(frame)?;
        self.check_next_slot()?;
        let frame = self.prepare(&frame.input, false)?;
        let passes = self.draw_passes();
        let views = engine_views(&self.plan, &frame.views, &passes);
        let (eyes, head, slot) = (self.plan.eyes, frame.world_from_head, frame.slot);
        let mut at_pass = |cmd: vk::CommandBuffer, index: usize| {
            let Some(pass) = passes.iter().find(|p| p.index == index) else {
                return;
            };
            let views = &views[pass.views.clone()];
            draw(&DrawContext {
                cmd,
                pass,
                views,
                superfrustum: superfrustum_of(views, &eyes, head),
                slot,
            });
        };
        let scene = SceneSteps::Engine(&mut at_pass);
        self.record_prepared(
            cmd,
            &frame,
            &FrameDraws::Engine,
            scene,
            SceneFigures::default(),
        )
    }

    /// Renders the frame whose views `frame` holds with the engine's `draw` into the next
    /// frame slot's own command buffer, submits it and waits for it: the convenience over
    /// [`FoveationLayer::record`] (and its errors) for programs that do not overlap frames.
    pub fn render(
        &mut self,
        frame: &FrameViewSet,
        draw: &mut dyn FnMut(&DrawContext),
    ) -> Result<FrameStats, GpuError> {
        let own = self.begin_own_buffer()?;
        // SAFETY: the buffer is the slot's own, recording; its previous frame was waited on.
        let record = unsafe { self.record(own.cmd, frame, draw)? };
        self.submit_own_buffer(own, record)
    }

    /// Whether `set` holds the views of the frame the layer records next: its number and slot,
    /// and the gaze and eyes the layer will place that frame's views with.
    fn check_view_set(&self, set: &FrameViewSet) -> Result<(), ConfigError> {
        let next = self.frames_rendered;
        if set.frame != next {
            return Err(ConfigError::new(
                "FrameViewSet::frame",
                set.frame,
                format!(
                    "the layer's next frame, {next}: call views() for each frame and record its set once"
                ),
            ));
        }
        if set.slot != self.next_slot() {
            return Err(ConfigError::new(
                "FrameViewSet::slot",
                set.slot,
                format!("the next frame's slot, {}", self.next_slot()),
            ));
        }
        let gaze = set.input.gaze.unwrap_or(self.gaze());
        as_placed("gaze", "set_gaze", gaze, set.gaze)?;
        let eyes = set.input.eyes.unwrap_or(self.plan.eyes);
        as_placed("eyes", "set_eyes", eyes, set.eyes)?;
        Ok(())
    }

    /// Whether `input` could be recorded: a head pose that is finite and invertible, a gaze
    /// within −1…1, eyes that fit the plan.
    pub(super) fn check_input(&self, input: &FrameInput) -> Result<(), ConfigError> {
        head_is_a_pose(input.world_from_head)?;
        if let Some(gaze) = input.gaze {
            crate::foveation::check_gaze(gaze)?;
        }
        if let Some(eyes) = &input.eyes {
            eyes_fit(eyes, &self.planned_eyes())?;
        }
        Ok(())
    }
}

/// `Ok` when the layer's `field` now is what a frame's views were placed with; else an error
/// naming it and `setter`, the call that moved it in between.
fn as_placed<T: PartialEq + std::fmt::Debug>(
    field: &'static str,
    setter: &str,
    now: T,
    placed: T,
) -> Result<(), ConfigError> {
    if now == placed {
        return Ok(());
    }
    Err(ConfigError::new(
        field,
        format!("{now:?}, the layer's now"),
        format!(
            "the {field} the frame's views were placed with, {placed:?}: {setter}() before views(), or views() again"
        ),
    ))
}

#[cfg(test)]
mod tests {
    use super::super::command_log::{Command, CommandLog};
    use crate::foveation::FoveationConfig;
    use crate::plan::{DeviceCaps, FoveaLayout, OutputStage, RenderConfig, Resolution};

    /// An engine's frame records in each pass it draws into the masks, then the engine's
    /// draws (nothing of foveate's scene), and the output stage after. Mutation: the scene
    /// steps recorded as foveate's meshes for an engine's plan, or the engine called in the
    /// output pass, fails it.
    #[test]
    fn an_engines_frame_records_the_masks_then_its_draws_then_the_output() {
        let config = RenderConfig {
            resolution: Some(Resolution::square(64)),
            foveation: Some(FoveationConfig::single_frame()),
            hmd_mask: true,
            fovea_layout: FoveaLayout::TwoPass,
            output: OutputStage::Lens,
            timestamps: false,
            ..RenderConfig::default()
        };
        let plan = crate::plan::plan_for_engine(&config, &DeviceCaps::generic()).unwrap();
        let log = CommandLog::record_engine(&plan).commands;
        let outline: Vec<String> = (log.iter())
            .filter_map(|c| match c {
                Command::BeginPass { pass, .. } => Some(format!("begin {pass}")),
                Command::BindStep { step, .. } => {
                    Some(step.to_string().split(" [").next().unwrap().to_string())
                }
                Command::EngineDraws { pass } => Some(format!("engine draws {pass}")),
                Command::BindGeometry | Command::DrawIndexed { .. } => {
                    Some("foveate's mesh".into())
                }
                _ => None,
            })
            .collect();
        assert_eq!(
            outline,
            [
                "begin 0",
                "mask fans",
                "scene",
                "engine draws 0",
                "begin 1",
                "mask fans",
                "scene",
                "engine draws 1",
                "begin 2",
                "output (fovea over periphery, lens-distorted)",
            ]
        );
    }
}
