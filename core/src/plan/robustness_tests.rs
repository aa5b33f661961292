//! Input never panics the planner or the per-frame foveation maths: every configuration plans
//! or is refused with an error, and every plan's fovea windows are finite and inside their
//! periphery for every gaze the renderer accepts. (The GPU half of the fuzzing, a frame
//! rendered from each configuration, is in the end-to-end tests.)

use std::sync::OnceLock;

use glam::Vec2;
use proptest::prelude::*;

use super::*;
use crate::foveation::{check_gaze, fovea_views, FoveationConfig, PeripheryFilter, TemporalConfig};
use crate::mffr::{MffrConfig, SplitDistance};
use crate::scene::{default_scene, Scene};
use crate::view::HMD_PROFILES;

fn scene() -> &'static Scene {
    static SCENE: OnceLock<Scene> = OnceLock::new();
    SCENE.get_or_init(default_scene)
}

fn foveated(hmd: &str, resolution: Option<Resolution>, ratio: f32) -> RenderConfig {
    RenderConfig {
        hmd: hmd.into(),
        resolution,
        foveation: Some(FoveationConfig {
            ratio,
            ..FoveationConfig::single_frame()
        }),
        ..RenderConfig::default()
    }
}

/// A plan's fovea windows for `gaze`: finite, of positive size, and inside each eye's
/// periphery (to a millionth of its extent: they are snapped to whole pixels in `f32`).
fn assert_windows_inside(plan: &FramePlan, gaze: Vec2) -> Result<(), TestCaseError> {
    let Some(g) = plan.foveation else {
        return Ok(());
    };
    let screen = (plan.eye_resolution.width, plan.eye_resolution.height);
    let windows = fovea_views(&plan.eyes, g.ratio, [gaze; 2], screen);
    for (eye, w) in crate::view::Eye::BOTH.into_iter().zip(windows) {
        let p = plan.eyes.fov(eye);
        let slack = 1e-6 * (p.left + p.right + p.up + p.down);
        prop_assert!(w.as_array().iter().all(|t| t.is_finite()), "{w:?}");
        prop_assert!(w.left + w.right > 0.0 && w.up + w.down > 0.0, "{w:?}");
        prop_assert!(
            w.left <= p.left + slack
                && w.right <= p.right + slack
                && w.up <= p.up + slack
                && w.down <= p.down + slack,
            "window {w:?} leaves periphery {p:?}"
        );
    }
    Ok(())
}

/// The cases that panicked: a fovea view that rounds to the full resolution (ratio 1 on the
/// index, vive and rift-cv1 profiles; 0.999 at 128 pixels). Negative control: `f32::clamp` in
/// place of `clamp_inside` in `fovea_tangents` panics here.
#[test]
fn a_fovea_as_large_as_the_view_plans_and_places_its_window() {
    for (hmd, res, ratio) in [
        ("index", None, 1.0),
        ("vive", None, 1.0),
        ("rift-cv1", None, 1.0),
        ("index", Some(Resolution::square(128)), 0.999),
    ] {
        let plan = plan(scene(), &foveated(hmd, res, ratio), &tests::caps())
            .unwrap_or_else(|e| panic!("{hmd} {ratio}: {e}"));
        for gaze in [Vec2::ZERO, Vec2::ONE, Vec2::new(-1.0, 0.3)] {
            assert_windows_inside(&plan, gaze).unwrap();
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(5000))]

    /// Ratio × resolution × profile × gaze: a plan or an error, and windows inside.
    #[test]
    fn every_ratio_resolution_and_profile_plans_or_errs_with_windows_inside(
        profile in 0..HMD_PROFILES.len(),
        ratio in prop_oneof![0.001f32..=1.0, Just(1.0), Just(0.999), Just(1.0 - f32::EPSILON)],
        width in 1u32..2500,
        height in 1u32..2500,
        native in any::<bool>(),
        gaze in (-1.0f32..=1.0, -1.0f32..=1.0),
    ) {
        let res = (!native).then_some(Resolution { width, height });
        let config = foveated(HMD_PROFILES[profile].name, res, ratio);
        if let Ok(plan) = plan(scene(), &config, &tests::caps()) {
            assert_windows_inside(&plan, Vec2::from(gaze))?;
        }
    }
}

/// Values that break assumptions: NaN, infinities, zero, negatives, just past a limit, huge.
fn hostile() -> impl Strategy<Value = f32> {
    prop_oneof![
        Just(f32::NAN),
        Just(f32::INFINITY),
        Just(-f32::INFINITY),
        Just(0.0),
        Just(-1.0),
        Just(1.0),
        Just(1.0 + f32::EPSILON),
        Just(1e30),
        -2.0f32..2.0,
        0.0f32..1.0,
    ]
}

/// `valid` nine times in ten, else `hostile`: each field breaks alone often enough that many
/// configurations plan and the rest fail at every check in turn.
fn mostly<T: std::fmt::Debug + Clone + 'static>(
    valid: impl Strategy<Value = T> + 'static,
    hostile: impl Strategy<Value = T> + 'static,
) -> BoxedStrategy<T> {
    prop_oneof![9 => valid, 1 => hostile].boxed()
}

prop_compose! {
    fn hostile_foveation()(
        ratio in mostly(0.05f32..=1.0, hostile()),
        view in mostly(Just(None), prop::option::of(0u32..3000)),
        fovea_size in mostly(Just(None), prop::option::of(0u32..3000)),
        band in mostly(prop_oneof![Just(-1.0f32), 0.0f32..40.0], hostile()),
        sharpen in mostly(0.0f32..=1.0, hostile()),
        density in mostly(prop::option::of(0.25f32..=1.0), prop::option::of(hostile())),
        periphery_msaa in mostly(prop::option::of(prop_oneof![Just(1u32), Just(4)]), prop::option::of(0u32..9)),
        temporal in prop::option::of((mostly(0.05f32..0.5, hostile()), mostly(1u32..16, 0u32..40), mostly(0.1f32..2.0, hostile()))),
        (stencil, bicubic) in (any::<bool>(), any::<bool>()),
    ) -> FoveationConfig {
        FoveationConfig {
            ratio,
            view_resolution: view,
            stencil,
            fovea_size,
            blend_band_px: band,
            periphery_sharpen: sharpen,
            periphery_density: density,
            periphery_msaa,
            periphery_filter: if bicubic { PeripheryFilter::CatmullRom } else { PeripheryFilter::Bilinear },
            periphery_temporal: temporal.map(|(blend, jitter_cycle, cut_distance_m)| TemporalConfig {
                blend,
                jitter_cycle,
                cut_distance_m,
                cut_angle_deg: cut_distance_m * 10.0,
                ..TemporalConfig::default()
            }),
            ..FoveationConfig::single_frame()
        }
    }
}

prop_compose! {
    /// A configuration where any number may be hostile and any effect on.
    pub(crate) fn hostile_config()(
        profile in mostly(0..HMD_PROFILES.len(), Just(HMD_PROFILES.len())),
        res in mostly(prop::option::of((8u32..1024, 8u32..1024)), prop::option::of((0u32..5000, 0u32..5000))),
        stereo in mostly(Just(0usize), 1usize..4),
        views in mostly(Just(None), prop::option::of(0u32..6)),
        msaa in mostly(prop_oneof![Just(1u32), Just(4)], 0u32..9),
        ipd in mostly(prop::option::of(0.05f32..0.08), prop::option::of(hostile())),
        cant in mostly(prop::option::of(-5.0f32..5.0), prop::option::of(hostile())),
        near in mostly(Just(0.05f32), hostile()),
        far in mostly(Just(500.0f32), hostile()),
        foveation in prop::option::of(hostile_foveation()),
        (hmd_mask, probe, lens) in (any::<bool>(), prop::bool::weighted(0.1), any::<bool>()),
        radial in prop::option::weighted(0.1, mostly((0.2f32..0.5, 0.6f32..0.9), (hostile(), hostile()))),
        mffr in prop::option::weighted(0.3, (mostly(0.5f32..4.0, hostile()), any::<bool>(), mostly(0.25f32..=1.0, hostile()))),
    ) -> RenderConfig {
        let stereo = [StereoMode::Multiview, StereoMode::TwoPass, StereoMode::PerObject, StereoMode::Instanced][stereo];
        let right_views = if foveation.is_some() { 4 } else { 2 };
        RenderConfig {
            hmd: HMD_PROFILES.get(profile).map_or("no-such-headset", |p| p.name).into(),
            resolution: res.map(|(width, height)| Resolution { width, height }),
            stereo,
            views: Some(views.unwrap_or(right_views)),
            msaa,
            ipd_m: ipd,
            cant_deg: cant,
            near,
            far,
            foveation,
            hmd_mask,
            coverage_probe: probe,
            output: if lens { OutputStage::Lens } else { OutputStage::Undistorted },
            radial_density: radial.map(|(inner, outer)| RadialDensity { inner, outer }),
            mffr: mffr.map(|(split, metres, far_density)| MffrConfig {
                split: if metres { SplitDistance::Metres(split) } else { SplitDistance::DisparityPx(split) },
                far_density,
                ..MffrConfig::default()
            }),
            ..RenderConfig::default()
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(20000))]

    /// The fuzz harness: any configuration with any gaze either plans (and places its fovea
    /// windows inside) or is an error; the gaze is accepted only inside −1…1 and finite.
    #[test]
    fn hostile_configurations_and_gazes_are_errors_or_plans(
        config in hostile_config(),
        gaze in mostly((-1.0f32..=1.0, -1.0f32..=1.0), (hostile(), hostile())),
    ) {
        let gaze = Vec2::from(gaze);
        let accepted = check_gaze([gaze; 2]).is_ok();
        prop_assert_eq!(accepted, gaze.is_finite() && gaze.abs().max_element() <= 1.0);
        if let Ok(plan) = plan(scene(), &config, &tests::caps()) {
            if accepted {
                assert_windows_inside(&plan, gaze)?;
            }
        }
    }
}
