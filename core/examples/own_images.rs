//! Rendering into images the program owns: the plan says its output is handed in
//! (`external_output`), the program makes images as `output_image_desc` describes (an engine's
//! swapchain images, or its own render targets) and names one with each frame.
//!
//! ```text
//! cargo run -p foveate --example own_images
//! ```

use foveate::foveation::FoveationConfig;
use foveate::glam::{Mat4, Vec3};
use foveate::gpu::{Gpu, GpuOptions, Image};
use foveate::plan::RenderConfig;
use foveate::plan::{OutputFormat, Resolution};
use foveate::render::{output_image_desc, FrameInput, Renderer};
use foveate::scene::default_scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let gpu = Gpu::new(&GpuOptions::default())?;
    let scene = default_scene();
    let config = RenderConfig {
        resolution: Some(Resolution::square(256)),
        foveation: Some(FoveationConfig::default()),
        external_output: true,
        // What the images hold: sRGB 8-bit (the default), UNORM 8-bit or half floats.
        output_format: OutputFormat::Float16,
        ..RenderConfig::default()
    };
    let plan = foveate::plan(&scene, &config, gpu.caps())?;
    // Three images, as a swapchain would have; each a two-layer array (left eye, right eye).
    let desc = output_image_desc(&plan);
    println!(
        "output images: {}x{}, {} layers, {:?}",
        desc.width, desc.height, desc.layers, desc.format
    );
    let images = (0..3)
        .map(|_| Image::new(&gpu, &desc))
        .collect::<Result<Vec<_>, _>>()?;
    let mut renderer = Renderer::new(&gpu, &plan, &scene)?;
    for frame in 0..6 {
        let head = scene.head * Mat4::from_translation(Vec3::new(0.05 * frame as f32, 0.0, 0.0));
        // Each frame names the image it ends in; the renderer makes its framebuffers for an
        // image the first time it sees it.
        let input = FrameInput::new(head).with_output(images[frame % images.len()].raw());
        let stats = renderer.render(&input)?;
        println!(
            "frame {frame} into image {}: GPU {:.2} ms",
            frame % images.len(),
            stats.gpu_ms.unwrap_or(0.0)
        );
    }
    // The renderer's readback reads an image it was handed (numbered as first handed in) and
    // converts it to sRGB 8-bit, whatever its format.
    renderer.select_output(2)?;
    let last = renderer.readback()?;
    println!(
        "image 2 holds the last frame: {}x{} per eye",
        last.left.width, last.left.height
    );
    drop(renderer);
    gpu.check_validation()?;
    Ok(())
}
