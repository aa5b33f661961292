//! FLIP (NVIDIA's perceptual difference evaluator, LDR; Andersson et al. 2020) through the
//! `nv-flip` crate, which builds NVIDIA's reference C++; and an eccentricity-aware FLIP that
//! lets the error count less the farther a pixel lies from the gaze.
//!
//! FLIP's viewing condition is its pixels per degree (ppd): the more pixels a degree holds, the
//! finer a difference must be to escape the eye. Away from the gaze the eye resolves less: its
//! minimum angle of resolution grows linearly with eccentricity, `MAR(e) = ω₀ + m·e` (Guenter et
//! al. 2012, "Foveated 3D graphics": ω₀ = 1/48° = 1.25 arcmin; their user study gives slopes m
//! of 1.32–1.65 arcmin per degree; we default to the lower, more demanding 1.32). A pixel at
//! eccentricity e is therefore judged as if the display had `ppd · MAR(e) / ω₀` pixels per degree.
//! FLIP is evaluated at ppd × 1, 2, 4, … 64 and each pixel takes its value from the two levels
//! around its own effective ppd, interpolated in log ppd. Limits: the model is isotropic (no
//! nasal/temporal asymmetry), ignores crowding and temporal sensitivity, and FLIP's own filters
//! assume foveal vision at every level. At coarse levels FLIP's filters, wider in pixels,
//! spread a local error thinly over more pixels: its peak falls but its sum need not, so judge
//! local errors by percentiles and peaks, and read means with that in mind.

use rayon::prelude::*;

use super::acuity::LEVELS;
use super::{Acuity, FlipMapper, FlipMaps, ImageError, JudgeError, RgbaImage};

/// FLIP's per-pixel error (0 = no visible difference … 1) between `reference` and `test` viewed
/// at `ppd` pixels per degree; alpha is ignored.
pub fn flip_map(reference: &RgbaImage, test: &RgbaImage, ppd: f64) -> Result<Vec<f32>, ImageError> {
    reference.check_size(test)?;
    let rgb = |img: &RgbaImage| {
        let data: Vec<u8> = img
            .data
            .chunks_exact(4)
            .flat_map(|p| [p[0], p[1], p[2]])
            .collect();
        nv_flip::FlipImageRgb8::with_data(img.width, img.height, &data)
    };
    Ok(nv_flip::flip(rgb(reference), rgb(test), ppd as f32).to_vec())
}

/// Both FLIP maps of `test` against `reference`, for an eye of `acuity`. `eccentricity(x, y)` is
/// the pixel's angle from the gaze in degrees, `None` to leave it out (say, hidden by the lens):
/// such pixels map to `NaN` in both maps. The levels run in parallel.
pub fn eccentric_flip_map(
    reference: &RgbaImage,
    test: &RgbaImage,
    ppd: f64,
    acuity: Acuity,
    eccentricity: &(dyn Fn(u32, u32) -> Option<f64> + Sync),
) -> Result<FlipMaps, ImageError> {
    let maps = LEVELS
        .par_iter()
        .map(|k| flip_map(reference, test, ppd * k))
        .collect::<Result<Vec<_>, _>>()?;
    let mut plain = vec![f32::NAN; maps[0].len()];
    let mut eccentric = plain.clone();
    for y in 0..reference.height {
        for x in 0..reference.width {
            let Some(e) = eccentricity(x, y) else {
                continue;
            };
            let t = acuity.level_position(e);
            let i = (t.floor() as usize).min(LEVELS.len() - 2);
            let f = (t - i as f64) as f32;
            let k = (y * reference.width + x) as usize;
            plain[k] = maps[0][k];
            eccentric[k] = maps[i][k] * (1.0 - f) + maps[i + 1][k] * f;
        }
    }
    Ok(FlipMaps { plain, eccentric })
}

/// NVIDIA's reference FLIP on the CPU ([`eccentric_flip_map`]): the oracle the GPU judge is
/// held to, and `--metric cpu` on the command line.
#[derive(Clone, Copy, Debug, Default)]
pub struct CpuFlip;

impl FlipMapper for CpuFlip {
    fn flip_maps(
        &mut self,
        reference: &RgbaImage,
        test: &RgbaImage,
        ppd: f64,
        acuity: Acuity,
        eccentricity: &(dyn Fn(u32, u32) -> Option<f64> + Sync),
    ) -> Result<FlipMaps, JudgeError> {
        Ok(eccentric_flip_map(
            reference,
            test,
            ppd,
            acuity,
            eccentricity,
        )?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::metrics::ErrorSummary;

    /// A textured test image: stripes and a gradient, so blur and noise show.
    fn pattern(w: u32, h: u32) -> RgbaImage {
        let mut img = RgbaImage::new(w, h);
        for y in 0..h {
            for x in 0..w {
                let stripe = if (x / 3 + y / 5) % 2 == 0 { 200 } else { 40 };
                img.set_pixel(
                    x,
                    y,
                    [stripe, (x * 255 / w) as u8, (y * 255 / h) as u8, 255],
                );
            }
        }
        img
    }

    /// A box blur of radius `r` (0: a copy).
    fn blurred(img: &RgbaImage, r: i64) -> RgbaImage {
        let mut out = img.clone();
        for y in 0..img.height as i64 {
            for x in 0..img.width as i64 {
                let mut sum = [0u32; 3];
                let mut n = 0;
                for dy in -r..=r {
                    for dx in -r..=r {
                        let (sx, sy) = (x + dx, y + dy);
                        if sx < 0 || sy < 0 || sx >= img.width as i64 || sy >= img.height as i64 {
                            continue;
                        }
                        let p = img.pixel(sx as u32, sy as u32);
                        for c in 0..3 {
                            sum[c] += p[c] as u32;
                        }
                        n += 1;
                    }
                }
                let p = sum.map(|s| (s / n) as u8);
                out.set_pixel(x as u32, y as u32, [p[0], p[1], p[2], 255]);
            }
        }
        out
    }

    fn mean(map: &[f32]) -> f64 {
        ErrorSummary::of(map).unwrap().mean
    }

    #[test]
    fn identical_images_score_zero_and_blur_scores_more_the_stronger_it_is() {
        let img = pattern(64, 48);
        assert_eq!(mean(&flip_map(&img, &img, 40.0).unwrap()), 0.0);
        let errors: Vec<f64> = [1, 2, 3]
            .iter()
            .map(|&r| mean(&flip_map(&img, &blurred(&img, r), 40.0).unwrap()))
            .collect();
        assert!(
            errors[0] > 0.0 && errors[0] < errors[1] && errors[1] < errors[2],
            "{errors:?}"
        );
        let other = pattern(32, 32);
        assert!(flip_map(&img, &other, 40.0).is_err());
    }

    /// The same localized error peaks higher at the gaze than 30° away. Negative control: plain
    /// FLIP scores the two about the same.
    #[test]
    fn eccentricity_discounts_error_away_from_the_gaze() {
        let (w, h) = (128u32, 64u32);
        let img = pattern(w, h);
        // Gaze at the left quarter's centre; the right quarter's centre 30° away (a linear
        // map from x to degrees is enough for the model).
        let (gaze, away) = ((w / 4, h / 2), (3 * w / 4, h / 2));
        let deg_per_px = 30.0 / (away.0 - gaze.0) as f64;
        let ecc = move |x: u32, y: u32| {
            let (dx, dy) = (x as f64 - gaze.0 as f64, y as f64 - gaze.1 as f64);
            Some((dx * dx + dy * dy).sqrt() * deg_per_px)
        };
        let with_spot = |at: (u32, u32)| {
            let mut t = img.clone();
            for y in at.1 - 3..at.1 + 3 {
                for x in at.0 - 3..at.0 + 3 {
                    t.set_pixel(x, y, [255, 0, 255, 255]);
                }
            }
            t
        };
        let score = |at, eccentric: bool| {
            let t = with_spot(at);
            let map = if eccentric {
                eccentric_flip_map(&img, &t, 30.0, Acuity::default(), &ecc)
                    .unwrap()
                    .eccentric
            } else {
                flip_map(&img, &t, 30.0).unwrap()
            };
            // A local error's visibility is its peak (at coarser levels FLIP's filters spread
            // it thinly over more pixels).
            map.iter().map(|&v| v as f64).fold(0.0, f64::max)
        };
        let (near, far) = (score(gaze, true), score(away, true));
        assert!(
            near > 4.0 * far,
            "peak at the gaze {near:.3}, 30° away {far:.3}"
        );
        let (near, far) = (score(gaze, false), score(away, false));
        assert!(
            (near - far).abs() < 0.2 * near,
            "plain FLIP: {near:.3} vs {far:.3}"
        );
        assert_eq!(Acuity::default().scale(0.0), 1.0);
        assert!((Acuity::default().scale(30.0) - (1.25 + 1.32 * 30.0) / 1.25).abs() < 1e-12);
    }
}
