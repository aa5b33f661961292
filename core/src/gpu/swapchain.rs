//! Presenting to a window: a surface on any platform `ash-window` knows (X11, Wayland, Android's
//! `ANativeWindow`, …), its swapchain, and a present that blits a frame's output images side by
//! side into the acquired image, scaled to fit and centred. Synchronous: each present waits
//! for its copy to finish, so a frame's images are free again when it returns.

use std::sync::Arc;

use ash::vk;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use super::blit_layout::{fit_side_by_side, BlitSource};
use super::{
    transition_image, Buffer, CommandPool, DeviceOwner, Fence, Gpu, GpuError, MemoryLocation,
    Semaphore, VkResultExt,
};
use crate::vocab::RgbaImage;

/// What a present did.
#[derive(Debug)]
pub enum Presented {
    /// Shown; with the presented image read back when asked.
    Shown(Option<RgbaImage>),
    /// Nothing shown: the window is minimised, or the swapchain was out of date and has been
    /// remade (present again).
    Skipped,
    /// Nothing shown: the window is gone (`VK_ERROR_SURFACE_LOST_KHR`; Android takes an app's
    /// window away when it likes). Drop this swapchain; a new window needs a new one.
    Lost,
}

/// A window's surface and swapchain, with what one present needs.
pub struct Swapchain {
    dev: Arc<DeviceOwner>,
    surface_loader: ash::khr::surface::Instance,
    loader: ash::khr::swapchain::Device,
    surface: vk::SurfaceKHR,
    raw: vk::SwapchainKHR,
    images: Vec<vk::Image>,
    /// One per image: the copy into it signals, its present waits.
    rendered: Vec<Semaphore>,
    acquired: Semaphore,
    fence: Fence,
    _pool: CommandPool,
    cmd: vk::CommandBuffer,
    readback: Option<Buffer>,
    /// The window's size as last told.
    window_size: (u32, u32),
    /// Remake the swapchain before the next present (resized, or suboptimal).
    stale: bool,
    /// Where the last present put each source (top-left, bottom-right).
    placed: Vec<[vk::Offset3D; 2]>,
    pub format: vk::Format,
    pub extent: vk::Extent2D,
}

impl Swapchain {
    /// A swapchain for `window` of `display` (the display the `Gpu` was opened for), `size`
    /// pixels.
    ///
    /// # Safety
    /// The handles must be valid and the window must outlive the swapchain.
    pub unsafe fn new(
        gpu: &Gpu,
        display: RawDisplayHandle,
        window: RawWindowHandle,
        size: (u32, u32),
    ) -> Result<Self, GpuError> {
        let instance = &gpu.dev.instance;
        // SAFETY: the caller vouches for the handles; the instance has the surface extensions
        // (GpuOptions::display).
        let surface = unsafe {
            ash_window::create_surface(&instance.entry, &instance.instance, display, window, None)
        }
        .vk("vkCreate*SurfaceKHR")?;
        let surface_loader = ash::khr::surface::Instance::new(&instance.entry, &instance.instance);
        let supported = unsafe {
            surface_loader.get_physical_device_surface_support(
                gpu.physical,
                gpu.queue_family,
                surface,
            )
        };
        if supported != Ok(true) {
            unsafe { surface_loader.destroy_surface(surface, None) };
            return Err(GpuError::NoPresentation(format!(
                "{}'s graphics queue cannot present to this window",
                gpu.info().name
            )));
        }
        let pool = gpu.command_pool(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER)?;
        let cmd = gpu.allocate_command_buffer(&pool)?;
        let mut swapchain = Swapchain {
            dev: gpu.dev.clone(),
            surface_loader,
            loader: ash::khr::swapchain::Device::new(&instance.instance, gpu.device()),
            surface,
            raw: vk::SwapchainKHR::null(),
            images: Vec::new(),
            rendered: Vec::new(),
            acquired: semaphore(gpu)?,
            fence: gpu.fence()?,
            _pool: pool,
            cmd,
            readback: None,
            window_size: size,
            stale: true,
            placed: Vec::new(),
            format: vk::Format::UNDEFINED,
            extent: vk::Extent2D::default(),
        };
        swapchain.remake(gpu)?;
        Ok(swapchain)
    }

    /// The window is now `size` pixels: the swapchain is remade before the next present.
    pub fn resize(&mut self, size: (u32, u32)) {
        if size != self.window_size {
            self.window_size = size;
            self.stale = true;
        }
    }

    /// Which source the last present showed at window pixel (`x`, `y`), and where in it:
    /// normalised to -1..1, x right and y up (a gaze).
    pub fn locate(&self, x: f64, y: f64) -> Option<(usize, [f32; 2])> {
        self.placed.iter().enumerate().find_map(|(i, [a, b])| {
            let u = (x - a.x as f64) / (b.x - a.x) as f64;
            let v = (y - a.y as f64) / (b.y - a.y) as f64;
            ((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v))
                .then_some((i, [(u * 2.0 - 1.0) as f32, (1.0 - v * 2.0) as f32]))
        })
    }

    fn remake(&mut self, gpu: &Gpu) -> Result<(), GpuError> {
        let caps = unsafe {
            self.surface_loader
                .get_physical_device_surface_capabilities(gpu.physical, self.surface)
        }
        .vk("vkGetPhysicalDeviceSurfaceCapabilitiesKHR")?;
        // The surface decides its size unless it says u32::MAX (Wayland): then the window's.
        let extent = if caps.current_extent.width != u32::MAX {
            caps.current_extent
        } else {
            vk::Extent2D {
                width: self
                    .window_size
                    .0
                    .clamp(caps.min_image_extent.width, caps.max_image_extent.width),
                height: self
                    .window_size
                    .1
                    .clamp(caps.min_image_extent.height, caps.max_image_extent.height),
            }
        };
        gpu.wait_idle()?;
        if extent.width == 0 || extent.height == 0 {
            // Minimised: no swapchain until the window has pixels again.
            self.destroy_swapchain();
            self.extent = extent;
            self.stale = false;
            return Ok(());
        }
        let formats = unsafe {
            self.surface_loader
                .get_physical_device_surface_formats(gpu.physical, self.surface)
        }
        .vk("vkGetPhysicalDeviceSurfaceFormatsKHR")?;
        // sRGB like the frame's outputs, so a 1:1 blit copies their bytes unchanged.
        let format = formats
            .iter()
            .find(|f| {
                matches!(
                    f.format,
                    vk::Format::B8G8R8A8_SRGB | vk::Format::R8G8B8A8_SRGB
                ) && f.color_space == vk::ColorSpaceKHR::SRGB_NONLINEAR
            })
            .or(formats.first())
            .copied()
            .ok_or_else(|| GpuError::NoPresentation("the surface offers no format".into()))?;
        let wanted = vk::ImageUsageFlags::TRANSFER_DST | vk::ImageUsageFlags::TRANSFER_SRC;
        if !caps.supported_usage_flags.contains(wanted) {
            return Err(GpuError::NoPresentation(format!(
                "swapchain images cannot be transfer targets and sources (usage {:?})",
                caps.supported_usage_flags
            )));
        }
        let mut count = caps.min_image_count + 1;
        if caps.max_image_count > 0 {
            count = count.min(caps.max_image_count);
        }
        let alpha = [
            vk::CompositeAlphaFlagsKHR::OPAQUE,
            vk::CompositeAlphaFlagsKHR::INHERIT,
            vk::CompositeAlphaFlagsKHR::PRE_MULTIPLIED,
            vk::CompositeAlphaFlagsKHR::POST_MULTIPLIED,
        ]
        .into_iter()
        .find(|&a| caps.supported_composite_alpha.contains(a))
        .unwrap_or(vk::CompositeAlphaFlagsKHR::OPAQUE);
        let old = self.raw;
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(self.surface)
            .min_image_count(count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(wanted)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(caps.current_transform)
            .composite_alpha(alpha)
            // FIFO: the one mode every implementation offers.
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true)
            .old_swapchain(old);
        let raw =
            unsafe { self.loader.create_swapchain(&info, None) }.vk("vkCreateSwapchainKHR")?;
        self.destroy_swapchain();
        self.raw = raw;
        self.images =
            unsafe { self.loader.get_swapchain_images(raw) }.vk("vkGetSwapchainImagesKHR")?;
        self.rendered = (0..self.images.len())
            .map(|_| semaphore(gpu))
            .collect::<Result<_, _>>()?;
        self.format = format.format;
        self.extent = extent;
        self.stale = false;
        log::info!(
            "swapchain: {}x{} {:?}, {} images",
            extent.width,
            extent.height,
            format.format,
            self.images.len()
        );
        Ok(())
    }

    fn destroy_swapchain(&mut self) {
        if self.raw != vk::SwapchainKHR::null() {
            // SAFETY: the caller waited for the device: no present or copy uses it.
            unsafe { self.loader.destroy_swapchain(self.raw, None) };
            self.raw = vk::SwapchainKHR::null();
            self.images.clear();
            self.rendered.clear();
        }
    }

    /// Shows `sources` side by side, scaled to fit the window and centred on black; `capture`
    /// reads the presented image back.
    pub fn present(
        &mut self,
        gpu: &Gpu,
        sources: &[BlitSource],
        capture: bool,
    ) -> Result<Presented, GpuError> {
        match self.try_present(gpu, sources, capture) {
            Err(GpuError::Vk {
                call,
                result: vk::Result::ERROR_SURFACE_LOST_KHR,
            }) => {
                log::info!("swapchain: {call} says the window is gone");
                Ok(Presented::Lost)
            }
            presented => presented,
        }
    }

    fn try_present(
        &mut self,
        gpu: &Gpu,
        sources: &[BlitSource],
        capture: bool,
    ) -> Result<Presented, GpuError> {
        if self.stale {
            self.remake(gpu)?;
        }
        if self.raw == vk::SwapchainKHR::null() {
            return Ok(Presented::Skipped);
        }
        let acquired = unsafe {
            self.loader
                .acquire_next_image(self.raw, u64::MAX, self.acquired.raw, vk::Fence::null())
        };
        let index = match acquired {
            Ok((index, suboptimal)) => {
                self.stale |= suboptimal;
                index
            }
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                self.remake(gpu)?;
                return Ok(Presented::Skipped);
            }
            Err(e) => {
                return Err(GpuError::Vk {
                    call: "vkAcquireNextImageKHR",
                    result: e,
                })
            }
        };
        let image = self.images[index as usize];
        let bytes = 4 * self.extent.width as u64 * self.extent.height as u64;
        if capture && self.readback.as_ref().is_none_or(|b| b.size < bytes) {
            self.readback = Some(Buffer::new(
                gpu,
                "presented image readback",
                bytes,
                vk::BufferUsageFlags::TRANSFER_DST,
                MemoryLocation::GpuToCpu,
            )?);
        }
        let placements = fit_side_by_side(sources, self.extent);
        self.placed = placements.iter().map(|(_, d)| *d).collect();
        self.record(
            gpu,
            image,
            &placements,
            capture.then_some(()).and(self.readback.as_ref()),
        )?;
        let waits = [self.acquired.raw];
        let stages = [vk::PipelineStageFlags::TRANSFER];
        let cmds = [self.cmd];
        let signals = [self.rendered[index as usize].raw];
        let submit = [vk::SubmitInfo::default()
            .wait_semaphores(&waits)
            .wait_dst_stage_mask(&stages)
            .command_buffers(&cmds)
            .signal_semaphores(&signals)];
        gpu.with_queue(|queue| unsafe {
            gpu.device().queue_submit(queue, &submit, self.fence.raw)
        })
        .vk("vkQueueSubmit")?;
        gpu.wait(&self.fence)?;
        let swapchains = [self.raw];
        let indices = [index];
        let present = vk::PresentInfoKHR::default()
            .wait_semaphores(&signals)
            .swapchains(&swapchains)
            .image_indices(&indices);
        match gpu.with_queue(|queue| unsafe { self.loader.queue_present(queue, &present) }) {
            Ok(suboptimal) => self.stale |= suboptimal,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.stale = true,
            Err(e) => {
                return Err(GpuError::Vk {
                    call: "vkQueuePresentKHR",
                    result: e,
                })
            }
        }
        let captured = match (capture, &self.readback) {
            (true, Some(buffer)) => Some(self.captured(buffer)),
            _ => None,
        };
        Ok(Presented::Shown(captured))
    }

    /// The presented image from the readback buffer, as RGBA.
    fn captured(&self, buffer: &Buffer) -> RgbaImage {
        let (w, h) = (self.extent.width, self.extent.height);
        let mut data = buffer.mapped_slice()[..(4 * w * h) as usize].to_vec();
        if matches!(
            self.format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::B8G8R8A8_UNORM
        ) {
            data.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
        }
        RgbaImage {
            width: w,
            height: h,
            data,
        }
    }

    fn record(
        &self,
        gpu: &Gpu,
        image: vk::Image,
        placements: &[(BlitSource, [vk::Offset3D; 2])],
        readback: Option<&Buffer>,
    ) -> Result<(), GpuError> {
        let device = gpu.device();
        let cmd = self.cmd;
        let range = vk::ImageSubresourceRange {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            base_mip_level: 0,
            level_count: 1,
            base_array_layer: 0,
            layer_count: 1,
        };
        // SAFETY: recorded into this swapchain's command buffer, between begin and end.
        let barrier = |from: vk::ImageLayout,
                       to: vk::ImageLayout,
                       src: (vk::PipelineStageFlags, vk::AccessFlags),
                       dst: (vk::PipelineStageFlags, vk::AccessFlags)| unsafe {
            transition_image(
                device,
                cmd,
                image,
                range,
                (src.0, src.1, from),
                (dst.0, dst.1, to),
            )
        };
        let transfer_write = (
            vk::PipelineStageFlags::TRANSFER,
            vk::AccessFlags::TRANSFER_WRITE,
        );
        unsafe {
            device
                .reset_command_buffer(cmd, vk::CommandBufferResetFlags::empty())
                .vk("vkResetCommandBuffer")?;
            device
                .begin_command_buffer(
                    cmd,
                    &vk::CommandBufferBeginInfo::default()
                        .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT),
                )
                .vk("vkBeginCommandBuffer")?;
        }
        barrier(
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            (vk::PipelineStageFlags::TRANSFER, vk::AccessFlags::empty()),
            transfer_write,
        );
        unsafe {
            device.cmd_clear_color_image(
                cmd,
                image,
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                &vk::ClearColorValue {
                    float32: [0.0, 0.0, 0.0, 1.0],
                },
                &[range],
            );
        }
        barrier(
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            vk::ImageLayout::TRANSFER_DST_OPTIMAL,
            transfer_write,
            transfer_write,
        );
        for &(source, dst) in placements {
            let filter = if dst[1].x - dst[0].x == source.width as i32
                && dst[1].y - dst[0].y == source.height as i32
            {
                vk::Filter::NEAREST
            } else {
                vk::Filter::LINEAR
            };
            let layers = |layer| vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: layer,
                layer_count: 1,
            };
            let blit = vk::ImageBlit::default()
                .src_subresource(layers(source.layer))
                .src_offsets([
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
                ])
                .dst_subresource(layers(0))
                .dst_offsets(dst);
            unsafe {
                device.cmd_blit_image(
                    cmd,
                    source.image,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    image,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    &[blit],
                    filter,
                )
            };
        }
        let present_read = (
            vk::PipelineStageFlags::BOTTOM_OF_PIPE,
            vk::AccessFlags::empty(),
        );
        match readback {
            Some(buffer) => {
                barrier(
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    transfer_write,
                    (
                        vk::PipelineStageFlags::TRANSFER,
                        vk::AccessFlags::TRANSFER_READ,
                    ),
                );
                let region = vk::BufferImageCopy::default()
                    .image_subresource(vk::ImageSubresourceLayers {
                        aspect_mask: vk::ImageAspectFlags::COLOR,
                        mip_level: 0,
                        base_array_layer: 0,
                        layer_count: 1,
                    })
                    .image_extent(vk::Extent3D {
                        width: self.extent.width,
                        height: self.extent.height,
                        depth: 1,
                    });
                unsafe {
                    device.cmd_copy_image_to_buffer(
                        cmd,
                        image,
                        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                        buffer.raw,
                        &[region],
                    );
                    let host = vk::MemoryBarrier::default()
                        .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
                        .dst_access_mask(vk::AccessFlags::HOST_READ);
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
                barrier(
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    vk::ImageLayout::PRESENT_SRC_KHR,
                    (
                        vk::PipelineStageFlags::TRANSFER,
                        vk::AccessFlags::TRANSFER_READ,
                    ),
                    present_read,
                );
            }
            None => barrier(
                vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                vk::ImageLayout::PRESENT_SRC_KHR,
                transfer_write,
                present_read,
            ),
        }
        unsafe { device.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        // SAFETY: after the device is idle nothing uses the swapchain or surface; the surface
        // goes after its swapchain, and the instance outlives both (`dev` holds it).
        unsafe {
            let _ = self.dev.device.device_wait_idle();
        }
        self.destroy_swapchain();
        unsafe { self.surface_loader.destroy_surface(self.surface, None) };
    }
}

fn semaphore(gpu: &Gpu) -> Result<Semaphore, GpuError> {
    let raw = unsafe {
        gpu.device()
            .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
    }
    .vk("vkCreateSemaphore")?;
    Ok(Semaphore::from_raw(&gpu.dev, raw))
}
