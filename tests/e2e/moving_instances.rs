//! A scene that moves: an instance moved between frames is drawn, culled and counted where it
//! now stands — the frame equals, pixel for pixel and instance for instance, the frame of a
//! renderer made with the instance there from the start; instances removed and added within
//! the room the plan made likewise.

use foveate::cull::Strategy;
use foveate::plan::{CullConfig, RenderConfig, Resolution, MAX_SPARE_INSTANCES};
use foveate::render::Renderer;
use foveate::scene::{default_scene, DrawBatch, Instance, Scene};
use foveate_tests::{assert_validation_clean, gpu, mesh_of, visible_instance};
use glam::{Mat4, Vec3};

fn config(culling: Option<CullConfig>) -> RenderConfig {
    RenderConfig {
        resolution: Some(Resolution::square(96)),
        moving_instances: true,
        culling,
        ..RenderConfig::default()
    }
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

/// `scene` without instance `index` (draw order), and with `added` of the same mesh, drawn
/// in a batch of its own.
fn changed(scene: &Scene, index: usize, added: &[Instance]) -> Scene {
    let mut scene = scene.clone();
    let mut left = index;
    let mut mesh = None;
    for batch in &mut scene.batches {
        if left < batch.instances.len() {
            batch.instances.remove(left);
            mesh = Some(batch.mesh);
            break;
        }
        left -= batch.instances.len();
    }
    scene.batches.push(DrawBatch {
        mesh: mesh.expect("instance found"),
        instances: added.to_vec(),
    });
    scene
}

/// Two spare instances per mesh: absent, they change nothing in the image or the counts; an
/// instance removed leaves the image and the drawn sets, one added shows where it was put —
/// each frame equal, pixel for pixel and instance for instance, to a renderer made for the
/// scene as it then stands. The room is what the plan made plus what removals freed; past
/// it, adding is an error naming the field. Mutations: absent instances drawn (the spares at
/// the origin, or the removed one), or culling not told which are absent, each fail.
#[test]
fn instances_come_and_go_within_the_room_the_plan_made() {
    let gpu = gpu();
    let scene = default_scene();
    let index = visible_instance(&scene);
    let mesh = mesh_of(&scene, index);
    let original = scene.flat_instances()[index];
    let mut moved = original;
    moved.model = Mat4::from_translation(Vec3::new(0.4, 0.2, 0.0)) * original.model;
    let culled = CullConfig {
        strategy: Strategy::Superfrustum,
        draw_distance: 100.0,
    };
    for base in [config(None), config(Some(culled))] {
        let config = RenderConfig {
            spare_instances: 2,
            ..base.clone()
        };
        let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
        assert_eq!(
            plan.scene_instances,
            scene.instance_count() + 2 * scene.meshes.len()
        );
        let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
        let frame_equals = |renderer: &mut Renderer, expected: &Scene, what: &str| {
            let stats = renderer.render_frame(scene.head).unwrap();
            let plan = foveate::plan(expected, &base, gpu.caps()).unwrap();
            let mut reference = Renderer::new(&gpu, &plan, expected).unwrap();
            let wanted = reference.render_frame(expected.head).unwrap();
            assert!(
                renderer.readback().unwrap() == reference.readback().unwrap(),
                "{what}: the image"
            );
            assert_eq!(stats.instances_drawn, wanted.instances_drawn, "{what}");
        };
        frame_equals(&mut renderer, &scene, "spares absent");
        renderer.remove_instance(index).unwrap();
        frame_equals(&mut renderer, &changed(&scene, index, &[]), "removed");
        let added = renderer.add_instance(mesh, moved).unwrap();
        assert!(added >= scene.instance_count(), "a spare first: {added}");
        frame_equals(&mut renderer, &changed(&scene, index, &[moved]), "added");
        renderer.add_instance(mesh, moved).unwrap();
        // The third goes where the removed instance was; then there is no room.
        assert_eq!(renderer.add_instance(mesh, original).unwrap(), index);
        let full = renderer
            .add_instance(mesh, original)
            .unwrap_err()
            .to_string();
        assert!(full.contains("spare_instances"), "{full}");
        let twice = renderer
            .remove_instance(added)
            .and_then(|()| renderer.remove_instance(added));
        assert!(twice.unwrap_err().to_string().contains("instance"));
        let bad_mesh = renderer
            .add_instance(scene.meshes.len(), original)
            .unwrap_err();
        assert!(bad_mesh.to_string().contains("mesh"), "{bad_mesh}");
    }
    assert_validation_clean(&gpu);
}

/// Spare instances without moving instances, or more than the limit, are refused by the plan.
#[test]
fn spare_instances_are_checked_by_the_plan() {
    let gpu = gpu();
    let scene = default_scene();
    for (moving_instances, spare_instances) in [(false, 1), (true, MAX_SPARE_INSTANCES + 1)] {
        let config = RenderConfig {
            moving_instances,
            spare_instances,
            ..config(None)
        };
        let error = foveate::plan(&scene, &config, gpu.caps()).unwrap_err();
        assert!(error.to_string().contains("spare_instances"), "{error}");
    }
}
