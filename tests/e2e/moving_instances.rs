//! A scene that moves: an instance moved between frames is drawn, culled and counted where it
//! now stands — the frame equals, pixel for pixel and instance for instance, the frame of a
//! renderer made with the instance there from the start.

use foveate::cull::Strategy;
use foveate::plan::{CullConfig, RenderConfig, Resolution};
use foveate::render::Renderer;
use foveate::scene::{default_scene, Scene};
use foveate_tests::{assert_validation_clean, gpu};
use glam::{Mat4, Vec3};

fn config(culling: Option<CullConfig>) -> RenderConfig {
    RenderConfig {
        resolution: Some(Resolution::square(96)),
        moving_instances: true,
        culling,
        ..RenderConfig::default()
    }
}

/// The instance nearest the head in front of it (so it shows), by its index in draw order.
fn visible_instance(scene: &Scene) -> usize {
    let head = scene.head.inverse();
    let spheres = scene.instance_spheres();
    (0..spheres.len())
        .filter(|&i| head.transform_point3(spheres[i].center).z < -1.0)
        .min_by(|&a, &b| {
            let d = |i: usize| head.transform_point3(spheres[i].center).length();
            d(a).total_cmp(&d(b))
        })
        .expect("something in front of the head")
}

/// `scene` with instance `index` (draw order) at `model`.
fn placed(scene: &Scene, index: usize, model: Mat4) -> Scene {
    let mut scene = scene.clone();
    let mut left = index;
    for batch in &mut scene.batches {
        if left < batch.instances.len() {
            batch.instances[left].model = model;
            return scene;
        }
        left -= batch.instances.len();
    }
    panic!("no instance {index}");
}

/// Moved behind the head (mirrored through it) the instance leaves the image and, culled,
/// the drawn set; moved beside where it was it shows there. Each frame equals a renderer's
/// made with the instance there from the start. Mutations: not writing the moved instances
/// leaves the image unmoved; not placing them again for culling keeps culling the instance at
/// its old place (one instance too many drawn, and the one moved into view missing).
#[test]
fn an_instance_moved_between_frames_moves_in_the_image_and_in_culling() {
    let gpu = gpu();
    let scene = default_scene();
    let index = visible_instance(&scene);
    let model = scene.flat_instances()[index].model;
    let head = scene.head.w_axis.truncate();
    let centre = model.w_axis.truncate();
    let moves = [
        Mat4::from_translation(2.0 * (head - centre)) * model,
        Mat4::from_translation(Vec3::new(0.4, 0.2, 0.0)) * model,
    ];
    let culled = CullConfig {
        strategy: Strategy::Superfrustum,
        draw_distance: 100.0,
    };
    for config in [config(None), config(Some(culled))] {
        let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
        let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
        let before = renderer.render_frame(scene.head).unwrap();
        let unmoved = renderer.readback().unwrap();
        for to in moves {
            renderer.move_instance(index, to).unwrap();
            let moved = renderer.render_frame(scene.head).unwrap();
            let image = renderer.readback().unwrap();
            let there = placed(&scene, index, to);
            let there_plan = foveate::plan(&there, &config, gpu.caps()).unwrap();
            assert_eq!(
                there_plan, plan,
                "the move changes nothing the plan decides"
            );
            let mut reference = Renderer::new(&gpu, &there_plan, &there).unwrap();
            let expected = reference.render_frame(there.head).unwrap();
            assert!(image != unmoved, "the instance moved in the image");
            assert!(
                image == reference.readback().unwrap(),
                "drawn where it stands"
            );
            assert_eq!(moved.instances_drawn, expected.instances_drawn);
            if config.culling.is_some() && to == moves[0] {
                let total =
                    |s: &foveate::render::FrameStats| -> u64 { s.instances_drawn.iter().sum() };
                assert_eq!(total(&moved) + 1, total(&before), "culled behind the head");
            }
        }
    }
    assert_validation_clean(&gpu);
}

/// Moving an instance that does not exist, to a matrix that is not finite, or in a plan whose
/// instances stay put is an error naming it; nothing moves.
#[test]
fn bad_moves_are_refused() {
    let gpu = gpu();
    let scene = default_scene();
    let plan = foveate::plan(&scene, &config(None), gpu.caps()).unwrap();
    let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
    let count = scene.instance_count();
    let error = renderer.move_instance(count, Mat4::IDENTITY).unwrap_err();
    assert!(error.to_string().contains(&count.to_string()), "{error}");
    let mut nan = Mat4::IDENTITY;
    nan.w_axis.x = f32::NAN;
    let error = renderer.move_instance(0, nan).unwrap_err();
    assert!(error.to_string().contains("model"), "{error}");
    let still = RenderConfig {
        moving_instances: false,
        ..config(None)
    };
    let plan = foveate::plan(&scene, &still, gpu.caps()).unwrap();
    assert!(
        plan.moving_instances().is_none(),
        "a still scene keeps one instance buffer"
    );
    let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
    let error = renderer.move_instance(0, Mat4::IDENTITY).unwrap_err();
    assert!(error.to_string().contains("moving_instances"), "{error}");
}
