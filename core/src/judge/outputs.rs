//! Judging two renderers' last frames where they lie: both outputs are copied on the device,
//! and one eye of each is gathered into the judge's 8-bit sRGB inputs (`shaders/flip_gather.comp`)
//! — the frames are never read back. What follows is the judgement of uploaded images.

use ash::vk;

use super::flip::{FlipJudge, Params, Source};
use super::GpuFlip;
use crate::gpu::{access, memory_barrier, Buffer, Gpu, GpuError, MemoryLocation};
use crate::metrics::perceptual::{combine_eyes, Maps, PerceptualError};
use crate::metrics::{Acuity, EyePixels, JudgeError};
use crate::plan::{ConfigError, Format};
use crate::render::{OutputTexels, Renderer};

/// The gather pass's index among the judge's pipelines.
const GATHER: usize = 7;

/// A device buffer the renderers' outputs are copied into.
pub(super) fn frames_buffer(gpu: &Gpu, bytes: u64) -> Result<Buffer, GpuError> {
    use vk::BufferUsageFlags as Usage;
    let usage = Usage::STORAGE_BUFFER | Usage::TRANSFER_DST;
    Buffer::new(gpu, "judged frames", bytes, usage, MemoryLocation::GpuOnly)
}

/// Records the barrier between the outputs' copies and the pass that reads them.
pub(super) fn copied(device: &ash::Device, cmd: vk::CommandBuffer) {
    // SAFETY: `cmd` is recording.
    unsafe { memory_barrier(device, cmd, access::TRANSFER_WRITE, access::COMPUTE_READ) };
}

/// An output's push constants for `eye`: its format, its first word in the frames buffer, the
/// eye's first texel, its rows' pitch (`shaders/output_texels.glsl`).
pub(super) fn image_params(texels: &OutputTexels, first_word: u64, eye: usize) -> [i32; 4] {
    let format = match texels.format {
        Format::Rgba8Unorm => 1,
        Format::Rgba16F => 2,
        _ => 0,
    };
    let (first, pitch) = texels.eyes[eye];
    [format, first_word as i32, first as i32, pitch as i32]
}

impl FlipJudge {
    /// Checks that both renderers' outputs are of the judge's size and makes room for them;
    /// returns each one's push constants for eye `eye`.
    pub(super) fn outputs_to_gather(
        &mut self,
        reference: &Renderer,
        test: &Renderer,
        eye: usize,
    ) -> Result<[[i32; 4]; 2], GpuError> {
        let texels = [reference, test].map(|r| r.output_texels());
        for (name, t) in ["reference's output", "test's output"].iter().zip(&texels) {
            if (t.width, t.height) != (self.width, self.height) {
                let size = format!("{}x{} per eye", t.width, t.height);
                let limit = format!("the judge's size, {}x{}", self.width, self.height);
                return Err(ConfigError::new(name, size, limit).into());
            }
        }
        if eye > 1 {
            return Err(ConfigError::new("eye", eye, "0 (left) or 1 (right)").into());
        }
        let bytes = texels[0].bytes + texels[1].bytes;
        if self.frames.size < bytes {
            self.frames = frames_buffer(&self.gpu, bytes)?;
        }
        Ok([
            image_params(&texels[0], 0, eye),
            image_params(&texels[1], texels[0].bytes / 4, eye),
        ])
    }

    /// Records copying both outputs and gathering the eye into the inputs.
    pub(super) fn record_gather(
        &self,
        cmd: vk::CommandBuffer,
        params: Params,
        reference: &Renderer,
        test: &Renderer,
    ) {
        let reference_bytes = reference.output_texels().bytes;
        reference.record_output_copy(cmd, self.frames.raw, 0);
        test.record_output_copy(cmd, self.frames.raw, reference_bytes);
        copied(self.gpu.device(), cmd);
        self.dispatch(cmd, GATHER, params, (self.width, self.height));
    }

    /// One eye's figures of `test`'s last frame against `reference`'s, read where they lie on
    /// the device (both finished; each output of the judge's size per eye), over the pixels
    /// `pixels` shows: as [`FlipJudge::flip_errors`] of the read-back eyes.
    pub fn flip_errors_of_outputs(
        &mut self,
        reference: &Renderer,
        test: &Renderer,
        eye: usize,
        pixels: &EyePixels,
        acuity: Acuity,
        keep_map: bool,
    ) -> Result<crate::metrics::EyeFlipErrors, GpuError> {
        let source = Source::Outputs {
            reference,
            test,
            eye,
        };
        self.eye_errors(source, pixels, acuity, keep_map)
    }
}

impl GpuFlip {
    /// Both eyes of `image`'s last frame judged against `reference`'s where they lie on the
    /// device (no frame read back): the figures [`crate::metrics::perceptual::perceptual_error`]
    /// gives for the read-back frames, the maps kept as `maps` says. Both renderers must have
    /// finished their frames, outputs of one size.
    pub fn frame_errors(
        &mut self,
        reference: &Renderer,
        image: &Renderer,
        pixels: &[EyePixels; 2],
        acuity: Acuity,
        maps: Maps,
    ) -> Result<PerceptualError, JudgeError> {
        let texels = reference.output_texels();
        let judge = self.judge((texels.width, texels.height))?;
        let mut eyes = Vec::with_capacity(2);
        for (eye, p) in pixels.iter().enumerate() {
            let keep = maps == Maps::Keep;
            eyes.push(judge.flip_errors_of_outputs(reference, image, eye, p, acuity, keep)?);
        }
        Ok(combine_eyes(eyes, maps))
    }
}
