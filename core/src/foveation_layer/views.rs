//! A frame's views as the shaders see them (`Views`, binding 0): the eyes, the fovea windows
//! around the gaze, and the MFFR far view, with what lit shading needs of each.

use glam::{Mat4, Vec2, Vec3, Vec4};

use super::far_view::FarView;
use crate::foveation::ring_views;
use crate::mffr::FAR_VIEW_INDEX;
use crate::plan::{FramePlan, FRAME_VIEWS};
use crate::view::{reverse_z_projection, Eye, FovTangents};

const SLOTS: usize = FRAME_VIEWS as usize + 1;

/// The per-frame uniform block (`Views` in the shaders, std140).
#[repr(C)]
#[derive(Clone, Copy)]
pub(crate) struct ViewsBlock {
    /// The eye views, then the MFFR far view at [`FAR_VIEW_INDEX`].
    view_proj: [Mat4; SLOTS],
    /// xyz: light direction; w: the far pass's near plane (its depth-in-alpha numerator).
    light_dir: Vec4,
    /// Each view's eye in world space, the MFFR far view's at [`FAR_VIEW_INDEX`].
    eye_pos: [Vec4; SLOTS],
    /// How each view's ray at unit depth moves per pixel right and down (world space): lit
    /// shading's analytic texture gradients. `ray_dx`'s w: how many of the screen's pixels
    /// (per axis) one texture footprint of a periphery view spans (above 1 where it is rendered
    /// coarser than the screen), for its specular prefilter; 1 for the fovea views, 0 for the
    /// far view.
    ray_dx: [Vec4; SLOTS],
    ray_dy: [Vec4; SLOTS],
}

/// One pixel's step of a view's ray at unit depth, right and down, in world space.
fn ray_steps(world_from_view: Mat4, fov: FovTangents, pixels: (u32, u32)) -> (Vec4, Vec4) {
    let right = world_from_view.transform_vector3(Vec3::X);
    let down = world_from_view.transform_vector3(Vec3::NEG_Y);
    (
        (right * (fov.left + fov.right) / pixels.0 as f32).extend(0.0),
        (down * (fov.up + fov.down) / pixels.1 as f32).extend(0.0),
    )
}

/// Each eye's parafoveal ring window around its `fovea` window, when the plan has a ring.
fn ring_windows(plan: &FramePlan, fovea: &[FovTangents; 2]) -> Option<[FovTangents; 2]> {
    let ring = plan.foveation?.ring?;
    let screen = (plan.eye_resolution.width, plan.eye_resolution.height);
    Some(ring_views(&plan.eyes, ring.ratio, fovea, screen))
}

/// Every view of a frame, in frame-view order: the eyes, then the fovea windows, then the
/// parafoveal ring's.
pub(crate) struct FrameViews {
    /// Each view's pose and field.
    pub views: Vec<(Mat4, FovTangents)>,
    /// Each view's projection: reverse-Z, with the frame's jitter (the guard band is the
    /// pass's, applied by its shaders).
    pub projections: Vec<Mat4>,
    /// The MFFR far view, when planned.
    pub far: Option<FarView>,
    /// Each eye's parafoveal ring window, when the plan has a ring (views 4, 5).
    pub ring: Option<[FovTangents; 2]>,
    /// The periphery views' sub-pixel offset (periphery pixels, x right, y down), when
    /// temporal accumulation jitters them.
    pub jitter: Option<Vec2>,
    pub block: ViewsBlock,
}

impl FrameViews {
    /// The views of a frame with the head at `world_from_head`: each eye, each eye's fovea
    /// window when foveated, and the far view with MFFR (whose split ends the eye views).
    pub fn new(
        plan: &FramePlan,
        world_from_head: Mat4,
        fovea: Option<&[FovTangents; 2]>,
        far: Option<FarView>,
        light_dir: Vec3,
        jitter: Option<Vec2>,
    ) -> Self {
        let world_from_eye = Eye::BOTH.map(|e| world_from_head * plan.eyes.head_from_eye(e));
        let mut views: Vec<(Mat4, FovTangents)> = Eye::BOTH
            .iter()
            .map(|&e| (world_from_eye[e.index()], plan.eyes.fov(e)))
            .collect();
        let ring = fovea.and_then(|f| ring_windows(plan, f));
        for windows in fovea.into_iter().chain(ring.as_ref()) {
            views.extend(Eye::BOTH.map(|e| (world_from_eye[e.index()], windows[e.index()])));
        }
        let eye_far = far.as_ref().map_or(plan.far, |f| f.split_m);
        // Views 0, 1 are the eyes (a foveated frame's periphery), 2, 3 the fovea windows, 4, 5
        // the ring's, in views of the fovea's size.
        let view_pixels = |i: usize| match plan.foveation {
            None => plan.eye_resolution,
            Some(f) if i < 2 => f.periphery_view,
            Some(f) => f.fovea_view,
        };
        // Texture detail is chosen for the pixels the image ends in: an accumulated periphery
        // gathers the screen's density over frames, so its textures are sampled at that
        // density (the negative mip bias of temporal upsampling), not the view's.
        let texture_pixels = |i: usize| match plan.foveation {
            Some(f) if i < 2 && f.temporal.is_some() => plan.eye_resolution,
            _ => view_pixels(i),
        };
        let mut block = ViewsBlock {
            view_proj: [Mat4::IDENTITY; SLOTS],
            light_dir: light_dir.extend(far.as_ref().map_or(0.0, |f| f.near)),
            eye_pos: [Vec4::ZERO; SLOTS],
            ray_dx: [Vec4::ZERO; SLOTS],
            ray_dy: [Vec4::ZERO; SLOTS],
        };
        let mut set = |i: usize, world_from_view: Mat4, view_proj: Mat4, fov, pixels| {
            block.view_proj[i] = view_proj;
            block.eye_pos[i] = world_from_view.w_axis;
            (block.ray_dx[i], block.ray_dy[i]) = ray_steps(world_from_view, fov, pixels);
        };
        let mut projections = Vec::with_capacity(views.len());
        for (i, &(world_from_view, fov)) in views.iter().enumerate() {
            let pixels = (view_pixels(i).width, view_pixels(i).height);
            let texels = (texture_pixels(i).width, texture_pixels(i).height);
            let projection = reverse_z_projection(fov, plan.near, eye_far);
            // Temporal accumulation shifts the periphery views (0, 1) by the frame's jitter: a
            // clip-space translation scaled by w moves the image by that many pixels (NDC y
            // points down, as pixel rows do).
            let projection = match jitter {
                Some(j) if i < 2 => {
                    let ndc = 2.0 * j / Vec2::new(pixels.0 as f32, pixels.1 as f32);
                    Mat4::from_translation(ndc.extend(0.0)) * projection
                }
                _ => projection,
            };
            let view_proj = projection * world_from_view.inverse();
            set(i, world_from_view, view_proj, fov, texels);
            projections.push(projection);
        }
        if let Some(f) = &far {
            let pixels = (f.resolution.width, f.resolution.height);
            let at = FAR_VIEW_INDEX as usize;
            set(at, f.world_from_far, f.view_proj, f.fov, pixels);
        }
        // The fovea views are at the screen's density by design, and the ring is refused with
        // the prefilter: not prefiltered.
        for (i, &(_, fov)) in views.iter().enumerate().take(2) {
            let screen = plan.eyes.fov(Eye::BOTH[i]);
            let screen_step = (screen.left + screen.right) / plan.eye_resolution.width as f32;
            let texels = texture_pixels(i).width as f32;
            block.ray_dx[i].w = (fov.left + fov.right) / texels / screen_step;
        }
        for dx in block.ray_dx.iter_mut().take(views.len()).skip(2) {
            dx.w = 1.0;
        }
        FrameViews {
            views,
            projections,
            far,
            ring,
            jitter,
            block,
        }
    }
}
