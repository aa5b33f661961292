use std::f32::consts::PI;

use super::{Mesh, Vertex};

/// Unit cube centred on the origin (side 1), flat-shaded: 24 vertices, 12 triangles.
pub fn cube() -> Mesh {
    let mut vertices = Vec::with_capacity(24);
    let mut indices = Vec::with_capacity(36);
    // Each face: its normal and two in-plane axes whose cross product is the normal, so the
    // quad winds counter-clockwise seen from outside.
    let faces: [([f32; 3], [f32; 3], [f32; 3]); 6] = [
        ([1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]),
        ([-1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]),
        ([0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]),
        ([0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
        ([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 0.0, -1.0], [-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
    ];
    for (n, u, v) in faces {
        let base = vertices.len() as u32;
        for (su, sv) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
            let p = [0, 1, 2].map(|k| n[k] * 0.5 + u[k] * su + v[k] * sv);
            vertices.push(Vertex {
                position: p,
                normal: n,
                uv: [su + 0.5, 0.5 - sv],
                tangent: [0.0; 4],
            });
        }
        indices.extend([base, base + 1, base + 2, base, base + 2, base + 3]);
    }
    Mesh {
        name: "cube".into(),
        vertices,
        indices,
        clusters: Vec::new(),
        lods: Vec::new(),
    }
}

/// Unit-radius UV sphere with `segments` around and `rings` from pole to pole.
pub fn uv_sphere(segments: u32, rings: u32) -> Mesh {
    let segments = segments.max(3);
    let rings = rings.max(2);
    let mut vertices = Vec::new();
    for r in 0..=rings {
        let theta = PI * r as f32 / rings as f32;
        for s in 0..=segments {
            let phi = 2.0 * PI * s as f32 / segments as f32;
            let n = [
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            ];
            vertices.push(Vertex {
                position: n,
                normal: n,
                uv: [s as f32 / segments as f32, r as f32 / rings as f32],
                tangent: [0.0; 4],
            });
        }
    }
    let row = segments + 1;
    let mut indices = Vec::new();
    for r in 0..rings {
        for s in 0..segments {
            let a = r * row + s;
            let b = a + row;
            // Skip the degenerate triangle at each pole.
            if r != 0 {
                indices.extend([a, b, a + 1]);
            }
            if r != rings - 1 {
                indices.extend([a + 1, b, b + 1]);
            }
        }
    }
    Mesh {
        name: "sphere".into(),
        vertices,
        indices,
        clusters: Vec::new(),
        lods: Vec::new(),
    }
}

/// A ground plane facing +Y around the origin, out to `half_extent` metres, in cells that
/// grow geometrically from `first_cell` metres at the centre: fine under the viewer, so that
/// the few triangles crossing the eye plane stay below the field of view, and coarse far away.
pub fn ground_grid(half_extent: f32, first_cell: f32) -> Mesh {
    let mut edges = vec![0.0f32];
    let mut cell = first_cell;
    while *edges.last().expect("starts non-empty") < half_extent {
        let next = (edges.last().expect("starts non-empty") + cell).min(half_extent);
        edges.push(next);
        cell *= 1.25;
    }
    let coords: Vec<f32> = edges
        .iter()
        .rev()
        .map(|e| -e)
        .chain(edges.iter().skip(1).copied())
        .collect();
    let n = coords.len() as u32;
    let normal = [0.0, 1.0, 0.0];
    let vertices = coords
        .iter()
        .flat_map(|&z| {
            coords.iter().map(move |&x| Vertex {
                position: [x, 0.0, z],
                normal,
                uv: [x, z],
                tangent: [0.0; 4],
            })
        })
        .collect();
    let mut indices = Vec::new();
    for row in 0..n - 1 {
        for col in 0..n - 1 {
            let a = row * n + col;
            let (b, c, d) = (a + 1, a + n, a + n + 1);
            // Rows run towards +z, so (a, c, d) winds counter-clockwise seen from above.
            indices.extend([a, c, d, a, d, b]);
        }
    }
    Mesh {
        name: "ground".into(),
        vertices,
        indices,
        clusters: Vec::new(),
        lods: Vec::new(),
    }
}

/// A closed cylinder of radius 0.5 and height 1 around the Y axis, centred on the origin, with
/// `segments` sides (smooth normals on the side, flat caps).
pub fn cylinder(segments: u32) -> Mesh {
    let segments = segments.max(3);
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    let ring = |s: u32| {
        let phi = 2.0 * PI * s as f32 / segments as f32;
        (phi.cos(), -phi.sin())
    };
    // The side: two rings, the seam duplicated for its texture coordinates.
    for s in 0..=segments {
        let (x, z) = ring(s);
        for (y, v) in [(-0.5, 1.0), (0.5, 0.0)] {
            vertices.push(Vertex {
                position: [0.5 * x, y, 0.5 * z],
                normal: [x, 0.0, z],
                uv: [s as f32 / segments as f32, v],
                tangent: [0.0; 4],
            });
        }
    }
    for s in 0..segments {
        let (a, b, c, d) = (2 * s, 2 * s + 1, 2 * s + 2, 2 * s + 3);
        indices.extend([a, c, d, a, d, b]);
    }
    // The caps: a fan around each centre.
    for (y, ny) in [(0.5f32, 1.0f32), (-0.5, -1.0)] {
        let centre = vertices.len() as u32;
        vertices.push(Vertex {
            position: [0.0, y, 0.0],
            normal: [0.0, ny, 0.0],
            uv: [0.5, 0.5],
            tangent: [0.0; 4],
        });
        for s in 0..segments {
            let (x, z) = ring(s);
            vertices.push(Vertex {
                position: [0.5 * x, y, 0.5 * z],
                normal: [0.0, ny, 0.0],
                uv: [0.5 + 0.5 * x, 0.5 + 0.5 * z],
                tangent: [0.0; 4],
            });
        }
        for s in 0..segments {
            let (a, b) = (centre + 1 + s, centre + 1 + (s + 1) % segments);
            if ny > 0.0 {
                indices.extend([centre, a, b]);
            } else {
                indices.extend([centre, b, a]);
            }
        }
    }
    Mesh {
        name: "cylinder".into(),
        vertices,
        indices,
        clusters: Vec::new(),
        lods: Vec::new(),
    }
}

/// Unit square in the XZ plane facing +Y (for the ground), or any plane once transformed.
pub fn ground_quad() -> Mesh {
    let n = [0.0, 1.0, 0.0];
    let vertices = [(-0.5, 0.5), (0.5, 0.5), (0.5, -0.5), (-0.5, -0.5)]
        .map(|(x, z)| Vertex {
            position: [x, 0.0, z],
            normal: n,
            uv: [x + 0.5, z + 0.5],
            tangent: [0.0; 4],
        })
        .to_vec();
    Mesh {
        name: "ground".into(),
        vertices,
        indices: vec![0, 1, 2, 0, 2, 3],
        clusters: Vec::new(),
        lods: Vec::new(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    /// Every triangle winds counter-clockwise seen from outside: its face normal points the
    /// same way as its vertices' normals.
    fn assert_outward(mesh: &Mesh) {
        for t in mesh.indices.chunks_exact(3) {
            let p = [0, 1, 2].map(|k| Vec3::from(mesh.vertices[t[k] as usize].position));
            let face = (p[1] - p[0]).cross(p[2] - p[0]);
            let n: Vec3 = t
                .iter()
                .map(|&i| Vec3::from(mesh.vertices[i as usize].normal))
                .sum();
            assert!(
                face.dot(n) > 0.0,
                "{} triangle {t:?} winds inward",
                mesh.name
            );
        }
    }

    #[test]
    fn shapes_wind_outward() {
        assert_outward(&cube());
        assert_outward(&uv_sphere(16, 8));
        assert_outward(&ground_quad());
        assert_outward(&ground_grid(10.0, 0.5));
        assert_outward(&cylinder(24));
    }

    #[test]
    fn sphere_counts() {
        let s = uv_sphere(64, 32);
        assert_eq!(s.triangle_count(), 64 * 32 * 2 - 2 * 64);
    }
}
