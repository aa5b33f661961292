//! Frames into output images handed in per frame (what `foveate xr` does with an OpenXR
//! runtime's swapchain images), per-frame eyes within the plan, and the HMD mask from a
//! runtime's hidden-area mesh — on lavapipe, no runtime needed: the images are made here as
//! a runtime would make them (`output_image_desc`).

use foveate::foveation::{FoveationConfig, TemporalConfig};
use foveate::gpu::{Gpu, Image};
use foveate::mffr::MffrConfig;
use foveate::plan::{RenderConfig, Resolution};
use foveate::render::{output_image_desc, Renderer, StereoImage};
use foveate::scene::{default_scene, Scene};
use foveate::view::{Eye, FovTangents, HiddenArea};
use foveate_tests::{assert_validation_clean, gpu};
use glam::{Mat4, Vec2, Vec3};

fn small(config: RenderConfig) -> RenderConfig {
    RenderConfig {
        resolution: Some(Resolution::square(96)),
        ..config
    }
}

fn reference(gpu: &Gpu, scene: &Scene, config: &RenderConfig, head: Mat4) -> StereoImage {
    let plan = foveate::plan(scene, config, gpu.caps()).unwrap();
    let mut renderer = Renderer::new(gpu, &plan, scene).unwrap();
    renderer.render_frame(head).unwrap();
    renderer.readback().unwrap()
}

/// Two frames into two handed-in images, each with its own head pose: each image holds its own
/// frame, pixel for pixel what a renderer with its own image makes. Mutation: ignoring
/// `select_output` leaves the second frame in the first image.
#[test]
fn each_frame_lands_in_the_image_selected_for_it() {
    let gpu = gpu();
    let scene = default_scene();
    let heads = [
        scene.head,
        scene.head * Mat4::from_translation(Vec3::new(0.3, 0.0, -0.5)),
    ];
    let configs = [
        RenderConfig::default(),
        RenderConfig {
            foveation: Some(FoveationConfig::single_frame()),
            hmd_mask: true,
            ..RenderConfig::default()
        },
        RenderConfig {
            mffr: Some(MffrConfig::default()),
            ..RenderConfig::default()
        },
    ];
    for config in configs.map(small) {
        let external = RenderConfig {
            external_output: true,
            ..config.clone()
        };
        let plan = foveate::plan(&scene, &external, gpu.caps()).unwrap();
        let desc = output_image_desc(&plan);
        let images: Vec<Image> = (0..2).map(|_| Image::new(&gpu, &desc).unwrap()).collect();
        let raw: Vec<_> = images.iter().map(|i| i.raw()).collect();
        let mut renderer = Renderer::with_output_images(&gpu, &plan, &scene, &raw).unwrap();
        for (index, head) in heads.iter().enumerate() {
            renderer.select_output(index).unwrap();
            renderer.render_frame(*head).unwrap();
        }
        for (index, head) in heads.iter().enumerate() {
            renderer.select_output(index).unwrap();
            let got = renderer.readback().unwrap();
            let want = reference(&gpu, &scene, &config, *head);
            assert!(
                got == want,
                "image {index} of {:?} differs from its frame",
                plan.to_string().lines().next()
            );
        }
        assert!(
            renderer.select_output(2).is_err(),
            "only two images were handed in"
        );
        drop(renderer);
        assert_validation_clean(&gpu);
    }
}

/// Frames accumulating the periphery, each into the next of three handed-in images (so an
/// image's frames alternate between the history pair's roles): each frame is pixel for pixel
/// the frame a renderer with its own image makes, the history carried across images.
/// Mutation: odd frames recording the even frames' output pass (the history pair unswapped)
/// fails it.
#[test]
fn accumulation_carries_its_history_across_handed_in_images() {
    let gpu = gpu();
    let scene = default_scene();
    let config = small(RenderConfig {
        msaa: 1,
        foveation: Some(FoveationConfig {
            periphery_density: Some(0.5),
            periphery_temporal: Some(TemporalConfig::default()),
            ..FoveationConfig::single_frame()
        }),
        ..RenderConfig::default()
    });
    let heads: Vec<Mat4> = (0..6)
        .map(|i| scene.head * Mat4::from_rotation_y(0.01 * i as f32))
        .collect();
    let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
    let mut own = Renderer::new(&gpu, &plan, &scene).unwrap();
    let external = RenderConfig {
        external_output: true,
        ..config.clone()
    };
    let plan = foveate::plan(&scene, &external, gpu.caps()).unwrap();
    let desc = output_image_desc(&plan);
    let images: Vec<Image> = (0..3).map(|_| Image::new(&gpu, &desc).unwrap()).collect();
    let raw: Vec<_> = images.iter().map(|i| i.raw()).collect();
    let mut handed = Renderer::with_output_images(&gpu, &plan, &scene, &raw).unwrap();
    for (frame, head) in heads.iter().enumerate() {
        own.render_frame(*head).unwrap();
        handed.select_output(frame % 3).unwrap();
        handed.render_frame(*head).unwrap();
        assert!(
            own.readback().unwrap() == handed.readback().unwrap(),
            "frame {frame} differs in handed-in image {}",
            frame % 3
        );
    }
    drop((own, handed));
    assert_validation_clean(&gpu);
}

/// Eyes narrower than the plan's render without a new plan (and change the image); a wider
/// field or IPD is refused, naming what outgrew the plan.
#[test]
fn per_frame_eyes_within_the_plan_need_no_replan() {
    let gpu = gpu();
    let scene = default_scene();
    let config = small(RenderConfig::default());
    let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
    let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
    renderer.render_frame(scene.head).unwrap();
    let planned = renderer.readback().unwrap();
    let narrow = |f: FovTangents| FovTangents {
        left: f.left * 0.8,
        ..f
    };
    let eyes = foveate::view::EyeParams {
        left_fov: narrow(plan.eyes.left_fov),
        right_fov: narrow(plan.eyes.right_fov),
        ipd_m: plan.eyes.ipd_m * 0.9,
        ..plan.eyes
    };
    renderer.set_eyes(eyes).unwrap();
    renderer.render_frame(scene.head).unwrap();
    assert!(
        renderer.readback().unwrap() != planned,
        "the narrower eyes were not used"
    );
    let wide = foveate::view::EyeParams {
        right_fov: FovTangents {
            up: plan.eyes.right_fov.up * 1.1,
            ..plan.eyes.right_fov
        },
        ..plan.eyes
    };
    assert_eq!(renderer.set_eyes(wide).unwrap_err().field, "right fov");
    let far_apart = foveate::view::EyeParams {
        ipd_m: plan.eyes.ipd_m + 0.005,
        ..plan.eyes
    };
    assert_eq!(renderer.set_eyes(far_apart).unwrap_err().field, "ipd");
    drop(renderer);
    assert_validation_clean(&gpu);
}

/// A hidden-area mesh covering the left eye's lower-left quarter masks exactly that: the
/// quarter shows only the clear colour, and nothing outside it changes. Mutation: a mesh the
/// renderer ignores leaves the scene in the quarter.
#[test]
fn the_hidden_area_mesh_masks_what_it_covers() {
    let gpu = gpu();
    let scene = default_scene();
    let config = small(RenderConfig {
        hmd_mask: true,
        hidden_area_mesh: true,
        ..RenderConfig::default()
    });
    let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
    let render = |areas: [HiddenArea; 2]| {
        let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
        renderer.set_hidden_area(areas).unwrap();
        renderer.render_frame(scene.head).unwrap();
        renderer.readback().unwrap()
    };
    let none = || HiddenArea {
        triangles: Vec::new(),
    };
    // The left eye's lower-left quarter in its tangent space (x right, y up).
    let f = plan.eyes.fov(Eye::Left);
    let (x0, x1) = (-f.left, (f.right - f.left) / 2.0);
    let (y0, y1) = (-f.down, (f.up - f.down) / 2.0);
    let corner = |x, y| Vec2::new(x, y);
    let quarter = HiddenArea::from_indexed(
        &[
            corner(x0, y0),
            corner(x1, y0),
            corner(x1, y1),
            corner(x0, y1),
        ],
        &[0, 1, 2, 0, 2, 3],
    )
    .unwrap();
    assert!((quarter.hidden_fraction(f) - 0.25).abs() < 1e-6);
    let open = render([none(), none()]);
    let masked = render([quarter, none()]);
    assert_validation_clean(&gpu);
    assert!(masked.right == open.right, "the right eye has no mesh");
    let (w, h) = (open.left.width, open.left.height);
    let px = |img: &foveate::metrics::RgbaImage, x: u32, y: u32| {
        let i = ((y * w + x) * 4) as usize;
        img.data[i..i + 4].to_vec()
    };
    let sky = px(&masked.left, 0, h - 1);
    let mut scene_in_quarter = 0;
    for y in 0..h {
        for x in 0..w {
            let in_quarter = x < w / 2 && y >= h / 2;
            if in_quarter {
                assert_eq!(
                    px(&masked.left, x, y),
                    sky,
                    "pixel ({x}, {y}) under the mesh"
                );
                scene_in_quarter += (px(&open.left, x, y) != sky) as u32;
            } else {
                assert_eq!(
                    px(&masked.left, x, y),
                    px(&open.left, x, y),
                    "pixel ({x}, {y}) outside the mesh"
                );
            }
        }
    }
    assert!(
        scene_in_quarter > w * h / 16,
        "the open quarter shows the scene ({scene_in_quarter} px)"
    );
}
