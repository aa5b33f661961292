//! Level of detail on the GPU: off, a scene with levels draws exactly what it drew without them;
//! on, the silhouettes move no further than the bound lets them, and the periphery's coarse
//! pixels take coarser levels than the fovea's (pipeline statistics).

use foveate::foveation::FoveationConfig;
use foveate::metrics::RgbaImage;
use foveate::plan::{FoveaLayout, RenderConfig, Resolution};
use foveate::scene::{uv_sphere, DrawBatch, Instance, LodSettings, Scene};
use foveate_tests::{gpu, render_at};
use glam::{Mat4, Vec2, Vec3};

/// Spheres of detail no 128² eye resolves (48 × 24 segments), at 3 to 15 m in a grid before the
/// eyes: the full mesh, and the same with simplified levels.
fn spheres() -> (Scene, Scene) {
    let instances = (0..5)
        .flat_map(|row| {
            (0..5).map(move |col| {
                let at = Vec3::new(
                    (col as f32 - 2.0) * 1.2,
                    (row as f32 - 2.0) * 1.2,
                    -3.0 - 3.0 * row as f32,
                );
                Instance::new(
                    Mat4::from_translation(at) * Mat4::from_scale(Vec3::splat(0.5)),
                    Vec3::new(0.8, 0.4, 0.2),
                )
            })
        })
        .collect();
    let full = Scene {
        meshes: vec![uv_sphere(48, 24)],
        batches: vec![DrawBatch { mesh: 0, instances }],
        ..Scene::empty()
    };
    let with_levels = full.clone().with_lod().unwrap();
    assert!(with_levels.lod_counts().0 >= 2, "the sphere has levels");
    (full, with_levels)
}

fn base() -> RenderConfig {
    RenderConfig {
        resolution: Some(Resolution::square(128)),
        msaa: 1,
        ..RenderConfig::default()
    }
}

fn lod(px: f32) -> Option<LodSettings> {
    Some(LodSettings::new(px).unwrap())
}

/// Off costs nothing: levels in the scene but none asked for plan and draw the frame of the
/// scene without them, pixel for pixel, with no cull slot. Mutation: planning LOD whenever the
/// scene has levels gives the frame a cull slot.
#[test]
fn levels_unasked_change_nothing() {
    let gpu = gpu();
    let (full, with_levels) = spheres();
    let plan = foveate::plan(&with_levels, &base(), gpu.caps()).unwrap();
    assert!(plan.lod.is_none() && plan.cull_slots.is_empty());
    assert_eq!(
        plan.to_string(),
        foveate::plan(&full, &base(), gpu.caps())
            .unwrap()
            .to_string()
    );
    let a = render_at(&gpu, &full, &base(), Vec2::ZERO);
    let b = render_at(&gpu, &with_levels, &base(), Vec2::ZERO);
    assert!(a == b, "levels changed an unasked frame");
}

/// Whether each pixel shows a sphere (differs from the empty scene's pixel there).
fn coverage(image: &RgbaImage, empty: &RgbaImage) -> Vec<bool> {
    image
        .data
        .chunks(4)
        .zip(empty.data.chunks(4))
        .map(|(a, b)| a != b)
        .collect()
}

/// A 1 px bound moves silhouettes by at most about a pixel: every pixel whose coverage the
/// levels change lies within 2 px (the bound, plus a pixel centre's rounding) of the full
/// frame's own silhouette. And levels are drawn: some pixel changes. Mutation: always the
/// coarsest level moves silhouettes by several pixels.
#[test]
fn silhouettes_stay_within_the_bound() {
    let gpu = gpu();
    let (full, with_levels) = spheres();
    let config = RenderConfig {
        lod: lod(1.0),
        ..base()
    };
    let empty = render_at(
        &gpu,
        &Scene {
            batches: Vec::new(),
            ..full.clone()
        },
        &base(),
        Vec2::ZERO,
    );
    let reference = render_at(&gpu, &full, &base(), Vec2::ZERO);
    let image = render_at(&gpu, &with_levels, &config, Vec2::ZERO);
    let mut changed = 0;
    for (eye, (r, i, e)) in [
        (&reference.left, &image.left, &empty.left),
        (&reference.right, &image.right, &empty.right),
    ]
    .into_iter()
    .enumerate()
    {
        let (w, h) = (r.width as i32, r.height as i32);
        let (want, got) = (coverage(r, e), coverage(i, e));
        let at = |x: i32, y: i32| want[(y.clamp(0, h - 1) * w + x.clamp(0, w - 1)) as usize];
        for y in 0..h {
            for x in 0..w {
                let k = (y * w + x) as usize;
                if want[k] == got[k] {
                    continue;
                }
                changed += 1;
                let near_edge = (-2..=2)
                    .flat_map(|dy| (-2..=2).map(move |dx| (dx, dy)))
                    .any(|(dx, dy)| at(x + dx, y + dy) != want[k]);
                assert!(
                    near_edge,
                    "eye {eye}: pixel ({x}, {y}) changed coverage more than 2 px from a silhouette"
                );
            }
        }
    }
    assert!(changed > 0, "no level was drawn");
}

/// The periphery's pixels are coarser than the eyes' own, so its pass draws coarser levels: the
/// two-pass fovea layout's periphery pass and a stereo frame's scene pass draw the same
/// instances (every one), and level of detail leaves the periphery fewer primitives than the
/// stereo pass, and the stereo pass fewer than the full meshes. Mutation: choosing the
/// periphery's levels with the eyes' resolution makes the two passes alike.
#[test]
fn the_periphery_takes_coarser_levels() {
    let gpu = gpu();
    let (_, with_levels) = spheres();
    let stereo = |lod| RenderConfig {
        lod,
        resolution: Some(Resolution::square(512)),
        ..base()
    };
    let foveated = RenderConfig {
        foveation: Some(FoveationConfig {
            ratio: 0.35,
            ..FoveationConfig::single_frame()
        }),
        fovea_layout: FoveaLayout::TwoPass,
        ..stereo(lod(1.0))
    };
    // The primitives the first pass (the scene's, or the periphery's) assembles.
    let count = |config: &RenderConfig| {
        let stats = foveate::render::counting_frame(
            &gpu,
            &with_levels,
            config,
            [Vec2::ZERO; 2],
            with_levels.head,
        )
        .expect("counting frame");
        foveate_tests::assert_validation_clean(&gpu);
        stats.pass_statistics.first().map(|p| p.assembled)
    };
    let (Some(full), Some(eyes), Some(periphery)) = (
        count(&stereo(None)),
        count(&stereo(lod(1.0))),
        count(&foveated),
    ) else {
        eprintln!("skipped: this device has no pipeline statistics");
        return;
    };
    assert!(
        periphery < eyes && eyes < full,
        "primitives: periphery {periphery}, eyes {eyes}, full meshes {full}"
    );
}
