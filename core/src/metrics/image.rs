//! Comparing images: SSIM, PSNR (over a region or all), matching within a disparity bound,
//! difference images. The image type itself is the vocabulary's ([`RgbaImage`]).

pub use crate::vocab::{FileError, ImageError, RgbaImage};

impl RgbaImage {
    /// Rec. 709 luma of every pixel in 0..1 (on the stored sRGB values, as SSIM is defined).
    pub(crate) fn luma(&self) -> Vec<f64> {
        self.data
            .chunks_exact(4)
            .map(|p| (0.2126 * p[0] as f64 + 0.7152 * p[1] as f64 + 0.0722 * p[2] as f64) / 255.0)
            .collect()
    }

    /// Mean structural similarity (SSIM) of the luma over 8×8 windows at stride 4: 1 for
    /// identical images, lower as structure differs.
    pub fn ssim(&self, other: &RgbaImage) -> Result<f64, ImageError> {
        Ok(self.ssim_where(other, |_, _| true)?.unwrap_or(1.0))
    }

    /// SSIM over the windows whose centre pixel `region(x, y)` selects; `None` if none does.
    pub fn ssim_where(
        &self,
        other: &RgbaImage,
        region: impl Fn(u32, u32) -> bool,
    ) -> Result<Option<f64>, ImageError> {
        self.check_size(other)?;
        let (a, b) = (self.luma(), other.luma());
        let (w, h) = (self.width as usize, self.height as usize);
        const WIN: usize = 8;
        const STRIDE: usize = 4;
        let (c1, c2) = ((0.01f64).powi(2), (0.03f64).powi(2));
        let mut total = 0.0;
        let mut windows = 0usize;
        for y in (0..=h.saturating_sub(WIN)).step_by(STRIDE) {
            for x in (0..=w.saturating_sub(WIN)).step_by(STRIDE) {
                if w < WIN || h < WIN || !region((x + WIN / 2) as u32, (y + WIN / 2) as u32) {
                    continue;
                }
                let (mut sa, mut sb, mut saa, mut sbb, mut sab) = (0.0, 0.0, 0.0, 0.0, 0.0);
                for dy in 0..WIN {
                    for dx in 0..WIN {
                        let i = (y + dy) * w + x + dx;
                        sa += a[i];
                        sb += b[i];
                        saa += a[i] * a[i];
                        sbb += b[i] * b[i];
                        sab += a[i] * b[i];
                    }
                }
                let n = (WIN * WIN) as f64;
                let (ma, mb) = (sa / n, sb / n);
                let va = saa / n - ma * ma;
                let vb = sbb / n - mb * mb;
                let cov = sab / n - ma * mb;
                total += ((2.0 * ma * mb + c1) * (2.0 * cov + c2))
                    / ((ma * ma + mb * mb + c1) * (va + vb + c2));
                windows += 1;
            }
        }
        Ok((windows > 0).then(|| total / windows as f64))
    }

    /// Peak signal-to-noise ratio over RGB in dB (infinite for identical images).
    pub fn psnr(&self, other: &RgbaImage) -> Result<f64, ImageError> {
        self.check_size(other)?;
        let mut sq = 0.0f64;
        let mut n = 0usize;
        for (pa, pb) in self.data.chunks_exact(4).zip(other.data.chunks_exact(4)) {
            for c in 0..3 {
                let d = pa[c] as f64 - pb[c] as f64;
                sq += d * d;
                n += 1;
            }
        }
        let mse = sq / n.max(1) as f64;
        Ok(if mse == 0.0 {
            f64::INFINITY
        } else {
            10.0 * (255.0f64 * 255.0 / mse).log10()
        })
    }

    /// PSNR over the pixels where `region(x, y)` holds (a fovea, a band, a periphery);
    /// `None` for an empty region.
    pub fn psnr_where(
        &self,
        other: &RgbaImage,
        region: impl Fn(u32, u32) -> bool,
    ) -> Result<Option<f64>, ImageError> {
        self.check_size(other)?;
        let (mut sq, mut n) = (0.0f64, 0usize);
        for y in 0..self.height {
            for x in 0..self.width {
                if region(x, y) {
                    let (a, b) = (self.pixel(x, y), other.pixel(x, y));
                    sq += (0..3)
                        .map(|c| (a[c] as f64 - b[c] as f64).powi(2))
                        .sum::<f64>();
                    n += 3;
                }
            }
        }
        Ok((n > 0).then(|| {
            if sq == 0.0 {
                f64::INFINITY
            } else {
                10.0 * (255.0f64.powi(2) * n as f64 / sq).log10()
            }
        }))
    }

    /// The fraction of this image's pixels that some pixel of `reference` within `radius`
    /// pixels along the same row matches (every colour channel within `tolerance`): how much of
    /// an image is the reference shifted horizontally by at most `radius` — a stereo image
    /// whose disparity is off by at most that much scores 1.
    pub fn matched_within(
        &self,
        reference: &RgbaImage,
        radius: u32,
        tolerance: u8,
    ) -> Result<f64, ImageError> {
        self.check_size(reference)?;
        let mut matched = 0u64;
        for y in 0..self.height {
            for x in 0..self.width {
                let p = self.pixel(x, y);
                let lo = x.saturating_sub(radius);
                let hi = (x + radius).min(self.width - 1);
                matched += (lo..=hi).any(|rx| {
                    let q = reference.pixel(rx, y);
                    (0..3).all(|c| p[c].abs_diff(q[c]) <= tolerance)
                }) as u64;
            }
        }
        Ok(matched as f64 / (self.width as u64 * self.height as u64).max(1) as f64)
    }

    /// A picture of where two images differ: black where equal, brighter red the larger the
    /// largest channel difference (amplified 4×).
    pub fn diff_image(&self, other: &RgbaImage) -> Result<RgbaImage, ImageError> {
        self.check_size(other)?;
        let mut out = RgbaImage::new(self.width, self.height);
        for (i, (pa, pb)) in self
            .data
            .chunks_exact(4)
            .zip(other.data.chunks_exact(4))
            .enumerate()
        {
            let d = (0..3).map(|c| pa[c].abs_diff(pb[c])).max().unwrap_or(0);
            let v = (d as u32 * 4).min(255) as u8;
            out.data[i * 4..i * 4 + 4].copy_from_slice(&[v, v / 4, v / 4, 255]);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_shifted_image_matches_within_its_shift_only() {
        let mut a = RgbaImage::new(16, 4);
        for y in 0..4 {
            for x in 0..16 {
                a.set_pixel(x, y, [(x * 15) as u8, 0, 0, 255]);
            }
        }
        let mut b = RgbaImage::new(16, 4);
        for y in 0..4 {
            for x in 0..16 {
                b.set_pixel(x, y, a.pixel(x.saturating_sub(2), y));
            }
        }
        assert_eq!(b.matched_within(&a, 2, 0).unwrap(), 1.0);
        assert!(b.matched_within(&a, 1, 0).unwrap() < 0.9);
    }

    fn gradient(w: u32, h: u32, shift: u8) -> RgbaImage {
        let mut img = RgbaImage::new(w, h);
        for y in 0..h {
            for x in 0..w {
                let v = ((x * 255 / w) as u8).wrapping_add(shift);
                img.set_pixel(x, y, [v, (y * 255 / h) as u8, 128, 255]);
            }
        }
        img
    }

    #[test]
    fn identical_images_are_perfect() {
        let a = gradient(32, 24, 0);
        assert_eq!(a.ssim(&a).unwrap(), 1.0);
        assert!(a.psnr(&a).unwrap().is_infinite());
    }

    #[test]
    fn noise_lowers_ssim_and_psnr() {
        let a = gradient(64, 64, 0);
        let mut b = a.clone();
        for (i, v) in b.data.iter_mut().enumerate() {
            if i % 4 != 3 {
                *v = v.wrapping_add(((i * 7919) % 41) as u8);
            }
        }
        let ssim = a.ssim(&b).unwrap();
        assert!(ssim < 0.9 && ssim > -1.0, "ssim {ssim}");
        assert!(a.psnr(&b).unwrap() < 30.0);
    }

    #[test]
    fn png_round_trip_and_side_by_side() {
        let a = gradient(8, 4, 0);
        let b = gradient(8, 4, 50);
        let sbs = RgbaImage::side_by_side(&a, &b);
        assert_eq!(sbs.crop(8, 0, 8, 4), b);
        let path = std::env::temp_dir().join(format!("foveate-png-{}.png", std::process::id()));
        sbs.save(&path).unwrap();
        assert_eq!(RgbaImage::load_png(&path).unwrap(), sbs);
        let _ = std::fs::remove_file(path);
    }

    #[test]
    fn size_mismatch_is_an_error() {
        assert!(matches!(
            gradient(4, 4, 0).ssim(&gradient(4, 5, 0)),
            Err(ImageError::SizeMismatch { .. })
        ));
    }
}
