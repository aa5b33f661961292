//! Judging a foveated frame against its full-quality reference: the same frame rendered
//! without foveation at 4× MSAA, then per eye PSNR, FLIP at the display's pixels per degree, and
//! the eccentricity-aware FLIP (each pixel judged at the acuity the eye has there, from the
//! gaze) over the pixels the lens shows, judged on the GPU (`judge::FlipJudge`); NVIDIA's
//! reference FLIP on the CPU (`metrics::flip`, feature `flip`) is the oracle it is tested against.
//!
//! ```text
//! cargo run -p foveate --example judge
//! ```

use foveate::foveation::FoveationConfig;
use foveate::glam::Vec2;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::judge::FlipJudge;
use foveate::metrics::Acuity;
use foveate::metrics::{ErrorSummary, EyePixels};
use foveate::plan::Resolution;
use foveate::plan::{FramePlan, RenderConfig};
use foveate::render::{FrameInput, Renderer, StereoImage};
use foveate::scene::{default_scene, Scene};
use foveate::view::Eye;

/// One frame of `config` at `gaze`: its plan and image.
fn frame(
    gpu: &Gpu,
    scene: &Scene,
    config: &RenderConfig,
    gaze: Vec2,
) -> Result<(FramePlan, StereoImage), Box<dyn std::error::Error>> {
    let plan = foveate::plan(scene, config, gpu.caps())?;
    let mut renderer = Renderer::new(gpu, &plan, scene)?;
    renderer.render(&FrameInput::new(scene.head).with_gaze([gaze; 2]))?;
    Ok((plan, renderer.readback()?))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let gpu = Gpu::new(&GpuOptions::default())?;
    let scene = default_scene();
    let gaze = Vec2::new(0.2, -0.1);
    let reference = RenderConfig {
        resolution: Some(Resolution::square(256)),
        msaa: 4,
        ..RenderConfig::default()
    };
    let foveated = RenderConfig {
        foveation: Some(FoveationConfig::default()),
        ..reference.clone()
    };
    let (_, want) = frame(&gpu, &scene, &reference, gaze)?;
    let (plan, got) = frame(&gpu, &scene, &foveated, gaze)?;
    // Where each output pixel lies for the eye: seen through the lens or not, its angle from
    // the gaze, and the region (fovea, band, periphery) of the foveated frame.
    let eyes = EyePixels::both(&plan, gaze, plan.foveation.as_ref());
    let (width, height) = (plan.eye_resolution.width, plan.eye_resolution.height);
    let mut judge = FlipJudge::new(&gpu, width, height)?;
    for eye in Eye::BOTH {
        let pixels = &eyes[eye.index()];
        let (want, got) = (want.eye(eye), got.eye(eye));
        let eccentricity = |x, y| pixels.at(x, y).map(|p| p.eccentricity_deg);
        let maps = judge.flip_maps(want, got, pixels.ppd, Acuity::default(), &eccentricity)?;
        let summary = |map: &[f32]| ErrorSummary::of(&pixels.select(map, |_| true));
        let (plain, eccentric) = (summary(&maps.plain), summary(&maps.eccentric));
        println!(
            "{eye:?} eye: PSNR {:.1} dB; FLIP mean {:.4}, p99 {:.4}; eccentricity-aware FLIP mean \
             {:.4}, p99 {:.4} ({} pixels the lens shows, {:.1} px/° at its axis)",
            got.psnr(want)?,
            plain.map_or(0.0, |s| s.mean),
            plain.map_or(0.0, |s| s.p99),
            eccentric.map_or(0.0, |s| s.mean),
            eccentric.map_or(0.0, |s| s.p99),
            eccentric.map_or(0, |s| s.pixels),
            pixels.ppd
        );
    }
    gpu.check_validation()?;
    Ok(())
}
