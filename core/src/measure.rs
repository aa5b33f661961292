//! Measurements over the culling module, kept outside it so that `cull` stays pure geometry
//! (this module also needs the scene's rails and timing statistics): the culling benchmarks
//! behind `foveate cull-bench` and the criterion bench: Hale's
//! intersection tables (Hale 2018, Tables 4.1–4.4) in form, and stereo strategies on the thesis
//! scene along the rails (Preißner 2020 §5–6). Every time is measured with `Instant` in this run;
//! ratios are to a baseline measured in the same run.

use std::hint::black_box;
use std::time::Instant;

use glam::{Mat4, Vec3};
use rayon::prelude::*;

use crate::cull::{
    oracle, Aabb, Cone, CullHierarchy, CullView, Frustum, PerEye, Sphere, SphereSoa, StereoFrusta,
    Strategy, Triangle,
};
use crate::metrics::Stats;
use crate::view::{EyeParams, FovTangents, LensRegion};

/// One row of an intersection table.
#[derive(Clone, Debug, PartialEq)]
pub struct MicroRow {
    /// Hale's table this row belongs to (4.1 … 4.4).
    pub table: &'static str,
    pub name: &'static str,
    /// Total time of all passes.
    pub total_ms: f64,
    pub ns_per_test: f64,
    /// Tests that returned true in one pass (a sanity check that all variants agree).
    pub hits: u64,
    /// Time per test relative to sphere–frustum in the same run.
    pub ratio: f64,
}

fn time<F: FnMut() -> u64>(passes: usize, tests_per_pass: usize, mut pass: F) -> (f64, f64, u64) {
    let mut hits = 0;
    let start = Instant::now();
    for _ in 0..passes {
        hits = black_box(pass());
    }
    let total = start.elapsed().as_secs_f64();
    (
        total * 1e3,
        total * 1e9 / (passes * tests_per_pass) as f64,
        hits,
    )
}

/// Hale's sphere–cone baseline (his Listing 3.1, with `acos`), corrected for the apex.
fn sphere_cone_acos(cone: &Cone, s: &Sphere) -> bool {
    let c = s.center - cone.origin;
    let len = c.length();
    let angle = (c.dot(cone.axis) / len).clamp(-1.0, 1.0).acos();
    let half = cone.tan.atan();
    let distance = if angle - half >= std::f32::consts::FRAC_PI_2 {
        len
    } else {
        len * (angle - half).sin()
    };
    angle <= half || distance <= s.radius
}

/// The objects Hale's tables test: a grid of spheres, points and boxes in front of a cone and
/// the frustum of the same angle (and a second eye's of each), and a triangle mesh.
struct MicroWorkload {
    spheres: Vec<Sphere>,
    points: Vec<Vec3>,
    boxes: Vec<Aabb>,
    soa: SphereSoa,
    triangles: Vec<Triangle>,
    frustum: Frustum,
    second_frustum: Frustum,
    cone: Cone,
    second_cone: Cone,
    view: crate::cull::ConeView,
}

/// `side`³ objects.
fn micro_workload(side: usize) -> MicroWorkload {
    let n = side * side * side;
    let half_angle = 0.6f32;
    let origin = Vec3::new(1.0, 2.0, 3.0);
    let axis = Vec3::new(0.3, -0.2, -1.0).normalize();
    let cone = Cone::new(origin, axis, half_angle);
    let view = cone.view();
    let t = half_angle.tan();
    let world_from_cone =
        Mat4::from_rotation_translation(glam::Quat::from_rotation_arc(Vec3::NEG_Z, axis), origin);
    // The frustum with the cone's angle on every side, from a pose.
    let same_angle = |pose: Mat4| {
        Frustum::from_eye(
            pose,
            FovTangents {
                left: t,
                right: t,
                up: t,
                down: t,
            },
            0.01,
            4.0 * side as f32,
        )
    };
    let frustum = same_angle(world_from_cone);
    let spacing = 1.0;
    let point = |i: usize| {
        let (x, y, z) = (i % side, (i / side) % side, i / (side * side));
        origin
            + Vec3::new(
                x as f32 - side as f32 / 2.0,
                y as f32 - side as f32 / 2.0,
                -(z as f32),
            ) * spacing
    };
    let spheres: Vec<Sphere> = (0..n).map(|i| Sphere::new(point(i), 0.4)).collect();
    let points: Vec<Vec3> = (0..n).map(point).collect();
    let boxes: Vec<Aabb> = spheres
        .iter()
        .map(|s| Aabb::new(s.center - Vec3::splat(0.3), s.center + Vec3::splat(0.3)))
        .collect();
    let mut soa = SphereSoa::with_capacity(n);
    spheres.iter().for_each(|&s| soa.push(s));
    let second_cone = Cone::new(origin + Vec3::X * 0.064, axis, half_angle);
    let second_frustum = same_angle(Mat4::from_translation(Vec3::X * 0.064) * world_from_cone);
    // Hale's Table 4.4 mesh: 188 928 vertices, i.e. 62 976 triangles (scaled with `side`).
    let triangle_count = 62_976 * n / (64 * 64 * 64);
    let triangles: Vec<Triangle> = (0..triangle_count.max(1))
        .map(|i| {
            let a = point(i * n / triangle_count.max(1));
            Triangle::new(
                a,
                a + Vec3::new(0.7, 0.1, 0.0),
                a + Vec3::new(0.0, 0.6, 0.3),
            )
        })
        .collect();
    MicroWorkload {
        spheres,
        points,
        boxes,
        soa,
        triangles,
        frustum,
        second_frustum,
        cone,
        second_cone,
        view,
    }
}

/// The intersection tables: `side`³ objects (Hale: 64³) tested `passes` times (Hale: 10) against
/// a cone off the origin with a non-axis-aligned normal and the frustum of the same angle.
pub fn hale_tables(side: usize, passes: usize) -> Vec<MicroRow> {
    let MicroWorkload {
        spheres,
        points,
        boxes,
        soa,
        triangles,
        frustum,
        second_frustum,
        cone,
        second_cone,
        view,
    } = micro_workload(side);
    let n = spheres.len();
    let count = |f: &dyn Fn(usize) -> bool, len: usize| (0..len).filter(|&i| f(i)).count() as u64;
    let mut rows: Vec<MicroRow> = Vec::new();
    let mut row = |table, name, tests: usize, pass: &mut dyn FnMut() -> u64| {
        let (total_ms, ns, hits) = time(passes, tests, pass);
        rows.push(MicroRow {
            table,
            name,
            total_ms,
            ns_per_test: ns,
            hits,
            ratio: f64::NAN,
        });
    };
    row("4.1", "sphere-frustum (baseline)", n, &mut || {
        count(&|i| frustum.intersects_sphere(&spheres[i]), n)
    });
    row(
        "4.1",
        "sphere-cone acos (Hale's baseline, Listing 3.1)",
        n,
        &mut || count(&|i| sphere_cone_acos(&cone, &spheres[i]), n),
    );
    row("4.1", "sphere-cone offset apex (ours)", n, &mut || {
        count(&|i| cone.intersects_sphere(&spheres[i]), n)
    });
    row(
        "4.1",
        "sphere-cone view transform (Listing 3.2, apex fixed)",
        n,
        &mut || count(&|i| view.intersects_sphere(&spheres[i]), n),
    );
    let mut out = Vec::with_capacity(n);
    row("batch", "sphere-frustum, SoA batch", n, &mut || {
        out.clear();
        soa.frustum_union_unchecked(std::slice::from_ref(&frustum), 0..n, &mut out);
        out.len() as u64
    });
    row("batch", "sphere-cone, SoA batch", n, &mut || {
        out.clear();
        soa.cone_union_unchecked(std::slice::from_ref(&cone), 0..n, &mut out);
        out.len() as u64
    });
    row(
        "batch",
        "sphere-dual-frustum (per-eye), SoA batch",
        n,
        &mut || {
            out.clear();
            soa.frustum_union_unchecked(&[frustum, second_frustum], 0..n, &mut out);
            out.len() as u64
        },
    );
    row("batch", "sphere-dual-cone, SoA batch", n, &mut || {
        out.clear();
        soa.cone_union_unchecked(&[cone, second_cone], 0..n, &mut out);
        out.len() as u64
    });
    row("4.2", "point-frustum", n, &mut || {
        count(&|i| frustum.contains_point(points[i]), n)
    });
    row("4.2", "point-cone view", n, &mut || {
        count(&|i| view.contains_point(points[i]), n)
    });
    row("4.2", "point-cone cos", n, &mut || {
        count(&|i| cone.contains_point_cos(points[i]), n)
    });
    row("4.2", "point-cone tan", n, &mut || {
        count(&|i| cone.contains_point_tan(points[i]), n)
    });
    row("4.3", "AABB-frustum", n, &mut || {
        count(&|i| frustum.aabb(&boxes[i]).visible(), n)
    });
    row("4.3", "AABB-cone", n, &mut || {
        count(&|i| cone.intersects_aabb(&boxes[i]), n)
    });
    let m = triangles.len();
    row("4.4", "triangle-frustum", m, &mut || {
        count(&|i| triangles[i].intersects_frustum(&frustum), m)
    });
    row("4.4", "triangle-cone", m, &mut || {
        count(&|i| triangles[i].intersects_cone(&cone), m)
    });

    let baseline = rows[0].ns_per_test;
    for r in &mut rows {
        r.ratio = r.ns_per_test / baseline;
    }
    rows
}

/// One strategy's results along the rails.
#[derive(Clone, Debug)]
pub struct StrategyReport {
    pub strategy: Strategy,
    /// Cull time per frame (ms), wall clock, the volume's construction included.
    pub time_ms: Stats,
    /// Objects accepted per frame.
    pub visible: Stats,
    pub node_tests: Stats,
    pub object_tests: Stats,
    /// Over the frames with an exact reference: accepted-but-invisible / accepted.
    pub false_positive_rate: Option<f64>,
    /// Over the frames with an exact reference: visible-but-rejected / visible.
    pub miss_rate: Option<f64>,
}

/// What the rails benchmark runs.
#[derive(Clone, Copy, Debug)]
pub struct RailsParams<'a> {
    pub eyes: &'a EyeParams,
    pub lens_regions: &'a [LensRegion; 2],
    pub frames: u64,
    pub draw_distance: f32,
    pub near: f32,
    /// Measure false positives and misses against the exact reference every this many frames
    /// (0: never). The reference is slow (f64, exact distances).
    pub reference_every: u64,
    pub extent: Vec3,
}

/// The objects truly visible to either eye within the draw distance, exactly (f64), as a
/// bitmap over hierarchy order. Only per-eye-accepted objects are candidates: the per-eye test
/// is conservative, so nothing visible is outside that set.
pub fn exact_reference(hierarchy: &CullHierarchy, view: &CullView<'_>) -> Vec<bool> {
    let frusta = StereoFrusta::new(
        view.eyes,
        view.world_from_head,
        view.near,
        view.draw_distance,
    );
    let centre = view.world_from_head.transform_point3(Vec3::ZERO).as_dvec3();
    let candidates: Vec<u32> = hierarchy
        .cull(&PerEye { frusta }, centre.as_vec3(), view.draw_distance)
        .visible
        .indices()
        .collect();
    let visible: Vec<u32> = candidates
        .into_par_iter()
        .filter(|&i| {
            let s = hierarchy.spheres.get(i as usize);
            s.center.as_dvec3().distance(centre) <= view.draw_distance as f64 + s.radius as f64
                && frusta.eyes.iter().any(|f| oracle::sphere_frustum(f, &s))
        })
        .collect();
    let mut bits = vec![false; hierarchy.len()];
    for i in visible {
        bits[i as usize] = true;
    }
    bits
}

/// Runs every strategy for every frame along the rails (frames spread over two rail loops),
/// calling `progress(done, total)` as it goes.
pub fn rails_bench(
    hierarchy: &CullHierarchy,
    strategies: &[Strategy],
    p: &RailsParams<'_>,
    progress: &mut dyn FnMut(u64, u64),
) -> Vec<StrategyReport> {
    let total = p.frames * strategies.len() as u64;
    let mut series: Vec<[Vec<f64>; 4]> = vec![Default::default(); strategies.len()];
    let mut errors = vec![(0u64, 0u64, 0u64, 0u64); strategies.len()]; // fp, accepted, misses, visible
    let step = (2 * crate::scene::RAIL_LOOP_FRAMES / p.frames.max(1)).max(1);
    for i in 0..p.frames {
        let frame = i * step;
        let view = CullView {
            eyes: p.eyes,
            world_from_head: crate::scene::rail_pose(frame, p.extent),
            near: p.near,
            draw_distance: p.draw_distance,
            frame,
            lens_regions: p.lens_regions,
        };
        let reference = (p.reference_every > 0 && i % p.reference_every == 0)
            .then(|| exact_reference(hierarchy, &view));
        for (k, &strategy) in strategies.iter().enumerate() {
            let start = Instant::now();
            let result = strategy.cull(hierarchy, &view);
            let ms = start.elapsed().as_secs_f64() * 1e3;
            let s = result.stats;
            for (v, x) in series[k].iter_mut().zip([
                ms,
                s.visible as f64,
                s.node_tests as f64,
                s.object_tests as f64,
            ]) {
                v.push(x);
            }
            if let Some(reference) = &reference {
                let mut accepted = vec![false; hierarchy.len()];
                result
                    .visible
                    .indices()
                    .for_each(|j| accepted[j as usize] = true);
                let e = &mut errors[k];
                for (a, r) in accepted.iter().zip(reference) {
                    e.0 += (*a && !*r) as u64;
                    e.1 += *a as u64;
                    e.2 += (!*a && *r) as u64;
                    e.3 += *r as u64;
                }
            }
            progress(i * strategies.len() as u64 + k as u64 + 1, total);
        }
    }
    strategies
        .iter()
        .zip(series)
        .zip(errors)
        .map(
            |((&strategy, [t, v, n, o]), (fp, acc, miss, vis))| StrategyReport {
                strategy,
                time_ms: Stats::of(&t).unwrap_or_default(),
                visible: Stats::of(&v).unwrap_or_default(),
                node_tests: Stats::of(&n).unwrap_or_default(),
                object_tests: Stats::of(&o).unwrap_or_default(),
                false_positive_rate: (acc > 0).then(|| fp as f64 / acc as f64),
                miss_rate: (vis > 0).then(|| miss as f64 / vis as f64),
            },
        )
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The false-positive rate of each strategy along the thesis rails (accepted but invisible to
    /// both eyes, against the exact f64 reference on every frame) stays under a bound set a little
    /// above what it measures today, so slack added to any test cannot grow unnoticed; and no
    /// strategy misses a visible object but those that cull to the lens, which miss only what
    /// the lens hides. Mutation: the cones' rounding slack 10⁴ times larger raises the elliptical
    /// cone's rate from 0.287 to 0.406, past its bound.
    #[test]
    fn false_positive_rates_on_the_rails_are_bounded() {
        let scene = crate::scene::ThesisScene::new(0.01).unwrap();
        let hierarchy =
            CullHierarchy::build(&scene.bounds(), crate::cull::HierarchyParams::default());
        let hmd = crate::view::HmdProfile::by_name("index").unwrap();
        let eyes = hmd.eyes(crate::view::DEFAULT_IPD_M);
        let regions = crate::view::Eye::BOTH.map(|e| {
            LensRegion::with_hidden_fraction(eyes.fov(e), hmd.hidden_area_fraction.unwrap_or(0.0))
        });
        let params = RailsParams {
            eyes: &eyes,
            lens_regions: &regions,
            frames: 16,
            draw_distance: 320.0,
            near: 0.05,
            reference_every: 1,
            extent: scene.extent(),
        };
        let reports = rails_bench(&hierarchy, &Strategy::ALL, &params, &mut |_, _| {});
        for r in &reports {
            let fp = r.false_positive_rate.unwrap();
            let miss = r.miss_rate.unwrap();
            // Measured on this scene and these frames: 0.0018, 0.0041, 0.258, 0.287, 0.0019.
            let (fp_bound, miss_bound) = match r.strategy {
                Strategy::PerEye => (0.0025, 0.0),
                Strategy::Superfrustum => (0.006, 0.0),
                Strategy::DualCone => (0.30, 0.0),
                Strategy::DualEllipticalCone => (0.32, 0.0),
                // One eye's frustum a frame: it misses what only the other eye sees, by design.
                Strategy::RoundRobin => (0.0025, 0.04),
            };
            assert!(
                fp <= fp_bound && miss <= miss_bound,
                "{}: false positives {fp:.4} (bound {fp_bound}), misses {miss:.4} (bound {miss_bound})",
                r.strategy.name()
            );
        }
    }
}
