//! Render passes and pipelines are shared by description, and the pipeline cache persists.

use foveate::foveation::FoveationConfig;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::plan::{RenderConfig, Resolution};
use foveate::render::Renderer;
use foveate::scene::default_scene;
use foveate_tests::{assert_validation_clean, gpu};

/// A second renderer for the same plan, while the first lives, creates no render pass and no
/// pipeline (it still makes its own images, buffers and framebuffers); a plan differing only in
/// its counters reuses the render passes. Mutation: a cache keyed by handle, or not consulted,
/// fails it.
#[test]
fn a_second_renderer_for_the_same_plan_creates_no_render_pass_or_pipeline() {
    let gpu = gpu();
    let scene = default_scene();
    let config = RenderConfig {
        resolution: Some(Resolution::square(64)),
        foveation: Some(FoveationConfig::single_frame()),
        hmd_mask: true,
        ..RenderConfig::default()
    };
    let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
    let first = Renderer::new(&gpu, &plan, &scene).unwrap();
    let before = gpu.live_objects();
    let second = Renderer::new(&gpu, &plan, &scene).unwrap();
    let after = gpu.live_objects();
    for kind in ["RenderPass", "Pipeline"] {
        assert_eq!(after.get(kind), before.get(kind), "{kind}");
    }
    assert!(
        after["Image"] > before["Image"],
        "each renderer has its own images"
    );
    let counting = foveate::plan(&scene, &config.counting(), gpu.caps()).unwrap();
    let third = Renderer::new(&gpu, &counting, &scene).unwrap();
    assert_eq!(
        gpu.live_objects().get("RenderPass"),
        before.get("RenderPass")
    );
    drop((first, second, third));
    assert_validation_clean(&gpu);
}

/// The pipeline cache is written where the options say when the GPU is dropped, in a file of
/// the device's own (its identity in the name, beside the name given), with Vulkan's header
/// (lavapipe stores nothing after it; a GPU driver stores its pipelines), and seeds the next
/// GPU, which renders validation-clean from it; a file of garbage (another device's, a torn
/// write) is ignored, not fed to the driver. Mutation: skipping the save, or passing unchecked
/// bytes as initial data, fails it.
#[test]
fn the_pipeline_cache_persists_between_runs() {
    let dir = std::env::temp_dir().join(format!("foveate-pipeline-cache-{}", std::process::id()));
    let path = dir.join("pipelines.bin");
    let options = GpuOptions {
        validation: true,
        device: std::env::var("FOVEATE_DEVICE").ok(),
        pipeline_cache: Some(path.clone()),
        display: None,
    };
    let scene = default_scene();
    let config = RenderConfig {
        resolution: Some(Resolution::square(32)),
        ..RenderConfig::default()
    };
    // The device's own file: where the first run saved it.
    let mut written: Option<std::path::PathBuf> = None;
    for run in 0..3 {
        if let (2, Some(file)) = (run, &written) {
            std::fs::write(file, [0x5au8; 256]).unwrap();
        }
        let gpu = Gpu::new(&options).unwrap();
        let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
        let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
        renderer.render_frame(scene.head).unwrap();
        drop(renderer);
        assert_validation_clean(&gpu);
        let saved = gpu
            .save_pipeline_cache()
            .unwrap()
            .expect("a path was given");
        drop(gpu);
        assert_eq!(saved.parent(), path.parent(), "beside the name given");
        let name = saved.file_name().unwrap().to_string_lossy().into_owned();
        assert!(
            name.starts_with("pipelines-") && name.ends_with(".bin"),
            "{name}"
        );
        assert!(
            written.as_ref().is_none_or(|w| *w == saved),
            "run {run}: one file a device"
        );
        written = Some(saved.clone());
        let data = std::fs::read(&saved).unwrap_or_else(|e| panic!("run {run}: {e}"));
        assert!(data.len() >= 32, "run {run}: at least the header");
        assert_eq!(u32::from_le_bytes(data[0..4].try_into().unwrap()), 32);
    }
    let _ = std::fs::remove_dir_all(dir);
}
