//! How far apart two triangle meshes' surfaces are, measured: a level of detail's error is the
//! larger of both one-sided distances (every point sampled on one surface to the nearest point
//! of the other), so a coarse triangle sagging below a curved surface and a feature the
//! simplifier removed both count.

use std::collections::HashMap;

use glam::{IVec3, Vec3};

/// Samples per triangle edge: a barycentric grid of (N + 1)(N + 2) / 2 points, its centroid
/// among them (N divisible by 3), where a flat triangle under a curved surface sags most. A
/// skewed triangle's deepest point can fall between samples: the distance is sampled, not
/// bounded (on a coarse sphere level, 1.1 % short of a grid twice as fine).
const SAMPLES_PER_EDGE: u32 = 6;

/// The largest distance from a point of either surface to the other (a sampled Hausdorff
/// distance). `positions` are shared; `a` and `b` index them, three per triangle.
pub(super) fn surface_distance(positions: &[Vec3], a: &[u32], b: &[u32]) -> f32 {
    one_sided(positions, a, b).max(one_sided(positions, b, a))
}

/// The largest distance from a sample of `from`'s triangles to `to`'s surface.
fn one_sided(positions: &[Vec3], from: &[u32], to: &[u32]) -> f32 {
    let grid = TriangleGrid::new(positions, to);
    let mut farthest = 0.0f32;
    for t in from.chunks_exact(3) {
        let [p, q, r] = [0, 1, 2].map(|k| positions[t[k] as usize]);
        for i in 0..=SAMPLES_PER_EDGE {
            for j in 0..=SAMPLES_PER_EDGE - i {
                let (u, v) = (
                    i as f32 / SAMPLES_PER_EDGE as f32,
                    j as f32 / SAMPLES_PER_EDGE as f32,
                );
                let d = grid.distance(p + (q - p) * u + (r - p) * v, farthest);
                farthest = farthest.max(d);
            }
        }
    }
    farthest
}

/// Triangles bucketed by the grid cells their bounding boxes overlap.
struct TriangleGrid {
    triangles: Vec<[Vec3; 3]>,
    cells: HashMap<IVec3, Vec<u32>>,
    cell: f32,
    origin: Vec3,
}

impl TriangleGrid {
    fn new(positions: &[Vec3], indices: &[u32]) -> Self {
        let triangles: Vec<[Vec3; 3]> = indices
            .chunks_exact(3)
            .map(|t| [0, 1, 2].map(|k| positions[t[k] as usize]))
            .collect();
        let (lo, hi) = triangles
            .iter()
            .flatten()
            .fold((Vec3::MAX, Vec3::MIN), |(lo, hi), &p| {
                (lo.min(p), hi.max(p))
            });
        // About one triangle per cell along a surface: the box's area over the triangles.
        let extent = (hi - lo).max(Vec3::splat(1e-6));
        let area = 2.0 * (extent.x * extent.y + extent.y * extent.z + extent.z * extent.x);
        let cell = (area / triangles.len().max(1) as f32).sqrt().max(1e-6);
        let mut grid = TriangleGrid {
            triangles,
            cells: HashMap::new(),
            cell,
            origin: lo,
        };
        for (k, t) in grid.triangles.iter().enumerate() {
            let lo = grid.cell_of(t[0].min(t[1]).min(t[2]));
            let hi = grid.cell_of(t[0].max(t[1]).max(t[2]));
            for x in lo.x..=hi.x {
                for y in lo.y..=hi.y {
                    for z in lo.z..=hi.z {
                        grid.cells
                            .entry(IVec3::new(x, y, z))
                            .or_default()
                            .push(k as u32);
                    }
                }
            }
        }
        grid
    }

    fn cell_of(&self, p: Vec3) -> IVec3 {
        ((p - self.origin) / self.cell).floor().as_ivec3()
    }

    /// The distance from `p` to the nearest triangle; the search stops early once it is known
    /// to be at most `enough` (the caller keeps only the largest distance).
    fn distance(&self, p: Vec3, enough: f32) -> f32 {
        let centre = self.cell_of(p);
        let mut best = f32::INFINITY;
        // Rings of cells around p's: once the nearest found lies within the rings searched,
        // nothing farther out can be nearer.
        for ring in 0i32.. {
            let reach = ring as f32 * self.cell;
            if best <= reach || best <= enough || ring > 1 << 12 {
                break;
            }
            for x in -ring..=ring {
                for y in -ring..=ring {
                    for z in -ring..=ring {
                        if x.abs().max(y.abs()).max(z.abs()) != ring {
                            continue;
                        }
                        let Some(ts) = self.cells.get(&(centre + IVec3::new(x, y, z))) else {
                            continue;
                        };
                        for &k in ts {
                            let [a, b, c] = self.triangles[k as usize];
                            best = best.min(closest_on_triangle(p, a, b, c).distance(p));
                        }
                    }
                }
            }
        }
        best
    }
}

/// The point of triangle abc nearest p (Ericson, Real-Time Collision Detection §5.1.5).
fn closest_on_triangle(p: Vec3, a: Vec3, b: Vec3, c: Vec3) -> Vec3 {
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return a;
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return b;
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return a + ab * (d1 / (d1 - d3));
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return c;
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return a + ac * (d2 / (d2 - d6));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        return b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6)));
    }
    let denom = 1.0 / (va + vb + vc);
    a + ab * (vb * denom) + ac * (vc * denom)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The nearest point against a dense sampling of the triangle, for points all around it
    /// (each region of the case analysis). Mutation: swapping the edge-bc branch's weights.
    #[test]
    fn closest_point_is_nearest() {
        let [a, b, c] = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(2.0, 0.3, 0.0),
            Vec3::new(0.4, 1.7, 0.5),
        ];
        for i in -4..=6 {
            for j in -4..=6 {
                for k in [-1.0, 0.0, 0.7] {
                    let p = Vec3::new(i as f32 * 0.5, j as f32 * 0.5, k);
                    let d = closest_on_triangle(p, a, b, c).distance(p);
                    let sampled = (0..=200)
                        .flat_map(|u| (0..=200 - u).map(move |v| (u, v)))
                        .map(|(u, v)| {
                            let q = a + (b - a) * (u as f32 / 200.0) + (c - a) * (v as f32 / 200.0);
                            q.distance(p)
                        })
                        .fold(f32::INFINITY, f32::min);
                    assert!(
                        d <= sampled + 1e-5 && d >= sampled - 0.02,
                        "{p}: {d} vs {sampled}"
                    );
                }
            }
        }
    }

    /// A grid of two triangles against the same square lifted by 0.25: 0.25 apart both ways;
    /// against itself, 0.
    #[test]
    fn surfaces_apart_by_a_lift() {
        let positions = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 0.25, 0.0),
            Vec3::new(1.0, 0.25, 0.0),
            Vec3::new(1.0, 0.25, 1.0),
            Vec3::new(0.0, 0.25, 1.0),
        ];
        let low = [0, 2, 1, 0, 3, 2];
        let high = [4, 6, 5, 4, 7, 6];
        assert!((surface_distance(&positions, &low, &high) - 0.25).abs() < 1e-6);
        assert!(surface_distance(&positions, &low, &low) < 1e-6);
    }
}
