//! Flicker measured on the device that rendered the frames ([`crate::metrics::temporal`]'s
//! measure): each frame's outputs are copied on the device, not read back; each pixel's luma
//! stays there for the next frame; only a histogram per region comes back.

use ash::vk;

use super::images::JudgedImage;
use super::outputs::{copied, frames_buffer, image_params};
use super::reduce::Reduction;
use super::vulkan::{compute_pipeline, SharedSet};
use crate::gpu::{Buffer, Gpu, GpuError, MemoryLocation, Pipeline};
use crate::metrics::temporal::FlickerSummary;
use crate::metrics::{ErrorHistogram, EyePixels, JudgeError, Region, HISTOGRAM_BINS};
use crate::plan::ConfigError;
use crate::render::OutputTexels;
use crate::shaders::FLICKER_COMP;

/// Pixels per workgroup side (`shaders/flicker.comp`'s `local_size_x`, `local_size_y`).
const GROUP: u32 = 16;

/// The shader's push constants (`shaders/flicker.comp`).
#[repr(C)]
#[derive(Clone, Copy, Default)]
struct Params {
    size: [i32; 2],
    bins: i32,
    compare: i32,
    reference: [i32; 4],
    test: [i32; 4],
}

/// The buffers for one output size.
struct Sized {
    texels: OutputTexels,
    /// Both frames' texels as copied: the reference's, then the approximation's.
    frames: Buffer,
    /// Each pixel's last luma (both eyes, the reference's then the approximation's).
    _luma: Buffer,
    reduction: Reduction,
}

/// Flicker of an approximation against its reference, frame after frame, on the GPU: push
/// each frame once both renderers have rendered it (and finished), then read the
/// [`FlickerSummary`]. The figures are [`crate::metrics::temporal::Flicker`]'s (the CPU
/// measure, its oracle), from histograms: within half a bin (1/32768) of the exact ones.
pub struct GpuFlicker {
    gpu: Gpu,
    pipeline: Pipeline,
    shared: SharedSet,
    sized: Option<Sized>,
    regions: [ErrorHistogram; 3],
    frames: usize,
}

impl GpuFlicker {
    /// Its compute pipeline's shader and what the driver's compiler reported of it (as
    /// [`FlipJudge::shader_statistics`](super::FlipJudge::shader_statistics)).
    pub fn shader_statistics(&self) -> Vec<(&'static str, &[crate::gpu::ShaderExecutable])> {
        super::vulkan::statistics([(&self.pipeline, &FLICKER_COMP)])
    }

    /// A measure with no frame yet, on `gpu` (the renderers' device).
    pub fn new(gpu: &Gpu) -> Result<Self, GpuError> {
        let shared = SharedSet::new(gpu, 4, std::mem::size_of::<Params>() as u32)?;
        let pipeline = compute_pipeline(gpu, &shared.layout, &FLICKER_COMP)?;
        Ok(GpuFlicker {
            gpu: gpu.clone(),
            pipeline,
            shared,
            sized: None,
            regions: Default::default(),
            frames: 0,
        })
    }

    /// Adds the frame both rendered last: `approximation`'s output against `reference`'s
    /// (two layers' or renderers' last frames, or images the engine owns:
    /// [`super::EyeLayers`]), pixels as `pixels` maps them (the regions at this frame's gaze).
    /// Both must be of one size, every frame the first's.
    pub fn push<'a>(
        &mut self,
        reference: impl Into<JudgedImage<'a>>,
        approximation: impl Into<JudgedImage<'a>>,
        pixels: &[EyePixels; 2],
    ) -> Result<(), JudgeError> {
        let (reference, approximation) = (reference.into(), approximation.into());
        let texels = [
            reference.texels("reference's output")?,
            approximation.texels("approximation's output")?,
        ];
        let size = |t: &OutputTexels| (t.width, t.height);
        let describe = |(w, h): (u32, u32)| format!("{w}x{h}");
        if size(&texels[1]) != size(&texels[0]) {
            let limit = format!("the reference's, {}", describe(size(&texels[0])));
            let e = ConfigError::new("approximation's output", describe(size(&texels[1])), limit);
            return Err(GpuError::from(e).into());
        }
        for p in pixels {
            if (p.width, p.height) != size(&texels[0]) {
                let limit = format!("the outputs', {}", describe(size(&texels[0])));
                let e = ConfigError::new("pixel map", describe((p.width, p.height)), limit);
                return Err(GpuError::from(e).into());
            }
        }
        self.size_for(texels)?;
        let sized = self.sized.as_mut().expect("sized above");
        sized.reduction.upload_labels(&[&pixels[0], &pixels[1]]);
        let compare = self.frames > 0;
        let frames = sized.frames.raw;
        let params = Params {
            size: [texels[0].width as i32, texels[0].height as i32],
            bins: HISTOGRAM_BINS as i32,
            compare: i32::from(compare),
            // The shader adds eye × the right eye's first texel: the right eye's parameters.
            reference: image_params(&texels[0], 0, 1),
            test: image_params(&texels[1], texels[0].bytes / 4, 1),
        };
        let device = self.gpu.device();
        let sized = self.sized.as_ref().expect("sized above");
        self.gpu.one_shot(|cmd| {
            sized.reduction.record_clear(device, cmd);
            reference.record_copy(device, cmd, frames, 0);
            approximation.record_copy(device, cmd, frames, texels[0].bytes);
            copied(device, cmd);
            let groups = [
                params.size[0].unsigned_abs().div_ceil(GROUP),
                params.size[1].unsigned_abs().div_ceil(GROUP),
                2,
            ];
            let push = crate::gpu::pod_bytes(std::slice::from_ref(&params));
            (self.shared).dispatch(device, cmd, &self.pipeline, push, groups);
            sized.reduction.record_read_back(device, cmd, true, None);
        })?;
        if compare {
            let sized = self.sized.as_mut().expect("sized above");
            for (all, one) in self.regions.iter_mut().zip(sized.reduction.histograms()) {
                all.merge(&one);
            }
        }
        self.frames += 1;
        Ok(())
    }

    /// What the frames pushed so far amount to.
    pub fn summary(&self) -> FlickerSummary {
        FlickerSummary::of_histograms(&self.regions, self.frames.saturating_sub(1))
    }

    /// Makes the buffers for outputs described by `texels` (the reference's, the
    /// approximation's) at the first frame; an error if a later frame's differ in size.
    fn size_for(&mut self, texels: [OutputTexels; 2]) -> Result<(), GpuError> {
        if let Some(sized) = &self.sized {
            let (w, h) = (sized.texels.width, sized.texels.height);
            if (texels[0].width, texels[0].height) != (w, h) {
                let size = format!("{}x{}", texels[0].width, texels[0].height);
                let limit = format!("the first frame's, {w}x{h}");
                return Err(ConfigError::new("output size", size, limit).into());
            }
            return Ok(());
        }
        use vk::BufferUsageFlags as Usage;
        let pixels = u64::from(texels[0].width) * u64::from(texels[0].height);
        let frames = frames_buffer(&self.gpu, texels[0].bytes + texels[1].bytes)?;
        let luma = Buffer::new(
            &self.gpu,
            "flicker luma",
            4 * 4 * pixels,
            Usage::STORAGE_BUFFER,
            MemoryLocation::GpuOnly,
        )?;
        let reduction = Reduction::new(&self.gpu, 2 * pixels, Region::ALL.len())?;
        self.shared.bind(
            &self.gpu,
            &[&frames, &luma, &reduction.labels, &reduction.counts],
        );
        self.sized = Some(Sized {
            texels: texels[0],
            frames,
            _luma: luma,
            reduction,
        });
        Ok(())
    }
}
