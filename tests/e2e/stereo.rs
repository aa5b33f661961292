use foveate::plan::{RenderConfig, Resolution, StereoMode};
use foveate::scene::{default_scene, uv_sphere, DrawBatch, Instance, Scene};
use foveate::view::FovTangents;
use foveate_tests::{centroid_of_non_background, gpu, render};
use glam::{Mat4, Vec3};

fn config(stereo: StereoMode, msaa: u32) -> RenderConfig {
    RenderConfig {
        stereo,
        msaa,
        resolution: Some(Resolution::square(128)),
        count_fragments: true,
        ..RenderConfig::default()
    }
}

/// The four submission strategies draw the same picture and shade the same fragments.
///
/// Fragment counts match exactly, except one case: at 4× MSAA a clipped triangle is shaded as
/// the fan of sub-triangles the clipper makes, and pixels on the fan's inner edges run the
/// shader once per sub-triangle. The guard band planned for multiview on some drivers clips
/// fewer triangles, so its count is lower by that (bounded) amount — true work, not an error.
#[test]
fn the_four_stereo_modes_agree() {
    let gpu = gpu();
    let scene = default_scene();
    for msaa in [1, 4] {
        let (reference, reference_stats) = render(&gpu, &scene, &config(StereoMode::TwoPass, msaa));
        for stereo in [
            StereoMode::Multiview,
            StereoMode::PerObject,
            StereoMode::Instanced,
        ] {
            let plan = foveate::plan(&scene, &config(stereo, msaa), gpu.caps()).unwrap();
            let (image, stats) = foveate_tests::render_plan(&gpu, &scene, &plan, 1);
            for eye in foveate::view::Eye::BOTH {
                let ssim = reference.eye(eye).ssim(image.eye(eye)).unwrap();
                assert!(
                    ssim > 0.995,
                    "{stereo} MSAA {msaa} {eye:?}: SSIM {ssim} against two-pass"
                );
            }
            let fewer_clips = msaa > 1 && plan.passes.iter().any(|p| p.guard_band > 1);
            assert_eq!(stats.fragments.len(), 2);
            assert_eq!(reference_stats.fragments.len(), 2);
            for (view, (&a, &b)) in reference_stats
                .fragments
                .iter()
                .zip(&stats.fragments)
                .enumerate()
            {
                if fewer_clips {
                    let rel = (a as f64 - b as f64) / a as f64;
                    assert!(
                        (0.0..0.03).contains(&rel),
                        "{stereo} MSAA {msaa} view {view}: {b} vs {a}"
                    );
                } else {
                    assert_eq!(
                        a, b,
                        "{stereo} MSAA {msaa} view {view}: fragments against two-pass"
                    );
                }
            }
        }
    }
}

/// A small sphere straight ahead at 2 m appears shifted by IPD·f/z pixels between the eyes:
/// to the right in the left eye, to the left in the right eye.
#[test]
fn eyes_see_the_expected_disparity() {
    let gpu = gpu();
    let (ipd, depth, size) = (0.064f32, 2.0f32, 128u32);
    let scene = Scene {
        meshes: vec![uv_sphere(48, 24)],
        batches: vec![DrawBatch {
            mesh: 0,
            instances: vec![Instance::new(
                Mat4::from_translation(Vec3::new(0.0, 0.0, -depth))
                    * Mat4::from_scale(Vec3::splat(0.12)),
                Vec3::ONE,
            )],
        }],
        head: Mat4::IDENTITY,
        light_dir: Vec3::new(0.0, 0.0, -1.0),
        materials: Vec::new(),
        lights: Vec::new(),
        reach: None,
    };
    let tan = 1.0;
    let config = RenderConfig {
        msaa: 1,
        resolution: Some(Resolution::square(size)),
        ipd_m: Some(ipd),
        fov: Some(FovTangents {
            left: tan,
            right: tan,
            up: tan,
            down: tan,
        }),
        ..RenderConfig::default()
    };
    let (image, _) = render(&gpu, &scene, &config);
    let sky = image.left.pixel(0, 0);
    let (lx, ly) =
        centroid_of_non_background(&image.left, sky, 8).expect("sphere visible in the left eye");
    let (rx, ry) =
        centroid_of_non_background(&image.right, sky, 8).expect("sphere visible in the right eye");
    let focal_px = size as f64 / (2.0 * tan as f64);
    let expected = ipd as f64 * focal_px / depth as f64;
    let measured = lx - rx;
    assert!(
        (measured - expected).abs() < 0.15,
        "disparity {measured:.3} px, expected {expected:.3} px"
    );
    assert!(
        lx > size as f64 / 2.0 && rx < size as f64 / 2.0,
        "left {lx}, right {rx}"
    );
    assert!(
        (ly - ry).abs() < 0.05,
        "no vertical disparity: {ly} vs {ry}"
    );
}

/// A renderer given a plan made for another scene refuses it with an error naming both
/// instance counts (it used to panic writing the culled ids into a buffer sized for the
/// planned scene). Mutation: removing the check in `Renderer::new` panics here.
#[test]
fn a_plan_for_another_scene_is_an_error() {
    let gpu = gpu();
    let small = foveate::scene::Scene::empty();
    let scene = default_scene();
    let config = RenderConfig {
        culling: Some(foveate::plan::CullConfig::THESIS),
        stereo: StereoMode::TwoPass,
        ..config(StereoMode::TwoPass, 1)
    };
    let plan = foveate::plan(&small, &config, gpu.caps()).unwrap();
    let err = foveate::render::Renderer::new(&gpu, &plan, &scene)
        .err()
        .expect("refused");
    let text = err.to_string();
    assert!(
        text.contains(&format!("{} instances", scene.instance_count()))
            && text.contains("(0 instances)"),
        "{text}"
    );
}

/// Reading back before rendering is an error, not a panic.
#[test]
fn readback_before_any_frame_is_an_error() {
    let gpu = gpu();
    let scene = default_scene();
    let plan = foveate::plan(&scene, &config(StereoMode::Multiview, 1), gpu.caps()).unwrap();
    let mut renderer = foveate::render::Renderer::new(&gpu, &plan, &scene).unwrap();
    assert!(matches!(
        renderer.readback(),
        Err(foveate::gpu::GpuError::NoFrameRendered)
    ));
}

/// A switched-off effect records and allocates nothing: no counter, no timestamps. A timed
/// frame (the default) has timestamps and no counts; its counting twin has counts and no
/// timestamps. Mutation: counting on by default fails it.
#[test]
fn switched_off_effects_measure_nothing() {
    let gpu = gpu();
    let scene = default_scene();
    let off = RenderConfig {
        timestamps: false,
        ..RenderConfig::default()
    };
    let (_, stats) = render(&gpu, &scene, &off);
    assert!(stats.fragments.is_empty() && stats.steps.is_empty() && stats.gpu_ms.is_none());
    let timed = RenderConfig {
        resolution: Some(Resolution::square(128)),
        ..RenderConfig::default()
    };
    let (_, stats) = render(&gpu, &scene, &timed);
    assert!(stats.fragments.is_empty() && stats.steps.is_empty());
    assert!(
        stats.gpu_ms.is_some_and(|t| t > 0.0) && stats.frame_ms > 0.0 && stats.cpu_record_ms > 0.0
    );
    let (_, stats) = render(&gpu, &scene, &timed.counting());
    assert_eq!(stats.fragments.len(), 2);
    assert!(stats.gpu_ms.is_none() && stats.total_fragments() > 0);
}

/// Canted and asymmetric eyes render through every mode alike, too.
#[test]
fn canted_asymmetric_eyes_agree_across_modes() {
    let gpu = gpu();
    let scene = default_scene();
    let canted = |stereo| RenderConfig {
        hmd: "rift-cv1".into(),
        cant_deg: Some(10.0),
        ..config(stereo, 1)
    };
    let (reference, _) = render(&gpu, &scene, &canted(StereoMode::Multiview));
    let (two_pass, _) = render(&gpu, &scene, &canted(StereoMode::TwoPass));
    let (instanced, _) = render(&gpu, &scene, &canted(StereoMode::Instanced));
    assert!(reference.right.ssim(&two_pass.right).unwrap() > 0.995);
    assert!(reference.left.ssim(&instanced.left).unwrap() > 0.995);
}
