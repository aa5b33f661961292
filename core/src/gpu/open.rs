//! A `Gpu` from a device: one foveate made ([`Gpu::new`], [`Gpu::with_creator`]) or one an
//! engine made and lends ([`Gpu::from_engine`]). Either way the same steps follow: the queue,
//! the allocator, the capabilities foveate plans with, the pipeline cache.

use std::collections::BTreeMap;
use std::ffi::CStr;
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

use ash::vk;
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};

use super::context::InstanceOwner;
use super::device_choice::{candidates, Candidate};
use super::pipeline_cache::{create_pipeline_cache, device_cache_file, PipelineCacheFile};
use super::{DeviceOwner, Gpu, GpuError, GpuOptions, VkResultExt, DEPTH_RESOLVE_EXTENSIONS};
use crate::vocab::DeviceCaps;

/// A Vulkan device an engine made, lent to foveate by [`Gpu::from_engine`]. foveate destroys
/// none of these handles.
#[derive(Clone, Debug)]
pub struct EngineDevice {
    /// The engine's instance.
    pub instance: vk::Instance,
    /// The physical device `device` was made on.
    pub physical: vk::PhysicalDevice,
    /// The engine's device.
    pub device: vk::Device,
    /// The queue foveate's own submissions go to (set-up uploads, readback, and
    /// a renderer's `render_frame`); a graphics queue.
    pub queue_family: u32,
    /// The queue's index in `queue_family`.
    pub queue_index: u32,
    /// The core features the engine enabled on `device`: foveate uses those of them it can use
    /// (fragment stores and atomics for counting frames, clip distances, depth clamp,
    /// anisotropy, pipeline statistics) and plans without the rest.
    pub enabled_features: vk::PhysicalDeviceFeatures,
    /// Whether the engine enabled `multiview` (Vulkan 1.1): foveate needs it.
    pub multiview: bool,
    /// Held by foveate around each use of the queue (`vkQueueSubmit`, `vkQueueWaitIdle`);
    /// the engine holds the same lock around its own uses, as Vulkan requires a queue's users
    /// to be synchronized.
    pub queue_lock: Arc<Mutex<()>>,
}

/// What the device is, beside its handle: where its queue is, what it has enabled, who owns it.
pub(super) struct DeviceParts {
    pub queue_family: u32,
    pub queue_index: u32,
    pub enabled: vk::PhysicalDeviceFeatures,
    /// The extensions a pass needs to resolve depth are enabled.
    pub depth_resolve: bool,
    /// `VK_KHR_pipeline_executable_properties` and its feature are enabled.
    pub statistics: bool,
    pub owned: bool,
    pub queue_lock: Arc<Mutex<()>>,
}

impl Gpu {
    /// A `Gpu` on a device the engine made: foveate allocates its own memory and objects on it
    /// and destroys them, never the instance, the device or the queue.
    ///
    /// Checks that the device can run foveate (Vulkan 1.1, a graphics queue, multiview
    /// supported and enabled): the error names what is missing. `options.pipeline_cache` is
    /// read and saved as for an owned device; `validation`, `device` and `display` are the
    /// engine's business and ignored.
    ///
    /// # Safety
    /// The handles are valid, `device` was made from `instance` on `physical` with
    /// `enabled_features` and `multiview` as stated and the queue (family, index) among its
    /// queues, all loaded by the system Vulkan loader; they outlive this `Gpu`, every clone of
    /// it and everything made with it.
    pub unsafe fn from_engine(
        engine: EngineDevice,
        options: &GpuOptions,
    ) -> Result<Self, GpuError> {
        // SAFETY: the caller's contract is this function's.
        unsafe { Self::from_engine_with_extensions(engine, &[], options) }
    }

    /// [`Gpu::from_engine`], told which device extensions the engine enabled on `device`
    /// (Vulkan has no query for them): foveate uses those it can use and plans without the
    /// rest. Today that is [`DEPTH_RESOLVE_EXTENSIONS`] (all, or none counts): with them a
    /// pass resolves its depth, which an accumulated periphery at more than one sample needs
    /// ([`DeviceCaps::depth_resolve`]). Others are ignored.
    ///
    /// A named extension the physical device does not offer is refused, naming it.
    ///
    /// # Safety
    /// As [`Gpu::from_engine`]; and every extension in `enabled_extensions` was enabled when
    /// `device` was made.
    pub unsafe fn from_engine_with_extensions(
        engine: EngineDevice,
        enabled_extensions: &[&CStr],
        options: &GpuOptions,
    ) -> Result<Self, GpuError> {
        // SAFETY: loading the system Vulkan loader library.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| GpuError::Loader(e.to_string()))?;
        // SAFETY: the caller vouches for the instance handle.
        let instance = unsafe { ash::Instance::load(entry.static_fn(), engine.instance) };
        let owner = Arc::new(InstanceOwner {
            entry,
            instance,
            messenger: None,
            owned: false,
        });
        let all = candidates(&owner.instance)?;
        let chosen = all
            .iter()
            .find(|c| c.physical == engine.physical)
            .ok_or(GpuError::NoDevice)?;
        let missing = |why: String| GpuError::Unusable {
            name: chosen.info.name.clone(),
            why,
        };
        if let Some(why) = &chosen.info.unusable {
            return Err(missing(why.clone()));
        }
        if !engine.multiview {
            return Err(missing(
                "EngineDevice.multiview is false: enable the `multiview` feature \
                 (VkPhysicalDeviceMultiviewFeatures) on the device"
                    .into(),
            ));
        }
        // SAFETY: a plain query on a valid physical device.
        let families = unsafe {
            owner
                .instance
                .get_physical_device_queue_family_properties(engine.physical)
        };
        let graphics = families
            .get(engine.queue_family as usize)
            .filter(|f| engine.queue_index < f.queue_count)
            .map(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS));
        match graphics {
            None => {
                return Err(missing(format!(
                    "EngineDevice.queue_family {} / queue_index {}: no such queue ({} families)",
                    engine.queue_family,
                    engine.queue_index,
                    families.len()
                )))
            }
            Some(false) => {
                return Err(missing(format!(
                    "EngineDevice.queue_family {} has no graphics queue",
                    engine.queue_family
                )))
            }
            Some(true) => {}
        }
        // SAFETY: a query on a valid physical device.
        let offered = unsafe {
            owner
                .instance
                .enumerate_device_extension_properties(engine.physical)
        }
        .vk("vkEnumerateDeviceExtensionProperties")?;
        if let Some(name) = enabled_extensions.iter().find(|&&name| {
            !offered
                .iter()
                .any(|e| e.extension_name_as_c_str() == Ok(name))
        }) {
            return Err(missing(format!(
                "enabled_extensions names {}, which the device does not offer",
                name.to_string_lossy()
            )));
        }
        let depth_resolve = DEPTH_RESOLVE_EXTENSIONS
            .iter()
            .all(|name| enabled_extensions.contains(name));
        // SAFETY: the caller vouches for the device handle.
        let device = unsafe { ash::Device::load(owner.instance.fp_v1_0(), engine.device) };
        let parts = DeviceParts {
            queue_family: engine.queue_family,
            queue_index: engine.queue_index,
            enabled: engine.enabled_features,
            depth_resolve,
            // An engine's device: whether it enabled the extension's feature is not told.
            statistics: false,
            owned: false,
            queue_lock: engine.queue_lock,
        };
        Self::assemble(owner, chosen, device, parts, options)
    }

    /// The `Gpu` around a created (or borrowed) device: its queue, allocator, capabilities
    /// and pipeline cache. An owned device is destroyed if this fails.
    pub(super) fn assemble(
        instance: Arc<InstanceOwner>,
        chosen: &Candidate,
        device: ash::Device,
        parts: DeviceParts,
        options: &GpuOptions,
    ) -> Result<Self, GpuError> {
        let physical = chosen.physical;
        let vk_instance = &instance.instance;
        // SAFETY: plain queries on a valid physical device and device.
        let (props, families, queue) = unsafe {
            (
                vk_instance.get_physical_device_properties(physical),
                vk_instance.get_physical_device_queue_family_properties(physical),
                device.get_device_queue(parts.queue_family, parts.queue_index),
            )
        };
        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: vk_instance.clone(),
            device: device.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: Default::default(),
        });
        let allocator = match allocator {
            Ok(a) => a,
            Err(e) => {
                if parts.owned {
                    // SAFETY: nothing was created on the device yet.
                    unsafe { device.destroy_device(None) };
                }
                return Err(e.into());
            }
        };
        let timestamps = props.limits.timestamp_compute_and_graphics == vk::TRUE
            || families[parts.queue_family as usize].timestamp_valid_bits > 0;
        let caps = device_caps(chosen, &props, &parts, timestamps);
        let render_pass2 = parts
            .depth_resolve
            .then(|| ash::khr::create_renderpass2::Device::new(vk_instance, &device));
        let executable_properties = parts
            .statistics
            .then(|| ash::khr::pipeline_executable_properties::Device::new(vk_instance, &device));
        log::info!(
            "device: {} ({:?}, driver {}{}); quirks: {:?}",
            chosen.info.name,
            props.device_type,
            chosen.info.driver,
            if parts.owned { "" } else { ", the engine's" },
            caps.quirks
        );
        let dev = Arc::new(DeviceOwner {
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            device,
            instance,
            live: Mutex::new(BTreeMap::new()),
            owned: parts.owned,
            lost: Mutex::new(super::lost::Loss::from_env()),
        });
        let cache_file = options
            .pipeline_cache
            .as_deref()
            .map(|p| device_cache_file(p, &props));
        let pipeline_cache = PipelineCacheFile {
            cache: create_pipeline_cache(&dev, &props, cache_file.as_deref())?,
            path: cache_file,
        };
        Ok(Gpu {
            dev,
            physical,
            queue,
            queue_index: parts.queue_index,
            queue_lock: parts.queue_lock,
            queue_family: parts.queue_family,
            timestamp_period_ns: props.limits.timestamp_period as f64,
            caps,
            info: chosen.info.clone(),
            render_passes: Arc::default(),
            pipelines: Arc::default(),
            pipeline_cache: Arc::new(pipeline_cache),
            render_pass2,
            executable_properties,
        })
    }

    /// Whether foveate made this device (and destroys it with the last handle), or borrows an
    /// engine's ([`Gpu::from_engine`]).
    pub fn owns_device(&self) -> bool {
        self.dev.owned
    }
}

/// What foveate plans with: the device's limits and the features enabled on it.
fn device_caps(
    chosen: &Candidate,
    props: &vk::PhysicalDeviceProperties,
    parts: &DeviceParts,
    timestamps: bool,
) -> DeviceCaps {
    let on = |f: vk::Bool32| f == vk::TRUE;
    let enabled = &parts.enabled;
    DeviceCaps {
        device_name: chosen.info.name.clone(),
        max_multiview_views: chosen.info.max_multiview_views,
        framebuffer_sample_counts: (props.limits.framebuffer_color_sample_counts
            & props.limits.framebuffer_depth_sample_counts)
            .as_raw(),
        max_image_dimension_2d: props.limits.max_image_dimension2_d,
        max_viewport_dimension: props.limits.max_viewport_dimensions[0]
            .min(props.limits.max_viewport_dimensions[1]),
        viewport_bounds: (
            props.limits.viewport_bounds_range[0],
            props.limits.viewport_bounds_range[1],
        ),
        lazily_allocated_memory: chosen.info.lazily_allocated_memory,
        fragment_stores_and_atomics: on(enabled.fragment_stores_and_atomics),
        shader_clip_distance: on(enabled.shader_clip_distance),
        depth_clamp: on(enabled.depth_clamp),
        timestamps,
        max_anisotropy: if on(enabled.sampler_anisotropy) {
            props.limits.max_sampler_anisotropy
        } else {
            0.0
        },
        pipeline_statistics: on(enabled.pipeline_statistics_query),
        depth_stencil: chosen.info.depth_stencil,
        depth_resolve: parts.depth_resolve,
        quirks: chosen.info.quirks.clone(),
    }
}
