//! The `--gaze X,Y` argument of the commands that place the fovea.

use anyhow::Result;

/// A `--gaze X,Y` argument: two finite numbers, clamped to −1…1.
pub fn gaze_from(values: &[f32]) -> Result<glam::Vec2> {
    anyhow::ensure!(
        values.len() == 2,
        "invalid gaze = {values:?}: two numbers X,Y in -1..1"
    );
    let gaze = glam::Vec2::new(values[0], values[1]);
    anyhow::ensure!(
        gaze.is_finite(),
        "invalid gaze = {},{}: finite numbers in -1..1",
        values[0],
        values[1]
    );
    Ok(gaze.clamp(glam::Vec2::NEG_ONE, glam::Vec2::ONE))
}
