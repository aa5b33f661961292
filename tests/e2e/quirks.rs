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
        materials: Vec::new(),
        lights: Vec::new(),
        reach: None,
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

/// Two-pass stereo into one layered image, each eye pass writing its own layer. Without MSAA
/// there is no resolve, so every driver renders it right: the layered frame equals the
/// multiview frame. With 4× MSAA, `layered_resolve_ignores_base_layer` is measured, not
/// assumed: planned without the quirk, a driver that has it resolves the right eye into layer
/// 0, so the right eye stays empty (sky) while planned with it (one image per eye) the frame is
/// right. Mutation: a two-pass layered plan resolving both eyes into layer 0, or a quirk the
/// driver no longer has, fails it.
#[test]
fn layered_two_pass_and_the_resolve_quirk() {
    let gpu = gpu();
    let scene = foveate::scene::default_scene();
    let config = |stereo, msaa| RenderConfig {
        stereo,
        msaa,
        resolution: Some(Resolution::square(64)),
        ..RenderConfig::default()
    };
    let mut unquirked = gpu.caps().clone();
    unquirked.quirks.layered_resolve_ignores_base_layer = false;
    let layered = foveate::plan(&scene, &config(StereoMode::TwoPass, 1), &unquirked).unwrap();
    assert_eq!(layered.layout, foveate::plan::TargetLayout::Layered);
    let (image, _) = render_plan(&gpu, &scene, &layered, 1);
    let multiview = foveate::plan(&scene, &config(StereoMode::Multiview, 1), gpu.caps()).unwrap();
    let (reference, _) = render_plan(&gpu, &scene, &multiview, 1);
    for eye in foveate::view::Eye::BOTH {
        let ssim = reference.eye(eye).ssim(image.eye(eye)).unwrap();
        assert!(ssim > 0.995, "{eye:?}: layered two-pass SSIM {ssim}");
    }

    let quirk = gpu.caps().quirks.layered_resolve_ignores_base_layer;
    let at_4x = foveate::plan(&scene, &config(StereoMode::TwoPass, 4), &unquirked).unwrap();
    let (unguarded, _) = render_plan(&gpu, &scene, &at_4x, 1);
    let planned = foveate::plan(&scene, &config(StereoMode::TwoPass, 4), gpu.caps()).unwrap();
    let (right, _) = render_plan(&gpu, &scene, &planned, 1);
    assert_eq!(
        planned.layout == foveate::plan::TargetLayout::PerEye,
        quirk,
        "the plan reads the quirk"
    );
    let right_eye_ssim = right.right.ssim(&unguarded.right).unwrap();
    if quirk {
        assert!(
            right_eye_ssim < 0.9,
            "{}: the quirk no longer shows (right eye SSIM {right_eye_ssim}); drop it",
            gpu.info().driver
        );
    } else {
        assert!(
            right_eye_ssim > 0.995,
            "{}: the right eye's resolve lands elsewhere; add the quirk",
            gpu.info().driver
        );
    }
}
