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

/// A named variant at `split`, its far image at the eyes' own density (the library's default
/// resamples it at 0.8): exact up to the disparity bound, which these tests hold it to.
fn mffr(name: &str, split: &str) -> Option<MffrConfig> {
    Some(MffrConfig {
        far_density: 1.0,
        ..MffrConfig::named(name, split.parse().unwrap()).unwrap()
    })
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

/// The far pass at its own samples and density: validation clean (its pipeline is built for
/// its own samples, not the frame's), far fragments that follow its pixels (half the density:
/// a quarter of the far image's pixels, and measured, a quarter of its fragments), and an
/// image that still matches the reference within the disparity bound plus a far pixel nearly
/// everywhere. Mutation: a far image that ignores its density shades as many fragments.
#[test]
fn far_pass_takes_its_own_samples_and_density() {
    let gpu = gpu();
    let scene = city_scene();
    let (reference, _) = render(&gpu, &scene, &config(None, StereoMode::Multiview));
    let far = |density| {
        let m = MffrConfig {
            far_msaa: Some(1),
            far_density: density,
            ..mffr("near-first", "2px").unwrap()
        };
        let c = config(Some(m), StereoMode::Multiview);
        let plan = foveate::plan(&scene, &c, gpu.caps()).unwrap();
        let size = plan.mffr.unwrap().resolution;
        let (image, stats) = render(&gpu, &scene, &c);
        let fragments = stats.far_fragments.unwrap() as f64;
        (image, fragments, size.width as f64 * size.height as f64)
    };
    let (_, full_fragments, full_pixels) = far(1.0);
    let (image, half_fragments, half_pixels) = far(0.5);
    let (measured, planned) = (half_fragments / full_fragments, half_pixels / full_pixels);
    for share in [measured, planned] {
        assert!(
            (share / 0.25 - 1.0).abs() < 0.1,
            "half density shades {measured:.3} of the far fragments; its image has {planned:.3} of the pixels"
        );
    }
    for (got, want) in [
        (&image.left, &reference.left),
        (&image.right, &reference.right),
    ] {
        let within = got.matched_within(want, 3, 24).unwrap();
        assert!(within > 0.98, "{within:.4} within 3 px");
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
        materials: Vec::new(),
        lights: Vec::new(),
        reach: None,
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
                    ..MffrConfig::default()
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

/// The HMD mask, measured per eye by the coverage probe, keeps exactly the pixels whose
/// centres lie in the fan the mask shader draws (the 128-gon circumscribing the lens ellipse),
/// counted on the CPU — within 0.05 % (a centre exactly on an edge may go either way). And the
/// lens ellipse hides the published hidden-area fraction (the circular fallback's 1 − π/4 where
/// there is none), integrated on a fine grid independently of the region's own formula — not
/// its bisection read back. Mutations: a mask fan with fewer segments, an ellipse radius off
/// by a pixel, or a region bisected to the wrong fraction fail it.
#[test]
fn hmd_mask_coverage_per_profile() {
    let gpu = gpu();
    let empty = Scene::empty();
    let size = 256u32;
    for profile in HMD_PROFILES {
        let c = RenderConfig {
            hmd: profile.name.into(),
            hmd_mask: true,
            coverage_probe: true,
            count_fragments: true,
            msaa: 1,
            resolution: Some(Resolution::square(size)),
            ..RenderConfig::default()
        };
        let plan = foveate::plan(&empty, &c, gpu.caps()).unwrap();
        let (_, stats) = foveate_tests::render_plan(&gpu, &empty, &plan, 1);
        let probe = stats.per_view(CountedStep::Probe);
        let expected_hidden = match profile.hidden_area_fraction {
            Some(f) => f as f64,
            None => 1.0 - std::f64::consts::FRAC_PI_4,
        };
        for (eye, lens) in plan.hmd_mask.unwrap().iter().enumerate() {
            let e = lens.ndc_ellipse().as_dvec4();
            // Ellipse-normalised coordinates of an NDC point.
            let q = |x: f64, y: f64| ((x - e.x) / e.z, (y - e.y) / e.w);
            let fan = mask_fan_pixels(size, &q);
            let measured = probe[eye];
            assert!(
                measured.abs_diff(fan) as f64 <= 5e-4 * (size * size) as f64,
                "{}: eye {eye} keeps {measured} pixels, the fan covers {fan}",
                profile.name
            );
            // The ellipse's hidden area over the image, on a 2048² grid of the NDC square.
            let n = 2048;
            let mut outside = 0u64;
            for j in 0..n {
                for i in 0..n {
                    let x = -1.0 + (2 * i + 1) as f64 / n as f64;
                    let y = -1.0 + (2 * j + 1) as f64 / n as f64;
                    let (u, v) = q(x, y);
                    outside += (u * u + v * v > 1.0) as u64;
                }
            }
            let hidden = outside as f64 / (n * n) as f64;
            assert!(
                (hidden - expected_hidden).abs() < 1e-3,
                "{}: eye {eye}: the ellipse hides {hidden:.4}, published {expected_hidden:.4}",
                profile.name
            );
        }
    }
}

/// Pixels of a `size`² view whose centres lie inside the mask fan: the regular 128-gon
/// circumscribing the unit circle in ellipse-normalised coordinates `q` (see
/// `shaders/mask.vert`), as its edges' half-planes.
fn mask_fan_pixels(size: u32, q: &dyn Fn(f64, f64) -> (f64, f64)) -> u64 {
    let segments = 128;
    let normals: Vec<(f64, f64)> = (0..segments)
        .map(|k| {
            let a = std::f64::consts::TAU * (k as f64 + 0.5) / segments as f64;
            (a.cos(), a.sin())
        })
        .collect();
    let mut inside = 0;
    for y in 0..size {
        for x in 0..size {
            let ndc = |p: u32| -1.0 + (2 * p + 1) as f64 / size as f64;
            let (u, v) = q(ndc(x), ndc(y));
            inside += normals.iter().all(|&(nx, ny)| u * nx + v * ny <= 1.0) as u64;
        }
    }
    inside
}

/// MFFR under foveation: the far composite runs in all four views and the composed eyes match
/// the foveated frame without MFFR within the disparity bound.
#[test]
fn mffr_composes_with_foveation() {
    let gpu = gpu();
    let scene = city_scene();
    let foveated = RenderConfig {
        foveation: Some(foveate::foveation::FoveationConfig {
            ratio: 0.5,
            ..foveate::foveation::FoveationConfig::single_frame()
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
