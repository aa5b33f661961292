//! Temporal stability: how much more an approximated output changes from frame to frame than
//! the full-quality reference does over the same frames — flicker, crawling edges and popping
//! as the fovea follows the gaze or the head moves. Per pixel, on luma (`RgbaImage::luma`:
//! Rec. 709 weights on the 8-bit values, 0..1): `max(0, |ΔT| − |ΔR|)`, T the approximation and
//! R the reference, both
//! differenced against their previous frame. Change the reference also shows (motion) is not
//! counted; neither is change the approximation lacks. Not discounted by eccentricity: the
//! periphery is, if anything, more sensitive to flicker than the fovea.

use super::display::{EyePixels, Region};
use super::{ErrorHistogram, ErrorSummary, ImageError, RgbaImage};

/// Frames of an approximation and its reference, in order, reduced to their excess change.
#[derive(Default)]
pub struct Flicker {
    previous: Option<[[Vec<f64>; 2]; 2]>,
    all: Vec<f32>,
    regions: [Vec<f32>; 3],
    frames: usize,
}

/// What a sequence's flicker amounts to: over every visible pixel of every frame after the
/// first, and per region (each frame's own regions, so a moving fovea's band moves with it).
#[derive(Clone, Debug, PartialEq)]
pub struct FlickerSummary {
    /// Over every visible pixel (`None`: none was).
    pub all: Option<ErrorSummary>,
    /// Per region, in `Region::ALL`'s order.
    pub regions: [Option<ErrorSummary>; 3],
    /// Frame-to-frame changes measured (frames pushed less one).
    pub changes: usize,
}

impl FlickerSummary {
    /// The summary of excess changes counted per region (in `Region::ALL`'s order) over
    /// `changes` frame-to-frame changes, as `judge::GpuFlicker` counts them: within half a bin
    /// of the exact figures ([`ErrorHistogram`]).
    pub fn of_histograms(regions: &[ErrorHistogram; 3], changes: usize) -> Self {
        let mut all = ErrorHistogram::default();
        regions.iter().for_each(|r| all.merge(r));
        FlickerSummary {
            all: all.summary(),
            regions: regions.each_ref().map(|r| r.summary()),
            changes,
        }
    }
}

impl Flicker {
    /// Adds the next frame: the approximation's `image` and the `reference`'s (left eye, right
    /// eye), whose pixels map as `pixels` (the regions at this frame's gaze).
    pub fn push(
        &mut self,
        reference: [&RgbaImage; 2],
        image: [&RgbaImage; 2],
        pixels: &[EyePixels; 2],
    ) -> Result<(), ImageError> {
        for eye in 0..2 {
            let (r, t) = (reference[eye], image[eye]);
            r.check_size(t)?;
            if (r.width, r.height) != (pixels[eye].width, pixels[eye].height) {
                return Err(ImageError::SizeMismatch {
                    a: (r.width, r.height),
                    b: (pixels[eye].width, pixels[eye].height),
                });
            }
        }
        let current = [0, 1].map(|eye| [reference[eye].luma(), image[eye].luma()]);
        if let Some(previous) = &self.previous {
            for eye in 0..2 {
                let ([r0, t0], [r1, t1]) = (&previous[eye], &current[eye]);
                let excess: Vec<f32> = (0..r1.len())
                    .map(|i| ((t1[i] - t0[i]).abs() - (r1[i] - r0[i]).abs()).max(0.0) as f32)
                    .collect();
                self.all.extend(pixels[eye].select(&excess, |_| true));
                for (values, region) in self.regions.iter_mut().zip(Region::ALL) {
                    values.extend(pixels[eye].select(&excess, |d| d.region == region));
                }
            }
        }
        self.previous = Some(current);
        self.frames += 1;
        Ok(())
    }

    /// What the frames pushed so far amount to.
    pub fn summary(&self) -> FlickerSummary {
        FlickerSummary {
            all: ErrorSummary::of(&self.all),
            regions: self.regions.each_ref().map(|v| ErrorSummary::of(v)),
            changes: self.frames.saturating_sub(1),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plan::{plan, DeviceCaps, RenderConfig, Resolution};
    use crate::scene::default_scene;
    use crate::view::Eye;
    use glam::Vec2;

    fn pixels(res: u32) -> [EyePixels; 2] {
        let config = RenderConfig {
            resolution: Some(Resolution::square(res)),
            ..RenderConfig::default()
        };
        let plan = plan(&default_scene(), &config, &DeviceCaps::generic()).unwrap();
        Eye::BOTH.map(|e| EyePixels::new(&plan, e, Vec2::ZERO, None))
    }

    fn grey(res: u32, v: u8) -> RgbaImage {
        let mut img = RgbaImage::new(res, res);
        img.data
            .chunks_exact_mut(4)
            .for_each(|p| p.copy_from_slice(&[v, v, v, 255]));
        img
    }

    fn flicker(frames: &[(u8, u8)]) -> FlickerSummary {
        let px = pixels(32);
        let mut f = Flicker::default();
        for &(r, t) in frames {
            let (r, t) = (grey(32, r), grey(32, t));
            f.push([&r, &r], [&t, &t], &px).unwrap();
        }
        f.summary()
    }

    #[test]
    fn only_change_beyond_the_references_counts() {
        let still = flicker(&[(100, 90), (100, 90), (100, 90)]);
        assert_eq!(
            still.all.unwrap().p99,
            0.0,
            "a steady error does not flicker"
        );
        assert_eq!(still.changes, 2);
        let both = flicker(&[(100, 100), (150, 150)]);
        assert_eq!(
            both.all.unwrap().mean,
            0.0,
            "motion the reference shows too"
        );
        let popping = flicker(&[(100, 100), (100, 151)]);
        assert!((popping.all.unwrap().mean - 51.0 / 255.0).abs() < 1e-4);
        let lacking = flicker(&[(100, 100), (151, 100)]);
        assert_eq!(
            lacking.all.unwrap().mean,
            0.0,
            "change it lacks is no flicker"
        );
        assert!(
            flicker(&[(1, 1)]).all.is_none(),
            "one frame: nothing to compare"
        );
    }
}
