//! Which physical device foveate opens: every device described (what it is, whether foveate
//! can use it and why not), scored (discrete > integrated > virtual > CPU), and chosen by the
//! user's index or name, or the best.

use std::ffi::CStr;

use ash::vk;

use super::context::DeviceInfo;
use super::{GpuError, VkResultExt};
use crate::vocab::DriverQuirks;

/// A physical device as foveate sees it: what it is, its graphics queue family, and how
/// much it is preferred.
pub(super) struct Candidate {
    pub(super) physical: vk::PhysicalDevice,
    pub(super) info: DeviceInfo,
    pub(super) queue_family: Option<u32>,
    pub(super) score: u32,
}

/// Every physical device with what foveate needs to know of it, scored.
pub(super) fn candidates(instance: &ash::Instance) -> Result<Vec<Candidate>, GpuError> {
    // SAFETY: plain queries on a valid instance.
    let physicals =
        unsafe { instance.enumerate_physical_devices() }.vk("vkEnumeratePhysicalDevices")?;
    let mut out = Vec::new();
    for (index, &physical) in physicals.iter().enumerate() {
        let props = unsafe { instance.get_physical_device_properties(physical) };
        let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
        let memory = unsafe { instance.get_physical_device_memory_properties(physical) };
        let extensions =
            unsafe { instance.enumerate_device_extension_properties(physical) }.unwrap_or_default();
        let has_ext = |name: &CStr| {
            extensions
                .iter()
                .any(|e| e.extension_name_as_c_str() == Ok(name))
        };
        let api = props.api_version;
        let api_ok = vk::api_version_major(api) > 1 || vk::api_version_minor(api) >= 1;
        let (mut multiview_props, mut multiview_features) = (
            vk::PhysicalDeviceMultiviewProperties::default(),
            vk::PhysicalDeviceMultiviewFeatures::default(),
        );
        let mut driver = vk::PhysicalDeviceDriverProperties::default();
        if api_ok {
            let mut p2 = vk::PhysicalDeviceProperties2::default()
                .push_next(&mut multiview_props)
                .push_next(&mut driver);
            let mut f2 = vk::PhysicalDeviceFeatures2::default().push_next(&mut multiview_features);
            unsafe {
                instance.get_physical_device_properties2(physical, &mut p2);
                instance.get_physical_device_features2(physical, &mut f2);
            }
        }
        let queue_family = families
            .iter()
            .position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS))
            .map(|i| i as u32);
        let multiview = multiview_features.multiview == vk::TRUE;
        let features = |f| unsafe {
            // SAFETY: a plain query on a valid physical device.
            instance
                .get_physical_device_format_properties(physical, f)
                .optimal_tiling_features
        };
        let unusable = if !api_ok {
            Some("needs Vulkan 1.1".to_string())
        } else if queue_family.is_none() {
            Some("no graphics queue".to_string())
        } else if !multiview {
            Some("no multiview".to_string())
        } else {
            missing_format(features)
        };
        let samples = props.limits.framebuffer_color_sample_counts
            & props.limits.framebuffer_depth_sample_counts;
        let lazily = memory.memory_types[..memory.memory_type_count as usize]
            .iter()
            .any(|t| {
                t.property_flags
                    .contains(vk::MemoryPropertyFlags::LAZILY_ALLOCATED)
            });
        let name = props
            .device_name_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let driver_name = driver
            .driver_name_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let driver_info = driver
            .driver_info_as_c_str()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let driver_line = format!("{driver_name} {driver_info}").trim().to_string();
        let info = DeviceInfo {
            index,
            name,
            device_type: format!("{:?}", props.device_type)
                .to_lowercase()
                .replace('_', " "),
            api_version: format!(
                "{}.{}.{}",
                vk::api_version_major(api),
                vk::api_version_minor(api),
                vk::api_version_patch(api)
            ),
            quirks: DriverQuirks::for_driver(driver.driver_id.as_raw(), &driver_info),
            driver: driver_line,
            max_multiview_views: if multiview {
                multiview_props.max_multiview_view_count
            } else {
                0
            },
            sample_counts: (0..7)
                .map(|b| 1u32 << b)
                .filter(|s| samples.as_raw() & s != 0)
                .collect(),
            fragment_density_map: has_ext(ash::ext::fragment_density_map::NAME),
            fragment_shading_rate: has_ext(ash::khr::fragment_shading_rate::NAME),
            lazily_allocated_memory: lazily,
            depth_stencil: features(vk::Format::D32_SFLOAT_S8_UINT)
                .contains(vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT),
            unusable,
        };
        let score = match props.device_type {
            vk::PhysicalDeviceType::DISCRETE_GPU => 4,
            vk::PhysicalDeviceType::INTEGRATED_GPU => 3,
            vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
            _ => 1,
        };
        out.push(Candidate {
            physical,
            info,
            queue_family,
            score,
        });
    }
    Ok(out)
}

/// The image formats every plan of foveate's may render with, and what it does with each
/// (optimal tiling). Of these only the 8-bit colour formats are ones every Vulkan device must
/// offer so. Depth with stencil (`D32_SFLOAT_S8_UINT`; `D24_UNORM_S8_UINT` on some devices
/// instead, which foveate does not use) is not among them: only plans with stencil masks need
/// it, and the planner refuses those on a device without it (`DeviceCaps::depth_stencil`).
const FORMATS: [(vk::Format, vk::FormatFeatureFlags, &str); 4] = {
    use vk::FormatFeatureFlags as F;
    let colour = F::from_raw(
        F::COLOR_ATTACHMENT.as_raw()
            | F::COLOR_ATTACHMENT_BLEND.as_raw()
            | F::SAMPLED_IMAGE.as_raw()
            | F::SAMPLED_IMAGE_FILTER_LINEAR.as_raw(),
    );
    [
        (
            vk::Format::R8G8B8A8_SRGB,
            colour,
            "colour attachments and textures",
        ),
        (
            vk::Format::R8G8B8A8_UNORM,
            F::COLOR_ATTACHMENT,
            "UNORM outputs",
        ),
        (
            vk::Format::R16G16B16A16_SFLOAT,
            colour,
            "the temporal history and half-float outputs",
        ),
        (vk::Format::D32_SFLOAT, F::DEPTH_STENCIL_ATTACHMENT, "depth"),
    ]
};

/// What the first of [`FORMATS`] that `features` (a format's optimal-tiling features) lacks is
/// missing, if one is.
fn missing_format(features: impl Fn(vk::Format) -> vk::FormatFeatureFlags) -> Option<String> {
    FORMATS.iter().find_map(|&(format, needed, what)| {
        let has = features(format);
        (!has.contains(needed)).then(|| {
            format!(
                "{format:?} lacks {:?} (foveate needs it for {what})",
                needed & !has
            )
        })
    })
}

/// The device `wanted` names (an index or part of a name), else the best usable one.
pub(super) fn choose<'a>(
    candidates: &'a [Candidate],
    wanted: Option<&str>,
) -> Result<&'a Candidate, GpuError> {
    let usable = || candidates.iter().filter(|c| c.info.unusable.is_none());
    match wanted {
        None => usable().max_by_key(|c| c.score).ok_or(GpuError::NoDevice),
        Some(w) => {
            let lower = w.to_lowercase();
            usable()
                .find(|c| {
                    w.parse::<usize>().ok() == Some(c.info.index)
                        || c.info.name.to_lowercase().contains(&lower)
                })
                .ok_or_else(|| GpuError::DeviceNotFound {
                    wanted: w.to_string(),
                    available: candidates
                        .iter()
                        .map(|c| match &c.info.unusable {
                            None => format!("{}: {}", c.info.index, c.info.name),
                            Some(why) => {
                                format!("{}: {} (unusable: {why})", c.info.index, c.info.name)
                            }
                        })
                        .collect::<Vec<_>>()
                        .join(", "),
                })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A device with every format as foveate uses it passes; one without a depth D32_SFLOAT
    /// is unusable, and the reason names the format, what it lacks and what foveate needs it
    /// for. Lacking depth-stencil D32_SFLOAT_S8_UINT (a tile GPU offering D24_UNORM_S8_UINT
    /// instead) leaves it usable: only plans with stencil masks need it (the planner's test).
    #[test]
    fn a_device_missing_a_format_is_unusable_naming_it() {
        let everything = |_| vk::FormatFeatureFlags::from_raw(u32::MAX);
        assert_eq!(missing_format(everything), None);
        let without = |missing: vk::Format| {
            move |f| match f {
                f if f == missing => vk::FormatFeatureFlags::SAMPLED_IMAGE,
                _ => vk::FormatFeatureFlags::from_raw(u32::MAX),
            }
        };
        assert_eq!(
            missing_format(without(vk::Format::D32_SFLOAT_S8_UINT)),
            None
        );
        let why = missing_format(without(vk::Format::D32_SFLOAT)).expect("unusable");
        assert!(
            why.contains("D32_SFLOAT")
                && why.contains("DEPTH_STENCIL_ATTACHMENT")
                && why.contains("depth"),
            "{why}"
        );
    }
}
