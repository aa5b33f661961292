use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
pub use gpu_allocator::MemoryLocation;

use super::{DeviceOwner, Gpu, GpuError, ImageView, VkResultExt};

/// A buffer and its memory.
pub struct Buffer {
    dev: Arc<DeviceOwner>,
    pub raw: vk::Buffer,
    pub size: u64,
    allocation: Option<Allocation>,
}

impl Buffer {
    pub fn new(
        gpu: &Gpu,
        name: &str,
        size: u64,
        usage: vk::BufferUsageFlags,
        location: MemoryLocation,
    ) -> Result<Self, GpuError> {
        let dev = &gpu.dev;
        let info = vk::BufferCreateInfo::default()
            .size(size.max(4))
            .usage(usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE);
        // SAFETY: valid create info; the buffer is owned by the returned value.
        let raw = unsafe { dev.device.create_buffer(&info, None) }.vk("vkCreateBuffer")?;
        dev.created("Buffer");
        let mut buffer = Buffer {
            dev: dev.clone(),
            raw,
            size,
            allocation: None,
        };
        let requirements = unsafe { dev.device.get_buffer_memory_requirements(raw) };
        let allocation = lock(dev).allocate(&AllocationCreateDesc {
            name,
            requirements,
            location,
            linear: true,
            allocation_scheme: AllocationScheme::GpuAllocatorManaged,
        })?;
        unsafe {
            dev.device
                .bind_buffer_memory(raw, allocation.memory(), allocation.offset())
        }
        .vk("vkBindBufferMemory")?;
        buffer.allocation = Some(allocation);
        Ok(buffer)
    }

    /// The mapped bytes of a host-visible buffer.
    pub fn mapped(&mut self) -> &mut [u8] {
        self.allocation
            .as_mut()
            .and_then(|a| a.mapped_slice_mut())
            .expect("buffer was allocated in host-visible memory")
    }

    /// The mapped bytes of a host-visible buffer, to read.
    pub fn mapped_slice(&self) -> &[u8] {
        self.allocation
            .as_ref()
            .and_then(|a| a.mapped_slice())
            .expect("buffer was allocated in host-visible memory")
    }

    /// Copies plain-old-data values into a host-visible buffer.
    pub fn write<T: Copy>(&mut self, values: &[T]) {
        let bytes = pod_bytes(values);
        self.mapped()[..bytes.len()].copy_from_slice(bytes);
    }

    /// Reads `u32`s out of a host-visible buffer.
    pub fn read_u32s(&mut self, count: usize) -> Vec<u32> {
        self.mapped()[..count * 4]
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .collect()
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        // SAFETY: owned handle; users keep buffers alive until GPU work using them completed.
        unsafe { self.dev.device.destroy_buffer(self.raw, None) };
        self.dev.destroyed("Buffer");
        if let Some(a) = self.allocation.take() {
            let _ = lock(&self.dev).free(a);
        }
    }
}

/// The bytes of a slice of plain-old-data values (`#[repr(C)]` structs of floats and ints).
pub(crate) fn pod_bytes<T: Copy>(values: &[T]) -> &[u8] {
    // SAFETY: T is Copy and used only with repr(C) types without padding-sensitive invariants;
    // reading their bytes is sound.
    unsafe {
        std::slice::from_raw_parts(values.as_ptr().cast::<u8>(), std::mem::size_of_val(values))
    }
}

fn lock(dev: &DeviceOwner) -> std::sync::MutexGuard<'_, gpu_allocator::vulkan::Allocator> {
    // A panic while holding the allocator lock leaves it usable: its state is updated
    // atomically per call.
    dev.allocator.lock().unwrap_or_else(|e| e.into_inner())
}

enum ImageMemory {
    Allocator(Allocation),
    /// A dedicated lazily allocated block (tile GPUs: may never get physical pages).
    Lazy(vk::DeviceMemory),
}

/// A 2D (array) image and its memory.
pub struct Image {
    dev: Arc<DeviceOwner>,
    pub(crate) raw: vk::Image,
    pub(crate) format: vk::Format,
    pub(crate) width: u32,
    pub(crate) height: u32,
    pub(crate) layers: u32,
    pub(crate) samples: u32,
    pub(crate) mip_levels: u32,
    pub(crate) aspect: vk::ImageAspectFlags,
    /// Whether its memory is lazily allocated.
    pub(crate) lazy: bool,
    memory: Option<ImageMemory>,
    /// Someone else's image (an OpenXR swapchain's): viewed and rendered to, never destroyed.
    borrowed: bool,
}

/// What to create an image with.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ImageDesc<'a> {
    /// Its debug label.
    pub name: &'a str,
    /// Its format.
    pub format: vk::Format,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Array layers.
    pub layers: u32,
    /// Samples per pixel.
    pub samples: u32,
    /// Mip levels (1 for attachments; a full chain for textures).
    pub mip_levels: u32,
    /// What it will be used for.
    pub usage: vk::ImageUsageFlags,
}

impl Image {
    /// The Vulkan image, to hand to `render::FrameInput::with_output` or to record
    /// with; it stays valid while this value lives.
    pub fn raw(&self) -> vk::Image {
        self.raw
    }

    /// Width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.width, self.height)
    }

    /// Samples per pixel.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// Creates an image; a `TRANSIENT_ATTACHMENT` image goes into lazily allocated memory when
    /// the device has it (tile GPUs), else into ordinary device-local memory.
    pub fn new(gpu: &Gpu, desc: &ImageDesc<'_>) -> Result<Self, GpuError> {
        let dev = &gpu.dev;
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D {
                width: desc.width,
                height: desc.height,
                depth: 1,
            })
            .mip_levels(desc.mip_levels)
            .array_layers(desc.layers)
            .samples(vk::SampleCountFlags::from_raw(desc.samples))
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .sharing_mode(vk::SharingMode::EXCLUSIVE)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: valid create info; the image is owned by the returned value.
        let raw = unsafe { dev.device.create_image(&info, None) }.vk("vkCreateImage")?;
        let aspect = aspect_of(desc.format);
        dev.created("Image");
        let mut image = Image::described(gpu, raw, desc, aspect, false);
        let requirements = unsafe { dev.device.get_image_memory_requirements(raw) };
        let lazy_type = desc
            .usage
            .contains(vk::ImageUsageFlags::TRANSIENT_ATTACHMENT)
            .then(|| lazy_memory_type(gpu, requirements.memory_type_bits))
            .flatten();
        let (memory, offset, kind) = match lazy_type {
            Some(type_index) => {
                let alloc = vk::MemoryAllocateInfo::default()
                    .allocation_size(requirements.size)
                    .memory_type_index(type_index);
                let memory =
                    unsafe { dev.device.allocate_memory(&alloc, None) }.vk("vkAllocateMemory")?;
                dev.created("LazyMemory");
                (memory, 0, ImageMemory::Lazy(memory))
            }
            None => {
                let a = lock(dev).allocate(&AllocationCreateDesc {
                    name: desc.name,
                    requirements,
                    location: MemoryLocation::GpuOnly,
                    linear: false,
                    allocation_scheme: AllocationScheme::GpuAllocatorManaged,
                })?;
                (unsafe { a.memory() }, a.offset(), ImageMemory::Allocator(a))
            }
        };
        image.lazy = matches!(kind, ImageMemory::Lazy(_));
        image.memory = Some(kind);
        unsafe { dev.device.bind_image_memory(raw, memory, offset) }.vk("vkBindImageMemory")?;
        Ok(image)
    }

    /// Someone else's image (an OpenXR runtime's swapchain image, an engine's render target)
    /// described by `desc`, to view and render to; dropping it destroys nothing.
    ///
    /// # Safety
    /// `raw` must be an image of `gpu`'s device made as `desc` says, alive while this value is.
    pub unsafe fn borrowed(gpu: &Gpu, raw: vk::Image, desc: &ImageDesc<'_>) -> Self {
        Image::described(gpu, raw, desc, aspect_of(desc.format), true)
    }

    /// `raw` as `desc` describes it, with no memory bound yet.
    fn described(
        gpu: &Gpu,
        raw: vk::Image,
        desc: &ImageDesc<'_>,
        aspect: vk::ImageAspectFlags,
        borrowed: bool,
    ) -> Self {
        Image {
            dev: gpu.dev.clone(),
            raw,
            format: desc.format,
            width: desc.width,
            height: desc.height,
            layers: desc.layers,
            samples: desc.samples,
            mip_levels: desc.mip_levels,
            aspect,
            lazy: false,
            memory: None,
            borrowed,
        }
    }

    /// A view of `count` layers from `base`: 2D for one layer, 2D array otherwise (multiview
    /// framebuffers need the array view even when the image has exactly its views' layers).
    pub(crate) fn view(&self, base: u32, count: u32, array: bool) -> Result<ImageView, GpuError> {
        self.view_of(self.aspect, base, count, array)
    }

    /// A view for sampling: like [`Image::view`], but of the depth alone in a depth/stencil
    /// image (a sampled view has one aspect).
    pub(crate) fn sampled_view(
        &self,
        base: u32,
        count: u32,
        array: bool,
    ) -> Result<ImageView, GpuError> {
        let aspect = if self.aspect.contains(vk::ImageAspectFlags::DEPTH) {
            vk::ImageAspectFlags::DEPTH
        } else {
            self.aspect
        };
        self.view_of(aspect, base, count, array)
    }

    fn view_of(
        &self,
        aspect: vk::ImageAspectFlags,
        base: u32,
        count: u32,
        array: bool,
    ) -> Result<ImageView, GpuError> {
        let view_type = if array {
            vk::ImageViewType::TYPE_2D_ARRAY
        } else {
            vk::ImageViewType::TYPE_2D
        };
        let info = vk::ImageViewCreateInfo::default()
            .image(self.raw)
            .view_type(view_type)
            .format(self.format)
            .subresource_range(vk::ImageSubresourceRange {
                aspect_mask: aspect,
                ..self.range(base, count)
            });
        let raw =
            unsafe { self.dev.device.create_image_view(&info, None) }.vk("vkCreateImageView")?;
        Ok(ImageView::from_raw(&self.dev, raw))
    }

    pub(crate) fn range(&self, base_layer: u32, layer_count: u32) -> vk::ImageSubresourceRange {
        vk::ImageSubresourceRange {
            aspect_mask: self.aspect,
            base_mip_level: 0,
            level_count: self.mip_levels,
            base_array_layer: base_layer,
            layer_count,
        }
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        if self.borrowed {
            return;
        }
        // SAFETY: owned handle; views die before (they are separate owned values whose users
        // drop them first) and GPU work using the image has completed.
        unsafe { self.dev.device.destroy_image(self.raw, None) };
        self.dev.destroyed("Image");
        match self.memory.take() {
            Some(ImageMemory::Allocator(a)) => {
                let _ = lock(&self.dev).free(a);
            }
            Some(ImageMemory::Lazy(m)) => {
                unsafe { self.dev.device.free_memory(m, None) };
                self.dev.destroyed("LazyMemory");
            }
            None => {}
        }
    }
}

pub(crate) fn is_depth_format(format: vk::Format) -> bool {
    matches!(
        format,
        vk::Format::D32_SFLOAT | vk::Format::D32_SFLOAT_S8_UINT | vk::Format::D24_UNORM_S8_UINT
    )
}

fn lazy_memory_type(gpu: &Gpu, type_bits: u32) -> Option<u32> {
    let props = unsafe {
        gpu.instance()
            .get_physical_device_memory_properties(gpu.physical)
    };
    (0..props.memory_type_count).find(|&i| {
        type_bits & (1 << i) != 0
            && props.memory_types[i as usize]
                .property_flags
                .contains(vk::MemoryPropertyFlags::LAZILY_ALLOCATED)
    })
}

/// The aspects of an image of `format`: depth (and stencil), or colour.
fn aspect_of(format: vk::Format) -> vk::ImageAspectFlags {
    if !is_depth_format(format) {
        return vk::ImageAspectFlags::COLOR;
    }
    match format {
        vk::Format::D32_SFLOAT_S8_UINT => {
            vk::ImageAspectFlags::DEPTH | vk::ImageAspectFlags::STENCIL
        }
        _ => vk::ImageAspectFlags::DEPTH,
    }
}
