//! The eye's acuity away from the gaze, as the eccentricity-aware FLIP models it (see
//! `metrics::flip`), the maps it produces, and what produces them: NVIDIA's reference FLIP on
//! the CPU (`metrics::flip::CpuFlip`, feature `flip`) or the GPU judge (`judge::GpuFlip`).

use super::display::{EyePixels, Region};
use super::{ErrorHistogram, ImageError, RgbaImage};
use crate::gpu::GpuError;
use crate::vocab::ConfigError;

/// The eye's acuity falloff: its minimum angle of resolution `MAR(e) = mar0 + slope · e`
/// (arcmin, eccentricity e in degrees).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Acuity {
    /// The minimum angle of resolution at the gaze (arcmin).
    pub mar0_arcmin: f64,
    /// How fast it grows with eccentricity (arcmin per degree).
    pub slope_arcmin_per_deg: f64,
}

impl Default for Acuity {
    /// Guenter et al. 2012: ω₀ = 1.25′, and the more demanding end of their 1.32–1.65′ per
    /// degree.
    fn default() -> Self {
        Acuity {
            mar0_arcmin: 1.25,
            slope_arcmin_per_deg: 1.32,
        }
    }
}

impl Acuity {
    /// Where a pixel at `eccentricity_deg` lies among the ppd levels the eccentricity-aware FLIP
    /// evaluates (`ppd × 2^i`): log2 of its [`Acuity::scale`], clamped to the levels.
    pub fn level_position(&self, eccentricity_deg: f64) -> f64 {
        self.scale(eccentricity_deg)
            .log2()
            .clamp(0.0, (LEVELS.len() - 1) as f64)
    }

    /// `Ok` for an acuity a judgement can use: a finite, positive `mar0_arcmin` and a finite
    /// slope of zero or more; else an error naming the field (a `NaN` or zero acuity would
    /// judge every frame perfect).
    pub fn check(&self) -> Result<(), ConfigError> {
        let mar0 = self.mar0_arcmin;
        if !(mar0.is_finite() && mar0 > 0.0) {
            return Err(ConfigError::new(
                "acuity.mar0_arcmin",
                mar0,
                "finite and > 0 (the eye's minimum angle of resolution, 1.25′ by default)",
            ));
        }
        let slope = self.slope_arcmin_per_deg;
        if !(slope.is_finite() && slope >= 0.0) {
            return Err(ConfigError::new(
                "acuity.slope_arcmin_per_deg",
                slope,
                "finite and ≥ 0 (1.32′ a degree by default)",
            ));
        }
        Ok(())
    }

    /// How much coarser than at the gaze the eye resolves at `eccentricity_deg`: `MAR(e) / ω₀`.
    pub fn scale(&self, eccentricity_deg: f64) -> f64 {
        1.0 + self.slope_arcmin_per_deg * eccentricity_deg.max(0.0) / self.mar0_arcmin
    }
}

/// The ppd multipliers FLIP is evaluated at for the eccentricity-aware figure: 2^i.
pub(crate) const LEVELS: [f64; 7] = [1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0];

/// FLIP at the display's ppd, and the eccentricity-aware FLIP map: each pixel's FLIP at the ppd
/// the eye has there (see the module's model), for display `ppd` at the gaze.
#[derive(Clone, Debug, PartialEq)]
pub struct FlipMaps {
    /// Each pixel's FLIP at the display's ppd, row after row.
    pub plain: Vec<f32>,
    /// Each pixel's FLIP at the ppd the eye has there, row after row.
    pub eccentric: Vec<f32>,
}

/// Why a pair of images could not be judged.
#[derive(Debug, thiserror::Error)]
pub enum JudgeError {
    /// The images could not be compared (different sizes, say).
    #[error(transparent)]
    Image(#[from] ImageError),
    /// The GPU judge failed.
    #[error("judging on the GPU: {0}")]
    Gpu(#[from] GpuError),
    /// A value handed to the judgement was refused (an acuity, say).
    #[error(transparent)]
    Config(#[from] ConfigError),
}

/// One eye's FLIP figures as a judge reduces them: histograms over the pixels the lens shows,
/// and the eccentricity-aware map only when it was asked for.
#[derive(Clone, Debug, PartialEq)]
pub struct EyeFlipErrors {
    /// FLIP at the display's ppd.
    pub plain: ErrorHistogram,
    /// The eccentricity-aware FLIP per region, in `Region::ALL`'s order.
    pub regions: [ErrorHistogram; 3],
    /// The eccentricity-aware map (`NaN` where the lens hides the pixel), if asked for.
    pub map: Option<Vec<f32>>,
}

/// What computes both FLIP maps of an image pair: the display's `ppd` at the gaze, the eye's
/// `acuity`, and each pixel's angle from the gaze (`None`: not judged, `NaN` in both maps).
pub trait FlipMapper {
    /// Both maps of `test` against `reference`.
    fn flip_maps(
        &mut self,
        reference: &RgbaImage,
        test: &RgbaImage,
        ppd: f64,
        acuity: Acuity,
        eccentricity: &(dyn Fn(u32, u32) -> Option<f64> + Sync),
    ) -> Result<FlipMaps, JudgeError>;

    /// One eye's figures of `test` against `reference`, over the pixels `pixels` shows (at its
    /// ppd, eccentricities and regions), the map kept if `keep_map`. By default the maps are
    /// computed and reduced on the host; the GPU judge reduces them where it computed them.
    fn flip_errors(
        &mut self,
        reference: &RgbaImage,
        test: &RgbaImage,
        pixels: &EyePixels,
        acuity: Acuity,
        keep_map: bool,
    ) -> Result<EyeFlipErrors, JudgeError> {
        let eccentricity = |x: u32, y: u32| pixels.at(x, y).map(|d| d.eccentricity_deg);
        let maps = self.flip_maps(reference, test, pixels.ppd, acuity, &eccentricity)?;
        let histogram = |map: &[f32], region: Option<Region>| {
            ErrorHistogram::of(pixels.select(map, |d| region.is_none_or(|r| d.region == r)))
        };
        Ok(EyeFlipErrors {
            plain: histogram(&maps.plain, None),
            regions: Region::ALL.map(|r| histogram(&maps.eccentric, Some(r))),
            map: keep_map.then_some(maps.eccentric),
        })
    }
}
