//! The GPU judge behind `metrics::FlipMapper`, the interface `metrics::perceptual` judges
//! through: one [`FlipJudge`] per image size.

use super::FlipJudge;
use crate::gpu::{Gpu, GpuError};
use crate::metrics::{
    Acuity, EyeFlipErrors, EyePixels, FlipMapper, FlipMaps, JudgeError, RgbaImage,
};

/// The GPU judge as a [`FlipMapper`] (what `metrics::perceptual` judges with): a [`FlipJudge`]
/// for each image size it is given, made the first time.
pub struct GpuFlip {
    gpu: Gpu,
    judges: Vec<FlipJudge>,
}

impl GpuFlip {
    /// Judges on `gpu`.
    pub fn new(gpu: &Gpu) -> Self {
        GpuFlip {
            gpu: gpu.clone(),
            judges: Vec::new(),
        }
    }
}

impl GpuFlip {
    /// The judge of `size` images, made the first time.
    pub(super) fn judge(&mut self, size: (u32, u32)) -> Result<&mut FlipJudge, GpuError> {
        let index = match self.judges.iter().position(|j| j.size() == size) {
            Some(i) => i,
            None => {
                self.judges.push(FlipJudge::new(&self.gpu, size.0, size.1)?);
                self.judges.len() - 1
            }
        };
        Ok(&mut self.judges[index])
    }
}

impl FlipMapper for GpuFlip {
    fn flip_maps(
        &mut self,
        reference: &RgbaImage,
        test: &RgbaImage,
        ppd: f64,
        acuity: Acuity,
        eccentricity: &(dyn Fn(u32, u32) -> Option<f64> + Sync),
    ) -> Result<FlipMaps, JudgeError> {
        reference.check_size(test)?;
        let judge = self.judge((reference.width, reference.height))?;
        Ok(judge.flip_maps(reference, test, ppd, acuity, eccentricity)?)
    }

    /// Reduced on the GPU: the maps come back only if `keep_map`.
    fn flip_errors(
        &mut self,
        reference: &RgbaImage,
        test: &RgbaImage,
        pixels: &EyePixels,
        acuity: Acuity,
        keep_map: bool,
    ) -> Result<EyeFlipErrors, JudgeError> {
        reference.check_size(test)?;
        let judge = self.judge((reference.width, reference.height))?;
        Ok(judge.flip_errors(reference, test, pixels, acuity, keep_map)?)
    }
}
