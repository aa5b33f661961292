use super::history::HistoryAt;
use super::ring::{resolve_ring, RingGeometry};
use super::temporal::TemporalConfig;
use crate::vocab::{named_enum, ConfigError, Resolution};

/// How the output stage upscales the periphery to the screen.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PeripheryFilter {
    /// The sampler's bilinear filter: four texels.
    #[default]
    Bilinear,
    /// The Catmull-Rom spline over sixteen texels (see `shaders/output.frag`).
    CatmullRom,
}

named_enum!(PeripheryFilter, "periphery filter", [
    PeripheryFilter::Bilinear => "bilinear",
    PeripheryFilter::CatmullRom => "catmull-rom",
]);

/// What a user chooses about foveation (Di Donato 2017 §3.3–3.6).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoveationConfig {
    /// Arm's ratio: the fovea window is `ratio` times the periphery's extent, and each view's
    /// resolution defaults to `ratio` times the screen's (so the fovea maps 1:1 to the screen).
    pub ratio: f32,
    /// Pixels per side of all four views, overriding screen × ratio (Arm rounded 358 up to 366).
    pub view_resolution: Option<u32>,
    /// Inset/outset stencil masks inside the pass.
    pub stencil: bool,
    /// The masks keep the reach of the filters that read near their edges
    /// ([`PERIPHERY_REACH_TEXELS`], [`FOVEA_REACH_TEXELS`]), so they change no output pixel.
    /// Off, they are cut at the edges as in Arm's pixel tables: fewer pixels shaded, and a
    /// seam of the cleared hole where the filters read into it (a ring at a band of 0).
    pub mask_margins: bool,
    /// Diameter of the fovea region on the screen in pixels (Arm's Table 4: 256); default: the
    /// whole fovea window.
    pub fovea_size: Option<u32>,
    /// Width in screen pixels of the band where fovea and periphery are blended; the periphery
    /// keeps it so both images exist there. Negative (the default): an eighth of the fovea's
    /// diameter. 0 is a hard edge (no seam either way: the stencil holes keep the filters'
    /// margin, [`PERIPHERY_REACH_TEXELS`]).
    pub blend_band_px: f32,
    /// Tint the composed image: fovea green, band yellow, a parafoveal ring orange, periphery blue.
    pub debug_tint: bool,
    /// The fovea views draw only the instances their frusta see (a superfrustum around both
    /// fovea frusta, culled per frame); off, they draw what the periphery draws.
    pub cull_fovea: bool,
    /// Contrast-adaptive sharpening of the upscaled periphery in the output pass (0 = off, up
    /// to 1 = strongest); see `shaders/output.frag`.
    pub periphery_sharpen: f32,
    /// How the output pass upscales the periphery.
    pub periphery_filter: PeripheryFilter,
    /// The periphery views' pixels per side as a fraction of the screen's, independent of the
    /// fovea's size; `None`: the ratio (Arm's coupling: all four views one size). Default:
    /// [`RECOMMENDED_PERIPHERY_DENSITY`].
    pub periphery_density: Option<f32>,
    /// The periphery views' MSAA sample count; default: the frame's, or 1 when accumulated
    /// (its jitter antialiases it: 4× was measured no better along the walk at the Quest Pro's
    /// panel, and slower on lavapipe). The fovea views always use the frame's.
    pub periphery_msaa: Option<u32>,
    /// Temporal accumulation of the periphery (jittered views, a history at the output's pixels
    /// in the output pass or at the periphery's own texels in a pass before it:
    /// [`TemporalConfig::history_at`]); `None`: each frame's periphery alone, upscaled by
    /// `periphery_filter`. Default: accumulated, [`TemporalConfig::default`].
    pub periphery_temporal: Option<TemporalConfig>,
    /// Lit scenes, single frames: prefilter the periphery's highlights. A periphery pixel
    /// covers several of the screen's, and should show their mean: each highlight is widened
    /// by the spread of the normals its coarser footprint averages beyond the screen's (Toksvig
    /// 2005, relative to the screen's density), so the fovea and a stereo frame are unchanged.
    /// Measured at the Quest Pro's panel it lost, still and walking, and did not flicker less
    /// (docs/foveation.md); off by default. Refused with an accumulated periphery, which
    /// samples its textures at the screen's density, and with a flat scene.
    pub periphery_prefilter: bool,
    /// A third level between the fovea and the periphery (density graded by eccentricity): a
    /// parafoveal ring, a window `ring_ratio` times the periphery's extent around the fovea,
    /// rendered into views of the fovea's pixels (so at `ratio / ring_ratio` of the screen's
    /// density, with the frame's MSAA) in the fovea's pass, blended over the periphery with
    /// smoothstep at its edge as the fovea is over it. `None`: two levels. Single frames only.
    /// Measured, it cuts the error where it lies, but the one-frame periphery beyond it still
    /// loses to stereo without MSAA below about 0.85 of the screen's density (docs/foveation.md);
    /// off by default.
    pub ring_ratio: Option<f32>,
}

/// The periphery accumulated over jittered frames at [`RECOMMENDED_PERIPHERY_DENSITY`] of the
/// screen's density, its history at the output's pixels, beside a fovea at ratio 0.35 and the
/// frame's MSAA: the cheapest configuration measured at least as accurate as stereo without MSAA
/// (eFLIP p99, every frame judged) with the head still, walking and through both saccade traces,
/// at both gazes, on the lit atrium at the Quest Pro's panel. It costs more than that stereo
/// frame in time on lavapipe and in bytes (the history), and it flickers more while the head
/// moves. The cheaper configurations measured lose in some motion: single frames
/// ([`FoveationConfig::single_frame`]) in every one, the history at the periphery's own texels
/// along one walk (BENCHMARKS.md, "Where the targets stand"). `foveate plan` prints the same
/// reasons.
impl Default for FoveationConfig {
    fn default() -> Self {
        FoveationConfig {
            periphery_density: Some(RECOMMENDED_PERIPHERY_DENSITY),
            periphery_temporal: Some(TemporalConfig::default()),
            ..FoveationConfig::single_frame()
        }
    }
}

/// The accumulated periphery's density (a fraction of the screen's pixels per side) that the
/// measurements recommend: the lowest at which the periphery accumulated at the output's pixels
/// held against stereo without MSAA in every motion measured at the Quest Pro's panel.
pub const RECOMMENDED_PERIPHERY_DENSITY: f32 = 0.6;

impl FoveationConfig {
    /// Single frames: the periphery at the fovea's ratio (Arm's four views of one size),
    /// upscaled, nothing kept between frames. The cheapest foveated frame: it reads and writes
    /// no history and nothing in it changes while the head is still, but it measured visibly
    /// less accurate than stereo without MSAA in every motion (the default accumulates instead).
    pub fn single_frame() -> Self {
        FoveationConfig {
            ratio: 0.35,
            view_resolution: None,
            stencil: true,
            mask_margins: true,
            fovea_size: None,
            // The band the measured verdicts use: an eighth of the fovea's diameter.
            blend_band_px: -1.0,
            debug_tint: false,
            cull_fovea: true,
            periphery_sharpen: 0.0,
            periphery_filter: PeripheryFilter::Bilinear,
            periphery_density: None,
            periphery_msaa: None,
            periphery_temporal: None,
            periphery_prefilter: false,
            ring_ratio: None,
        }
    }
}

/// How far past the point it samples, in periphery texels, anything reading the periphery
/// reaches: Catmull-Rom's 4×4 texels (2√2 diagonally), sharpening's taps a texel apart, the
/// accumulation's 3×3 neighbourhood around its nearest jittered texel (about 3.2).
pub const PERIPHERY_REACH_TEXELS: f32 = 3.5;

/// How far past the point it samples, in fovea texels, the output's bilinear read of the fovea
/// reaches (√2, diagonally).
pub const FOVEA_REACH_TEXELS: f32 = 1.5;

/// How far past the point it samples, in screen pixels, the output stage's filters reach into
/// the accumulated periphery at the screen's density (in its texels where it is accumulated at
/// the periphery's own, `HistoryAt::Periphery`).
pub const ACCUMULATED_REACH_PX: f32 = 3.0;

/// Foveation as the planner resolved it for a screen resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoveationGeometry {
    /// The window's size relative to the periphery as used: the configured ratio, or exactly
    /// view / screen when the view size is derived.
    pub ratio: f32,
    /// Size of each fovea view (the fovea window at the screen's density).
    pub fovea_view: Resolution,
    /// Size of each periphery view (the whole field at the periphery's density).
    pub periphery_view: Resolution,
    /// The periphery views' sample count, when it differs from the frame's.
    pub periphery_msaa: Option<u32>,
    /// The fovea region's diameter on the screen (pixels).
    pub fovea_screen_px: f32,
    /// The inset circle's diameter in fovea-view pixels.
    pub fovea_circle_px: f32,
    /// The periphery's stencil hole, in periphery pixels: what the fovea covers, less the
    /// blend band and the reach of the filters that read the periphery near it.
    pub periphery_hole_px: f32,
    /// With accumulation, the accumulated periphery's hole in screen pixels: what the fovea
    /// covers, less the band and the reach of the output's filter.
    pub accumulated_hole_px: f32,
    /// [`FoveationConfig::stencil`].
    pub stencil: bool,
    /// The blend band's width in screen pixels, as resolved from [`FoveationConfig::blend_band_px`].
    pub blend_band_px: f32,
    /// [`FoveationConfig::debug_tint`].
    pub debug_tint: bool,
    /// [`FoveationConfig::cull_fovea`].
    pub cull_fovea: bool,
    /// [`FoveationConfig::periphery_sharpen`].
    pub periphery_sharpen: f32,
    /// [`FoveationConfig::periphery_filter`].
    pub periphery_filter: PeripheryFilter,
    /// Temporal accumulation of the periphery, when on.
    pub temporal: Option<TemporalConfig>,
    /// [`FoveationConfig::periphery_prefilter`].
    pub periphery_prefilter: bool,
    /// The parafoveal ring, when asked for ([`FoveationConfig::ring_ratio`]).
    pub ring: Option<RingGeometry>,
}

impl FoveationConfig {
    /// Validates and resolves against the per-eye screen resolution.
    pub fn geometry(&self, screen: Resolution) -> Result<FoveationGeometry, ConfigError> {
        if !self.ratio.is_finite() || self.ratio <= 0.0 || self.ratio > 1.0 {
            return Err(ConfigError::new("ratio", self.ratio, "0 < ratio ≤ 1"));
        }
        let view = match self.view_resolution {
            Some(0) => return Err(ConfigError::new("view_resolution", 0, "at least 1 pixel")),
            Some(v) => Resolution::square(v),
            None => screen.scaled(self.ratio),
        };
        // With the view size derived, the window is exactly the view's width in screen pixels
        // (ratio V / screen), so the fovea maps 1:1 onto the screen.
        let ratio = if self.view_resolution.is_some() {
            self.ratio
        } else {
            view.width as f32 / screen.width as f32
        };
        let window_px = ratio * screen.width as f32;
        let fovea_screen_px = match self.fovea_size {
            Some(f) if f == 0 || f as f32 > window_px + 0.5 => {
                return Err(ConfigError::new(
                    "fovea_size",
                    f,
                    format!(
                        "1..={} screen pixels (the fovea window at ratio {})",
                        window_px.round(),
                        self.ratio
                    ),
                ))
            }
            Some(f) => f as f32,
            None => window_px,
        };
        // A negative band asks for the default: an eighth of the fovea's diameter.
        let band = if self.blend_band_px < 0.0 {
            (fovea_screen_px / 8.0).floor()
        } else {
            self.blend_band_px
        };
        if !band.is_finite() || 2.0 * band >= fovea_screen_px {
            return Err(ConfigError::new(
                "blend_band",
                self.blend_band_px,
                format!(
                    "0 ≤ band < {} (half the fovea's {fovea_screen_px} px)",
                    fovea_screen_px / 2.0
                ),
            ));
        }
        if !(0.0..=1.0).contains(&self.periphery_sharpen) {
            return Err(ConfigError::new(
                "periphery_sharpen",
                self.periphery_sharpen,
                "0 (off) ≤ sharpen ≤ 1",
            ));
        }
        let periphery_view = match self.periphery_density {
            None => view,
            Some(d) if d.is_finite() && d > 0.0 && d <= 1.0 => screen.scaled(d),
            Some(d) => {
                return Err(ConfigError::new(
                    "periphery_density",
                    d,
                    "0 < density ≤ 1 (of the screen's pixels per side)",
                ))
            }
        };
        self.validate_periphery_rendering()?;
        // Fovea-view pixels per screen pixel, and periphery pixels per screen pixel.
        let fovea_scale = view.width as f32 / window_px;
        let periphery_scale = periphery_view.width as f32 / screen.width as f32;
        // The holes stay inside what is still read: the band's inner edge, less the reach of
        // the filters that read there (into the accumulated periphery, when accumulated; then
        // into the periphery). Cut up to the edge, a band of 0 showed the cleared hole as a
        // ring around the fovea.
        let margin = |reach: f32| if self.mask_margins { reach } else { 0.0 };
        // Accumulated at the periphery's own texels, the filters' reach is in its texels.
        let accumulated_reach = match self.periphery_temporal {
            None => 0.0,
            Some(t) if t.history_at == HistoryAt::Periphery => {
                margin(ACCUMULATED_REACH_PX) / t.history_density.unwrap_or(periphery_scale)
            }
            Some(_) => margin(ACCUMULATED_REACH_PX),
        };
        let accumulated_hole_px = fovea_screen_px - 2.0 * (band + accumulated_reach);
        let ring = resolve_ring(self, screen, view, accumulated_hole_px, &margin)?;
        // With a ring, the periphery's hole is under the ring's inner edge instead.
        let covered_px = ring.map_or(accumulated_hole_px, |r| r.screen_px - 2.0 * r.band_px);
        let periphery_hole_px =
            (covered_px * periphery_scale - 2.0 * margin(PERIPHERY_REACH_TEXELS)).max(0.0);
        Ok(FoveationGeometry {
            ratio,
            fovea_view: view,
            periphery_view,
            periphery_msaa: self.periphery_msaa,
            fovea_screen_px,
            // Past the circle by the bilinear footprint the output reads the fovea with.
            fovea_circle_px: fovea_screen_px * fovea_scale + 2.0 * margin(FOVEA_REACH_TEXELS),
            periphery_hole_px,
            accumulated_hole_px: accumulated_hole_px.max(0.0),
            stencil: self.stencil,
            blend_band_px: band,
            debug_tint: self.debug_tint,
            cull_fovea: self.cull_fovea,
            periphery_sharpen: self.periphery_sharpen,
            periphery_filter: self.periphery_filter,
            temporal: self.periphery_temporal,
            periphery_prefilter: self.periphery_prefilter,
            ring,
        })
    }
}

impl FoveationConfig {
    /// The periphery's samples, accumulation and prefilter.
    fn validate_periphery_rendering(&self) -> Result<(), ConfigError> {
        if let Some(m) = self.periphery_msaa.filter(|m| !matches!(m, 1 | 4)) {
            return Err(ConfigError::new("periphery_msaa", m, "1 or 4"));
        }
        if let Some(t) = &self.periphery_temporal {
            t.validate()?;
            if self.periphery_prefilter {
                return Err(ConfigError::new(
                    "periphery_prefilter",
                    true,
                    "single frames: an accumulated periphery samples its textures at the screen's density, so there is nothing to prefilter",
                ));
            }
        }
        Ok(())
    }
}

impl FoveationGeometry {
    /// The periphery views' sample count in a frame of `frame_msaa` samples.
    pub fn periphery_samples(&self, frame_msaa: u32) -> u32 {
        let default = if self.temporal.is_some() {
            1
        } else {
            frame_msaa
        };
        self.periphery_msaa.unwrap_or(default)
    }

    /// Whether the periphery and fovea views differ in size or samples, or a ring shares the
    /// fovea's images, so that they need images of their own (only the two-pass layout has
    /// them).
    pub fn views_differ(&self, frame_msaa: u32) -> bool {
        self.periphery_view != self.fovea_view
            || self.periphery_samples(frame_msaa) != frame_msaa
            || self.ring.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn arms_rows_resolve_to_arms_geometry() {
        let screen = Resolution::square(1024);
        let g = FoveationConfig {
            ratio: 0.35,
            view_resolution: Some(366),
            blend_band_px: 0.0,
            ..FoveationConfig::single_frame()
        }
        .geometry(screen)
        .unwrap();
        assert_eq!(g.fovea_view, Resolution::square(366));
        assert_eq!(
            g.periphery_view, g.fovea_view,
            "Arm: one size for all four views"
        );
        // Arm: the hole is view × ratio and the inset circle fills the fovea view; here each
        // keeps the filters' margin from what the output reads.
        assert!(
            (g.periphery_hole_px - (366.0 * 0.35 - 2.0 * PERIPHERY_REACH_TEXELS)).abs() < 0.01,
            "the hole: view × ratio, less the periphery filters' reach"
        );
        assert!(
            (g.fovea_circle_px - (366.0 + 2.0 * FOVEA_REACH_TEXELS)).abs() < 0.01,
            "the inset circle: the fovea view, and the fovea filter's reach"
        );
        let g = FoveationConfig {
            ratio: 0.5,
            fovea_size: Some(256),
            blend_band_px: 0.0,
            ..FoveationConfig::single_frame()
        }
        .geometry(screen)
        .unwrap();
        assert_eq!(
            (g.fovea_view.width, g.fovea_circle_px, g.periphery_hole_px),
            (
                512,
                256.0 + 2.0 * FOVEA_REACH_TEXELS,
                128.0 - 2.0 * PERIPHERY_REACH_TEXELS
            )
        );
    }

    /// The periphery's density is its own: the fovea keeps the ratio's window at the screen's
    /// density, the periphery's views and hole scale with the density. Mutation: sizing the
    /// periphery by the ratio fails it.
    #[test]
    fn periphery_density_is_independent_of_the_fovea() {
        let screen = Resolution::square(1024);
        let g = FoveationConfig {
            ratio: 0.25,
            periphery_density: Some(0.5),
            blend_band_px: 0.0,
            ..FoveationConfig::single_frame()
        }
        .geometry(screen)
        .unwrap();
        assert_eq!(g.fovea_view, Resolution::square(256));
        assert_eq!(g.periphery_view, Resolution::square(512));
        assert_eq!(
            (g.fovea_circle_px, g.periphery_hole_px),
            (
                256.0 + 2.0 * FOVEA_REACH_TEXELS,
                128.0 - 2.0 * PERIPHERY_REACH_TEXELS
            )
        );
        assert!(g.views_differ(4));
        let same = FoveationConfig::single_frame().geometry(screen).unwrap();
        assert!(!same.views_differ(4));
        let msaa = FoveationConfig {
            periphery_msaa: Some(1),
            ..FoveationConfig::single_frame()
        }
        .geometry(screen)
        .unwrap();
        assert!(msaa.views_differ(4) && !msaa.views_differ(1));
        for (config, field) in [
            (
                FoveationConfig {
                    periphery_density: Some(1.5),
                    ..FoveationConfig::single_frame()
                },
                "periphery_density",
            ),
            (
                FoveationConfig {
                    periphery_msaa: Some(2),
                    ..FoveationConfig::single_frame()
                },
                "periphery_msaa",
            ),
        ] {
            assert_eq!(config.geometry(screen).unwrap_err().field, field);
        }
    }

    /// The output pass's filters reach 3 texels into the accumulated periphery: screen pixels
    /// where it is at the output's pixels, the periphery's texels (1 / density of a pixel
    /// each) where it is at its own. The hole keeps clear of that reach. Mutation: the reach
    /// left in screen pixels for both fails it.
    #[test]
    fn the_hole_keeps_clear_of_the_accumulated_periphery_in_its_own_texels() {
        let screen = Resolution::square(1024);
        let hole = |history_at| {
            FoveationConfig {
                ratio: 0.5,
                periphery_density: Some(0.25),
                blend_band_px: 0.0,
                periphery_temporal: Some(TemporalConfig {
                    history_at,
                    ..Default::default()
                }),
                ..FoveationConfig::single_frame()
            }
            .geometry(screen)
            .unwrap()
            .accumulated_hole_px
        };
        assert_eq!(hole(HistoryAt::Output), 512.0 - 2.0 * ACCUMULATED_REACH_PX);
        assert_eq!(
            hole(HistoryAt::Periphery),
            512.0 - 2.0 * ACCUMULATED_REACH_PX / 0.25
        );
    }

    #[test]
    fn bad_values_name_field_value_and_limit() {
        let screen = Resolution::square(1024);
        let e = FoveationConfig {
            ratio: 0.0,
            ..FoveationConfig::single_frame()
        }
        .geometry(screen)
        .unwrap_err();
        assert_eq!((e.field, e.value.as_str()), ("ratio", "0"));
        let e = FoveationConfig {
            ratio: f32::NAN,
            ..FoveationConfig::single_frame()
        }
        .geometry(screen)
        .unwrap_err();
        assert_eq!(e.field, "ratio");
        let e = FoveationConfig {
            fovea_size: Some(900),
            ..FoveationConfig::single_frame()
        }
        .geometry(screen)
        .unwrap_err();
        assert_eq!((e.field, e.value.as_str()), ("fovea_size", "900"));
        let e = FoveationConfig {
            blend_band_px: 500.0,
            ..FoveationConfig::single_frame()
        }
        .geometry(screen)
        .unwrap_err();
        assert_eq!(e.field, "blend_band");
    }

    #[test]
    fn blend_band_defaults_to_an_eighth_of_the_fovea_and_rejects_nan() {
        let screen = Resolution::square(1024);
        let auto = FoveationConfig {
            ratio: 0.5,
            blend_band_px: -1.0,
            ..FoveationConfig::single_frame()
        }
        .geometry(screen)
        .unwrap();
        assert_eq!(auto.blend_band_px, 64.0, "an eighth of the 512 px fovea");
        let e = FoveationConfig {
            blend_band_px: f32::NAN,
            ..FoveationConfig::single_frame()
        }
        .geometry(screen)
        .unwrap_err();
        assert_eq!(e.field, "blend_band");
    }
}
