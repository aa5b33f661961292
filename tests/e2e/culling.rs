//! Per-frame culling in the renderer: conservative (a culled frame is the unculled frame),
//! really culling (fewer instances drawn), per eye in two-pass stereo, and distance culling at
//! the draw distance.

use foveate::cull::Strategy;
use foveate::plan::{CullConfig, DrawSet, RenderConfig, StereoMode};
use foveate::scene::{rail_pose, Scene, ThesisScene};
use foveate_tests::{gpu, render};

fn thesis() -> Scene {
    let thesis = ThesisScene::new(0.01).unwrap();
    let mut scene = thesis.to_scene();
    scene.head = rail_pose(400, thesis.extent());
    scene
}

fn config(stereo: StereoMode, culling: Option<CullConfig>) -> RenderConfig {
    RenderConfig {
        resolution: Some(foveate::plan::Resolution::square(96)),
        stereo,
        msaa: 1,
        far: 1000.0,
        count_fragments: false,
        culling,
        ..RenderConfig::default()
    }
}

#[test]
fn culled_frames_equal_unculled_frames_and_draw_fewer_instances() {
    let gpu = gpu();
    let scene = thesis();
    let total = scene.instance_count() as u64;
    for stereo in [StereoMode::Multiview, StereoMode::TwoPass] {
        for strategy in [
            Strategy::PerEye,
            Strategy::Superfrustum,
            Strategy::DualCone,
            Strategy::DualEllipticalCone,
        ] {
            // Lens-region culling is compared under the HMD mask it requires; with the mask the
            // culled frame is still the unculled (masked) frame, pixel for pixel.
            let hmd_mask = strategy.culls_to_lens();
            let unculled = RenderConfig {
                hmd_mask,
                ..config(stereo, None)
            };
            let (reference, all) = render(&gpu, &scene, &unculled);
            assert!(all.instances_drawn.iter().all(|&n| n == total));
            let culling = CullConfig {
                strategy,
                draw_distance: 900.0,
            };
            let culled = RenderConfig {
                hmd_mask,
                ..config(stereo, Some(culling))
            };
            let (image, stats) = render(&gpu, &scene, &culled);
            assert_eq!(image, reference, "{stereo} {}", strategy.name());
            assert!(
                stats.instances_drawn.iter().all(|&n| n > 0 && n < total),
                "{stereo} {}: {:?} of {total}",
                strategy.name(),
                stats.instances_drawn
            );
            assert!(stats.triangles < all.triangles && stats.draw_calls > 0);
        }
    }
}

/// Lens-region culling without the HMD mask would drop objects the frame still shows: it is
/// refused with an error naming the field. Mutation: removing the check lets the plan through.
#[test]
fn lens_region_culling_needs_the_hmd_mask() {
    let scene = thesis();
    let caps = gpu().caps().clone();
    for strategy in [Strategy::DualCone, Strategy::DualEllipticalCone] {
        let culling = Some(CullConfig {
            strategy,
            draw_distance: 900.0,
        });
        let error =
            foveate::plan(&scene, &config(StereoMode::Multiview, culling), &caps).unwrap_err();
        assert_eq!(error.field, "culling");
        assert!(error.to_string().contains("HMD mask"), "{error}");
    }
}

#[test]
fn two_pass_per_eye_culling_draws_each_eye_its_own_set() {
    let gpu = gpu();
    let scene = thesis();
    let per_eye = config(StereoMode::TwoPass, Some(CullConfig::THESIS));
    let plan = foveate::plan(&scene, &per_eye, gpu.caps()).unwrap();
    let sets: Vec<DrawSet> = plan.passes.iter().filter_map(|p| p.draw_set()).collect();
    assert_eq!(
        sets,
        [
            DrawSet::VisibleToEye(foveate::view::Eye::Left),
            DrawSet::VisibleToEye(foveate::view::Eye::Right)
        ]
    );
    let (_, eyes) = render(&gpu, &scene, &per_eye);
    let superfrustum = CullConfig {
        strategy: Strategy::Superfrustum,
        ..CullConfig::THESIS
    };
    let (_, shared) = render(
        &gpu,
        &scene,
        &config(StereoMode::TwoPass, Some(superfrustum)),
    );
    // One superfrustum set drawn by both passes; each eye's own set lies within it.
    assert_eq!(shared.instances_drawn[0], shared.instances_drawn[1]);
    let within = |&n: &u64| n > 0 && n <= shared.instances_drawn[0];
    assert!(eyes.instances_drawn.iter().all(within), "{eyes:?}");
}

#[test]
fn nothing_beyond_the_draw_distance_is_drawn() {
    let gpu = gpu();
    let scene = thesis();
    let near = |d| {
        config(
            StereoMode::Multiview,
            Some(CullConfig {
                strategy: Strategy::PerEye,
                draw_distance: d,
            }),
        )
    };
    let (_, short) = render(&gpu, &scene, &near(5.0));
    let (_, long) = render(&gpu, &scene, &near(60.0));
    assert!(short.instances_drawn[0] < long.instances_drawn[0]);
    let error = foveate::plan(&scene, &near(f32::NAN), gpu.caps()).unwrap_err();
    assert_eq!(error.field, "draw distance");
}
