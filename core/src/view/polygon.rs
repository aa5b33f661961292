//! Convex polygons in a view's 2D spaces (tangent space, NDC): clipping and area.

use glam::DVec2;

/// Sutherland–Hodgman: the polygon clipped to the rectangle `min`…`max`.
pub(crate) fn clip_to_rect(mut polygon: Vec<DVec2>, min: DVec2, max: DVec2) -> Vec<DVec2> {
    // Each edge of the rectangle as (axis, sign, bound): inside where sign · (p[axis] − bound) ≥ 0.
    for (axis, sign, bound) in [
        (0, 1.0, min.x),
        (0, -1.0, max.x),
        (1, 1.0, min.y),
        (1, -1.0, max.y),
    ] {
        let inside = |p: DVec2| sign * (p[axis] - bound) >= 0.0;
        let mut out = Vec::with_capacity(polygon.len() + 1);
        for (i, &a) in polygon.iter().enumerate() {
            let b = polygon[(i + 1) % polygon.len()];
            if inside(a) {
                out.push(a);
            }
            if inside(a) != inside(b) {
                let t = (bound - a[axis]) / (b[axis] - a[axis]);
                out.push(a + (b - a) * t);
            }
        }
        polygon = out;
        if polygon.is_empty() {
            break;
        }
    }
    polygon
}

/// The polygon's area (shoelace; either winding).
pub(crate) fn area(p: &[DVec2]) -> f64 {
    let twice: f64 = (0..p.len())
        .map(|i| p[i].perp_dot(p[(i + 1) % p.len()]))
        .sum();
    twice.abs() / 2.0
}
