use foveate::plan::{RenderConfig, Resolution, StereoMode};
use foveate::scene::{ground_quad, DrawBatch, Instance, Scene};
use foveate::view::look_at_head;
use foveate_tests::{gpu, render_plan};
use glam::{Mat4, Quat, Vec3};

/// A wall in front of the viewer, wider than the view: every triangle crosses the viewport's
/// left or right edge, so the driver has to clip all of them.
fn wide_wall() -> Scene {
    let model = Mat4::from_scale_rotation_translation(
        Vec3::new(13.0, 1.0, 2.0),
        Quat::from_rotation_x(std::f32::consts::FRAC_PI_2),
        Vec3::new(0.0, 1.6, -5.0),
    );
    Scene {
        meshes: vec![ground_quad()],
        batches: vec![DrawBatch {
            mesh: 0,
            instances: vec![Instance::new(model, Vec3::ONE)],
        }],
        head: look_at_head(Vec3::new(0.0, 1.6, 0.0), Vec3::new(0.0, 1.3, -10.0)),
        light_dir: -Vec3::Y,
    }
}

/// `multiview_clipping_drops_views` is measured, not assumed: without the guard band a driver
/// with the quirk loses view 1's clipped triangles (they land in layer 0), with it multiview
/// matches two-pass exactly; a driver without the quirk gets no guard band and loses nothing.
#[test]
fn lavapipe_multiview_clipping_quirk_is_real() {
    let gpu = gpu();
    let scene = wide_wall();
    let config = |stereo| RenderConfig {
        stereo,
        msaa: 1,
        resolution: Some(Resolution::square(64)),
        count_fragments: true,
        ..RenderConfig::default()
    };
    let two_pass = foveate::plan(&scene, &config(StereoMode::TwoPass), gpu.caps()).unwrap();
    let (_, reference) = render_plan(&gpu, &scene, &two_pass, 1);
    let planned = foveate::plan(&scene, &config(StereoMode::Multiview), gpu.caps()).unwrap();
    let (_, as_planned) = render_plan(&gpu, &scene, &planned, 1);
    assert_eq!(
        as_planned.fragments, reference.fragments,
        "planned multiview matches two-pass"
    );

    let quirk = gpu.caps().quirks.multiview_clipping_drops_views;
    assert_eq!(planned.passes[0].guard_band > 1, quirk);
    let mut unguarded = planned.clone();
    unguarded.passes[0].guard_band = 1;
    let (_, without_guard) = render_plan(&gpu, &scene, &unguarded, 1);
    let (expected, got) = (reference.fragments[1], without_guard.fragments[1]);
    if quirk {
        assert!(
            got < expected / 2,
            "{}: the quirk no longer shows ({got} of {expected}); drop it",
            gpu.info().driver
        );
    } else {
        assert_eq!(
            got,
            expected,
            "{}: multiview loses view-1 fragments; add the quirk",
            gpu.info().driver
        );
    }
}
