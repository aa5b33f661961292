//! What the judge reads where it lies on the device: a layer's (or a renderer's) last frame, or
//! any image an engine owns whose two array layers are the left and right eye. Each is copied
//! into the judge's buffer (the judge's own submission, or the engine's command buffer:
//! [`crate::judge::GpuFlip::record_capture`]) and gathered from there; nothing is read back.

use ash::vk;

use crate::gpu::{transition_image, GpuError, ImageState};
use crate::plan::{ConfigError, Format};
use crate::render::{FoveationLayer, OutputTexels, Renderer};

/// Both eyes of a frame, as the judge reads them.
#[derive(Clone, Copy)]
pub enum JudgedImage<'a> {
    /// The last frame of a layer: an engine's draws composed, or a [`Renderer`]'s frame (its
    /// layer's). It must have finished before the judgement runs.
    Frame(&'a FoveationLayer),
    /// An image the engine owns.
    Eyes(EyeLayers),
}

/// An image whose array layers 0 and 1 are the left and right eye: 8-bit sRGB or UNORM RGBA,
/// or half-float RGBA, made with `TRANSFER_SRC` usage. The judge's copy moves it from
/// `layout` (colour attachment, shader read-only, transfer source or general) to
/// `TRANSFER_SRC_OPTIMAL` and back, after the work that uses an image in that layout.
#[derive(Clone, Copy, Debug)]
pub struct EyeLayers {
    /// The image (the engine's, alive until the copy has run).
    pub image: vk::Image,
    /// Its format.
    pub format: vk::Format,
    /// One eye's pixels across.
    pub width: u32,
    /// One eye's pixels down.
    pub height: u32,
    /// Its layout where the copy is recorded (and after it).
    pub layout: vk::ImageLayout,
}

impl<'a> From<&'a FoveationLayer> for JudgedImage<'a> {
    fn from(layer: &'a FoveationLayer) -> Self {
        JudgedImage::Frame(layer)
    }
}

impl<'a> From<&'a Renderer> for JudgedImage<'a> {
    fn from(renderer: &'a Renderer) -> Self {
        JudgedImage::Frame(renderer.layer())
    }
}

impl From<EyeLayers> for JudgedImage<'_> {
    fn from(eyes: EyeLayers) -> Self {
        JudgedImage::Eyes(eyes)
    }
}

impl JudgedImage<'_> {
    /// Where its eyes lie once copied into a buffer; an error for an image the judge cannot
    /// read (its format, or no pixel).
    pub(crate) fn texels(&self, name: &'static str) -> Result<OutputTexels, GpuError> {
        match self {
            JudgedImage::Frame(layer) if layer.frames_recorded() == 0 => Err(ConfigError::new(
                name,
                "a layer that has rendered no frame",
                "a layer or renderer whose first frame has been recorded and has run",
            )
            .into()),
            JudgedImage::Frame(layer) => Ok(layer.output_texels()),
            JudgedImage::Eyes(e) => {
                let format = match e.format {
                    vk::Format::R8G8B8A8_SRGB => Format::Rgba8Srgb,
                    vk::Format::R8G8B8A8_UNORM => Format::Rgba8Unorm,
                    vk::Format::R16G16B16A16_SFLOAT => Format::Rgba16F,
                    other => {
                        return Err(ConfigError::new(
                            name,
                            format!("{other:?}"),
                            "R8G8B8A8_SRGB, R8G8B8A8_UNORM or R16G16B16A16_SFLOAT",
                        )
                        .into())
                    }
                };
                if e.width == 0 || e.height == 0 {
                    let size = format!("{}x{}", e.width, e.height);
                    return Err(ConfigError::new(name, size, "at least 1x1 per eye").into());
                }
                if layout_access(e.layout).is_none() {
                    let limit = "COLOR_ATTACHMENT_OPTIMAL, SHADER_READ_ONLY_OPTIMAL, \
                                 TRANSFER_SRC_OPTIMAL or GENERAL: the layout its eyes are in";
                    return Err(ConfigError::new(name, format!("{:?}", e.layout), limit).into());
                }
                let layer = u64::from(e.width) * u64::from(e.height);
                Ok(OutputTexels {
                    format,
                    width: e.width,
                    height: e.height,
                    bytes: 2 * layer * format.bytes_per_pixel(),
                    eyes: [(0, e.width), (layer, e.width)],
                })
            }
        }
    }

    /// Records copying both eyes into `buffer` from byte `start`, after everything recorded
    /// before (a barrier before reading the copy is the caller's).
    pub(crate) fn record_copy(
        &self,
        device: &ash::Device,
        cmd: vk::CommandBuffer,
        buffer: vk::Buffer,
        start: u64,
    ) {
        let e = match self {
            JudgedImage::Frame(layer) => return layer.record_output_copy(cmd, buffer, start),
            JudgedImage::Eyes(e) => e,
        };
        let range = vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 2,
        };
        // Who wrote it last and who touches it next, as its layout has them.
        let (stage, access) = layout_access(e.layout).expect("checked by texels()");
        let before: ImageState = (stage, access.1, e.layout);
        let after: ImageState = (stage, access.0 | access.1, e.layout);
        let copying: ImageState = (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_READ,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        );
        let region = vk::BufferImageCopy::default()
            .buffer_offset(start)
            .image_subresource(vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: 0,
                layer_count: 2,
            })
            .image_extent(vk::Extent3D {
                width: e.width,
                height: e.height,
                depth: 1,
            });
        // SAFETY: `cmd` is recording; the image and buffer outlive its submission.
        unsafe {
            transition_image(device, cmd, e.image, range, before, copying);
            let layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
            device.cmd_copy_image_to_buffer(cmd, e.image, layout, buffer, &[region]);
            transition_image(device, cmd, e.image, range, copying, after);
        }
    }
}

/// The stage and the accesses (reads, writes) an image in `layout` is used with: what the
/// judge's copy waits for and what waits for it; `None` for a layout it does not read from.
fn layout_access(
    layout: vk::ImageLayout,
) -> Option<(vk::PipelineStageFlags, (vk::AccessFlags, vk::AccessFlags))> {
    use vk::AccessFlags as A;
    use vk::PipelineStageFlags as S;
    Some(match layout {
        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL => (
            S::COLOR_ATTACHMENT_OUTPUT,
            (A::COLOR_ATTACHMENT_READ, A::COLOR_ATTACHMENT_WRITE),
        ),
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL => (
            S::FRAGMENT_SHADER | S::COMPUTE_SHADER,
            (A::SHADER_READ, A::empty()),
        ),
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL => (S::TRANSFER, (A::TRANSFER_READ, A::empty())),
        vk::ImageLayout::GENERAL => (
            S::FRAGMENT_SHADER | S::COMPUTE_SHADER,
            (A::SHADER_READ, A::SHADER_WRITE),
        ),
        _ => return None,
    })
}
