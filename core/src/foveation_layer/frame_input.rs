//! The per-frame input a caller hands the renderer, checked before it is used: eyes must fit
//! the plan, the head must be a finite pose. (The gaze's check is foveation's,
//! `foveation::check_gaze`.) Each refusal names the field, the value and the limit. And what
//! recording a frame gives back: which frame, in which slot.

use glam::{Mat4, Vec2};

use crate::view::{Eye, EyeParams};
use crate::vocab::ConfigError;

/// What a frame is rendered from: the head's pose, and what changed since the last frame.
///
/// ```
/// use foveate::render::FrameInput;
/// use glam::{Mat4, Vec2, Vec3};
///
/// let head = Mat4::from_translation(Vec3::new(0.0, 1.6, 0.0));
/// let input = FrameInput::new(head).with_gaze([Vec2::new(0.2, 0.0); 2]);
/// assert_eq!(input.gaze, Some([Vec2::new(0.2, 0.0); 2]));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub struct FrameInput {
    /// The head's pose in the world (a finite matrix).
    pub world_from_head: Mat4,
    /// Each eye's gaze (normalised −1…1, x right, y up), kept for the following frames;
    /// `None` keeps the last one (see `Renderer::set_gaze`).
    pub gaze: Option<[Vec2; 2]>,
    /// This frame's eyes, kept for the following frames; `None` keeps the last ones (see
    /// `Renderer::set_eyes`).
    pub eyes: Option<EyeParams>,
    /// The image this frame ends in, when the plan's output is handed in
    /// ([`crate::plan::RenderConfig::external_output`]): any image made as
    /// `render::output_image_desc` says, on the renderer's device, alive while frames render
    /// into it; kept for the following frames. `None` keeps the last one (or the renderer's
    /// own image, when none was handed in).
    pub output: Option<ash::vk::Image>,
}

impl FrameInput {
    /// A frame from the head at `world_from_head`, gaze and eyes as before.
    pub fn new(world_from_head: Mat4) -> Self {
        Self {
            world_from_head,
            gaze: None,
            eyes: None,
            output: None,
        }
    }

    /// The same frame with each eye's gaze.
    pub fn with_gaze(mut self, gaze: [Vec2; 2]) -> Self {
        self.gaze = Some(gaze);
        self
    }

    /// The same frame rendered into `image` (see [`FrameInput::output`]).
    pub fn with_output(mut self, image: ash::vk::Image) -> Self {
        self.output = Some(image);
        self
    }

    /// The same frame with these eyes (an OpenXR runtime's located views).
    pub fn with_eyes(mut self, eyes: EyeParams) -> Self {
        self.eyes = Some(eyes);
        self
    }
}

/// A frame recorded by `Renderer::record`: its number and the frame slot it used.
/// Its figures are read with `Renderer::frame_stats` once it has run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRecord {
    /// Frames recorded before this one by the same renderer.
    pub frame: u64,
    /// The frame slot whose resources it uses: the slot is used again
    /// [`crate::plan::FramePlan::frame_slots`] frames later, by which time this frame must
    /// have finished on the GPU.
    pub slot: usize,
}

/// Whether `eyes` fit `planned` (see [`Renderer::set_eyes`]).
pub(super) fn eyes_fit(eyes: &EyeParams, planned: &EyeParams) -> Result<(), ConfigError> {
    // A thousandth of a tangent (0.06° at the axis): runtimes report the same field with
    // rounding from frame to frame.
    const SLACK: f32 = 1e-3;
    for eye in Eye::BOTH {
        let (fov, bound) = (eyes.fov(eye), planned.fov(eye));
        let inside = fov
            .as_array()
            .iter()
            .zip(bound.as_array())
            .all(|(t, b)| t.is_finite() && *t <= b + SLACK)
            && fov.left + fov.right > 0.0
            && fov.up + fov.down > 0.0;
        if !inside {
            return Err(ConfigError::new(
                if eye == Eye::Left {
                    "left fov"
                } else {
                    "right fov"
                },
                format!("{:?}", fov.as_array()),
                format!(
                    "within the planned tangents {:?}, of positive width and height (replan for a wider field)",
                    bound.as_array()
                ),
            ));
        }
    }
    if !eyes.ipd_m.is_finite() || eyes.ipd_m < 0.0 || eyes.ipd_m > planned.ipd_m + 1e-4 {
        return Err(ConfigError::new(
            "ipd",
            eyes.ipd_m,
            format!(
                "0 ≤ ipd ≤ the planned {} m (replan for a wider one)",
                planned.ipd_m
            ),
        ));
    }
    let off = (eyes.cant_rad - planned.cant_rad).abs();
    if off.is_nan() || off > 1e-4 {
        return Err(ConfigError::new(
            "cant",
            eyes.cant_rad.to_degrees(),
            format!(
                "the planned {}° (replan for another)",
                planned.cant_rad.to_degrees()
            ),
        ));
    }
    Ok(())
}

/// A head pose the frame can be rendered from: every element finite, and invertible (the
/// views' matrices are its inverse's), its determinant nonzero and its inverse finite in f32.
pub(super) fn head_is_a_pose(world_from_head: Mat4) -> Result<(), ConfigError> {
    const LOST: &str = "a lost head-tracking sample: keep the last good pose";
    finite_matrix(
        "world_from_head",
        world_from_head,
        &format!("a finite matrix ({LOST})"),
    )?;
    let determinant = world_from_head.as_dmat4().determinant();
    if determinant == 0.0 || !world_from_head.inverse().is_finite() {
        return Err(ConfigError::new(
            "world_from_head",
            format!(
                "{:?} (determinant {determinant:e})",
                world_from_head.to_cols_array()
            ),
            format!("an invertible pose, its inverse finite ({LOST})"),
        ));
    }
    Ok(())
}

/// `matrix`, handed in as `field`, with every element finite; else an error naming the field,
/// the matrix and `limit`.
pub(crate) fn finite_matrix(
    field: &'static str,
    matrix: Mat4,
    limit: &str,
) -> Result<(), ConfigError> {
    if matrix.is_finite() {
        return Ok(());
    }
    Err(ConfigError::new(
        field,
        format!("{:?}", matrix.to_cols_array()),
        limit,
    ))
}
