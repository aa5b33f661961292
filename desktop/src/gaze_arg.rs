//! The `--gaze X,Y` argument of the commands that place the fovea.

use anyhow::Result;

/// A `--gaze X,Y` argument: two finite numbers in −1…1 (the library's one policy,
/// [`foveate::foveation::check_gaze`]: outside it is an error naming the limit, not a clamp).
pub fn gaze_from(values: &[f32]) -> Result<glam::Vec2> {
    anyhow::ensure!(
        values.len() == 2,
        "invalid gaze = {values:?}: two numbers X,Y in -1..1"
    );
    let gaze = glam::Vec2::new(values[0], values[1]);
    foveate::foveation::check_gaze([gaze; 2]).map_err(|_| {
        anyhow::anyhow!(
            "invalid gaze = {},{}: X and Y finite, in -1..1",
            values[0],
            values[1]
        )
    })?;
    Ok(gaze)
}
