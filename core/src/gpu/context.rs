use std::collections::BTreeMap;
use std::ffi::{c_void, CStr, CString};
use std::mem::ManuallyDrop;
use std::sync::{Arc, Mutex};

use ash::vk;
use gpu_allocator::vulkan::Allocator;

use super::device_choice::{candidates, choose};
use super::open::DeviceParts;
use super::pipeline_cache::PipelineCacheFile;
use super::shader_statistics;
use super::{GpuError, ObjectCache, Pipeline, PipelineKey, RenderPass, VkResultExt};
use crate::vocab::{DeviceCaps, DriverQuirks};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// How to open the GPU.
#[derive(Clone, Debug, Default)]
pub struct GpuOptions {
    /// Enable `VK_LAYER_KHRONOS_validation` and collect its messages.
    pub validation: bool,
    /// Pick a device by index or by (case-insensitive) part of its name instead of the best.
    pub device: Option<String>,
    /// Where the pipeline cache persists between runs (`Gpu::save_pipeline_cache` writes it):
    /// each device keeps its own file, this name with the device's identity before the
    /// extension (`pipelines.bin`: `pipelines-10005-0000-1a2b3c4d.bin`); `None` keeps it in
    /// memory for this run only.
    pub pipeline_cache: Option<std::path::PathBuf>,
    /// Present to windows of this display: the instance gets its surface extensions and the
    /// device `VK_KHR_swapchain` (see [`super::Swapchain`]). `None`: headless.
    pub display: Option<raw_window_handle::RawDisplayHandle>,
}

impl GpuOptions {
    /// Options from the environment: `FOVEATE_VALIDATION=1` and `FOVEATE_DEVICE=<index|name>`.
    pub fn from_env() -> Self {
        Self {
            validation: std::env::var("FOVEATE_VALIDATION")
                .is_ok_and(|v| v != "0" && !v.is_empty()),
            device: std::env::var("FOVEATE_DEVICE")
                .ok()
                .filter(|d| !d.is_empty()),
            pipeline_cache: None,
            display: None,
        }
    }
}

/// Who makes the Vulkan instance and device and picks the physical device, when foveate must
/// not do it alone: an OpenXR runtime (`XR_KHR_vulkan_enable2`) adds the instance and device
/// extensions it needs to share images with its compositor, and chooses the GPU the headset is
/// on. Given foveate's create infos (layers, extensions, features, validation), it answers with
/// the handles it made from them.
pub trait VulkanCreator {
    /// `vkCreateInstance` with `info`, plus what the creator needs.
    ///
    /// # Safety
    /// `info` must be a valid create info.
    unsafe fn create_instance(
        &self,
        entry: &ash::Entry,
        info: &vk::InstanceCreateInfo,
    ) -> Result<vk::Instance, GpuError>;

    /// The physical device to render on.
    ///
    /// # Safety
    /// `instance` must come from [`VulkanCreator::create_instance`].
    unsafe fn physical_device(
        &self,
        instance: vk::Instance,
    ) -> Result<vk::PhysicalDevice, GpuError>;

    /// `vkCreateDevice` on `physical` with `info`, plus what the creator needs.
    ///
    /// # Safety
    /// `info` must be a valid create info for `physical`.
    unsafe fn create_device(
        &self,
        entry: &ash::Entry,
        physical: vk::PhysicalDevice,
        info: &vk::DeviceCreateInfo,
    ) -> Result<vk::Device, GpuError>;
}

/// Validation messages the debug messenger collected, for the owner to inspect.
#[derive(Default)]
struct ValidationLog {
    messages: Mutex<Vec<String>>,
}

unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    let relevant = severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
        || (severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING)
            && kind.contains(vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION));
    if relevant && !data.is_null() && !user.is_null() {
        // SAFETY: the loader passes valid callback data; `user` is the boxed log owned by the
        // instance, which outlives the messenger.
        let (data, log) = unsafe { (&*data, &*(user as *const ValidationLog)) };
        let text = unsafe { data.message_as_c_str() }
            .map(|m| m.to_string_lossy().into_owned())
            .unwrap_or_default();
        log::warn!("validation [{severity:?}]: {text}");
        if let Ok(mut messages) = log.messages.lock() {
            messages.push(format!("[{severity:?}] {text}"));
        }
    }
    vk::FALSE
}

pub(super) struct Messenger {
    loader: ash::ext::debug_utils::Instance,
    raw: vk::DebugUtilsMessengerEXT,
    log: Box<ValidationLog>,
}

/// Owns the instance and the debug messenger.
pub(crate) struct InstanceOwner {
    pub(crate) entry: ash::Entry,
    pub(crate) instance: ash::Instance,
    pub(super) messenger: Option<Messenger>,
    /// Whether foveate made the instance (and destroys it); an engine's is only borrowed.
    pub(crate) owned: bool,
}

impl Drop for InstanceOwner {
    fn drop(&mut self) {
        // SAFETY: every device and object of this instance has been destroyed: devices hold an
        // Arc to this owner.
        unsafe {
            if let Some(m) = self.messenger.take() {
                m.loader.destroy_debug_utils_messenger(m.raw, None);
            }
            if self.owned {
                self.instance.destroy_instance(None);
            }
        }
    }
}

impl InstanceOwner {
    fn new(
        options: &GpuOptions,
        creator: Option<&dyn VulkanCreator>,
    ) -> Result<Arc<Self>, GpuError> {
        // SAFETY: loading the system Vulkan loader library.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| GpuError::Loader(e.to_string()))?;
        let mut layers = Vec::new();
        let mut extensions = Vec::new();
        if options.validation {
            let available = unsafe { entry.enumerate_instance_layer_properties() }
                .vk("vkEnumerateInstanceLayerProperties")?;
            if !available
                .iter()
                .any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER))
            {
                return Err(GpuError::NoValidationLayer);
            }
            layers.push(VALIDATION_LAYER.as_ptr());
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
        }
        if let Some(display) = options.display {
            extensions.extend_from_slice(
                ash_window::enumerate_required_extensions(display)
                    .vk("vkEnumerateInstanceExtensionProperties (surface)")?,
            );
        }
        let app_name = CString::new("foveate").expect("no NUL in literal");
        let app = vk::ApplicationInfo::default()
            .application_name(&app_name)
            .engine_name(&app_name)
            .api_version(vk::API_VERSION_1_1);
        // Synchronization validation (hazards between commands, passes and submissions) and
        // best-practices checks on top of the core checks: any message they raise fails the
        // caller. VK_EXT_validation_features is the layer's own extension, offered by every
        // layer version since 1.2 (newer ones also read it as layer settings).
        // Best practices judge style, not correctness: on a device an OpenXR runtime made, they
        // judge the runtime's own choices (the promoted extensions it enables, the barriers its
        // compositor records on its images), which no application can change, so there only
        // the core and synchronization checks run.
        let all_checks = [
            vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION,
            vk::ValidationFeatureEnableEXT::BEST_PRACTICES,
        ];
        let checks = if creator.is_some() {
            &all_checks[..1]
        } else {
            &all_checks[..]
        };
        let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(checks);
        if options.validation {
            extensions.push(ash::ext::validation_features::NAME.as_ptr());
        }
        let info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&extensions);
        let info = if options.validation {
            info.push_next(&mut features)
        } else {
            info
        };
        // SAFETY: the create info only points at locals that outlive the call; a creator's
        // instance is loaded from the same loader.
        let instance = match creator {
            None => unsafe { entry.create_instance(&info, None) }.vk("vkCreateInstance")?,
            Some(c) => unsafe {
                let raw = c.create_instance(&entry, &info)?;
                ash::Instance::load(entry.static_fn(), raw)
            },
        };
        let mut owner = InstanceOwner {
            entry,
            instance,
            messenger: None,
            owned: true,
        };
        if options.validation {
            let log = Box::<ValidationLog>::default();
            let loader = ash::ext::debug_utils::Instance::new(&owner.entry, &owner.instance);
            let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
                .message_severity(
                    vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                        | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
                )
                .message_type(
                    vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                        | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                        | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
                )
                .pfn_user_callback(Some(debug_callback))
                .user_data(&*log as *const ValidationLog as *mut c_void);
            // SAFETY: `log` is boxed and lives in the owner as long as the messenger.
            let raw = unsafe { loader.create_debug_utils_messenger(&info, None) }
                .vk("vkCreateDebugUtilsMessengerEXT")?;
            owner.messenger = Some(Messenger { loader, raw, log });
        }
        Ok(Arc::new(owner))
    }
}

/// Owns the logical device and the allocator; every resource holds an `Arc` to it, so the
/// device is destroyed only after the last resource.
pub(crate) struct DeviceOwner {
    pub(crate) allocator: ManuallyDrop<Mutex<Allocator>>,
    pub(crate) device: ash::Device,
    pub(crate) instance: Arc<InstanceOwner>,
    /// Vulkan objects alive now, by kind: what a renderer creates is counted, not assumed.
    pub(super) live: Mutex<BTreeMap<&'static str, i64>>,
    /// Whether foveate made the device (and destroys it); an engine's is only borrowed.
    pub(super) owned: bool,
    /// The call that found the device lost, once one has (`gpu/lost.rs`).
    pub(super) lost: Mutex<super::lost::Loss>,
}

impl DeviceOwner {
    /// One more live object of `kind` (each owning wrapper calls this once, at construction).
    pub(crate) fn created(&self, kind: &'static str) {
        if let Ok(mut live) = self.live.lock() {
            *live.entry(kind).or_default() += 1;
        }
    }

    /// One fewer live object of `kind` (the owning wrapper's `Drop`).
    pub(crate) fn destroyed(&self, kind: &'static str) {
        if let Ok(mut live) = self.live.lock() {
            *live.entry(kind).or_default() -= 1;
        }
    }
}

impl Drop for DeviceOwner {
    fn drop(&mut self) {
        // SAFETY: no resource of this device remains (they hold Arcs to it); the allocator
        // frees its memory blocks before the device goes. A borrowed device is the engine's:
        // its queues are the engine's to synchronize (no wait idle here) and it stays.
        unsafe {
            if self.owned {
                let _ = self.device.device_wait_idle();
            }
            ManuallyDrop::drop(&mut self.allocator);
            if self.owned {
                self.device.destroy_device(None);
            }
        }
    }
}

/// What `foveate devices` prints about a physical device.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    /// Its index in the instance's device list (what `--device` takes).
    pub index: usize,
    /// The device's name.
    pub name: String,
    /// Integrated, discrete, virtual or CPU.
    pub device_type: String,
    /// The Vulkan version it supports.
    pub api_version: String,
    /// The driver's name and version.
    pub driver: String,
    /// The most views one multiview pass may have.
    pub max_multiview_views: u32,
    /// Sample counts a colour and depth attachment both support.
    pub sample_counts: Vec<u32>,
    /// Whether it offers `VK_EXT_fragment_density_map`.
    pub fragment_density_map: bool,
    /// Whether it offers `VK_KHR_fragment_shading_rate`.
    pub fragment_shading_rate: bool,
    /// Whether it has lazily allocated memory (tile GPUs: attachments that may live on tile only).
    pub lazily_allocated_memory: bool,
    /// `D32_SFLOAT_S8_UINT` as a depth-stencil attachment (stencil masks need it).
    pub depth_stencil: bool,
    /// What its driver gets wrong, from the driver's ID and version.
    pub quirks: DriverQuirks,
    /// Why foveate cannot use it, if it cannot.
    pub unusable: Option<String>,
}

/// Raw handles of an opened [`Gpu`], for an OpenXR session's graphics binding.
#[derive(Clone, Copy, Debug)]
pub struct RawHandles {
    /// The instance.
    pub instance: vk::Instance,
    /// The physical device.
    pub physical: vk::PhysicalDevice,
    /// The logical device.
    pub device: vk::Device,
    /// The queue family foveate submits to.
    pub queue_family: u32,
    /// The queue's index in its family.
    pub queue_index: u32,
}

/// The opened GPU: device, graphics queue, capabilities.
///
/// A `Gpu` is a handle: cloning it is cheap and gives another handle to the same device, so a
/// renderer keeps one and has no borrow to outlive. The device goes when the
/// last handle and the last object made on it are gone (a borrowed device is never destroyed:
/// see [`Gpu::from_engine`]).
#[derive(Clone)]
pub struct Gpu {
    pub(crate) dev: Arc<DeviceOwner>,
    pub(crate) physical: vk::PhysicalDevice,
    pub(crate) queue: vk::Queue,
    pub(crate) queue_index: u32,
    /// Held around every use of `queue` (submit, present, wait idle): Vulkan requires the
    /// caller to synchronize a queue's users, and a `Gpu` is shared between threads.
    pub(super) queue_lock: Arc<Mutex<()>>,
    pub(crate) queue_family: u32,
    /// Nanoseconds per timestamp tick.
    pub(crate) timestamp_period_ns: f64,
    pub(super) caps: DeviceCaps,
    pub(super) info: DeviceInfo,
    /// Render passes and pipelines alive, by description (see [`ObjectCache`]).
    pub(crate) render_passes: Arc<ObjectCache<RenderPass>>,
    pub(crate) pipelines: Arc<ObjectCache<Pipeline, PipelineKey>>,
    /// The driver's pipeline cache, saved where it was loaded from when the last handle goes.
    pub(crate) pipeline_cache: Arc<PipelineCacheFile>,
    /// `vkCreateRenderPass2KHR`, where [`DeviceCaps::depth_resolve`] is on: the render passes
    /// that resolve depth are made with it.
    pub(crate) render_pass2: Option<ash::khr::create_renderpass2::Device>,
    /// Where the device reports its compiler's statistics (a device foveate opened, with the
    /// extension): every pipeline is created capturing them.
    pub(crate) executable_properties: Option<ash::khr::pipeline_executable_properties::Device>,
}

/// The device extensions a pass needs to resolve its depth (`DeviceCaps::depth_resolve`),
/// enabled wherever all are offered (Vulkan 1.1 devices; core in 1.2). An engine that lends
/// its device enables these and names them to [`Gpu::from_engine_with_extensions`].
pub const DEPTH_RESOLVE_EXTENSIONS: [&std::ffi::CStr; 2] = [
    ash::khr::create_renderpass2::NAME,
    ash::khr::depth_stencil_resolve::NAME,
];

impl Gpu {
    /// Opens the best device (discrete > integrated > virtual > CPU, so lavapipe where nothing
    /// else exists), or the one `options.device` names.
    pub fn new(options: &GpuOptions) -> Result<Self, GpuError> {
        Self::open(options, None)
    }

    /// Opens the device `creator` picks, with the instance and device it makes from foveate's
    /// create infos (an OpenXR runtime's, see [`VulkanCreator`]); `options.device` is ignored.
    pub fn with_creator(
        options: &GpuOptions,
        creator: &dyn VulkanCreator,
    ) -> Result<Self, GpuError> {
        Self::open(options, Some(creator))
    }

    fn open(options: &GpuOptions, creator: Option<&dyn VulkanCreator>) -> Result<Self, GpuError> {
        let instance = InstanceOwner::new(options, creator)?;
        let candidates = candidates(&instance.instance)?;
        let chosen = match creator {
            None => choose(&candidates, options.device.as_deref())?,
            Some(c) => {
                // SAFETY: the instance is the creator's.
                let physical = unsafe { c.physical_device(instance.instance.handle()) }?;
                let chosen = candidates
                    .iter()
                    .find(|c| c.physical == physical)
                    .ok_or(GpuError::NoDevice)?;
                if let Some(why) = &chosen.info.unusable {
                    return Err(GpuError::Unusable {
                        name: chosen.info.name.clone(),
                        why: why.clone(),
                    });
                }
                chosen
            }
        };
        let queue_family = chosen.queue_family.ok_or(GpuError::NoDevice)?;
        let physical = chosen.physical;
        let vk_instance = &instance.instance;

        // SAFETY: a query on a valid physical device.
        let supported = unsafe { vk_instance.get_physical_device_features(physical) };
        let features = vk::PhysicalDeviceFeatures::default()
            .fragment_stores_and_atomics(supported.fragment_stores_and_atomics == vk::TRUE)
            .shader_clip_distance(supported.shader_clip_distance == vk::TRUE)
            .depth_clamp(supported.depth_clamp == vk::TRUE)
            .sampler_anisotropy(supported.sampler_anisotropy == vk::TRUE)
            .pipeline_statistics_query(supported.pipeline_statistics_query == vk::TRUE);
        let mut multiview = vk::PhysicalDeviceMultiviewFeatures::default().multiview(true);
        let priorities = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family)
            .queue_priorities(&priorities)];
        let mut device_extensions = Vec::new();
        // SAFETY: a query on a valid physical device.
        let offered = unsafe { vk_instance.enumerate_device_extension_properties(physical) }
            .vk("vkEnumerateDeviceExtensionProperties")?;
        let offers = |name| {
            offered
                .iter()
                .any(|e| e.extension_name_as_c_str() == Ok(name))
        };
        let depth_resolve = DEPTH_RESOLVE_EXTENSIONS.iter().all(|&name| offers(name));
        if depth_resolve {
            device_extensions.extend(DEPTH_RESOLVE_EXTENSIONS.iter().map(|n| n.as_ptr()));
        }
        let statistics =
            shader_statistics::offered(vk_instance, physical, offers(shader_statistics::EXTENSION));
        let mut executable_info =
            vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default()
                .pipeline_executable_info(statistics);
        if statistics {
            device_extensions.push(shader_statistics::EXTENSION.as_ptr());
        }
        if options.display.is_some() {
            if !offers(ash::khr::swapchain::NAME) {
                return Err(GpuError::NoPresentation(format!(
                    "{} does not offer VK_KHR_swapchain",
                    chosen.info.name
                )));
            }
            device_extensions.push(ash::khr::swapchain::NAME.as_ptr());
        }
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_features(&features)
            .enabled_extension_names(&device_extensions)
            .push_next(&mut multiview)
            .push_next(&mut executable_info);
        // SAFETY: the create info points at locals that outlive the call; a creator's device is
        // loaded through this instance.
        let device = match creator {
            None => {
                unsafe { vk_instance.create_device(physical, &info, None) }.vk("vkCreateDevice")?
            }
            Some(c) => unsafe {
                let raw = c.create_device(&instance.entry, physical, &info)?;
                ash::Device::load(vk_instance.fp_v1_0(), raw)
            },
        };
        let parts = DeviceParts {
            queue_family,
            queue_index: 0,
            enabled: features,
            depth_resolve,
            statistics,
            owned: true,
            queue_lock: Arc::default(),
        };
        Self::assemble(instance, chosen, device, parts, options)
    }

    /// Every physical device with what foveate needs to know of it.
    pub fn list_devices() -> Result<Vec<DeviceInfo>, GpuError> {
        let instance = InstanceOwner::new(&GpuOptions::default(), None)?;
        Ok(candidates(&instance.instance)?
            .into_iter()
            .map(|c| c.info)
            .collect())
    }

    /// The handles an OpenXR session binds to (`XrGraphicsBindingVulkanKHR`).
    pub fn raw_handles(&self) -> RawHandles {
        RawHandles {
            instance: self.dev.instance.instance.handle(),
            physical: self.physical,
            device: self.dev.device.handle(),
            queue_family: self.queue_family,
            queue_index: self.queue_index,
        }
    }

    /// What the device can do, as the planner reads it.
    pub fn caps(&self) -> &DeviceCaps {
        &self.caps
    }

    /// The device's description, as `foveate devices` prints it.
    pub fn info(&self) -> &DeviceInfo {
        &self.info
    }

    /// The `ash` device, to record and submit with.
    pub fn device(&self) -> &ash::Device {
        &self.dev.device
    }

    /// The `ash` instance: with [`RawHandles::physical`] (from [`Gpu::raw_handles`]) an engine
    /// on foveate's own device reads the memory types (`get_physical_device_memory_properties`)
    /// to allocate its own buffers and images, or hands both to an allocator of its own.
    /// (An engine with a device of its own lends it instead: [`Gpu::from_engine`].)
    pub fn instance(&self) -> &ash::Instance {
        &self.dev.instance.instance
    }

    /// Takes the validation messages collected so far (empty without validation).
    pub fn take_validation_messages(&self) -> Vec<String> {
        self.dev
            .instance
            .messenger
            .as_ref()
            .and_then(|m| {
                m.log
                    .messages
                    .lock()
                    .ok()
                    .map(|mut v| std::mem::take(&mut *v))
            })
            .unwrap_or_default()
    }

    /// An error listing the validation messages collected so far, if there are any.
    pub fn check_validation(&self) -> Result<(), GpuError> {
        let messages = self.take_validation_messages();
        if messages.is_empty() {
            Ok(())
        } else {
            Err(GpuError::Validation(messages))
        }
    }

    /// Bytes of device memory the allocator has handed out right now (lazily allocated
    /// transient images, which commit no memory up front, are not among them).
    pub fn allocated_bytes(&self) -> u64 {
        self.dev
            .allocator
            .lock()
            .map_or(0, |a| a.generate_report().total_allocated_bytes)
    }

    /// Vulkan objects foveate holds alive on this device, by kind (`Image`, `Buffer`,
    /// `Pipeline`, `QueryPool`, `LazyMemory`, …); kinds with none alive are left out.
    pub fn live_objects(&self) -> BTreeMap<&'static str, i64> {
        self.dev.live.lock().map_or_else(
            |_| BTreeMap::new(),
            |live| {
                live.iter()
                    .filter(|(_, &n)| n != 0)
                    .map(|(&k, &n)| (k, n))
                    .collect()
            },
        )
    }

    /// Waits until the device is idle.
    pub fn wait_idle(&self) -> Result<(), GpuError> {
        self.check_alive()?;
        // vkDeviceWaitIdle synchronizes every queue of the device: no submission meanwhile.
        let waited = self.with_queue(|_| unsafe { self.dev.device.device_wait_idle() });
        self.noting_loss(waited.vk("vkDeviceWaitIdle"))
    }

    /// Runs `f` with the graphics queue, no other thread using it meanwhile.
    pub(crate) fn with_queue<T>(&self, f: impl FnOnce(vk::Queue) -> T) -> T {
        let _held = self.queue_lock.lock().unwrap_or_else(|e| e.into_inner());
        f(self.queue)
    }
}
