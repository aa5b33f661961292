//! The commands that put a frame's output images into an acquired swapchain image: a clear to
//! black, one blit per source to where `fit_side_by_side` placed it, optionally a copy of the
//! result into a readback buffer, and the image left ready to present.

use ash::vk;

use super::blit_layout::BlitSource;
use super::{transition_image, Buffer};

/// What the copy writes: the swapchain image, its size, and where each source goes.
pub(super) struct CopyTarget<'a> {
    pub image: vk::Image,
    pub extent: vk::Extent2D,
    pub placements: &'a [(BlitSource, [vk::Offset3D; 2])],
    /// The buffer the presented image is copied into, when asked.
    pub readback: Option<&'a Buffer>,
}

type StageAccess = (vk::PipelineStageFlags, vk::AccessFlags);

const TRANSFER_WRITE: StageAccess = (
    vk::PipelineStageFlags::TRANSFER,
    vk::AccessFlags::TRANSFER_WRITE,
);
const TRANSFER_READ: StageAccess = (
    vk::PipelineStageFlags::TRANSFER,
    vk::AccessFlags::TRANSFER_READ,
);
/// The present reads the image after the semaphore the submission signals: no stage of this
/// command buffer needs to wait for it.
const PRESENT_READ: StageAccess = (
    vk::PipelineStageFlags::BOTTOM_OF_PIPE,
    vk::AccessFlags::empty(),
);

const COLOR_LAYER: vk::ImageSubresourceRange = vk::ImageSubresourceRange {
    aspect_mask: vk::ImageAspectFlags::COLOR,
    base_mip_level: 0,
    level_count: 1,
    base_array_layer: 0,
    layer_count: 1,
};

fn layer(layer: u32) -> vk::ImageSubresourceLayers {
    vk::ImageSubresourceLayers {
        aspect_mask: vk::ImageAspectFlags::COLOR,
        mip_level: 0,
        base_array_layer: layer,
        layer_count: 1,
    }
}

/// Records the copy into `cmd`. The sources are in `TRANSFER_SRC_OPTIMAL` and were written
/// before (the frame's own barriers make them readable by transfers); the acquired image's
/// submission waits for the acquire at the transfer stage.
///
/// # Safety
/// `cmd` is recording outside a render pass; the images and the buffer outlive its execution.
pub(super) unsafe fn record_copy(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    target: &CopyTarget,
) {
    let image = target.image;
    // SAFETY (for the closure's calls): as this function's.
    let barrier = |from, to, src: StageAccess, dst: StageAccess| unsafe {
        transition_image(
            device,
            cmd,
            image,
            COLOR_LAYER,
            (src.0, src.1, from),
            (dst.0, dst.1, to),
        )
    };
    barrier(
        vk::ImageLayout::UNDEFINED,
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
        (vk::PipelineStageFlags::TRANSFER, vk::AccessFlags::empty()),
        TRANSFER_WRITE,
    );
    let black = vk::ClearColorValue {
        float32: [0.0, 0.0, 0.0, 1.0],
    };
    let dst = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
    unsafe { device.cmd_clear_color_image(cmd, image, dst, &black, &[COLOR_LAYER]) };
    barrier(dst, dst, TRANSFER_WRITE, TRANSFER_WRITE);
    for (source, to) in target.placements {
        unsafe { blit(device, cmd, source, image, *to) };
    }
    match target.readback {
        Some(buffer) => {
            let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
            barrier(dst, src, TRANSFER_WRITE, TRANSFER_READ);
            unsafe { copy_to_buffer(device, cmd, image, target.extent, buffer) };
            barrier(
                src,
                vk::ImageLayout::PRESENT_SRC_KHR,
                TRANSFER_READ,
                PRESENT_READ,
            );
        }
        None => barrier(
            dst,
            vk::ImageLayout::PRESENT_SRC_KHR,
            TRANSFER_WRITE,
            PRESENT_READ,
        ),
    }
}

/// One source scaled into `to` of `image`: nearest at 1:1 (texels copied unchanged), linear
/// otherwise.
unsafe fn blit(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    source: &BlitSource,
    image: vk::Image,
    to: [vk::Offset3D; 2],
) {
    let one_to_one =
        to[1].x - to[0].x == source.width as i32 && to[1].y - to[0].y == source.height as i32;
    let filter = if one_to_one {
        vk::Filter::NEAREST
    } else {
        vk::Filter::LINEAR
    };
    let from = [
        vk::Offset3D {
            x: source.x as i32,
            y: 0,
            z: 0,
        },
        vk::Offset3D {
            x: (source.x + source.width) as i32,
            y: source.height as i32,
            z: 1,
        },
    ];
    let region = vk::ImageBlit::default()
        .src_subresource(layer(source.layer))
        .src_offsets(from)
        .dst_subresource(layer(0))
        .dst_offsets(to);
    unsafe {
        device.cmd_blit_image(
            cmd,
            source.image,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            image,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            &[region],
            filter,
        )
    };
}

/// The whole image into `buffer`, made visible to the host once the submission's fence
/// signals.
unsafe fn copy_to_buffer(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    extent: vk::Extent2D,
    buffer: &Buffer,
) {
    let region = vk::BufferImageCopy::default()
        .image_subresource(layer(0))
        .image_extent(vk::Extent3D {
            width: extent.width,
            height: extent.height,
            depth: 1,
        });
    let host = vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
        .dst_access_mask(vk::AccessFlags::HOST_READ);
    unsafe {
        device.cmd_copy_image_to_buffer(
            cmd,
            image,
            vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
            buffer.raw,
            &[region],
        );
        device.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::HOST,
            vk::DependencyFlags::empty(),
            &[host],
            &[],
            &[],
        );
    }
}
