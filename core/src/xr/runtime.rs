//! The OpenXR runtime: the loader, the instance and the headset's system, what the runtime
//! offers, its events, and the Vulkan device it asks for (`XR_KHR_vulkan_enable2`: it makes the
//! instance and device from foveate's create infos and picks the GPU).

use ash::vk::{self, Handle};
use openxr as xr;

use super::error::{XrError, XrResultExt};
use super::lifecycle::{RuntimeEvent, SessionState};
use crate::gpu::{Gpu, GpuError, GpuOptions, VulkanCreator};
use crate::plan::Resolution;

/// The one view configuration foveate submits.
pub(super) const STEREO: xr::ViewConfigurationType = xr::ViewConfigurationType::PRIMARY_STEREO;

/// What the runtime offered, for the log and the run's summary.
#[derive(Clone, Debug)]
pub struct RuntimeReport {
    /// The runtime's name and version.
    pub runtime: String,
    /// The headset's name.
    pub system: String,
    /// The extensions of interest the runtime offers, by name.
    pub extensions: Vec<&'static str>,
    /// The view configurations it offers.
    pub view_configurations: Vec<String>,
    /// Each eye's recommended and largest image size.
    pub recommended: Resolution,
    /// Each eye's largest image size.
    pub max: Resolution,
    /// Whether it has an eye tracker (`XR_EXT_eye_gaze_interaction`).
    pub eye_gaze: bool,
}

/// What the OpenXR loader needs of the platform: nothing on desktops; on Android the JavaVM
/// and the activity (`XR_KHR_loader_init_android`, `XR_KHR_android_create_instance`).
#[cfg(not(target_os = "android"))]
pub type Platform = ();
/// What the OpenXR loader needs of the platform: on Android the JavaVM and the activity
/// (`XR_KHR_loader_init_android`, `XR_KHR_android_create_instance`).
#[cfg(target_os = "android")]
pub type Platform = xr::AndroidPlatformInfo;

/// The runtime: loader, instance, the headset's system.
pub struct XrRuntime {
    pub(super) instance: xr::Instance,
    pub(super) system: xr::SystemId,
    /// What it offered.
    pub report: RuntimeReport,
    /// The runtime offers `XR_KHR_visibility_mask` (enabled).
    pub(super) visibility_mask: bool,
}

impl XrRuntime {
    /// Loads the OpenXR loader and opens the active runtime's headset (`&()` for `platform`
    /// on desktops).
    pub fn new(platform: &Platform) -> Result<Self, XrError> {
        // SAFETY: the system's OpenXR loader, a conforming library.
        let entry =
            unsafe { xr::Entry::load(platform) }.map_err(|e| XrError::NoLoader(e.to_string()))?;
        let offered = entry.enumerate_extensions().map_err(XrError::NoRuntime)?;
        if !offered.khr_vulkan_enable2 {
            return Err(XrError::NoVulkan);
        }
        let mut enabled = xr::ExtensionSet::default();
        enabled.khr_vulkan_enable2 = true;
        #[cfg(target_os = "android")]
        {
            enabled.khr_android_create_instance = true;
        }
        enabled.khr_visibility_mask = offered.khr_visibility_mask;
        enabled.ext_eye_gaze_interaction = offered.ext_eye_gaze_interaction;
        let of_interest = [
            ("XR_KHR_vulkan_enable2", offered.khr_vulkan_enable2),
            (
                "XR_KHR_composition_layer_depth",
                offered.khr_composition_layer_depth,
            ),
            ("XR_KHR_visibility_mask", offered.khr_visibility_mask),
            (
                "XR_EXT_eye_gaze_interaction",
                offered.ext_eye_gaze_interaction,
            ),
            ("XR_VARJO_quad_views", offered.varjo_quad_views),
            (
                "XR_VARJO_foveated_rendering",
                offered.varjo_foveated_rendering,
            ),
            ("XR_FB_foveation", offered.fb_foveation),
            (
                "XR_META_foveation_eye_tracked",
                offered.meta_foveation_eye_tracked,
            ),
        ];
        let app = xr::ApplicationInfo {
            application_name: "foveate",
            application_version: 1,
            engine_name: "foveate",
            engine_version: 1,
            api_version: xr::Version::new(1, 0, 0),
        };
        let instance = entry
            .create_instance(&app, &enabled, &[], platform)
            .map_err(XrError::NoRuntime)?;
        let props = instance.properties().xr("xrGetInstanceProperties")?;
        let system = instance
            .system(xr::FormFactor::HEAD_MOUNTED_DISPLAY)
            .map_err(XrError::NoHeadset)?;
        let system_props = instance
            .system_properties(system)
            .xr("xrGetSystemProperties")?;
        let configurations = instance
            .enumerate_view_configurations(system)
            .xr("xrEnumerateViewConfigurations")?;
        let names: Vec<String> = configurations.iter().map(|c| format!("{c:?}")).collect();
        if !configurations.contains(&STEREO) {
            return Err(XrError::NoStereo(names.join(", ")));
        }
        let views = instance
            .enumerate_view_configuration_views(system, STEREO)
            .xr("xrEnumerateViewConfigurationViews")?;
        let size = |w: u32, h: u32| Resolution {
            width: w,
            height: h,
        };
        let requirements = instance
            .graphics_requirements::<xr::Vulkan>(system)
            .xr("xrGetVulkanGraphicsRequirements2KHR")?;
        let (min, max) = (
            requirements.min_api_version_supported,
            requirements.max_api_version_supported,
        );
        if xr::Version::new(1, 1, 0) < xr::Version::new(min.major(), min.minor(), 0)
            || xr::Version::new(max.major(), max.minor(), 0) < xr::Version::new(1, 1, 0)
        {
            return Err(XrError::VulkanVersion {
                min: format!("{}.{}", min.major(), min.minor()),
                max: format!("{}.{}", max.major(), max.minor()),
            });
        }
        let eye_gaze = offered.ext_eye_gaze_interaction && supports_eye_gaze(&instance, system);
        let report = RuntimeReport {
            runtime: format!("{} {}", props.runtime_name, props.runtime_version),
            system: system_props.system_name,
            extensions: of_interest
                .iter()
                .filter(|(_, on)| *on)
                .map(|(n, _)| *n)
                .collect(),
            view_configurations: names,
            recommended: size(
                views[0].recommended_image_rect_width,
                views[0].recommended_image_rect_height,
            ),
            max: size(
                views[0].max_image_rect_width,
                views[0].max_image_rect_height,
            ),
            eye_gaze,
        };
        Ok(XrRuntime {
            instance,
            system,
            report,
            visibility_mask: offered.khr_visibility_mask,
        })
    }

    /// The GPU the runtime renders with, its instance and device made by the runtime from
    /// foveate's create infos.
    pub fn gpu(&self, options: &GpuOptions) -> Result<Gpu, XrError> {
        let creator = RuntimeCreator {
            instance: &self.instance,
            system: self.system,
        };
        Ok(Gpu::with_creator(options, &creator)?)
    }

    /// The runtime's next event, as the lifecycle needs it (`None`: no more for now). A
    /// visibility mask change is reported through `mask_changed`.
    pub fn poll(&self, mask_changed: &mut bool) -> Result<Option<RuntimeEvent>, XrError> {
        let mut buffer = xr::EventDataBuffer::new();
        loop {
            let Some(event) = self.instance.poll_event(&mut buffer).xr("xrPollEvent")? else {
                return Ok(None);
            };
            let state = match event {
                xr::Event::SessionStateChanged(e) => e.state(),
                xr::Event::InstanceLossPending(_) => {
                    return Ok(Some(RuntimeEvent::InstanceLossPending))
                }
                xr::Event::VisibilityMaskChangedKHR(_) => {
                    *mask_changed = true;
                    continue;
                }
                xr::Event::EventsLost(e) => {
                    log::warn!("OpenXR: the runtime lost {} events", e.lost_event_count());
                    continue;
                }
                _ => continue,
            };
            let state = match state {
                xr::SessionState::IDLE => SessionState::Idle,
                xr::SessionState::READY => SessionState::Ready,
                xr::SessionState::SYNCHRONIZED => SessionState::Synchronized,
                xr::SessionState::VISIBLE => SessionState::Visible,
                xr::SessionState::FOCUSED => SessionState::Focused,
                xr::SessionState::STOPPING => SessionState::Stopping,
                xr::SessionState::LOSS_PENDING => SessionState::LossPending,
                xr::SessionState::EXITING => SessionState::Exiting,
                _ => continue,
            };
            return Ok(Some(RuntimeEvent::State(state)));
        }
    }
}

/// Whether the system delivers eye gaze (`XrSystemEyeGazeInteractionPropertiesEXT`).
fn supports_eye_gaze(instance: &xr::Instance, system: xr::SystemId) -> bool {
    let mut gaze = xr::sys::SystemEyeGazeInteractionPropertiesEXT {
        ty: xr::sys::SystemEyeGazeInteractionPropertiesEXT::TYPE,
        next: std::ptr::null_mut(),
        supports_eye_gaze_interaction: false.into(),
    };
    // SAFETY: a zeroed properties struct with a valid chain, as xrGetSystemProperties wants.
    unsafe {
        let mut props: xr::sys::SystemProperties = std::mem::zeroed();
        props.ty = xr::sys::SystemProperties::TYPE;
        props.next = &mut gaze as *mut _ as *mut _;
        let result = (instance.fp().get_system_properties)(instance.as_raw(), system, &mut props);
        result == xr::sys::Result::SUCCESS && gaze.supports_eye_gaze_interaction.into()
    }
}

/// Vulkan objects made by the runtime (`XR_KHR_vulkan_enable2`).
struct RuntimeCreator<'a> {
    instance: &'a xr::Instance,
    system: xr::SystemId,
}

impl RuntimeCreator<'_> {
    fn proc_addr(entry: &ash::Entry) -> xr::sys::platform::VkGetInstanceProcAddr {
        // SAFETY: the same C signature, `PFN_vkGetInstanceProcAddr`, in two crates' spelling.
        unsafe { std::mem::transmute(entry.static_fn().get_instance_proc_addr) }
    }
}

fn runtime_error(call: &'static str) -> impl Fn(xr::sys::Result) -> GpuError {
    move |e| GpuError::Runtime(format!("{call}: {e}"))
}

fn vk_error(call: &'static str) -> impl Fn(i32) -> GpuError {
    move |r| GpuError::Vk {
        call,
        result: vk::Result::from_raw(r),
    }
}

impl VulkanCreator for RuntimeCreator<'_> {
    unsafe fn create_instance(
        &self,
        entry: &ash::Entry,
        info: &vk::InstanceCreateInfo,
    ) -> Result<vk::Instance, GpuError> {
        let raw = unsafe {
            self.instance.create_vulkan_instance(
                self.system,
                Self::proc_addr(entry),
                info as *const _ as *const _,
            )
        }
        .map_err(runtime_error("xrCreateVulkanInstanceKHR"))?
        .map_err(vk_error("vkCreateInstance (by the OpenXR runtime)"))?;
        Ok(vk::Instance::from_raw(raw as u64))
    }

    unsafe fn physical_device(
        &self,
        instance: vk::Instance,
    ) -> Result<vk::PhysicalDevice, GpuError> {
        let raw = unsafe {
            self.instance
                .vulkan_graphics_device(self.system, instance.as_raw() as _)
        }
        .map_err(runtime_error("xrGetVulkanGraphicsDevice2KHR"))?;
        Ok(vk::PhysicalDevice::from_raw(raw as u64))
    }

    unsafe fn create_device(
        &self,
        entry: &ash::Entry,
        physical: vk::PhysicalDevice,
        info: &vk::DeviceCreateInfo,
    ) -> Result<vk::Device, GpuError> {
        let raw = unsafe {
            self.instance.create_vulkan_device(
                self.system,
                Self::proc_addr(entry),
                physical.as_raw() as _,
                info as *const _ as *const _,
            )
        }
        .map_err(runtime_error("xrCreateVulkanDeviceKHR"))?
        .map_err(vk_error("vkCreateDevice (by the OpenXR runtime)"))?;
        Ok(vk::Device::from_raw(raw as u64))
    }
}
