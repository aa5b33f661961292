//! The driver's pipeline cache across runs: seeded from a file written for this very device,
//! saved atomically when the run ends, so the next run compiles no pipeline this one compiled.

use std::sync::Arc;

use ash::vk;

use super::context::DeviceOwner;
use super::{Gpu, GpuError, PipelineCache, VkResultExt};

impl Gpu {
    /// Writes the pipeline cache where `GpuOptions::pipeline_cache` said (dropping the last
    /// handle to the `Gpu` does it too, ignoring errors: a cache is an optimisation), so the
    /// next run compiles no pipeline this one compiled; returns the path written, if any.
    pub fn save_pipeline_cache(&self) -> Result<Option<std::path::PathBuf>, GpuError> {
        self.pipeline_cache.save()
    }
}

/// The driver's pipeline cache and the file it persists in, shared by a `Gpu`'s handles.
pub(crate) struct PipelineCacheFile {
    pub(crate) cache: PipelineCache,
    pub(crate) path: Option<std::path::PathBuf>,
}

impl Drop for PipelineCacheFile {
    fn drop(&mut self) {
        let _ = self.save();
    }
}

impl PipelineCacheFile {
    fn save(&self) -> Result<Option<std::path::PathBuf>, GpuError> {
        let Some(path) = &self.path else {
            return Ok(None);
        };
        // SAFETY: the cache belongs to this device, alive while `self.cache` is.
        let data = unsafe { self.cache.device().get_pipeline_cache_data(self.cache.raw) }
            .vk("vkGetPipelineCacheData")?;
        // Written aside and renamed into place: runs in parallel never read a torn file, and a
        // failed write (a full disk, a path that is a folder) leaves nothing behind.
        let fail = |error: String| GpuError::PipelineCache {
            path: path.display().to_string(),
            error,
        };
        if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
            std::fs::create_dir_all(dir).map_err(|e| fail(e.to_string()))?;
        }
        crate::vocab::write_atomic(path, &data).map_err(|e| fail(e.why))?;
        Ok(Some(path.clone()))
    }
}

/// Where a device keeps its cache, given the file `GpuOptions::pipeline_cache` names: that
/// name with the device's vendor, device and cache UUID (its first four bytes) before the
/// extension, so each device and driver keeps its own (a run on another driver, such as
/// turnip beside lavapipe, or Mesa 25 beside 22, leaves the others' caches as they were).
pub(super) fn device_cache_file(
    path: &std::path::Path,
    props: &vk::PhysicalDeviceProperties,
) -> std::path::PathBuf {
    let uuid: String = props.pipeline_cache_uuid[..4]
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect();
    let mut name = path.file_stem().unwrap_or_default().to_owned();
    name.push(format!(
        "-{:04x}-{:04x}-{uuid}",
        props.vendor_id, props.device_id
    ));
    if let Some(extension) = path.extension() {
        name.push(".");
        name.push(extension);
    }
    path.with_file_name(name)
}

/// The pipeline cache, seeded from `path` when it holds data written for this very device
/// (the header's vendor, device and cache UUID match); anything else starts it empty.
pub(super) fn create_pipeline_cache(
    dev: &Arc<DeviceOwner>,
    props: &vk::PhysicalDeviceProperties,
    path: Option<&std::path::Path>,
) -> Result<PipelineCache, GpuError> {
    // Bounded, and only a regular file: a cache path at a device or a pipe must not hang or
    // exhaust memory (a cache is an optimisation; anything unreadable starts it empty).
    const MAX_CACHE_BYTES: u64 = 1 << 30;
    let read = path.and_then(|p| {
        crate::vocab::read_bounded(p, MAX_CACHE_BYTES, "foveate reads of a pipeline cache").ok()
    });
    let data = match (path, read) {
        (Some(p), Some(d)) if pipeline_cache_matches(&d, props) => {
            log::info!("pipeline cache: {} bytes from {}", d.len(), p.display());
            d
        }
        (Some(p), Some(_)) => {
            log::info!(
                "pipeline cache: {} was written for another device or driver; starting empty",
                p.display()
            );
            Vec::new()
        }
        (Some(p), None) => {
            log::debug!("pipeline cache: none at {} yet", p.display());
            Vec::new()
        }
        (None, _) => Vec::new(),
    };
    let info = vk::PipelineCacheCreateInfo::default().initial_data(&data);
    // SAFETY: the data's header was checked against this device.
    let raw =
        unsafe { dev.device.create_pipeline_cache(&info, None) }.vk("vkCreatePipelineCache")?;
    Ok(PipelineCache::from_raw(dev, raw))
}

/// Vulkan's pipeline cache header (version one): length 32, version 1, vendor ID, device ID,
/// then the 16-byte cache UUID.
fn pipeline_cache_matches(data: &[u8], props: &vk::PhysicalDeviceProperties) -> bool {
    let word = |i: usize| {
        data.get(4 * i..4 * i + 4)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    };
    word(0) == Some(32)
        && word(1) == Some(1)
        && word(2) == Some(props.vendor_id)
        && word(3) == Some(props.device_id)
        && data.get(16..32) == Some(&props.pipeline_cache_uuid[..])
}
