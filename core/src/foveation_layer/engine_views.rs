//! What an engine that draws into a [`super::FoveationLayer`]'s frame is told: the passes it
//! draws into and what its pipelines must match there ([`DrawPass`]), each frame's views
//! ([`View`], [`FrameViewSet`]) and, at each pass, the context of its draws ([`DrawContext`]).

use std::ops::Range;

use ash::vk;
use glam::{Mat4, Vec2, Vec3};

use super::frame_input::FrameInput;
use super::targets::{vk_format, CompiledPass};
use super::views::FrameViews;
use crate::cull::{Frustum, Superfrustum};
use crate::plan::{FramePlan, PassKind, Resolution, Step};
use crate::view::{Eye, EyeParams, FovTangents};

/// What a view shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewKind {
    /// An eye's whole field: the frame's eye view, or a foveated frame's periphery.
    Eye,
    /// A foveated frame's fovea inset: the window around the eye's gaze, at the screen's
    /// density.
    Fovea,
}

/// One view of a frame, as an engine draws it.
#[derive(Clone, Copy, Debug)]
pub struct View {
    /// Its index among the frame's views: the eyes (left, right), then with foveation the
    /// fovea insets (left, right).
    pub index: usize,
    /// Whose eye it is.
    pub eye: Eye,
    /// What it shows.
    pub kind: ViewKind,
    /// The pass it is drawn in (an index into [`FramePlan::passes`] and the layer's
    /// [`DrawPass`]es) and its layer there: `gl_ViewIndex` in that pass's multiview draws.
    pub pass: usize,
    /// Its layer in the pass's images (`gl_ViewIndex`).
    pub layer: u32,
    /// The view's pose in the world (its camera: x right, y up, looking down −z).
    pub world_from_view: Mat4,
    /// Clip space from the view's space: reverse-Z (depth 1 at the near plane, 0 at the far),
    /// Vulkan's y down, with this frame's jitter and the pass's guard band (see
    /// [`View::viewport`]) applied: use it as it is.
    pub projection: Mat4,
    /// `projection * world_from_view⁻¹`: clip space from the world.
    pub clip_from_world: Mat4,
    /// Its field: tangents from its axis.
    pub fov: FovTangents,
    /// Its near and far planes, metres.
    pub near: f32,
    /// See [`View::near`].
    pub far: f32,
    /// Its image's pixels.
    pub extent: Resolution,
    /// The viewport to draw it with (dynamic state): its image, grown on each side where a
    /// driver quirk needs a guard band (the projection shrinks x and y to match).
    pub viewport: vk::Viewport,
    /// The scissor: its image.
    pub scissor: vk::Rect2D,
    /// Pixels per side as a fraction of the screen's over the same field: the periphery's
    /// density, or about 1 for a fovea inset and an unfoveated eye.
    pub density: f32,
    /// The sub-pixel offset this frame's projection carries (the view's pixels, x right, y
    /// down): nonzero when the periphery accumulates over frames, already in
    /// [`View::projection`].
    pub jitter: Vec2,
    /// The view's frustum, to cull against.
    pub frustum: Frustum,
}

/// A pass an engine draws into: foveate's render pass, its images and what the engine's
/// pipelines must match to draw there. Made once per layer; the same every frame.
#[derive(Clone, Debug)]
pub struct DrawPass {
    /// Its index in [`FramePlan::passes`] (its name there, its time in the frame's figures).
    pub index: usize,
    /// Its name ("scene (periphery views)", …).
    pub name: &'static str,
    /// The render pass (subpass 0) an engine's pipelines for this pass are made with: alive
    /// as long as the layer.
    pub render_pass: vk::RenderPass,
    /// The pipelines' `rasterizationSamples`.
    pub samples: vk::SampleCountFlags,
    /// Its multiview view mask: one layer per view. `0b1` on a driver that misplaces what a
    /// multiview pass clips (lavapipe before Mesa 25), where each view has a pass of its own.
    pub view_mask: u32,
    /// The frame's views it draws ([`View::index`]), in layer order: `gl_ViewIndex` draws
    /// view `views.start + gl_ViewIndex`.
    pub views: Range<usize>,
    /// Its images' pixels.
    pub extent: Resolution,
    /// The colour attachment's format (location 0). Alpha: 1, or 0 where a surface moved on
    /// its own since the last frame (not with the head): an accumulated periphery takes no
    /// history there.
    pub color_format: vk::Format,
    /// The depth attachment's format: reverse-Z, cleared to 0, tested `GREATER` (or
    /// `GREATER_OR_EQUAL`) and written by the engine; an accumulated periphery reprojects
    /// with it.
    pub depth_format: vk::Format,
    /// The stencil test the engine's pipelines must use (front and back), so the masks the
    /// pass wrote first keep fragments off what nobody sees; `None` when the pass has none.
    pub stencil: Option<vk::StencilOpState>,
}

/// What an engine's draws at one pass are given.
pub struct DrawContext<'a> {
    /// The command buffer, inside the pass: the engine binds its pipelines and resources and
    /// draws; the viewport and scissor it sets are its views' (dynamic state). It must not end
    /// the pass.
    pub cmd: vk::CommandBuffer,
    /// The pass.
    pub pass: &'a DrawPass,
    /// The pass's views this frame, in layer order.
    pub views: &'a [View],
    /// One frustum containing every view of the pass: cull once, draw into all.
    pub superfrustum: Frustum,
    /// The frame slot the frame records into (where the engine's per-frame uniforms for it
    /// should be).
    pub slot: usize,
}

/// A frame's views, before it is recorded: the engine writes its uniforms from these, then
/// hands the set to [`super::FoveationLayer::record`], which records the frame they are the
/// views of (the input they were placed from): a set of another frame, slot or gaze is an
/// error there.
#[derive(Clone, Debug)]
pub struct FrameViewSet {
    /// The frame slot the frame records into.
    pub slot: usize,
    /// The frame's number (frames recorded before it).
    pub frame: u64,
    /// Every view, in [`View::index`] order.
    pub views: Vec<View>,
    /// The input the views were placed from.
    pub(super) input: FrameInput,
    /// The gaze and eyes they were placed with (the input's, or the layer's then).
    pub(super) gaze: [Vec2; 2],
    pub(super) eyes: EyeParams,
}

impl FrameViewSet {
    /// The input the views were placed from.
    pub fn input(&self) -> &FrameInput {
        &self.input
    }
}

/// The passes an engine draws into, from the plan and its compiled passes.
pub(super) fn draw_passes(plan: &FramePlan, compiled: &[CompiledPass]) -> Vec<DrawPass> {
    (plan.passes.iter().enumerate())
        .filter(|(_, p)| p.kind == PassKind::Scene)
        .filter_map(|(index, p)| {
            let stencil = p.steps.iter().find_map(|s| match s {
                Step::Scene { stencil, .. } => Some(*stencil),
                _ => None,
            })?;
            let colour = &plan.attachments[p.color.attachment];
            let depth = p.depth.map(|d| plan.attachments[d.attachment].format)?;
            let count = p.view_mask.count_ones() as usize;
            let first = p.first_view as usize;
            Some(DrawPass {
                index,
                name: p.name,
                render_pass: compiled[index].render_pass.raw,
                samples: vk::SampleCountFlags::from_raw(colour.samples),
                view_mask: p.view_mask,
                views: first..first + count,
                extent: Resolution {
                    width: colour.width,
                    height: colour.height,
                },
                color_format: vk_format(colour.format),
                depth_format: vk_format(depth),
                stencil: stencil.map(super::pipelines::vk_stencil),
            })
        })
        .collect()
}

/// Each view of `frame` as the engine draws it, in the passes `passes` say.
pub(super) fn engine_views(plan: &FramePlan, frame: &FrameViews, passes: &[DrawPass]) -> Vec<View> {
    (0..frame.views.len())
        .filter_map(|index| engine_view(plan, frame, passes, index))
        .collect()
}

/// View `index` of `frame`, when a pass of `passes` draws it.
fn engine_view(
    plan: &FramePlan,
    frame: &FrameViews,
    passes: &[DrawPass],
    index: usize,
) -> Option<View> {
    let (world_from_view, fov) = frame.views[index];
    let far = frame.far.as_ref().map_or(plan.far, |f| f.split_m);
    let pass = passes.iter().find(|p| p.views.contains(&index))?;
    // The guard band's viewport is `guard_band` times the image: x and y shrink to match.
    let guard_band = plan.passes[pass.index].guard_band as f32;
    let shrink = Mat4::from_scale(Vec3::new(1.0 / guard_band, 1.0 / guard_band, 1.0));
    let projection = shrink * frame.projections[index];
    let (kind, density) = match (plan.foveation, index) {
        (Some(_), 0 | 1) => (
            ViewKind::Eye,
            plan.periphery_density().unwrap_or(1.0) as f32,
        ),
        (Some(f), _) => (
            ViewKind::Fovea,
            f.fovea_view.width as f32 / f.fovea_screen_px,
        ),
        (None, _) => (ViewKind::Eye, 1.0),
    };
    let extent = pass.extent;
    let jitter = match index {
        0 | 1 => frame.jitter.unwrap_or(Vec2::ZERO),
        _ => Vec2::ZERO,
    };
    Some(View {
        index,
        eye: Eye::BOTH[index % 2],
        kind,
        pass: pass.index,
        layer: (index - pass.views.start) as u32,
        world_from_view,
        projection,
        clip_from_world: projection * world_from_view.inverse(),
        fov,
        near: plan.near,
        far,
        extent,
        viewport: viewport(extent, guard_band),
        scissor: vk::Rect2D {
            offset: vk::Offset2D::default(),
            extent: vk::Extent2D {
                width: extent.width,
                height: extent.height,
            },
        },
        density,
        jitter,
        frustum: Frustum::from_eye(world_from_view, fov, plan.near, far),
    })
}

/// The viewport of an image of `extent` grown `guard_band` times around it.
fn viewport(extent: Resolution, guard_band: f32) -> vk::Viewport {
    let (w, h) = (extent.width as f32, extent.height as f32);
    vk::Viewport {
        x: -(guard_band - 1.0) * 0.5 * w,
        y: -(guard_band - 1.0) * 0.5 * h,
        width: guard_band * w,
        height: guard_band * h,
        min_depth: 0.0,
        max_depth: 1.0,
    }
}

/// One frustum around `views` (both eyes' views of a pass): the superfrustum of their poses and
/// fields.
pub(super) fn superfrustum_of(views: &[View], eyes: &EyeParams, world_from_head: Mat4) -> Frustum {
    match views {
        [left, right, ..] => {
            let eyes = EyeParams {
                left_fov: left.fov,
                right_fov: right.fov,
                ..*eyes
            };
            Superfrustum::new(&eyes, world_from_head, left.near, left.far).frustum
        }
        [one] => one.frustum,
        [] => Frustum::from_eye(world_from_head, eyes.left_fov, 1.0, 2.0),
    }
}
