//! What a viewer sees of an approximation in a stereo frame's output images, over the pixels
//! the lens shows, whole and per foveation region: PSNR and SSIM, FLIP at the display's pixels
//! per degree and the eccentricity-aware FLIP (`flip`); and the eccentricity-aware map as a
//! picture. Every command that reports an error reports these.

use super::display::{EyePixels, Region};
use super::{Acuity, EyeFlipErrors, FlipMapper, JudgeError};
use super::{ErrorHistogram, ErrorSummary, ImageError, RgbaImage};

/// Every error figure of one frame against its reference, both eyes together.
#[derive(Clone, Debug, PartialEq)]
pub struct FrameAccuracy {
    /// PSNR (dB; infinite: identical) and SSIM over every visible pixel (SSIM: every window
    /// wholly visible).
    pub psnr: Option<f64>,
    /// SSIM over every window wholly visible.
    pub ssim: Option<f64>,
    /// The same per region, in `Region::ALL`'s order (`None`: the region is empty).
    pub region_psnr: [Option<f64>; 3],
    /// SSIM per region.
    pub region_ssim: [Option<f64>; 3],
    /// FLIP and the eccentricity-aware FLIP.
    pub perceptual: PerceptualError,
}

/// Every error figure of `image` against `reference` (left eye, right eye), the
/// eccentricity-aware one for an eye of `acuity`, its FLIP maps from `flip`.
pub fn frame_accuracy(
    reference: [&RgbaImage; 2],
    image: [&RgbaImage; 2],
    pixels: &[EyePixels; 2],
    acuity: Acuity,
    flip: &mut dyn FlipMapper,
    maps: Maps,
) -> Result<FrameAccuracy, JudgeError> {
    let (a, b) = (
        RgbaImage::side_by_side(reference[0], reference[1]),
        RgbaImage::side_by_side(image[0], image[1]),
    );
    let w = pixels[0].width;
    let at = |x: u32, y: u32| pixels[(x >= w) as usize].at(x % w, y);
    let psnr = |keep: &dyn Fn(Region) -> bool| {
        a.psnr_where(&b, |x, y| at(x, y).is_some_and(|p| keep(p.region)))
    };
    // SSIM's 8-pixel windows (given by their centre): the centre in the region, and the whole
    // window visible.
    let window_visible = |x: u32, y: u32| {
        [(0, 0), (7, 0), (0, 7), (7, 7)]
            .iter()
            .all(|&(dx, dy)| at((x + dx).saturating_sub(4), (y + dy).saturating_sub(4)).is_some())
    };
    let ssim = |keep: &dyn Fn(Region) -> bool| {
        a.ssim_where(&b, |x, y| {
            at(x, y).is_some_and(|p| keep(p.region)) && window_visible(x, y)
        })
    };
    Ok(FrameAccuracy {
        psnr: psnr(&|_| true)?,
        ssim: ssim(&|_| true)?,
        region_psnr: per_region(&psnr)?,
        region_ssim: per_region(&ssim)?,
        perceptual: perceptual_error(reference, image, pixels, acuity, flip, maps)?,
    })
}

/// A figure over the pixels of some regions, measured once per region.
type RegionMeasure<'a> = dyn Fn(&dyn Fn(Region) -> bool) -> Result<Option<f64>, ImageError> + 'a;

/// `measure` of each region alone, in `Region::ALL`'s order.
fn per_region(measure: &RegionMeasure) -> Result<[Option<f64>; 3], ImageError> {
    let mut out = [None; 3];
    for (value, region) in out.iter_mut().zip(Region::ALL) {
        *value = measure(&|r| r == region)?;
    }
    Ok(out)
}

/// FLIP figures of one frame, both eyes together. The summaries come from the judges'
/// histograms ([`ErrorHistogram`]): within half a bin (1/32768) of the exact figures.
#[derive(Clone, Debug, PartialEq)]
pub struct PerceptualError {
    /// FLIP at the display's ppd, every pixel judged as if the eye looked at it.
    pub flip: Option<ErrorSummary>,
    /// The eccentricity-aware FLIP, for the eye at the gaze.
    pub eccentric: Option<ErrorSummary>,
    /// The eccentricity-aware FLIP per region, in `Region::ALL`'s order.
    pub regions: [Option<ErrorSummary>; 3],
    /// Each eye's eccentricity-aware map (`NaN` where the lens hides the pixel), if asked for.
    pub maps: Option<[Vec<f32>; 2]>,
}

/// Whether a judgement brings its per-pixel maps back (for heat maps) or only its figures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Maps {
    /// The figures only: on the GPU, a few histograms come back instead of the maps.
    Drop,
    /// The figures and each eye's eccentricity-aware map.
    Keep,
}

/// FLIP figures of `image` against `reference` (left eye, right eye), pixels as `pixels` maps
/// them, the eccentricity-aware one for an eye of `acuity`, judged by `flip` (the GPU judge,
/// or NVIDIA's reference on the CPU); the maps kept as `maps` says.
pub fn perceptual_error(
    reference: [&RgbaImage; 2],
    image: [&RgbaImage; 2],
    pixels: &[EyePixels; 2],
    acuity: Acuity,
    flip: &mut dyn FlipMapper,
    maps: Maps,
) -> Result<PerceptualError, JudgeError> {
    acuity.check()?;
    let mut eyes = Vec::with_capacity(2);
    for eye in 0..2 {
        let p = &pixels[eye];
        let test = hidden_as_reference(reference[eye], image[eye], p)?;
        eyes.push(flip.flip_errors(reference[eye], &test, p, acuity, maps == Maps::Keep)?);
    }
    Ok(combine_eyes(eyes, maps))
}

/// Both eyes' figures as one frame's: the histograms merged, the maps kept as `maps` says.
pub(crate) fn combine_eyes(eyes: Vec<EyeFlipErrors>, maps: Maps) -> PerceptualError {
    let mut plain = ErrorHistogram::default();
    let mut regions: [ErrorHistogram; 3] = Default::default();
    let mut kept: [Vec<f32>; 2] = Default::default();
    for (eye, e) in eyes.into_iter().enumerate().take(2) {
        plain.merge(&e.plain);
        for (all, one) in regions.iter_mut().zip(&e.regions) {
            all.merge(one);
        }
        kept[eye] = e.map.unwrap_or_default();
    }
    let mut eccentric = ErrorHistogram::default();
    regions.iter().for_each(|r| eccentric.merge(r));
    PerceptualError {
        flip: plain.summary(),
        eccentric: eccentric.summary(),
        regions: regions.each_ref().map(|r| r.summary()),
        maps: (maps == Maps::Keep).then_some(kept),
    }
}

/// `image` with the pixels the lens hides taken from `reference`: FLIP's filters (wider at the
/// coarser levels) would otherwise carry a difference no one sees — say, what the HMD mask left
/// black — into the visible pixels around it.
fn hidden_as_reference(
    reference: &RgbaImage,
    image: &RgbaImage,
    pixels: &EyePixels,
) -> Result<RgbaImage, ImageError> {
    reference.check_size(image)?;
    let mut out = image.clone();
    for (i, p) in pixels.pixels.iter().enumerate() {
        if p.is_none() {
            out.data[4 * i..4 * i + 4].copy_from_slice(&reference.data[4 * i..4 * i + 4]);
        }
    }
    Ok(out)
}

/// An error map as a picture: FLIP's magma scale from 0 (black) to 1 (pale yellow), pixels the
/// lens hides grey, and the gaze (the visible pixel nearest it) ringed in cyan.
pub fn heat_map(map: &[f32], pixels: &EyePixels) -> RgbaImage {
    const HIDDEN: [u8; 4] = [80, 80, 80, 255];
    let mut img = RgbaImage::new(pixels.width, pixels.height);
    for y in 0..pixels.height {
        for x in 0..pixels.width {
            let v = map[(y * pixels.width + x) as usize];
            let c = if v.is_finite() && pixels.at(x, y).is_some() {
                magma(v.clamp(0.0, 1.0))
            } else {
                HIDDEN
            };
            img.set_pixel(x, y, c);
        }
    }
    if let Some((gx, gy)) = pixels.gaze_px() {
        let r = (pixels.width.min(pixels.height) as f32 / 48.0).max(4.0);
        for y in 0..pixels.height {
            for x in 0..pixels.width {
                let d = ((x as f32 - gx as f32).powi(2) + (y as f32 - gy as f32).powi(2)).sqrt();
                let cross = (x == gx || y == gy) && d < r * 0.6;
                if (d - r).abs() < 1.0 || cross {
                    img.set_pixel(x, y, [0, 255, 255, 255]);
                }
            }
        }
    }
    img
}

/// Matplotlib's magma at five stops (FLIP's own heat-map scale), linearly between them.
fn magma(v: f32) -> [u8; 4] {
    const STOPS: [[f32; 3]; 5] = [
        [0.0, 0.0, 4.0],
        [81.0, 18.0, 124.0],
        [183.0, 55.0, 121.0],
        [252.0, 137.0, 97.0],
        [252.0, 253.0, 191.0],
    ];
    let t = v * (STOPS.len() - 1) as f32;
    let i = (t.floor() as usize).min(STOPS.len() - 2);
    let f = t - i as f32;
    let c = |k: usize| (STOPS[i][k] + (STOPS[i + 1][k] - STOPS[i][k]) * f).round() as u8;
    [c(0), c(1), c(2), 255]
}
