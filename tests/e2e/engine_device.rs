//! foveate on a device an engine made: the engine creates the instance and device (here with
//! `ash`, as an engine would), lends them through `Gpu::from_engine`, renders, drops foveate —
//! and its device still works and is destroyed by the engine alone.

use std::ffi::CStr;
use std::sync::{Arc, Mutex};

use ash::vk;
use foveate::foveation::{FoveationConfig, TemporalConfig};
use foveate::gpu::{EngineDevice, Gpu, GpuOptions, DEPTH_RESOLVE_EXTENSIONS};
use foveate::plan::{RenderConfig, Resolution};
use foveate::render::Renderer;
use foveate::scene::{atrium_scene, default_scene};
use foveate_tests::gpu;

/// The engine's own instance and device: Vulkan 1.1, multiview on, the features foveate can
/// use when offered.
struct Engine {
    _entry: ash::Entry,
    instance: ash::Instance,
    physical: vk::PhysicalDevice,
    device: ash::Device,
    family: u32,
    features: vk::PhysicalDeviceFeatures,
}

impl Engine {
    fn new() -> Engine {
        Engine::with_extensions(&[])
    }

    /// The engine's device, with these device extensions enabled as well.
    fn with_extensions(extensions: &[&CStr]) -> Engine {
        let entry = unsafe { ash::Entry::load() }.unwrap();
        let app = vk::ApplicationInfo::default().api_version(vk::API_VERSION_1_1);
        let info = vk::InstanceCreateInfo::default().application_info(&app);
        let instance = unsafe { entry.create_instance(&info, None) }.unwrap();
        let physical = unsafe { instance.enumerate_physical_devices() }.unwrap()[0];
        let families = unsafe { instance.get_physical_device_queue_family_properties(physical) };
        let family = families
            .iter()
            .position(|f| f.queue_flags.contains(vk::QueueFlags::GRAPHICS))
            .unwrap() as u32;
        let features = unsafe { instance.get_physical_device_features(physical) };
        let mut multiview = vk::PhysicalDeviceMultiviewFeatures::default().multiview(true);
        let priorities = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(family)
            .queue_priorities(&priorities)];
        let names: Vec<_> = extensions.iter().map(|n| n.as_ptr()).collect();
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&names)
            .enabled_features(&features)
            .push_next(&mut multiview);
        let device = unsafe { instance.create_device(physical, &info, None) }.unwrap();
        Engine {
            _entry: entry,
            instance,
            physical,
            device,
            family,
            features,
        }
    }

    fn lend(&self, multiview: bool) -> EngineDevice {
        EngineDevice {
            instance: self.instance.handle(),
            physical: self.physical,
            device: self.device.handle(),
            queue_family: self.family,
            queue_index: 0,
            enabled_features: self.features,
            multiview,
            queue_lock: Arc::new(Mutex::new(())),
        }
    }
}

impl Drop for Engine {
    fn drop(&mut self) {
        unsafe {
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}

/// A frame on the engine's device is the frame on foveate's own, pixel for pixel; when foveate
/// is gone the engine's device still creates, submits and waits, and the engine destroys it.
/// Mutation: a borrowed `DeviceOwner` that destroys its device makes the engine's calls after
/// the drop fail (or crash) and its own destroy a double free.
#[test]
fn a_borrowed_device_renders_and_survives_the_renderer() {
    let scene = default_scene();
    let config = RenderConfig {
        resolution: Some(Resolution::square(64)),
        ..RenderConfig::default()
    };
    let expected = {
        let gpu = gpu();
        let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
        let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
        renderer.render_frame(scene.head).unwrap();
        renderer.readback().unwrap()
    };
    let engine = Engine::new();
    {
        // SAFETY: the engine's handles outlive the Gpu and the renderer (dropped in this block).
        let gpu = unsafe { Gpu::from_engine(engine.lend(true), &GpuOptions::default()) }.unwrap();
        assert!(!gpu.owns_device());
        let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
        let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
        renderer.render_frame(scene.head).unwrap();
        assert!(renderer.readback().unwrap() == expected);
        assert!(gpu.live_objects().values().any(|&n| n > 0));
    }
    // The engine's device after foveate: an object made, a submission, a wait.
    unsafe {
        let fence = engine
            .device
            .create_fence(&vk::FenceCreateInfo::default(), None)
            .unwrap();
        let queue = engine.device.get_device_queue(engine.family, 0);
        engine.device.queue_submit(queue, &[], fence).unwrap();
        engine
            .device
            .wait_for_fences(&[fence], true, u64::MAX)
            .unwrap();
        engine.device.destroy_fence(fence, None);
    }
}

/// A device lent without multiview (or with a queue it does not have) is refused, naming what
/// is missing.
#[test]
fn a_borrowed_device_without_what_foveate_needs_is_refused() {
    let engine = Engine::new();
    let without_multiview = unsafe { Gpu::from_engine(engine.lend(false), &GpuOptions::default()) };
    let error = without_multiview.err().expect("refused").to_string();
    assert!(error.contains("multiview"), "{error}");
    let mut no_queue = engine.lend(true);
    no_queue.queue_index = 99;
    let error = unsafe { Gpu::from_engine(no_queue, &GpuOptions::default()) }
        .err()
        .expect("refused")
        .to_string();
    assert!(error.contains("queue_index 99"), "{error}");
}

/// An engine that enabled depth resolve and says so (`from_engine_with_extensions`) gets a
/// multisampled accumulated periphery, pixel for pixel foveate's own device's frames; lent
/// without saying so, the plan refuses it naming `periphery_msaa`; a name the device does not
/// offer is refused, named. Mutation: the declared list ignored (depth resolve left off)
/// makes the declared device's plan fail.
#[test]
fn an_engine_declares_the_extensions_it_enabled() {
    let owned = gpu();
    if !owned.caps().depth_resolve {
        eprintln!("skipped: {} cannot resolve depth", owned.caps().device_name);
        return;
    }
    let scene = atrium_scene();
    let base = super::temporal::config(64, Some(TemporalConfig::default()));
    let config = RenderConfig {
        msaa: 4,
        foveation: base.foveation.map(|f| FoveationConfig {
            periphery_msaa: Some(4),
            ..f
        }),
        ..base
    };
    let frames = |gpu: &Gpu| {
        let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
        let mut renderer = Renderer::new(gpu, &plan, &scene).unwrap();
        (0..3)
            .map(|_| {
                renderer.render_frame(scene.head).unwrap();
                renderer.readback().unwrap()
            })
            .collect::<Vec<_>>()
    };
    let expected = frames(&owned);
    let engine = Engine::with_extensions(&DEPTH_RESOLVE_EXTENSIONS);
    let options = GpuOptions::default();
    {
        // SAFETY: the engine's handles outlive the Gpus (dropped in this block), and it
        // enabled what it declares.
        let declared = unsafe {
            Gpu::from_engine_with_extensions(engine.lend(true), &DEPTH_RESOLVE_EXTENSIONS, &options)
        }
        .unwrap();
        assert!(declared.caps().depth_resolve);
        assert!(frames(&declared) == expected);
        let undeclared = unsafe { Gpu::from_engine(engine.lend(true), &options) }.unwrap();
        let error = foveate::plan(&scene, &config, undeclared.caps())
            .expect_err("refused")
            .to_string();
        assert!(error.contains("periphery_msaa"), "{error}");
        let unknown = c"VK_EXT_nothing_of_the_kind";
        let error =
            unsafe { Gpu::from_engine_with_extensions(engine.lend(true), &[unknown], &options) }
                .err()
                .expect("refused")
                .to_string();
        assert!(error.contains("VK_EXT_nothing_of_the_kind"), "{error}");
    }
}
