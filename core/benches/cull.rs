//! Culling CPU paths: batch SoA tests per object, and each stereo strategy over a small copy of
//! the thesis scene along the rails. Side by side in one run:
//! `cargo bench -p foveate --bench cull`. (`foveate cull-bench` runs the full tables.)

use std::time::Duration;

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use foveate::cull::{
    CullHierarchy, CullView, HierarchyParams, Sphere, SphereSoa, StereoFrusta, Strategy,
    Superfrustum,
};
use foveate::scene::{rail_pose, ThesisScene};
use foveate::view::{Eye, HmdProfile, LensRegion};
use glam::{Mat4, Vec3};

fn batch(c: &mut Criterion) {
    let n = 1 << 18;
    let mut soa = SphereSoa::with_capacity(n);
    for i in 0..n {
        let f = i as f32;
        soa.push(Sphere::new(
            Vec3::new(
                (f * 0.37).sin() * 100.0,
                (f * 0.11).cos() * 30.0,
                -(f * 0.013) % 200.0,
            ),
            0.9,
        ));
    }
    let eyes = HmdProfile::by_name("index").unwrap().eyes(0.064);
    let frusta = StereoFrusta::new(&eyes, Mat4::IDENTITY, 0.05, 320.0);
    let superfrustum = Superfrustum::new(&eyes, Mat4::IDENTITY, 0.05, 320.0);
    let regions = Eye::BOTH.map(|e| LensRegion::with_hidden_fraction(eyes.fov(e), 0.19));
    let cones = foveate::cull::DualCone::new(&eyes, Mat4::IDENTITY, &regions, false).cones;
    let mut group = c.benchmark_group("batch per object");
    group
        .throughput(Throughput::Elements(n as u64))
        .sample_size(20)
        .measurement_time(Duration::from_secs(2));
    let mut out = Vec::with_capacity(n);
    group.bench_function("sphere-superfrustum", |b| {
        b.iter(|| {
            out.clear();
            soa.frustum_union(std::slice::from_ref(&superfrustum.frustum), 0..n, &mut out)
                .expect("valid batch input");
            out.len()
        })
    });
    group.bench_function("sphere-per-eye frusta", |b| {
        b.iter(|| {
            out.clear();
            soa.frustum_union(&frusta.eyes, 0..n, &mut out)
                .expect("valid batch input");
            out.len()
        })
    });
    group.bench_function("sphere-dual-cone", |b| {
        b.iter(|| {
            out.clear();
            soa.cone_union(&cones, 0..n, &mut out)
                .expect("valid batch input");
            out.len()
        })
    });
    group.finish();
}

fn strategies(c: &mut Criterion) {
    let scene = ThesisScene::new(0.1).expect("valid scale");
    let hierarchy = CullHierarchy::build(&scene.bounds(), HierarchyParams::default());
    let hmd = HmdProfile::by_name("index").unwrap();
    let eyes = hmd.eyes(0.064);
    let regions = Eye::BOTH.map(|e| LensRegion::with_hidden_fraction(eyes.fov(e), 0.19));
    let mut group = c.benchmark_group("thesis scene 0.1 along the rails");
    group
        .sample_size(20)
        .measurement_time(Duration::from_secs(2));
    for strategy in Strategy::ALL {
        let mut frame = 0u64;
        group.bench_function(strategy.name(), |b| {
            b.iter(|| {
                frame = (frame + 13) % 5400;
                let view = CullView {
                    eyes: &eyes,
                    world_from_head: rail_pose(frame, scene.extent()),
                    near: 0.05,
                    draw_distance: 320.0,
                    frame,
                    lens_regions: &regions,
                };
                strategy.cull(&hierarchy, &view).stats.visible
            })
        });
    }
    group.finish();
}

criterion_group!(benches, batch, strategies);
criterion_main!(benches);
