//! Geometry the glTF loader derives from a file: the head that frames a scene without a
//! camera, triangle lists from strips and fans, unwelded and double-sided meshes, flat normals
//! and MikkTSpace tangents where a file has none.

use glam::{Mat4, Vec3, Vec4};
use gltf::mesh::Mode;

use super::{Mesh, Scene, Vertex};
use crate::cull::Aabb;
use crate::view::look_at_head;

/// A head that sees the whole scene: on its bounding box's +z side, level with its centre,
/// looking at it from 1.1 times the box's half-diagonal away (the box of every instance's
/// transformed mesh box).
pub(super) fn framing_head(scene: &Scene) -> Mat4 {
    let mesh_boxes: Vec<Aabb> = scene
        .meshes
        .iter()
        .map(|m| {
            let p = |v: &Vertex| Vec3::from(v.position);
            let first = Aabb::new(p(&m.vertices[0]), p(&m.vertices[0]));
            m.vertices
                .iter()
                .fold(first, |b, v| b.union(&Aabb::new(p(v), p(v))))
        })
        .collect();
    let bounds = scene
        .batches
        .iter()
        .flat_map(|b| {
            let mesh_box = mesh_boxes[b.mesh];
            b.instances
                .iter()
                .flat_map(move |i| mesh_box.corners().map(|c| i.model.transform_point3(c)))
        })
        .map(|c| Aabb::new(c, c))
        .reduce(|a, b| a.union(&b))
        .expect("a scene with instances");
    let centre = bounds.center();
    let radius = bounds.extents().length().max(1e-3);
    log::info!(
        "no camera in the file: framing its bounds {} to {} from {radius:.3} m",
        bounds.min,
        bounds.max
    );
    look_at_head(centre + Vec3::Z * radius * 1.1, centre)
}

pub(super) fn finite_or_zero<const N: usize>(v: [f32; N]) -> [f32; N] {
    v.map(|c| if c.is_finite() { c } else { 0.0 })
}

/// Triangle-list indices of a primitive of `mode` (strips and fans unrolled, keeping their
/// winding; an incomplete last triangle dropped).
pub(super) fn triangle_list(mode: Mode, raw: &[u32]) -> Vec<u32> {
    match mode {
        Mode::TriangleStrip => (2..raw.len())
            .flat_map(|i| {
                if i % 2 == 0 {
                    [raw[i - 2], raw[i - 1], raw[i]]
                } else {
                    [raw[i - 1], raw[i - 2], raw[i]]
                }
            })
            .collect(),
        Mode::TriangleFan => (2..raw.len())
            .flat_map(|i| [raw[0], raw[i - 1], raw[i]])
            .collect(),
        _ => raw[..raw.len() / 3 * 3].to_vec(),
    }
}

/// Each triangle its own three vertices.
pub(super) fn unweld(vertices: &[Vertex], indices: &[u32]) -> (Vec<Vertex>, Vec<u32>) {
    let out: Vec<Vertex> = indices.iter().map(|&i| vertices[i as usize]).collect();
    let indices = (0..out.len() as u32).collect();
    (out, indices)
}

/// A double-sided material's back faces: every triangle again, wound the other way, its
/// normals flipped (the pipeline culls back faces, so one pipeline serves every material).
pub(super) fn add_back_faces(mesh: &mut Mesh) {
    let first = mesh.vertices.len() as u32;
    let back: Vec<Vertex> = mesh
        .vertices
        .iter()
        .map(|v| Vertex {
            normal: (-Vec3::from(v.normal)).to_array(),
            tangent: [v.tangent[0], v.tangent[1], v.tangent[2], -v.tangent[3]],
            ..*v
        })
        .collect();
    mesh.vertices.extend(back);
    let flipped: Vec<u32> = mesh
        .indices
        .chunks_exact(3)
        .flat_map(|t| [t[0] + first, t[2] + first, t[1] + first])
        .collect();
    mesh.indices.extend(flipped);
}

/// MikkTSpace tangents (what glTF prescribes when a file has none), written to each vertex.
pub(super) fn generate_tangents(vertices: &mut [Vertex], indices: &[u32]) {
    struct Geometry<'a> {
        vertices: &'a mut [Vertex],
        indices: &'a [u32],
    }
    impl Geometry<'_> {
        fn vertex(&self, face: usize, vert: usize) -> &Vertex {
            &self.vertices[self.indices[face * 3 + vert] as usize]
        }
    }
    impl mikktspace::Geometry for Geometry<'_> {
        fn num_faces(&self) -> usize {
            self.indices.len() / 3
        }
        fn num_vertices_of_face(&self, _face: usize) -> usize {
            3
        }
        fn position(&self, face: usize, vert: usize) -> [f32; 3] {
            self.vertex(face, vert).position
        }
        fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
            self.vertex(face, vert).normal
        }
        fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
            self.vertex(face, vert).uv
        }
        fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
            let i = self.indices[face * 3 + vert] as usize;
            // Shared vertices get one tangent (MikkTSpace gives a vertex the same tangent in
            // every face unless a seam splits it, and seams split vertices in glTF files).
            let t = Vec4::from(tangent);
            self.vertices[i].tangent = if t.is_finite() {
                [t.x, t.y, t.z, if t.w < 0.0 { -1.0 } else { 1.0 }]
            } else {
                [0.0; 4]
            };
        }
    }
    // MikkTSpace (translated C) indexes out of bounds when no triangle has area: such a mesh
    // shows nothing a tangent could matter to.
    let has_area = indices.chunks_exact(3).any(|t| {
        let p = [0, 1, 2].map(|k| Vec3::from(vertices[t[k] as usize].position));
        (p[1] - p[0]).cross(p[2] - p[0]).length_squared() > 0.0
    });
    if !has_area {
        return;
    }
    if !mikktspace::generate_tangents(&mut Geometry { vertices, indices }) {
        log::debug!("mikktspace generated no tangents; the frame comes from derivatives");
    }
}

/// The vertices with their normals: the file's, or without them (glTF: flat shading) each
/// triangle's own, its vertices unwelded.
pub(super) fn with_normals(
    mut vertices: Vec<Vertex>,
    indices: Vec<u32>,
    normals: Option<Vec<[f32; 3]>>,
) -> (Vec<Vertex>, Vec<u32>) {
    match normals {
        Some(normals) => {
            for (v, n) in vertices.iter_mut().zip(normals) {
                v.normal = Vec3::from(finite_or_zero(n))
                    .normalize_or(Vec3::Y)
                    .to_array();
            }
            (vertices, indices)
        }
        None => {
            let (mut vertices, i) = unweld(&vertices, &indices);
            for t in i.chunks_exact(3) {
                let p = [0, 1, 2].map(|k| Vec3::from(vertices[t[k] as usize].position));
                let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize_or(Vec3::Y);
                for &k in t {
                    vertices[k as usize].normal = n.to_array();
                }
            }
            (vertices, i)
        }
    }
}
