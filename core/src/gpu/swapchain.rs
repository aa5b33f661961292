//! Presenting to a window: a surface on any platform `ash-window` knows (X11, Wayland, Android's
//! `ANativeWindow`, …) and its swapchain. A frame shows in three steps that fit frames in
//! flight: [`Swapchain::acquire`] an image, [`Swapchain::record_copy`] of the frame's output
//! images side by side (scaled to fit and centred) into the frame's own command buffer, and
//! [`Swapchain::present`] after the caller submitted it with the image's semaphores.

use ash::vk;
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use super::blit_layout::{fit_side_by_side, BlitSource};
use super::present_copy::{record_copy, CopyTarget};
use super::{Buffer, Gpu, GpuError, MemoryLocation, Semaphore, VkResultExt};
use crate::vocab::RgbaImage;

/// What acquiring an image gave.
#[derive(Debug)]
pub enum Acquired {
    /// An image to copy the frame into and present.
    Image(SwapchainImage),
    /// No image: the window is minimised, or the swapchain was out of date and has been
    /// remade (acquire again next frame).
    Skipped,
    /// No image: the window is gone (`VK_ERROR_SURFACE_LOST_KHR`; Android takes an app's
    /// window away when it likes). Drop this swapchain; a new window needs a new one.
    Lost,
}

/// An acquired swapchain image: the frame's submission waits for [`SwapchainImage::waits`]
/// and signals [`SwapchainImage::signals`], then [`Swapchain::present`] shows it.
#[derive(Debug)]
#[must_use = "an acquired image is presented with Swapchain::present"]
pub struct SwapchainImage {
    index: u32,
    /// Signalled by the acquire.
    acquired: vk::Semaphore,
    /// Signalled by the frame's submission, waited for by the present.
    rendered: vk::Semaphore,
}

impl SwapchainImage {
    /// What the frame's submission waits for: the acquire, before its copy writes the image.
    pub fn waits(&self) -> [(vk::Semaphore, vk::PipelineStageFlags); 1] {
        [(self.acquired, vk::PipelineStageFlags::TRANSFER)]
    }

    /// What the frame's submission signals: the present waits for it.
    pub fn signals(&self) -> [vk::Semaphore; 1] {
        [self.rendered]
    }
}

/// What a present did.
#[derive(Debug, PartialEq, Eq)]
pub enum Presented {
    /// Queued for display.
    Shown,
    /// Nothing shown: the window is gone (see [`Acquired::Lost`]).
    Lost,
}

/// A window's surface and swapchain, with what one present needs.
pub struct Swapchain {
    dev: std::sync::Arc<super::DeviceOwner>,
    surface_loader: ash::khr::surface::Instance,
    loader: ash::khr::swapchain::Device,
    surface: vk::SurfaceKHR,
    raw: vk::SwapchainKHR,
    images: Vec<vk::Image>,
    /// One per image: the frame's submission signals, its present waits.
    rendered: Vec<Semaphore>,
    /// One per frame slot: the acquire signals, the frame's submission waits.
    acquired: Vec<Semaphore>,
    readback: Option<Buffer>,
    /// The size of the image the last capturing copy wrote.
    captured_extent: Option<vk::Extent2D>,
    /// The window's size as last told.
    window_size: (u32, u32),
    /// Remake the swapchain before the next acquire (resized, or suboptimal).
    stale: bool,
    /// Where the last copy put each source (top-left, bottom-right).
    placed: Vec<[vk::Offset3D; 2]>,
    /// The swapchain images' format.
    pub format: vk::Format,
    /// The swapchain images' size.
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
        let mut swapchain = Swapchain {
            dev: gpu.dev.clone(),
            surface_loader,
            loader: ash::khr::swapchain::Device::new(&instance.instance, gpu.device()),
            surface,
            raw: vk::SwapchainKHR::null(),
            images: Vec::new(),
            rendered: Vec::new(),
            acquired: Vec::new(),
            readback: None,
            captured_extent: None,
            window_size: size,
            stale: true,
            placed: Vec::new(),
            format: vk::Format::UNDEFINED,
            extent: vk::Extent2D::default(),
        };
        swapchain.remake(gpu)?;
        Ok(swapchain)
    }

    /// The window is now `size` pixels: the swapchain is remade before the next acquire.
    pub fn resize(&mut self, size: (u32, u32)) {
        if size != self.window_size {
            self.window_size = size;
            self.stale = true;
        }
    }

    /// Which source the last copy put at window pixel (`x`, `y`), and where in it:
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

    /// Acquires the next image to show a frame in, for the frame in frame slot `slot` (each
    /// slot has its own acquire semaphore). Remakes the swapchain first when the window
    /// changed.
    ///
    /// # Safety
    /// The frame that last acquired with `slot` has finished on the GPU (its fence waited on:
    /// `render::FramesInFlight::begin` does it), and its submission waited for the
    /// image's [`SwapchainImage::waits`] (an acquire's semaphore that nothing waited for is
    /// still signalled, and cannot be acquired with again).
    pub unsafe fn acquire(&mut self, gpu: &Gpu, slot: usize) -> Result<Acquired, GpuError> {
        match unsafe { self.try_acquire(gpu, slot) } {
            Err(GpuError::Vk {
                call,
                result: vk::Result::ERROR_SURFACE_LOST_KHR,
            }) => {
                log::info!("swapchain: {call} says the window is gone");
                Ok(Acquired::Lost)
            }
            acquired => acquired,
        }
    }

    unsafe fn try_acquire(&mut self, gpu: &Gpu, slot: usize) -> Result<Acquired, GpuError> {
        if self.stale {
            self.remake(gpu)?;
        }
        if self.raw == vk::SwapchainKHR::null() {
            return Ok(Acquired::Skipped);
        }
        while self.acquired.len() <= slot {
            self.acquired.push(semaphore(gpu)?);
        }
        let signal = self.acquired[slot].raw;
        let acquired = unsafe {
            self.loader
                .acquire_next_image(self.raw, u64::MAX, signal, vk::Fence::null())
        };
        let index = match acquired {
            Ok((index, suboptimal)) => {
                self.stale |= suboptimal;
                index
            }
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                self.remake(gpu)?;
                return Ok(Acquired::Skipped);
            }
            Err(result) => {
                return Err(GpuError::Vk {
                    call: "vkAcquireNextImageKHR",
                    result,
                })
            }
        };
        Ok(Acquired::Image(SwapchainImage {
            index,
            acquired: signal,
            rendered: self.rendered[index as usize].raw,
        }))
    }

    /// Records into `cmd` the copy of `sources` side by side into `image`, scaled to fit the
    /// window and centred on black; `capture` also copies the result into a buffer that
    /// [`Swapchain::captured`] reads once the frame finished. Submit `cmd` waiting for
    /// [`SwapchainImage::waits`] and signalling [`SwapchainImage::signals`].
    ///
    /// # Safety
    /// `cmd` is a command buffer of this device, recording outside a render pass; the sources
    /// are in `TRANSFER_SRC_OPTIMAL` (a renderer's `render::Renderer::present_sources`,
    /// recorded before into the same buffer) and outlive its execution.
    pub unsafe fn record_copy(
        &mut self,
        gpu: &Gpu,
        cmd: vk::CommandBuffer,
        image: &SwapchainImage,
        sources: &[BlitSource],
        capture: bool,
    ) -> Result<(), GpuError> {
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
        self.captured_extent = capture.then_some(self.extent);
        let placements = fit_side_by_side(sources, self.extent);
        self.placed = placements.iter().map(|(_, d)| *d).collect();
        let target = CopyTarget {
            image: self.images[image.index as usize],
            extent: self.extent,
            placements: &placements,
            readback: self.readback.as_ref().filter(|_| capture),
        };
        // SAFETY: as this function's.
        unsafe { record_copy(gpu.device(), cmd, &target) };
        Ok(())
    }

    /// Shows `image` once the submission that signals its [`SwapchainImage::signals`] has run.
    pub fn present(&mut self, gpu: &Gpu, image: SwapchainImage) -> Result<Presented, GpuError> {
        let swapchains = [self.raw];
        let indices = [image.index];
        let waits = [image.rendered];
        let present = vk::PresentInfoKHR::default()
            .wait_semaphores(&waits)
            .swapchains(&swapchains)
            .image_indices(&indices);
        match gpu.with_queue(|queue| unsafe { self.loader.queue_present(queue, &present) }) {
            Ok(suboptimal) => self.stale |= suboptimal,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.stale = true,
            Err(vk::Result::ERROR_SURFACE_LOST_KHR) => {
                log::info!("swapchain: vkQueuePresentKHR says the window is gone");
                return Ok(Presented::Lost);
            }
            Err(result) => {
                return Err(GpuError::Vk {
                    call: "vkQueuePresentKHR",
                    result,
                })
            }
        }
        Ok(Presented::Shown)
    }

    /// The image the last copy recorded with `capture` wrote, as RGBA; read it after that
    /// frame finished (its fence). `None` when no copy captured.
    pub fn captured(&self) -> Option<RgbaImage> {
        let (buffer, extent) = (self.readback.as_ref()?, self.captured_extent?);
        let (w, h) = (extent.width, extent.height);
        let mut data = buffer.mapped_slice()[..(4 * w * h) as usize].to_vec();
        if matches!(
            self.format,
            vk::Format::B8G8R8A8_SRGB | vk::Format::B8G8R8A8_UNORM
        ) {
            data.chunks_exact_mut(4).for_each(|p| p.swap(0, 2));
        }
        Some(RgbaImage {
            width: w,
            height: h,
            data,
        })
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
