//! The GPU judge behind `metrics::FlipMapper`, the interface `metrics::perceptual` judges
//! through: one [`FlipJudge`] per image size.

use super::FlipJudge;
use crate::gpu::Gpu;
use crate::metrics::{Acuity, FlipMapper, FlipMaps, JudgeError, RgbaImage};

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
        let size = (reference.width, reference.height);
        let index = match self.judges.iter().position(|j| j.size() == size) {
            Some(i) => i,
            None => {
                self.judges.push(FlipJudge::new(&self.gpu, size.0, size.1)?);
                self.judges.len() - 1
            }
        };
        let judge = &mut self.judges[index];
        Ok(judge.flip_maps(reference, test, ppd, acuity, eccentricity)?)
    }
}
