//! Output images an engine hands in frame by frame (`FrameInput::output`), and the output
//! formats a plan allows: sRGB and UNORM 8-bit, and half floats — each read back as the same
//! picture the sRGB default gives.

use foveate::foveation::FoveationConfig;
use foveate::gpu::{Gpu, Image};
use foveate::metrics::RgbaImage;
use foveate::plan::{OutputFormat, RenderConfig, Resolution};
use foveate::render::{output_image_desc, FrameInput, Renderer, StereoImage, MAX_OUTPUT_IMAGES};
use foveate::scene::{default_scene, Scene};
use foveate_tests::{assert_validation_clean, gpu, linear};
use glam::{Mat4, Vec3};

fn small(config: RenderConfig) -> RenderConfig {
    RenderConfig {
        resolution: Some(Resolution::square(80)),
        ..config
    }
}

fn foveated() -> RenderConfig {
    small(RenderConfig {
        foveation: Some(FoveationConfig::single_frame()),
        ..RenderConfig::default()
    })
}

fn own(gpu: &Gpu, scene: &Scene, config: &RenderConfig, head: Mat4) -> StereoImage {
    let plan = foveate::plan(scene, config, gpu.caps()).unwrap();
    let mut renderer = Renderer::new(gpu, &plan, scene).unwrap();
    renderer.render_frame(head).unwrap();
    renderer.readback().unwrap()
}

/// A renderer made with no output image renders into its own until images are handed in with
/// the frames; then each frame lands in the image it names — three images taken in turn, the
/// plan's two frame slots in turn — equal to the frame rendered into a renderer's own image. Mutation:
/// ignoring `FrameInput::output` leaves every frame in the renderer's own image, and no image
/// handed in to select.
#[test]
fn images_handed_in_frame_by_frame_each_hold_their_frame() {
    let gpu = gpu();
    let scene = default_scene();
    for config in [small(RenderConfig::default()), foveated()] {
        let external = RenderConfig {
            external_output: true,
            ..config.clone()
        };
        let plan = foveate::plan(&scene, &external, gpu.caps()).unwrap();
        let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
        renderer.render_frame(scene.head).unwrap();
        assert!(renderer.readback().unwrap() == own(&gpu, &scene, &config, scene.head));
        let desc = output_image_desc(&plan);
        let images: Vec<Image> = (0..3).map(|_| Image::new(&gpu, &desc).unwrap()).collect();
        let heads: Vec<Mat4> = (0..6)
            .map(|i| scene.head * Mat4::from_translation(Vec3::new(0.05 * i as f32, 0.0, 0.0)))
            .collect();
        for (i, head) in heads.iter().enumerate() {
            let input = FrameInput::new(*head).with_output(images[i % 3].raw());
            renderer.render(&input).unwrap();
        }
        // Each image holds the last frame handed it (images are numbered as first handed in).
        for (i, head) in heads[3..].iter().enumerate() {
            renderer.select_output(i).unwrap();
            let got = renderer.readback().unwrap();
            assert!(got == own(&gpu, &scene, &config, *head), "image {i}");
        }
        drop(renderer);
        assert_validation_clean(&gpu);
    }
}

/// More distinct images than a renderer keeps framebuffers for are refused, naming the
/// limit; an output handed to a plan that owns its output is refused, naming the field.
#[test]
fn output_images_beyond_the_limit_or_plan_are_refused() {
    let gpu = gpu();
    let scene = default_scene();
    let external = small(RenderConfig {
        external_output: true,
        ..RenderConfig::default()
    });
    let plan = foveate::plan(&scene, &external, gpu.caps()).unwrap();
    let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
    let desc = output_image_desc(&plan);
    let images: Vec<Image> = (0..=MAX_OUTPUT_IMAGES)
        .map(|_| Image::new(&gpu, &desc).unwrap())
        .collect();
    for image in &images[..MAX_OUTPUT_IMAGES] {
        renderer
            .render(&FrameInput::new(scene.head).with_output(image.raw()))
            .unwrap();
    }
    let last = FrameInput::new(scene.head).with_output(images[MAX_OUTPUT_IMAGES].raw());
    let error = renderer.render(&last).unwrap_err().to_string();
    assert!(error.contains(&MAX_OUTPUT_IMAGES.to_string()), "{error}");
    let owned = foveate::plan(&scene, &small(RenderConfig::default()), gpu.caps()).unwrap();
    let mut renderer = Renderer::new(&gpu, &owned, &scene).unwrap();
    let error = renderer.render(&last).unwrap_err().to_string();
    assert!(
        error.contains("output") && error.contains("external_output"),
        "{error}"
    );
    drop(renderer);
    assert_validation_clean(&gpu);
}

/// The largest difference between two images in linear light, in 8-bit steps.
fn linear_difference(a: &RgbaImage, b: &RgbaImage) -> f64 {
    a.data
        .chunks_exact(4)
        .zip(b.data.chunks_exact(4))
        .flat_map(|(p, q)| (0..3).map(move |c| (linear(p[c]) - linear(q[c])).abs() * 255.0))
        .fold(0.0, f64::max)
}

/// A frame in half floats reads back as the sRGB frame, to an sRGB step; in 8-bit UNORM, to
/// the steps its linear quantisation costs (at most 3 steps of linear light). Both as
/// the renderer's own image and as an image handed in. Mutation: reading a half-float image as
/// 8-bit texels garbles it.
#[test]
fn every_output_format_reads_back_as_the_srgb_frame() {
    let gpu = gpu();
    let scene = default_scene();
    for config in [small(RenderConfig::default()), foveated()] {
        let reference = own(&gpu, &scene, &config, scene.head);
        for format in [OutputFormat::Float16, OutputFormat::Unorm8] {
            for external_output in [false, true] {
                let config = RenderConfig {
                    output_format: format,
                    external_output,
                    ..config.clone()
                };
                let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
                let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
                let desc = output_image_desc(&plan);
                let handed = Image::new(&gpu, &desc).unwrap();
                let mut input = FrameInput::new(scene.head);
                if external_output {
                    input = input.with_output(handed.raw());
                }
                renderer.render(&input).unwrap();
                let got = renderer.readback().unwrap();
                for (g, r) in got.eyes().into_iter().zip(reference.eyes()) {
                    if format == OutputFormat::Float16 {
                        let d = g.data.iter().zip(&r.data).map(|(a, b)| a.abs_diff(*b));
                        let d = d.max().unwrap_or(0);
                        assert!(d <= 1, "{format:?}: {d} sRGB steps apart");
                    } else {
                        let d = linear_difference(g, r);
                        assert!(d <= 3.0, "{format:?}: {d:.2} steps of linear light apart");
                    }
                }
                drop(renderer);
            }
        }
    }
    assert_validation_clean(&gpu);
}
