//! The per-frame input a caller hands the renderer, checked before it is used: eyes must fit
//! the plan, the head must be a finite pose. (The gaze's check is foveation's,
//! `foveation::check_gaze`.) Each refusal names the field, the value and the limit.

use glam::Mat4;

use crate::view::{Eye, EyeParams};
use crate::vocab::ConfigError;

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

/// A head pose the frame can be rendered from: every element finite.
pub(super) fn head_is_finite(world_from_head: Mat4) -> Result<(), ConfigError> {
    if world_from_head.is_finite() {
        return Ok(());
    }
    Err(ConfigError::new(
        "world_from_head",
        format!("{:?}", world_from_head.to_cols_array()),
        "a finite matrix (a lost head-tracking sample: keep the last good pose)",
    ))
}
