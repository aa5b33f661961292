//! Output images handed in from outside: an OpenXR runtime's swapchain images, or an engine's
//! images handed in frame by frame, into which the frame's last pass renders directly (no
//! copy). Each image gets its own framebuffer of every pass that writes the output, made the
//! first time the image is used; the frame picks one image before it is recorded, or renders
//! into the renderer's own output image when none is picked.

use ash::vk;

use super::setup::odd_frame_passes;
use super::targets::{compile_pass, image_desc, CompiledPass};
use crate::gpu::{Gpu, GpuError, Image};
use crate::plan::{AttachmentId, FramePlan};

/// The most distinct images a renderer renders into (a swapchain has 2 to 4; an engine that
/// makes new images each frame should make a new renderer, or reuse them).
pub const MAX_OUTPUT_IMAGES: usize = 16;

pub(super) struct OutputTargets {
    /// Per image, the passes writing the output compiled for it (`(pass index, pass)`): every
    /// writer for even frames, and for odd ones those that touch a history pair, with the
    /// pair's roles swapped (the output pass writes the next history); before `images`, whose
    /// views they hold.
    passes: Vec<[Vec<(usize, CompiledPass)>; 2]>,
    images: Vec<Image>,
    /// The passes that write the output.
    writers: Vec<usize>,
    /// The image the next frame renders into; `None`: the renderer's own.
    current: Option<usize>,
}

impl OutputTargets {
    /// Framebuffers for each of `raw` (made as the plan's output image: see
    /// [`super::output_image_desc`]), with `images` the frame's other attachments; the first
    /// of them selected, if any.
    pub fn new(
        gpu: &Gpu,
        plan: &FramePlan,
        raw: &[vk::Image],
        images: &[Image],
    ) -> Result<Self, GpuError> {
        let output: AttachmentId = plan.outputs()[0];
        let mut targets = OutputTargets {
            passes: Vec::new(),
            images: Vec::new(),
            writers: (0..plan.passes.len())
                .filter(|&i| plan.passes[i].uses().any(|u| u.attachment == output))
                .collect(),
            current: None,
        };
        for &r in raw {
            targets.add(gpu, plan, r, images)?;
        }
        targets.current = (!raw.is_empty()).then_some(0);
        Ok(targets)
    }

    /// Compiles the output's passes for `raw`, which must be made as the plan's output image.
    fn add(
        &mut self,
        gpu: &Gpu,
        plan: &FramePlan,
        raw: vk::Image,
        images: &[Image],
    ) -> Result<usize, GpuError> {
        if self.images.len() >= MAX_OUTPUT_IMAGES {
            return Err(GpuError::TooManyOutputImages {
                limit: MAX_OUTPUT_IMAGES,
            });
        }
        let output: AttachmentId = plan.outputs()[0];
        // SAFETY: the caller made the image as the plan's output description says, on this
        // device, and keeps it alive while the renderer may render into it.
        let target = unsafe { Image::borrowed(gpu, raw, &image_desc(plan, output)) };
        let image = |id: AttachmentId| if id == output { &target } else { &images[id] };
        let even = self
            .writers
            .iter()
            .map(|&i| Ok((i, compile_pass(gpu, plan, i, &image)?)))
            .collect::<Result<Vec<_>, GpuError>>()?;
        // Only the writers that touch a history pair differ on odd frames.
        let odd = odd_frame_passes(gpu, plan, self.writers.iter().copied(), &image)?;
        self.passes.push([even, odd]);
        self.images.push(target);
        Ok(self.images.len() - 1)
    }

    pub fn select(&mut self, index: usize) -> Result<(), GpuError> {
        if index >= self.images.len() {
            return Err(GpuError::NoSuchOutputImage {
                index,
                count: self.images.len(),
            });
        }
        self.current = Some(index);
        Ok(())
    }

    /// Selects `raw` for the next frame, compiling for it the first time it is seen.
    pub fn select_image(
        &mut self,
        gpu: &Gpu,
        plan: &FramePlan,
        raw: vk::Image,
        images: &[Image],
    ) -> Result<(), GpuError> {
        let index = match self.images.iter().position(|i| i.raw == raw) {
            Some(i) => i,
            None => self.add(gpu, plan, raw, images)?,
        };
        self.current = Some(index);
        Ok(())
    }

    /// The passes a frame of `parity` (0 even, 1 odd) records into the selected image instead
    /// of the plan's (none when the frame renders into the renderer's own image), in two
    /// lists searched in order: on odd frames the swapped writers come first.
    pub fn passes(&self, parity: usize) -> [&[(usize, CompiledPass)]; 2] {
        let Some(c) = self.current else {
            return [&[], &[]];
        };
        let [even, odd] = &self.passes[c];
        if parity == 1 {
            [odd, even]
        } else {
            [even, &[]]
        }
    }

    /// The selected image, if one is.
    pub fn image(&self) -> Option<&Image> {
        self.current.map(|c| &self.images[c])
    }
}
