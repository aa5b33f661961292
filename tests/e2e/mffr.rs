//! MFFR on the GPU: the composited far field matches a full stereo reference within its
//! disparity bound, leaves no seam at the split, and the HMD mask hides what the lens hides.

use foveate::mffr::{MffrConfig, MffrOrder, MffrVariant, SplitDistance};
use foveate::plan::{CountedStep, RenderConfig, Resolution, StereoMode};
use foveate::scene::{city_scene, ground_grid, DrawBatch, Instance, Scene};
use foveate::view::HMD_PROFILES;
use foveate_tests::{gpu, render};
use glam::{Mat4, Vec3};

fn config(mffr: Option<MffrConfig>, stereo: StereoMode) -> RenderConfig {
    RenderConfig {
        stereo,
        msaa: 4,
        resolution: Some(Resolution::square(192)),
        mffr,
        count_fragments: true,
        ..RenderConfig::default()
    }
}

fn mffr(name: &str, split: &str) -> Option<MffrConfig> {
    Some(MffrConfig::named(name, split.parse().unwrap()).unwrap())
}

/// Every variant at a 2 px split: nearly every pixel of each eye is the reference's pixel moved
/// along its row by no more than the variant's bound (half the split disparity from the head
/// centre, all of it for the eye the alternating view is not rendered from), plus one pixel of
/// resampling.
#[test]
fn composited_far_field_matches_stereo_within_the_disparity_bound() {
    let gpu = gpu();
    let scene = city_scene();
    for stereo in [StereoMode::Multiview, StereoMode::TwoPass] {
        let (reference, _) = render(&gpu, &scene, &config(None, stereo));
        for (name, _, variant) in MffrConfig::NAMED {
            let c = config(mffr(name, "2px"), stereo);
            let (image, stats) = render(&gpu, &scene, &c);
            let disparity = 2.0f32;
            let bound = match variant {
                MffrVariant::AlternateEye => disparity,
                _ => disparity / 2.0,
            };
            let radius = bound.ceil() as u32 + 1;
            for (eye, (got, want)) in [
                (&image.left, &reference.left),
                (&image.right, &reference.right),
            ]
            .into_iter()
            .enumerate()
            {
                let within = got.matched_within(want, radius, 24).unwrap();
                let exact = got.matched_within(want, 0, 24).unwrap();
                assert!(
                    within > 0.995,
                    "{stereo} {name} eye {eye}: {within:.4} within {radius} px ({exact:.4} unshifted)"
                );
            }
            assert!(
                stats.far_fragments.unwrap() > 0,
                "{name}: the far pass drew"
            );
        }
    }
}

/// Near-first and far-first differ only in who reaches a pixel first, never in the result.
#[test]
fn near_first_and_far_first_give_the_same_image() {
    let gpu = gpu();
    let scene = city_scene();
    let (near, _) = render(
        &gpu,
        &scene,
        &config(mffr("near-first", "2px"), StereoMode::Multiview),
    );
    let (far, _) = render(
        &gpu,
        &scene,
        &config(mffr("far-first", "2px"), StereoMode::Multiview),
    );
    for (a, b) in [(&near.left, &far.left), (&near.right, &far.right)] {
        assert!(a.matched_within(b, 0, 1).unwrap() > 0.9999);
    }
}

/// A ground plane crossing the split: wherever the reference shows ground, MFFR shows ground
/// too — no sky shows through a crack at the split, for parallel and canted eyes.
#[test]
fn no_seam_at_the_split() {
    let gpu = gpu();
    let scene = Scene {
        meshes: vec![ground_grid(420.0, 0.25)],
        batches: vec![DrawBatch {
            mesh: 0,
            instances: vec![Instance::new(Mat4::IDENTITY, Vec3::new(0.9, 0.3, 0.2))],
        }],
        head: foveate::view::look_at_head(Vec3::new(0.0, 1.7, 0.0), Vec3::new(0.0, 0.0, -12.0)),
        light_dir: Vec3::NEG_Y,
    };
    for cant in [0.0, 10.0] {
        for order in [MffrOrder::NearFirst, MffrOrder::FarFirst] {
            let base = RenderConfig {
                cant_deg: Some(cant),
                ..config(None, StereoMode::Multiview)
            };
            let c = RenderConfig {
                mffr: Some(MffrConfig {
                    split: SplitDistance::Metres(8.0),
                    order,
                    variant: MffrVariant::Centre,
                }),
                ..base.clone()
            };
            let (reference, _) = render(&gpu, &scene, &base);
            let (image, _) = render(&gpu, &scene, &c);
            let sky = reference.left.pixel(96, 0);
            let is_sky = |p: [u8; 4]| (0..3).all(|i| p[i].abs_diff(sky[i]) <= 8);
            for (got, want) in [
                (&image.left, &reference.left),
                (&image.right, &reference.right),
            ] {
                let mut cracks = 0;
                for y in 0..got.height {
                    for x in 0..got.width {
                        cracks += (is_sky(got.pixel(x, y)) && !is_sky(want.pixel(x, y))) as u32;
                    }
                }
                assert_eq!(cracks, 0, "cant {cant}, {order:?}: sky through the split");
            }
        }
    }
}

/// The far image reprojected by its depth is closer to the reference than the rotation-only
/// one, at a split coarse enough for the difference to show.
#[test]
fn depth_shift_beats_rotation_only() {
    let gpu = gpu();
    let scene = city_scene();
    let (reference, _) = render(&gpu, &scene, &config(None, StereoMode::Multiview));
    let psnr = |name| {
        let (image, _) = render(
            &gpu,
            &scene,
            &config(mffr(name, "6px"), StereoMode::Multiview),
        );
        image.left.psnr(&reference.left).unwrap() + image.right.psnr(&reference.right).unwrap()
    };
    let (centre, shifted) = (psnr("near-first"), psnr("depth-shift"));
    assert!(
        shifted > centre + 0.5,
        "depth shift {shifted:.2} dB vs {centre:.2} dB (sum of eyes)"
    );
}

/// The HMD mask hides, measured per eye by the coverage probe, the fraction its lens region
/// hides: the published hidden-area fraction where there is one, the circular fallback's
/// 1 − π/4 where not.
#[test]
fn hmd_mask_coverage_per_profile() {
    let gpu = gpu();
    let empty = Scene::empty();
    for profile in HMD_PROFILES {
        let c = RenderConfig {
            hmd: profile.name.into(),
            hmd_mask: true,
            coverage_probe: true,
            count_fragments: true,
            msaa: 1,
            resolution: Some(Resolution::square(256)),
            ..RenderConfig::default()
        };
        let plan = foveate::plan(&empty, &c, gpu.caps()).unwrap();
        let (_, stats) = foveate_tests::render_plan(&gpu, &empty, &plan, 1);
        let probe = stats.per_view(CountedStep::Probe);
        for (eye, lens) in plan.hmd_mask.unwrap().iter().enumerate() {
            let measured = 1.0 - probe[eye] as f64 / (256.0 * 256.0);
            let expected = match profile.hidden_area_fraction {
                Some(f) => f as f64,
                None => 1.0 - std::f64::consts::FRAC_PI_4,
            };
            assert!((lens.hidden_fraction() - expected).abs() < 1e-4);
            assert!(
                (measured - expected).abs() < 0.01,
                "{}: eye {eye} hides {measured:.4}, expected {expected:.4}",
                profile.name
            );
        }
    }
}

/// MFFR under foveation: the far composite runs in all four views and the composed eyes match
/// the foveated frame without MFFR within the disparity bound.
#[test]
fn mffr_composes_with_foveation() {
    let gpu = gpu();
    let scene = city_scene();
    let foveated = RenderConfig {
        views: 4,
        foveation: Some(foveate::foveation::FoveationConfig {
            ratio: 0.5,
            ..Default::default()
        }),
        ..config(None, StereoMode::Multiview)
    };
    let (reference, _) = render(&gpu, &scene, &foveated);
    let (image, stats) = render(
        &gpu,
        &scene,
        &RenderConfig {
            mffr: mffr("near-first", "2px"),
            ..foveated.clone()
        },
    );
    assert!(stats.far_fragments.unwrap() > 0);
    for (got, want) in [
        (&image.left, &reference.left),
        (&image.right, &reference.right),
    ] {
        let within = got.matched_within(want, 2, 24).unwrap();
        assert!(within > 0.99, "{within:.4}");
    }
}
