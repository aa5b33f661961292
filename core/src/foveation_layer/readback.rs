//! The frame's output, read back to the CPU or handed to a swapchain.

use ash::vk;

use super::layer::FoveationLayer;
use crate::gpu::{
    access, memory_barrier, transition_image, BlitSource, Buffer, GpuError, ImageState,
    MemoryLocation,
};
use crate::metrics::RgbaImage;
use crate::plan::{AttachmentId, Format, TargetLayout};
use crate::view::Eye;

/// The two eyes' images of the last frame.
#[derive(Clone, Debug, PartialEq)]
pub struct StereoImage {
    /// The left eye.
    pub left: RgbaImage,
    /// The right eye.
    pub right: RgbaImage,
}

impl StereoImage {
    /// The image of `eye`.
    pub fn eye(&self, eye: Eye) -> &RgbaImage {
        match eye {
            Eye::Left => &self.left,
            Eye::Right => &self.right,
        }
    }

    /// Left, right.
    pub fn eyes(&self) -> [&RgbaImage; 2] {
        [&self.left, &self.right]
    }

    /// Both eyes side by side, left first.
    pub fn side_by_side(&self) -> RgbaImage {
        RgbaImage::side_by_side(&self.left, &self.right)
    }
}

/// Where a frame's two eyes lie in a buffer its outputs were copied into
/// ([`FoveationLayer::output_texels`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct OutputTexels {
    /// The outputs' format.
    pub format: Format,
    /// One eye's size.
    pub width: u32,
    pub height: u32,
    /// The bytes the copy fills.
    pub bytes: u64,
    /// Each eye's first texel (counted from the buffer's start) and its rows' pitch in texels.
    pub eyes: [(u64, u32); 2],
}

impl FoveationLayer {
    /// Copies the last frame's stereo image back to the CPU.
    pub fn readback(&mut self) -> Result<StereoImage, GpuError> {
        self.gpu.check_alive()?;
        if self.frames_rendered == 0 {
            return Err(GpuError::NoFrameRendered);
        }
        let outputs = self.plan.outputs();
        let size: u64 = outputs
            .iter()
            .map(|&i| self.plan.attachments[i].bytes())
            .sum();
        if self.readback.as_ref().is_none_or(|b| b.size < size) {
            self.readback = Some(Buffer::new(
                &self.gpu,
                "readback",
                size,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?);
        }
        let buffer_raw = self.readback.as_ref().expect("created above").raw;
        let device = self.gpu.device();
        self.gpu.one_shot(|cmd| {
            self.record_output_copy(cmd, buffer_raw, 0);
            // SAFETY: `cmd` is recording; the host reads the buffer after the fence.
            unsafe { memory_barrier(device, cmd, access::TRANSFER_WRITE, access::HOST_READ) };
        })?;
        let buffer = self.readback.as_mut().expect("created above");
        let bytes = &buffer.mapped()[..size as usize];
        let first = &self.plan.attachments[outputs[0]];
        let (w, h) = (first.width, first.height);
        let layer_bytes = (w * h) as u64 * first.format.bytes_per_pixel();
        let mut slices = bytes
            .chunks_exact(layer_bytes as usize)
            .map(|texels| RgbaImage {
                width: w,
                height: h,
                data: super::output_pixels::to_srgb8(first.format, texels),
            });
        let mut next = || slices.next().expect("two eyes' worth of layers");
        Ok(match self.plan.output_layout() {
            TargetLayout::Layered | TargetLayout::PerEye => StereoImage {
                left: next(),
                right: next(),
            },
            TargetLayout::SideBySide => {
                let both = next();
                StereoImage {
                    left: both.crop(0, 0, w / 2, h),
                    right: both.crop(w / 2, 0, w / 2, h),
                }
            }
        })
    }

    /// Where the last frame's eyes lie once [`FoveationLayer::record_output_copy`] has copied its
    /// outputs into a buffer.
    pub(crate) fn output_texels(&self) -> OutputTexels {
        let outputs = self.plan.outputs();
        let first = &self.plan.attachments[outputs[0]];
        let (w, h) = (first.width, first.height);
        let bytes = outputs
            .iter()
            .map(|&i| self.plan.attachments[i].bytes())
            .sum();
        let layer = u64::from(w) * u64::from(h);
        let eyes = match self.plan.output_layout() {
            TargetLayout::Layered | TargetLayout::PerEye => [(0, w), (layer, w)],
            TargetLayout::SideBySide => [(0, w), (u64::from(w / 2), w)],
        };
        let width = match self.plan.output_layout() {
            TargetLayout::SideBySide => w / 2,
            _ => w,
        };
        OutputTexels {
            format: first.format,
            width,
            height: h,
            bytes,
            eyes,
        }
    }

    /// Records copying every layer of every output of the last frame, one after the other,
    /// into `buffer` from byte `start` ([`OutputTexels::bytes`] of it; a transfer
    /// destination); the frame must have finished. A barrier before reading the copy is the
    /// caller's.
    pub(crate) fn record_output_copy(
        &self,
        cmd: vk::CommandBuffer,
        buffer: vk::Buffer,
        start: u64,
    ) {
        let outputs = self.plan.outputs();
        let mut copies = Vec::new();
        let mut offset = start;
        for &id in &outputs {
            let a = &self.plan.attachments[id];
            let region = vk::BufferImageCopy::default()
                .buffer_offset(offset)
                .image_subresource(vk::ImageSubresourceLayers {
                    aspect_mask: vk::ImageAspectFlags::COLOR,
                    mip_level: 0,
                    base_array_layer: 0,
                    layer_count: a.layers,
                })
                .image_extent(vk::Extent3D {
                    width: a.width,
                    height: a.height,
                    depth: 1,
                });
            copies.push((self.output_image(id), region));
            offset += a.bytes();
        }
        let device = self.gpu.device();
        // The outputs' render passes left them in TRANSFER_SRC_OPTIMAL; an image handed in
        // (a runtime's) in COLOR_ATTACHMENT_OPTIMAL, where it goes back after the copy.
        let external = self.plan.external_output;
        let range = vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: self.plan.attachments[outputs[0]].layers,
        };
        let attachment: ImageState = (
            vk::PipelineStageFlags::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags::COLOR_ATTACHMENT_WRITE,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        );
        let copying: ImageState = (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_READ,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        );
        // SAFETY: `cmd` is recording; the images and `buffer` outlive its submission.
        unsafe {
            for (image, region) in &copies {
                if external {
                    transition_image(device, cmd, *image, range, attachment, copying);
                }
                device.cmd_copy_image_to_buffer(
                    cmd,
                    *image,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    buffer,
                    &[*region],
                );
                if external {
                    transition_image(device, cmd, *image, range, copying, attachment);
                }
            }
        }
    }

    /// The last frame's eye images where they lie (left, right) for a swapchain to show
    /// ([`crate::gpu::Swapchain::present`]); the outputs stay in `TRANSFER_SRC_OPTIMAL`.
    pub fn present_sources(&self) -> Result<[BlitSource; 2], GpuError> {
        if self.frames_rendered == 0 {
            return Err(GpuError::NoFrameRendered);
        }
        let outputs = self.plan.outputs();
        let first = &self.plan.attachments[outputs[0]];
        let source = |id: AttachmentId, layer, x, width| BlitSource {
            image: self.images[id].raw,
            layer,
            x,
            width,
            height: first.height,
        };
        let w = first.width;
        Ok(match self.plan.output_layout() {
            TargetLayout::Layered => [source(outputs[0], 0, 0, w), source(outputs[0], 1, 0, w)],
            TargetLayout::PerEye => [source(outputs[0], 0, 0, w), source(outputs[1], 0, 0, w)],
            TargetLayout::SideBySide => [
                source(outputs[0], 0, 0, w / 2),
                source(outputs[0], 0, w / 2, w / 2),
            ],
        })
    }
}
