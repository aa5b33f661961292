//! The per-view fragment counter, proven on shapes whose exact pixel count is known.

use foveate::plan::{RenderConfig, Resolution, StereoMode};
use foveate::scene::{ground_quad, DrawBatch, Instance, Mesh, Scene, Vertex};
use foveate::view::FovTangents;
use foveate_tests::{gpu, render};
use glam::{Mat4, Vec3};

const SIZE: u32 = 64;

/// A 90° view (tangents 1) of a `SIZE`² image: where pixel edge `c` (column) or `r` (row) lies,
/// as a tangent.
fn column_tangent(c: u32) -> f32 {
    -1.0 + 2.0 * c as f32 / SIZE as f32
}
fn row_tangent(r: u32) -> f32 {
    1.0 - 2.0 * r as f32 / SIZE as f32
}

/// A quad facing the viewer at `depth` metres covering exactly pixel columns `cols` and rows
/// `rows`: its edges sit on pixel edges, half a pixel from every pixel centre.
fn pixel_rect(cols: (u32, u32), rows: (u32, u32), depth: f32) -> Instance {
    let (x0, x1) = (
        column_tangent(cols.0) * depth,
        column_tangent(cols.1) * depth,
    );
    let (y0, y1) = (row_tangent(rows.1) * depth, row_tangent(rows.0) * depth);
    let model = Mat4::from_translation(Vec3::new((x0 + x1) / 2.0, (y0 + y1) / 2.0, -depth))
        * Mat4::from_scale(Vec3::new(x1 - x0, y1 - y0, 1.0))
        * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    Instance::new(model, Vec3::ONE)
}

fn scene(instances: Vec<Instance>) -> Scene {
    Scene {
        meshes: vec![ground_quad()],
        batches: vec![DrawBatch { mesh: 0, instances }],
        head: Mat4::IDENTITY,
        light_dir: Vec3::new(0.0, 0.0, -1.0),
        materials: Vec::new(),
        lights: Vec::new(),
        reach: None,
    }
}

fn config(stereo: StereoMode, msaa: u32) -> RenderConfig {
    RenderConfig {
        stereo,
        msaa,
        resolution: Some(Resolution::square(SIZE)),
        ipd_m: Some(0.0),
        fov: Some(FovTangents {
            left: 1.0,
            right: 1.0,
            up: 1.0,
            down: 1.0,
        }),
        count_fragments: true,
        ..RenderConfig::default()
    }
}

/// A pixel rectangle: columns [c0, c1) × rows [r0, r1).
#[derive(Clone, Copy)]
struct Rect {
    cols: (u32, u32),
    rows: (u32, u32),
}

impl Rect {
    fn contains_pixel(&self, x: u32, y: u32) -> bool {
        (self.cols.0..self.cols.1).contains(&x) && (self.rows.0..self.rows.1).contains(&y)
    }

    /// The quad's two triangles in pixel coordinates, as `ground_quad` splits it: along the
    /// diagonal from bottom-left to top-right.
    fn triangles(&self) -> [[(f64, f64); 3]; 2] {
        let (x0, x1) = (self.cols.0 as f64, self.cols.1 as f64);
        let (y0, y1) = (self.rows.0 as f64, self.rows.1 as f64);
        let (bl, br, tr, tl) = ((x0, y1), (x1, y1), (x1, y0), (x0, y0));
        [[bl, br, tr], [bl, tr, tl]]
    }
}

/// Vulkan's standard sample positions within a pixel.
const STANDARD_1X: [(f64, f64); 1] = [(0.5, 0.5)];
const STANDARD_4X: [(f64, f64); 4] = [
    (0.375, 0.125),
    (0.875, 0.375),
    (0.125, 0.625),
    (0.625, 0.875),
];

/// Strictly inside (f64 edge functions); a sample exactly on an edge would need the top-left
/// rule, and the shapes here are chosen so none is.
fn inside(t: [(f64, f64); 3], p: (f64, f64)) -> bool {
    let edge = |a: (f64, f64), b: (f64, f64)| (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0);
    let e = [edge(t[0], t[1]), edge(t[1], t[2]), edge(t[2], t[0])];
    assert!(
        e.iter().all(|v| v.abs() > 1e-9),
        "sample {p:?} on an edge of {t:?}: pick another shape"
    );
    e.iter().all(|&v| v > 0.0) || e.iter().all(|&v| v < 0.0)
}

/// The f64 oracle: fragment shader invocations for pixel-aligned quads drawn in order, each
/// with its depth. A pixel of a quad is hidden where an earlier-drawn, nearer quad covers it
/// (pixel-aligned quads cover whole pixels). At 1× each visible pixel runs the shader once —
/// Vulkan gives a centre sample on the shared diagonal to exactly one triangle. At 4× each
/// triangle runs it once per visible pixel where any of its samples is covered.
fn oracle(drawn: &[(Rect, f32)], samples: &[(f64, f64)]) -> u64 {
    let mut count = 0;
    for (i, (rect, depth)) in drawn.iter().enumerate() {
        let hidden = |x, y| {
            drawn[..i]
                .iter()
                .any(|(r, d)| d < depth && r.contains_pixel(x, y))
        };
        let visible: Vec<(u32, u32)> = (rect.rows.0..rect.rows.1)
            .flat_map(|y| (rect.cols.0..rect.cols.1).map(move |x| (x, y)))
            .filter(|&(x, y)| !hidden(x, y))
            .collect();
        if samples.len() == 1 {
            count += visible.len() as u64;
            continue;
        }
        for tri in rect.triangles() {
            let shaded = visible.iter().filter(|&&(x, y)| {
                samples
                    .iter()
                    .any(|&(sx, sy)| inside(tri, (x as f64 + sx, y as f64 + sy)))
            });
            count += shaded.count() as u64;
        }
    }
    count
}

/// Renders the quads in the given draw order in every mode at 1× and 4× MSAA and compares the
/// counter with the oracle.
fn assert_counts(drawn: &[(Rect, f32)]) {
    let gpu = gpu();
    let scene = scene(
        drawn
            .iter()
            .map(|(r, d)| pixel_rect(r.cols, r.rows, *d))
            .collect(),
    );
    for (msaa, samples) in [(1, &STANDARD_1X[..]), (4, &STANDARD_4X[..])] {
        let expected = oracle(drawn, samples);
        for stereo in StereoMode::ALL {
            let (_, stats) = render(&gpu, &scene, &config(stereo, msaa));
            assert_eq!(
                stats.fragments,
                vec![expected, expected],
                "{stereo}, MSAA {msaa}"
            );
        }
    }
}

#[test]
fn one_rectangle_counts_exactly_in_every_view_mode_and_msaa() {
    let rect = Rect {
        cols: (10, 47),
        rows: (5, 34),
    };
    assert_eq!(
        oracle(&[(rect, 2.0)], &STANDARD_1X),
        37 * 29,
        "1x: exactly the area"
    );
    // 4x: the area plus the pixels on the diagonal that both triangles touch.
    assert!(oracle(&[(rect, 2.0)], &STANDARD_4X) > 37 * 29);
    assert_counts(&[(rect, 2.0)]);
}

#[test]
fn hidden_fragments_are_not_counted_but_overdraw_is() {
    let front = (
        Rect {
            cols: (10, 30),
            rows: (10, 30),
        },
        2.0,
    );
    let back = (
        Rect {
            cols: (21, 50),
            rows: (20, 41),
        },
        4.0,
    );
    // Front first: the back quad's overlap fails the early depth test.
    assert_eq!(oracle(&[front, back], &STANDARD_1X), 400 + 29 * 21 - 9 * 10);
    assert_counts(&[front, back]);
    // Back first: both are shaded in full (overdraw).
    assert_counts(&[back, front]);
}

/// A point at pixel coordinates `p` (x right, y down, any real value) on the plane `depth`
/// metres in front of the 90° view.
fn at_pixel(p: (f64, f64), depth: f32) -> Vec3 {
    let (x, y) = (p.0 as f32, p.1 as f32);
    let t = |c: f32| -1.0 + 2.0 * c / SIZE as f32;
    Vec3::new(t(x) * depth, -t(y) * depth, -depth)
}

/// One mesh of triangles given in pixel coordinates, each wound to face the viewer.
fn pixel_triangles(triangles: &[[(f64, f64); 3]]) -> Scene {
    let mut mesh = Mesh {
        name: "pixel triangles".into(),
        vertices: Vec::new(),
        indices: Vec::new(),
        clusters: Vec::new(),
        lods: Vec::new(),
    };
    for t in triangles {
        // Counter-clockwise in the world (y up) is clockwise in pixels (y down).
        let area = (t[1].0 - t[0].0) * (t[2].1 - t[0].1) - (t[1].1 - t[0].1) * (t[2].0 - t[0].0);
        let order = if area < 0.0 { [0, 1, 2] } else { [0, 2, 1] };
        for i in order {
            mesh.indices.push(mesh.vertices.len() as u32);
            mesh.vertices.push(Vertex {
                position: at_pixel(t[i], 2.0).to_array(),
                normal: [0.0, 0.0, 1.0],
                uv: [0.0, 0.0],
                tangent: [0.0; 4],
            });
        }
    }
    Scene {
        meshes: vec![mesh],
        batches: vec![DrawBatch {
            mesh: 0,
            instances: vec![Instance::new(Mat4::IDENTITY, Vec3::ONE)],
        }],
        head: Mat4::IDENTITY,
        light_dir: Vec3::new(0.0, 0.0, -1.0),
        materials: Vec::new(),
        lights: Vec::new(),
        reach: None,
    }
}

/// The f64 oracle for triangles at one depth that overlap nowhere but along `shared`, an edge
/// two of them have in common: per triangle, the pixels of the view where any sample is
/// strictly inside it — or lies on `shared`, where exactly one of the two covers it (Vulkan's
/// top-left rule gives such a sample to one triangle; which one does not change the count).
/// Pixels outside the view do not exist, which clips.
fn triangle_oracle(
    triangles: &[[(f64, f64); 3]],
    shared: Option<((f64, f64), (f64, f64))>,
    samples: &[(f64, f64)],
) -> u64 {
    let has_shared =
        |t: &[(f64, f64); 3]| shared.is_some_and(|(a, b)| t.contains(&a) && t.contains(&b));
    // The shared edge's line; on it, a sample is covered only between the edge's ends.
    let on_line = |p: (f64, f64)| {
        shared.is_some_and(|(a, b)| {
            ((b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0)).abs() < 1e-9
        })
    };
    let within_edge = |p: (f64, f64)| {
        shared.is_some_and(|(a, b)| {
            let along = (p.0 - a.0) * (b.0 - a.0) + (p.1 - a.1) * (b.1 - a.1);
            along > 0.0 && along < (b.0 - a.0).powi(2) + (b.1 - a.1).powi(2)
        })
    };
    let owner = triangles.iter().position(has_shared);
    let mut count = 0;
    for (i, t) in triangles.iter().enumerate() {
        let covers = |p: (f64, f64)| {
            if has_shared(t) && on_line(p) {
                within_edge(p) && owner == Some(i)
            } else {
                inside(*t, p)
            }
        };
        for y in 0..SIZE {
            for x in 0..SIZE {
                count += samples
                    .iter()
                    .any(|&(sx, sy)| covers((x as f64 + sx, y as f64 + sy)))
                    as u64;
            }
        }
    }
    count
}

/// Renders `triangles` in every stereo mode at 1× and 4× MSAA: exact at 1×; at 4× exact too,
/// except where the view clips a triangle into a fan whose inner edges' pixels are shaded once
/// per sub-triangle (`clipped`: then at least the oracle's count).
fn assert_triangle_counts(
    triangles: &[[(f64, f64); 3]],
    shared: Option<((f64, f64), (f64, f64))>,
    clipped: bool,
) {
    let gpu = gpu();
    let scene = pixel_triangles(triangles);
    for (msaa, samples) in [(1, &STANDARD_1X[..]), (4, &STANDARD_4X[..])] {
        let expected = triangle_oracle(triangles, shared, samples);
        assert!(expected > 0);
        for stereo in StereoMode::ALL {
            let (_, stats) = render(&gpu, &scene, &config(stereo, msaa));
            assert_eq!(stats.fragments.len(), 2);
            for &n in &stats.fragments {
                if clipped && msaa > 1 {
                    assert!(n >= expected, "{stereo}, MSAA {msaa}: {n} < {expected}");
                } else {
                    assert_eq!(n, expected, "{stereo}, MSAA {msaa}");
                }
            }
        }
    }
}

/// Slanted edges at non-integer positions: the count is the samples strictly inside.
/// Mutation: a counter that counts bounding boxes, or pixels by their corners, fails it.
#[test]
fn slanted_triangles_count_exactly() {
    assert_triangle_counts(
        &[
            [(3.3, 5.7), (60.2, 12.9), (20.6, 58.1)],
            [(45.1, 40.2), (62.7, 61.3), (40.4, 62.9)],
        ],
        None,
        false,
    );
}

/// Two triangles sharing an edge that runs through 31 pixel centres: at 1× each of those
/// samples is counted once (the top-left rule), never twice or not at all. Mutation: the
/// oracle giving the shared samples to both triangles (or neither) is 31 off and fails.
#[test]
fn a_shared_edge_through_pixel_centres_is_counted_once() {
    let (a, b) = ((8.75, 8.75), (40.25, 40.25));
    let triangles = [[a, b, (44.3, 6.2)], [b, a, (5.1, 43.7)]];
    // The oracle itself: the 31 centres (k + ½, k + ½), k = 9..=39, are counted once.
    let once = triangle_oracle(&triangles, Some((a, b)), &STANDARD_1X);
    let each: u64 = triangles
        .iter()
        .map(|t| triangle_oracle(&[*t], Some((a, b)), &STANDARD_1X))
        .sum();
    assert_eq!(
        each - once,
        31,
        "both triangles alone claim the shared samples"
    );
    assert_triangle_counts(&triangles, Some((a, b)), false);
}

/// Triangles reaching past the view's edges are clipped: only the view's own pixels count.
/// Mutation: an oracle (or counter) counting the whole triangle fails it.
#[test]
fn triangles_clipped_by_the_view_count_only_visible_pixels() {
    assert_triangle_counts(
        &[
            [(-20.3, 30.1), (30.7, -15.2), (35.9, 40.4)],
            [(50.2, 20.6), (90.3, 35.1), (52.8, 80.7)],
        ],
        None,
        true,
    );
}
