//! The parafoveal ring: a third level of density between the fovea and the periphery, in views
//! of the fovea's pixels over a wider window (Guenter et al. 2012, "Foveated 3D Graphics":
//! nested layers, each coarser farther from the gaze).

use std::fmt;

use super::config::{FoveationConfig, FOVEA_REACH_TEXELS};
use crate::vocab::{ConfigError, Resolution};

/// The parafoveal ring as resolved: views of the fovea's pixels over a wider window.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RingGeometry {
    /// The ring's window relative to the periphery's extent.
    pub ratio: f32,
    /// Its views' pixels per screen pixel (the fovea view's pixels over the wider window).
    pub density: f32,
    /// The ring's diameter on the screen (pixels): its whole window.
    pub screen_px: f32,
    /// The blend band at its edge, in screen pixels (an eighth of its diameter).
    pub band_px: f32,
    /// The circle the ring views keep, in ring-view pixels (its window and the reach of the
    /// output's bilinear read).
    pub circle_px: f32,
    /// The hole the ring views drop under the fovea, in ring-view pixels.
    pub hole_px: f32,
}

/// The parafoveal ring around a fovea of `view` pixels whose inner edge, less the band,
/// is `fovea_hole_px` screen pixels across.
pub(super) fn resolve_ring(
    config: &FoveationConfig,
    screen: Resolution,
    view: Resolution,
    fovea_hole_px: f32,
    margin: &dyn Fn(f32) -> f32,
) -> Result<Option<RingGeometry>, ConfigError> {
    let Some(ratio) = config.ring_ratio else {
        return Ok(None);
    };
    if !ratio.is_finite() || ratio <= config.ratio || ratio > 1.0 {
        return Err(ConfigError::new(
            "ring_ratio",
            ratio,
            format!("{} (the fovea's ratio) < ring ratio ≤ 1", config.ratio),
        ));
    }
    if config.periphery_temporal.is_some() || config.view_resolution.is_some() {
        return Err(ConfigError::new(
            "ring_ratio",
            ratio,
            "single frames with the fovea at the screen's density: not with an accumulated periphery or a view resolution",
        ));
    }
    let screen_px = ratio * screen.width as f32;
    let density = view.width as f32 / screen_px;
    let band_px = (screen_px / 8.0).floor();
    Ok(Some(RingGeometry {
        ratio,
        density,
        screen_px,
        band_px,
        circle_px: screen_px * density + 2.0 * margin(FOVEA_REACH_TEXELS),
        hole_px: (fovea_hole_px * density - 2.0 * margin(FOVEA_REACH_TEXELS)).max(0.0),
    }))
}

impl fmt::Display for RingGeometry {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "a window {} of the field wide at {:.2} of the screen's density, {:.0} px on screen, blend band {} px, its views keep a {:.1} px circle and drop the fovea's {:.1} px hole; measured to cut the error where it lies, not beyond it (docs/foveation.md)",
            self.ratio, self.density, self.screen_px, self.band_px, self.circle_px, self.hole_px
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::foveation::{TemporalConfig, PERIPHERY_REACH_TEXELS};

    /// The ring's views have the fovea's pixels over its wider window: at 1024² with the fovea
    /// at 0.25 (256 px) and the ring at 0.5 (512 px on screen), half the screen's density.
    /// They keep their window and the reach of the fovea's read, and drop the fovea's inner
    /// edge less that reach; the periphery's hole moves out to the ring's inner edge.
    /// Mutations: the periphery's hole left under the fovea, or the ring's density taken from
    /// the periphery, fail it.
    #[test]
    fn the_ring_sits_between_the_fovea_and_the_periphery() {
        let g = FoveationConfig {
            ratio: 0.25,
            periphery_density: Some(0.25),
            ring_ratio: Some(0.5),
            blend_band_px: 0.0,
            ..FoveationConfig::single_frame()
        }
        .geometry(Resolution::square(1024))
        .unwrap();
        let r = g.ring.expect("a ring");
        assert_eq!((r.screen_px, r.density, r.band_px), (512.0, 0.5, 64.0));
        assert_eq!(r.circle_px, 256.0 + 2.0 * FOVEA_REACH_TEXELS);
        assert_eq!(r.hole_px, 256.0 * 0.5 - 2.0 * FOVEA_REACH_TEXELS);
        assert_eq!(
            g.periphery_hole_px,
            (512.0 - 2.0 * 64.0) * 0.25 - 2.0 * PERIPHERY_REACH_TEXELS
        );
    }

    /// A ring no wider than the fovea, wider than the field, not a number, or beside an
    /// accumulated periphery is refused, naming the field.
    #[test]
    fn bad_rings_name_the_field() {
        for (ring, temporal) in [
            (0.25, false),
            (0.2, false),
            (1.5, false),
            (f32::NAN, false),
            (0.5, true),
        ] {
            let e = FoveationConfig {
                ratio: 0.25,
                ring_ratio: Some(ring),
                periphery_temporal: temporal.then(TemporalConfig::default),
                ..FoveationConfig::single_frame()
            }
            .geometry(Resolution::square(1024))
            .unwrap_err();
            assert_eq!(e.field, "ring_ratio", "{ring}, {temporal}: {e}");
        }
    }
}
