//! Judging two frames where they lie (two layers' or renderers' outputs, or images an engine
//! owns): both are copied on the device — in the judge's submission, or captured beforehand in
//! the engine's command buffer — and one eye of each is gathered into the judge's 8-bit sRGB
//! inputs (`shaders/flip_gather.comp`); the frames are never read back. What follows is the
//! judgement of uploaded images.

use ash::vk;

use super::flip::{FlipJudge, Params, Source};
use super::images::JudgedImage;
use super::GpuFlip;
use crate::gpu::{access, memory_barrier, Buffer, Gpu, GpuError, MemoryLocation};
use crate::metrics::perceptual::{combine_eyes, Maps, PerceptualError};
use crate::metrics::{Acuity, EyePixels, JudgeError};
use crate::plan::{ConfigError, Format};
use crate::render::OutputTexels;

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
    /// Checks that both images are of the judge's size and makes room for them; returns each
    /// one's push constants for eye `eye`.
    pub(super) fn outputs_to_gather(
        &mut self,
        texels: [OutputTexels; 2],
        eye: usize,
    ) -> Result<[[i32; 4]; 2], GpuError> {
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

    /// Records copying both images into the frames buffer (unless they were captured there)
    /// and gathering the eye into the inputs.
    pub(super) fn record_gather(
        &self,
        cmd: vk::CommandBuffer,
        params: Params,
        images: Option<[JudgedImage; 2]>,
        texels: [OutputTexels; 2],
    ) {
        if let Some([reference, test]) = images {
            let device = self.gpu.device();
            reference.record_copy(device, cmd, self.frames.raw, 0);
            test.record_copy(device, cmd, self.frames.raw, texels[0].bytes);
            copied(device, cmd);
        }
        self.dispatch(cmd, GATHER, params, (self.width, self.height));
    }

    /// One eye's figures of `test` against `reference`, read where they lie on the device
    /// (both finished; each of the judge's size per eye), over the pixels `pixels` shows: as
    /// [`FlipJudge::flip_errors`] of the read-back eyes.
    pub fn flip_errors_of_outputs<'a>(
        &mut self,
        reference: impl Into<JudgedImage<'a>>,
        test: impl Into<JudgedImage<'a>>,
        eye: usize,
        pixels: &EyePixels,
        acuity: Acuity,
        keep_map: bool,
    ) -> Result<crate::metrics::EyeFlipErrors, GpuError> {
        let images = [reference.into(), test.into()];
        let texels = [
            images[0].texels("reference's output")?,
            images[1].texels("test's output")?,
        ];
        self.capture = None;
        let source = Source::Outputs {
            images: Some(images),
            texels,
            eye,
        };
        self.eye_errors(source, pixels, acuity, keep_map)
    }
}

/// Two images copied into a judge's buffer by [`GpuFlip::record_capture`], in a command buffer
/// of the caller's: judged by [`GpuFlip::captured_errors`] once that has run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Capture {
    size: (u32, u32),
    texels: [OutputTexels; 2],
    /// Which capture of the judge's this is: a later one (or a judgement that copies) takes
    /// its place.
    number: u64,
}

impl GpuFlip {
    /// Both eyes of `image` judged against `reference` where they lie on the device (no frame
    /// read back): the figures [`crate::metrics::perceptual::perceptual_error`] gives for the
    /// read-back frames, the maps kept as `maps` says. Both must have finished, of one size:
    /// two layers' or renderers' last frames, or images the engine owns ([`EyeLayers`](crate::judge::EyeLayers)).
    pub fn frame_errors<'a>(
        &mut self,
        reference: impl Into<JudgedImage<'a>>,
        image: impl Into<JudgedImage<'a>>,
        pixels: &[EyePixels; 2],
        acuity: Acuity,
        maps: Maps,
    ) -> Result<PerceptualError, JudgeError> {
        let (reference, image) = (reference.into(), image.into());
        let texels = reference.texels("reference's output")?;
        let judge = self.judge((texels.width, texels.height))?;
        let mut eyes = Vec::with_capacity(2);
        for (eye, p) in pixels.iter().enumerate() {
            let keep = maps == Maps::Keep;
            eyes.push(judge.flip_errors_of_outputs(reference, image, eye, p, acuity, keep)?);
        }
        Ok(combine_eyes(eyes, maps))
    }

    /// Records copying `reference` and `image` (both eyes of each) into the judge's buffer in
    /// `cmd`, the caller's command buffer, after everything recorded before it there: the
    /// judgement of an engine's frame without a submission of the judge's between the frame
    /// and its copy. Judge it with [`GpuFlip::captured_errors`] once `cmd` has run; a later
    /// capture of the same size takes its place.
    ///
    /// # Safety
    /// `cmd` is a primary command buffer of the judge's device, recording outside a render
    /// pass; the images stay alive until it has run.
    pub unsafe fn record_capture<'a>(
        &mut self,
        cmd: vk::CommandBuffer,
        reference: impl Into<JudgedImage<'a>>,
        image: impl Into<JudgedImage<'a>>,
    ) -> Result<Capture, JudgeError> {
        let images = [reference.into(), image.into()];
        let texels = [
            images[0].texels("reference's output")?,
            images[1].texels("test's output")?,
        ];
        let size = (texels[0].width, texels[0].height);
        let judge = self.judge(size)?;
        judge.outputs_to_gather(texels, 0)?;
        let device = judge.gpu.device();
        images[0].record_copy(device, cmd, judge.frames.raw, 0);
        images[1].record_copy(device, cmd, judge.frames.raw, texels[0].bytes);
        copied(device, cmd);
        judge.captures += 1;
        let capture = Capture {
            size,
            texels,
            number: judge.captures,
        };
        judge.capture = Some(capture.number);
        Ok(capture)
    }

    /// The figures of a [`GpuFlip::record_capture`] whose command buffer has run: as
    /// [`GpuFlip::frame_errors`] gives them. An error if a later capture or judgement took its
    /// place.
    pub fn captured_errors(
        &mut self,
        capture: &Capture,
        pixels: &[EyePixels; 2],
        acuity: Acuity,
        maps: Maps,
    ) -> Result<PerceptualError, JudgeError> {
        let judge = self.judge(capture.size)?;
        if judge.capture != Some(capture.number) {
            let limit = "the judge's last capture of its size, not yet replaced";
            let e = ConfigError::new("capture", capture.number, limit);
            return Err(GpuError::from(e).into());
        }
        let mut eyes = Vec::with_capacity(2);
        for (eye, p) in pixels.iter().enumerate() {
            judge.outputs_to_gather(capture.texels, eye)?;
            let source = Source::Outputs {
                images: None,
                texels: capture.texels,
                eye,
            };
            eyes.push(judge.eye_errors(source, p, acuity, maps == Maps::Keep)?);
        }
        Ok(combine_eyes(eyes, maps))
    }
}
