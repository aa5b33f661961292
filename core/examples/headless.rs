//! A foveated frame, headless: plan it, print the plan's decisions, render a few frames and
//! print each pass's GPU time by name, then save both eyes side by side.
//!
//! ```text
//! cargo run -p foveate --example headless [OUT.png]
//! ```

use foveate::foveation::FoveationConfig;
use foveate::glam::Vec2;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::plan::RenderConfig;
use foveate::plan::Resolution;
use foveate::render::{FrameInput, Renderer};
use foveate::scene::default_scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).map_or_else(
        || std::env::temp_dir().join("foveate-headless.png"),
        Into::into,
    );
    // Foveate's own device: the best Vulkan 1.1 device with multiview (lavapipe will do).
    let gpu = Gpu::new(&GpuOptions::default())?;
    let scene = default_scene();
    // Foveation at its defaults (fovea 0.35 of the field, the periphery at the same density,
    // stencil masks, a blend band an eighth of the fovea); everything else the defaults too.
    let config = RenderConfig {
        resolution: Some(Resolution::square(512)),
        foveation: Some(FoveationConfig::default()),
        ..RenderConfig::default()
    };
    // Planning is pure: it checks the configuration against the device and decides every
    // pass, attachment and barrier; the plan prints what it decided.
    let plan = foveate::plan(&scene, &config, gpu.caps())?;
    println!("{plan}");
    let mut renderer = Renderer::new(&gpu, &plan, &scene)?;
    // The gaze a little right of and below the centre, in both eyes.
    let input = FrameInput::new(scene.head).with_gaze([Vec2::new(0.2, -0.1); 2]);
    for frame in 0..3 {
        // Records, submits and waits: the simplest way to a frame and its figures.
        let stats = renderer.render(&input)?;
        println!("frame {frame}: GPU {:.2} ms", stats.gpu_ms.unwrap_or(0.0));
        for (pass, ms) in stats.gpu_pass_times() {
            println!("  {pass}: {ms:.2} ms");
        }
    }
    let image = renderer.readback()?;
    image.side_by_side().save(&out)?;
    println!("saved {} (left eye, right eye)", out.display());
    gpu.check_validation()?;
    Ok(())
}
