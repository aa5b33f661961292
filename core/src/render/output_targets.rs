//! Output images handed in from outside: an OpenXR runtime's swapchain images, into which the
//! frame's last pass renders directly (no copy). Each image gets its own framebuffer of every
//! pass that writes the output; the frame picks one image before it is recorded.

use ash::vk;

use super::targets::{compile_pass, image_desc, CompiledPass};
use crate::gpu::{Gpu, GpuError, Image};
use crate::plan::{AttachmentId, FramePlan};

pub(super) struct OutputTargets {
    /// Per image, the passes writing the output compiled for it (`(pass index, pass)`);
    /// before `images`, whose views they hold.
    passes: Vec<Vec<(usize, CompiledPass)>>,
    images: Vec<Image>,
    current: usize,
}

impl OutputTargets {
    /// Framebuffers for each of `raw` (made as the plan's output image: see
    /// [`super::output_image_desc`]), with `images` the frame's other attachments.
    pub fn new(
        gpu: &Gpu,
        plan: &FramePlan,
        raw: &[vk::Image],
        images: &[Image],
    ) -> Result<Self, GpuError> {
        let output: AttachmentId = plan.outputs()[0];
        let desc = image_desc(plan, output);
        // SAFETY: the caller made each image as `desc` says, on this device.
        let targets: Vec<Image> = raw
            .iter()
            .map(|&r| unsafe { Image::borrowed(gpu, r, &desc) })
            .collect();
        let writers: Vec<usize> = (0..plan.passes.len())
            .filter(|&i| plan.passes[i].uses().any(|u| u.attachment == output))
            .collect();
        let passes = targets
            .iter()
            .map(|target| {
                let image = |id: AttachmentId| if id == output { target } else { &images[id] };
                writers
                    .iter()
                    .map(|&i| Ok((i, compile_pass(gpu, plan, i, &image)?)))
                    .collect::<Result<Vec<_>, GpuError>>()
            })
            .collect::<Result<Vec<_>, GpuError>>()?;
        Ok(OutputTargets {
            passes,
            images: targets,
            current: 0,
        })
    }

    pub fn select(&mut self, index: usize) -> Result<(), GpuError> {
        if index >= self.images.len() {
            return Err(GpuError::NoSuchOutputImage {
                index,
                count: self.images.len(),
            });
        }
        self.current = index;
        Ok(())
    }

    /// The passes this frame records into the selected image instead of the plan's.
    pub fn passes(&self) -> &[(usize, CompiledPass)] {
        &self.passes[self.current]
    }

    pub fn image(&self) -> &Image {
        &self.images[self.current]
    }
}
