//! Not compiled on the host (no Android toolchain here): keep it a thin layer over host-tested
//! core calls.

use android_activity::{AndroidApp, MainEvent, PollEvent};
use foveate::gpu::{Gpu, GpuOptions};
use foveate::plan::RenderConfig;
use foveate::render::Renderer;
use foveate::scene::default_scene;

#[no_mangle]
fn android_main(app: AndroidApp) {
    android_logger::init_once(
        android_logger::Config::default().with_max_level(log::LevelFilter::Info),
    );
    if let Err(e) = run(&app) {
        log::error!("foveate: {e}");
    }
}

fn run(app: &AndroidApp) -> Result<(), Box<dyn std::error::Error>> {
    let gpu = Gpu::new(&GpuOptions::default())?;
    let scene = default_scene();
    let config = RenderConfig {
        msaa: 4,
        ..RenderConfig::default()
    };
    let plan = foveate::plan(&scene, &config, gpu.caps())?;
    log::info!("{plan}");
    let mut renderer = Renderer::new(&gpu, &plan, &scene)?;
    let mut quit = false;
    while !quit {
        app.poll_events(Some(std::time::Duration::ZERO), |event| {
            if let PollEvent::Main(MainEvent::Destroy) = event {
                quit = true;
            }
        });
        let stats = renderer.render_frame(scene.head)?;
        log::info!("frame {:.2} ms, GPU {:?} ms", stats.frame_ms, stats.gpu_ms);
    }
    Ok(())
}
