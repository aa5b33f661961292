//! Where each pixel of an eye's output image looks: the rendered pixel it shows, its angle from
//! the gaze and its foveation region, or hidden by the lens. Every error measure on output
//! images (PSNR/SSIM per region, FLIP, flicker) selects its pixels through this one map.

use glam::{DVec3, Vec2};
use rayon::prelude::*;

use crate::foveation::{fovea_centre_px, fovea_views, gaze_tangent, FoveationGeometry};
use crate::plan::FramePlan;
use crate::view::Eye;

/// A foveated frame's regions on the screen: the fovea (inside the circle, less the band), the
/// blend band, and the periphery beyond. A frame without foveation is all periphery.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Region {
    /// Inside the inset circle, less the blend band.
    Fovea,
    /// The blend band, where fovea and periphery mix.
    Band,
    /// Beyond the circle (or everything, without foveation).
    Periphery,
}

impl Region {
    /// Every region, inside out.
    pub const ALL: [Region; 3] = [Region::Fovea, Region::Band, Region::Periphery];

    /// Its name in tables.
    pub fn name(self) -> &'static str {
        match self {
            Region::Fovea => "fovea",
            Region::Band => "band",
            Region::Periphery => "periphery",
        }
    }
}

/// One visible display pixel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DisplayPixel {
    /// Degrees between the pixel's direction and the gaze.
    pub eccentricity_deg: f64,
    /// The region it lies in.
    pub region: Region,
}

/// Every display pixel of one eye's output image, row by row; `None` where the lens hides it:
/// beyond the rendered field (black on the display) or where the rendered pixel it shows is not
/// wholly inside the headset's lens region.
#[derive(Clone, Debug, PartialEq)]
pub struct EyePixels {
    /// The output image's width.
    pub width: u32,
    /// The output image's height.
    pub height: u32,
    /// Each pixel, row after row.
    pub pixels: Vec<Option<DisplayPixel>>,
    /// Display pixels per degree at the lens axis ([`FramePlan::pixels_per_degree`]).
    pub ppd: f64,
}

/// What a plan's [`EyePixels`] depend on beyond its headset and the gaze: the eye's screen,
/// whether the output is pre-distorted for the lens, and the fovea's ratio, size and blend band
/// (the fields [`EyePixels::seen`] reads; none for a frame without foveation). Plans of one
/// headset with equal keys have equal maps at every gaze, whatever their periphery (its
/// density, samples or accumulation), so a caller judging many configurations can share them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelsKey {
    screen: (u32, u32),
    lens: bool,
    fovea: Option<(f32, f32, f32)>,
}

impl PixelsKey {
    /// The key of `plan`'s maps, its own foveation placing the regions.
    pub fn of(plan: &FramePlan) -> PixelsKey {
        PixelsKey::placed(plan, plan.foveation.as_ref())
    }

    /// The key of the maps of `plan`'s frame with `foveation` placing the regions (as
    /// [`EyePixels::new`] takes it: a frame without a fovea judged where another frame puts
    /// its fovea).
    pub fn placed(plan: &FramePlan, foveation: Option<&FoveationGeometry>) -> PixelsKey {
        PixelsKey {
            screen: (plan.eye_resolution.width, plan.eye_resolution.height),
            lens: plan.lens.is_some(),
            fovea: foveation.map(|f| (f.ratio, f.fovea_screen_px, f.blend_band_px)),
        }
    }
}

impl EyePixels {
    /// The map for `eye` of a frame planned as `plan` (its lens and output resolution), the eye
    /// looking at `gaze` (normalised, as `set_gaze`); regions from `foveation` when the frame
    /// is foveated.
    pub fn new(
        plan: &FramePlan,
        eye: Eye,
        gaze: Vec2,
        foveation: Option<&FoveationGeometry>,
    ) -> EyePixels {
        Self::seen(plan, eye, gaze, gaze, foveation)
    }

    /// As [`EyePixels::new`], for an eye looking at `gaze` while the frame's fovea was placed
    /// at `fovea_gaze` (the tracker's latency): eccentricities from the one, regions from the
    /// other.
    pub fn seen(
        plan: &FramePlan,
        eye: Eye,
        gaze: Vec2,
        fovea_gaze: Vec2,
        foveation: Option<&FoveationGeometry>,
    ) -> EyePixels {
        let fov = plan.eyes.fov(eye);
        let screen = plan.eye_resolution;
        let (w, h) = (screen.width, screen.height);
        let lens_region = plan.hmd.lens_region(fov);
        let g = gaze_tangent(fov, gaze);
        let gaze_dir = DVec3::new(g.x as f64, g.y as f64, -1.0).normalize();
        // The fovea circle is centred on the fovea window, which stays inside the periphery.
        let fovea = foveation.map(|f| {
            let views = fovea_views(&plan.eyes, f.ratio, [fovea_gaze; 2], (w, h));
            let centre = fovea_centre_px(fov, views[eye.index()], (w, h));
            (centre, f.fovea_screen_px / 2.0, f.blend_band_px)
        });
        let pixel = |x: u32, y: u32| -> Option<DisplayPixel> {
            let p = match &plan.lens {
                Some(lens) => lens.rendered_px(eye, fov, screen, x, y)?,
                None => Vec2::new(x as f32 + 0.5, y as f32 + 0.5),
            };
            let t = Vec2::new(
                -fov.left + p.x / w as f32 * (fov.left + fov.right),
                fov.up - p.y / h as f32 * (fov.up + fov.down),
            );
            // Only rendered pixels wholly inside the lens region: the HMD mask's edge may
            // darken a pixel it partly covers (MSAA), where the lens barely shows it anyway.
            let (rx, ry) = (p.x.floor() as u32, p.y.floor() as u32);
            if !lens_region.contains_pixel(rx.min(w - 1), ry.min(h - 1), w, h) {
                return None;
            }
            let dir = DVec3::new(t.x as f64, t.y as f64, -1.0).normalize();
            let region = match fovea {
                Some((centre, radius, band)) => {
                    let d = p.distance(centre);
                    if d < radius - band {
                        Region::Fovea
                    } else if d <= radius {
                        Region::Band
                    } else {
                        Region::Periphery
                    }
                }
                None => Region::Periphery,
            };
            Some(DisplayPixel {
                eccentricity_deg: dir.angle_between(gaze_dir).to_degrees(),
                region,
            })
        };
        EyePixels {
            width: w,
            height: h,
            // Rows in parallel: at a headset's panel the map is ~10⁷ lens inversions, made
            // again at every gaze a motion visits.
            pixels: (0..h)
                .into_par_iter()
                .flat_map_iter(|y| (0..w).map(move |x| pixel(x, y)))
                .collect(),
            ppd: plan.pixels_per_degree(eye),
        }
    }

    /// Both eyes' maps (left, right), both eyes looking at `gaze`.
    pub fn both(
        plan: &FramePlan,
        gaze: Vec2,
        foveation: Option<&FoveationGeometry>,
    ) -> [EyePixels; 2] {
        Eye::BOTH.map(|e| EyePixels::new(plan, e, gaze, foveation))
    }

    /// The pixel at column `x`, row `y` (panics outside the image).
    pub fn at(&self, x: u32, y: u32) -> Option<DisplayPixel> {
        self.pixels[(y * self.width + x) as usize]
    }

    /// The visible pixel nearest the gaze (where a picture marks it), if any is visible.
    pub fn gaze_px(&self) -> Option<(u32, u32)> {
        self.pixels
            .iter()
            .enumerate()
            .filter_map(|(i, p)| p.map(|p| (i, p.eccentricity_deg)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(i, _)| (i as u32 % self.width, i as u32 / self.width))
    }

    /// The finite values of a per-pixel `map` of this eye, at visible pixels `keep` accepts.
    pub fn select(&self, map: &[f32], keep: impl Fn(DisplayPixel) -> bool) -> Vec<f32> {
        map.iter()
            .zip(&self.pixels)
            .filter_map(|(&v, p)| p.filter(|&p| v.is_finite() && keep(p)).map(|_| v))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::foveation::FoveationConfig;
    use crate::plan::{plan, DeviceCaps, OutputStage, RenderConfig, Resolution};
    use crate::scene::default_scene;

    fn eye_pixels(output: OutputStage, gaze: Vec2) -> EyePixels {
        let screen = Resolution::square(64);
        let foveation = FoveationConfig {
            ratio: 0.5,
            blend_band_px: 4.0,
            ..FoveationConfig::single_frame()
        };
        let config = RenderConfig {
            resolution: Some(screen),
            output,
            ..RenderConfig::default()
        };
        let plan = plan(&default_scene(), &config, &DeviceCaps::generic()).unwrap();
        let geometry = foveation.geometry(screen).unwrap();
        EyePixels::new(&plan, Eye::Left, gaze, Some(&geometry))
    }

    /// The regions nest around the gaze, the lens hides the corners, and eccentricity grows
    /// away from the gaze. Mutation: the regions centred on the image instead of the fovea
    /// window fails it.
    #[test]
    fn regions_follow_the_gaze_and_the_lens_hides_the_corners() {
        for output in [OutputStage::Undistorted, OutputStage::Lens] {
            let gaze = Vec2::new(0.6, -0.5);
            let p = eye_pixels(output, gaze);
            assert!(p.at(0, 0).is_none(), "{output}: a corner is hidden");
            let (gx, gy) = p.gaze_px().unwrap();
            let at_gaze = p.at(gx, gy).unwrap();
            assert_eq!(at_gaze.region, Region::Fovea, "{output}");
            assert!(at_gaze.eccentricity_deg < 2.0, "{output}: {at_gaze:?}");
            assert!(
                gx > 32 && gy > 32,
                "{output}: gaze right and down: {gx},{gy}"
            );
            let count = |r| p.pixels.iter().flatten().filter(|d| d.region == r).count();
            assert!(
                count(Region::Fovea) > 0 && count(Region::Band) > 0,
                "{output}"
            );
            assert!(count(Region::Periphery) > count(Region::Fovea), "{output}");
            // Farther along the row from the gaze, farther from it in angle.
            let left = p.at(gx - 20, gy).unwrap().eccentricity_deg;
            let nearer = p.at(gx - 10, gy).unwrap().eccentricity_deg;
            assert!(
                left > nearer && nearer > at_gaze.eccentricity_deg,
                "{output}"
            );
        }
    }

    #[test]
    fn centre_ppd_follows_the_field_and_the_pixels() {
        // 90° across 1000 pixels: tan 45° on each side.
        let ppd = crate::view::FovTangents::symmetric_deg(90.0, 90.0).pixels_per_degree(1000);
        assert!((ppd - 1.0 / (0.002f64).atan().to_degrees()).abs() < 1e-9);
        assert!((ppd - 8.73).abs() < 0.01, "{ppd}");
    }
}
