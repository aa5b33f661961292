//! The judge as middleware: eFLIP and flicker of two images an engine owns (each eye a layer),
//! read where they lie — copied by the judge's own submission, or captured in the engine's
//! command buffer right after its frame — give the figures of judging the renderers that drew
//! them; images the judge cannot read are refused by name.

use foveate::ash::vk;
use foveate::foveation::FoveationConfig;
use foveate::gpu::{Gpu, Image};
use foveate::judge::{reference_config, EyeLayers, GpuFlicker, GpuFlip};
use foveate::metrics::perceptual::Maps;
use foveate::metrics::{Acuity, EyePixels};
use foveate::plan::{RenderConfig, Resolution};
use foveate::render::{output_image_desc, FrameInput, Renderer};
use foveate::scene::default_scene;
use foveate_tests::{assert_validation_clean, gpu};
use glam::Vec2;

/// A renderer whose frames end in an image of the test's own (the engine's), and that image.
fn into_own_image(gpu: &Gpu, config: &RenderConfig) -> (Renderer, Image) {
    let scene = default_scene();
    let config = RenderConfig {
        external_output: true,
        ..config.clone()
    };
    let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
    let image = Image::new(gpu, &output_image_desc(&plan)).unwrap();
    let renderer = Renderer::new(gpu, &plan, &scene).unwrap();
    (renderer, image)
}

/// The image as the judge reads it: a handed-in output stays in `COLOR_ATTACHMENT_OPTIMAL`.
fn eyes_of(image: &Image, size: u32) -> EyeLayers {
    EyeLayers {
        image: image.raw(),
        format: vk::Format::R8G8B8A8_SRGB,
        width: size,
        height: size,
        layout: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
    }
}

/// Judging two images the engine owns gives the figures of judging the renderers that drew
/// them, whether the judge copies them or the engine's command buffer captured them; flicker
/// too. Mutation: the capture copying the reference twice, or the eyes' layers swapped in the
/// copy, fails it.
#[test]
fn the_judge_reads_images_an_engine_owns() {
    let gpu = gpu();
    let scene = default_scene();
    let size = 96;
    let config = RenderConfig {
        resolution: Some(Resolution::square(size)),
        foveation: Some(FoveationConfig::single_frame()),
        ..RenderConfig::default()
    };
    let gaze = Vec2::new(0.3, -0.2);
    let (mut reference, reference_image) = into_own_image(&gpu, &reference_config(&config));
    let (mut test, test_image) = into_own_image(&gpu, &config);
    let (ours, theirs) = (eyes_of(&reference_image, size), eyes_of(&test_image, size));
    let plan = test.plan().clone();
    let pixels = EyePixels::both(&plan, gaze, plan.foveation.as_ref());
    let acuity = Acuity::default();
    let mut flip = GpuFlip::new(&gpu);
    let mut flicker = [
        GpuFlicker::new(&gpu).unwrap(),
        GpuFlicker::new(&gpu).unwrap(),
    ];
    let pool = gpu
        .command_pool(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER)
        .unwrap();
    let (cmd, fence) = (
        gpu.allocate_command_buffer(&pool).unwrap(),
        gpu.fence().unwrap(),
    );
    for frame in 0..3 {
        let head = scene.head * glam::Mat4::from_rotation_y(0.02 * frame as f32);
        let input = |image: &Image| {
            FrameInput::new(head)
                .with_gaze([gaze; 2])
                .with_output(image.raw())
        };
        reference.render(&input(&reference_image)).unwrap();
        // The engine's frame and the capture in one command buffer of its own.
        let device = gpu.device();
        let capture = unsafe {
            device
                .begin_command_buffer(cmd, &vk::CommandBufferBeginInfo::default())
                .unwrap();
            test.record(cmd, &input(&test_image)).unwrap();
            let capture = flip.record_capture(cmd, ours, theirs).unwrap();
            device.end_command_buffer(cmd).unwrap();
            gpu.submit(cmd, &fence).unwrap();
            capture
        };
        gpu.wait(&fence).unwrap();
        let captured = flip
            .captured_errors(&capture, &pixels, acuity, Maps::Drop)
            .unwrap();
        let copied = flip
            .frame_errors(ours, theirs, &pixels, acuity, Maps::Drop)
            .unwrap();
        let renderers = flip
            .frame_errors(&reference, &test, &pixels, acuity, Maps::Drop)
            .unwrap();
        assert_eq!(captured, renderers, "frame {frame}: captured");
        assert_eq!(copied, renderers, "frame {frame}: copied by the judge");
        assert!(renderers.eccentric.unwrap().p99 > 0.0, "something to judge");
        assert!(
            flip.captured_errors(&capture, &pixels, acuity, Maps::Drop)
                .is_err(),
            "a capture another judgement overwrote is refused"
        );
        flicker[0].push(ours, theirs, &pixels).unwrap();
        flicker[1].push(&reference, &test, &pixels).unwrap();
    }
    assert_eq!(flicker[0].summary(), flicker[1].summary());
    drop((reference, test));
    assert_validation_clean(&gpu);
}

/// An image the judge cannot read is refused before anything runs, naming what is wrong:
/// its format, its size against the judge's, an undefined layout.
#[test]
fn images_the_judge_cannot_read_are_refused_by_name() {
    let gpu = gpu();
    let size = 64;
    let config = RenderConfig {
        resolution: Some(Resolution::square(size)),
        ..RenderConfig::default()
    };
    let (mut renderer, image) = into_own_image(&gpu, &config);
    renderer
        .render(&FrameInput::new(default_scene().head).with_output(image.raw()))
        .unwrap();
    let plan = renderer.plan().clone();
    let pixels = EyePixels::both(&plan, Vec2::ZERO, None);
    let good = eyes_of(&image, size);
    let cases = [
        (
            EyeLayers {
                format: vk::Format::B8G8R8A8_UNORM,
                ..good
            },
            "B8G8R8A8_UNORM",
        ),
        (
            EyeLayers {
                width: size / 2,
                ..good
            },
            "the judge's size",
        ),
        (
            EyeLayers {
                layout: vk::ImageLayout::UNDEFINED,
                ..good
            },
            "UNDEFINED",
        ),
    ];
    let mut flip = GpuFlip::new(&gpu);
    for (bad, why) in cases {
        let err = flip
            .frame_errors(good, bad, &pixels, Acuity::default(), Maps::Drop)
            .unwrap_err()
            .to_string();
        assert!(err.contains("test's output") && err.contains(why), "{err}");
    }
    drop(renderer);
    assert_validation_clean(&gpu);
}
