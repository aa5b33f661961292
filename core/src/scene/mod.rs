//! Scenes: meshes, instances drawn with instanced draws, and the head pose to view them from.

mod atrium;
mod city;
mod clusters;
mod default_scene;
#[cfg_attr(not(feature = "clusters"), allow(dead_code))]
mod deviation;
mod gltf_file;
mod gltf_geometry;
mod gltf_uri;
mod lod;
mod materials;
mod motion;
mod shapes;
pub(crate) mod textures;
mod thesis;

pub use atrium::atrium_scene;
pub use city::city_scene;
pub use clusters::{
    Cluster, ClusterError, ClusterSettings, NormalCone, PlacedClusters, CLUSTER_TRIANGLES_RANGE,
    DEFAULT_CLUSTER_TRIANGLES,
};
pub use default_scene::{default_scene, fill_scene};
pub use gltf_file::{gltf_from_slice, is_scene_file, load_gltf, SceneFileError};
pub use lod::{
    LodError, LodLevel, LodSettings, DEFAULT_LOD_ERROR_PX, LOD_ERROR_PX_RANGE, LOD_MIN_TRIANGLES,
    MAX_LOD_LEVELS,
};
pub use materials::{Material, Pattern, PointLight, Shading, Surface, MAX_POINT_LIGHTS};
pub use motion::{walking_pose, Walker, TURN_DEG_S, WALK_SPEED_M_S};
pub use textures::{MaterialTextures, Texture, TEXTURE_SIZE};

/// The scenes the command line offers, by name.
pub const SCENE_NAMES: [&str; 5] = ["default", "fill", "city", "thesis", "atrium"];

/// The size at which `--scene thesis` renders the thesis scene (14 × 22 × 14 instances);
/// `foveate bench --scale` picks others.
pub const THESIS_PREVIEW_SCALE: f32 = 0.02;

/// Why `--scene` named no scene.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error(transparent)]
    /// No scene has that name.
    Name(#[from] crate::vocab::ConfigError),
    #[error(transparent)]
    /// The scene file could not be loaded.
    File(#[from] SceneFileError),
}

/// A scene by its command-line name, shaded as it was built (`atrium` and glTF files lit, the
/// others flat): a built-in scene, or a path ending in `.gltf` or `.glb`.
pub fn named_scene(name: &str) -> Result<Scene, SceneError> {
    if is_scene_file(name) {
        return Ok(load_gltf(std::path::Path::new(name))?);
    }
    Ok(match name {
        "default" => default_scene(),
        "fill" => fill_scene(),
        "city" => city_scene(),
        "thesis" => ThesisScene::new(THESIS_PREVIEW_SCALE)?.to_scene(),
        "atrium" => atrium_scene(),
        _ => {
            return Err(crate::vocab::ConfigError::new(
                "scene",
                name,
                format!("one of {}, or a .gltf or .glb file", SCENE_NAMES.join(", ")),
            )
            .into())
        }
    })
}
pub use shapes::{cube, cylinder, ground_grid, ground_quad, uv_sphere};
pub use thesis::{
    entropy, rail_pose, ThesisObject, ThesisScene, RAIL_LOOP_FRAMES, THESIS_COUNTS, THESIS_SPACING,
};

use glam::{Mat4, Vec3, Vec4};

use crate::cull::{Aabb, Sphere};

/// A vertex as the scene shaders read it (location 0: position, 1: normal, 2: texture
/// coordinates, 3: tangent).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Vertex {
    /// Position in the mesh's space.
    pub position: [f32; 3],
    /// Unit normal.
    pub normal: [f32; 3],
    /// Texture coordinates.
    pub uv: [f32; 2],
    /// xyz along +u, w the bitangent's sign (glTF's convention); all zero: no tangent, and a
    /// normal map takes its frame from screen-space derivatives (the built-in shapes).
    pub tangent: [f32; 4],
}

/// Indexed triangle geometry.
#[derive(Clone, Debug, PartialEq)]
pub struct Mesh {
    /// Its name (the glTF mesh's, or the shape's).
    pub name: String,
    /// Its vertices.
    pub vertices: Vec<Vertex>,
    /// Three indices into `vertices` per triangle, counter-clockwise from the front.
    pub indices: Vec<u32>,
    /// Its triangles in clusters, each a contiguous run of `indices`; empty: drawn and culled
    /// whole ([`Scene::with_clusters`]).
    pub clusters: Vec<Cluster>,
    /// Simplified versions, coarser one after another, for views that cannot resolve the
    /// detail; empty: only the full mesh ([`Scene::with_lod`]).
    pub lods: Vec<LodLevel>,
}

impl Mesh {
    /// Its triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len() / 3
    }

    /// A sphere around every vertex: centred on their bounding box.
    pub fn bounding_sphere(&self) -> Sphere {
        let points = self.vertices.iter().map(|v| Vec3::from(v.position));
        let Some(first) = points.clone().next() else {
            return Sphere::new(Vec3::ZERO, 0.0);
        };
        let b = points
            .clone()
            .fold(Aabb::new(first, first), |b, p| b.union(&Aabb::new(p, p)));
        let c = b.center();
        Sphere::new(c, points.map(|p| p.distance(c)).fold(0.0, f32::max))
    }
}

/// One placed object, laid out as the shaders' `Instance` struct (std430: mat4, vec4, uvec4).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Instance {
    /// The object's world pose (mesh space to world).
    pub model: Mat4,
    /// Flat shading's colour; lit, the tint of its material's base colour.
    pub color: Vec4,
    /// Index into [`Scene::materials`] (ignored when the scene is flat).
    pub material: u32,
    /// 1 once the renderer has moved or added it (`Renderer::move_instance`,
    /// `Renderer::add_instance`): the scene pass marks its pixels, and the periphery's
    /// accumulation clips its history there (`HistoryClip::Moved`).
    pub(crate) moves: u32,
    _pad: [u32; 2],
}

impl Instance {
    /// An instance at `model`, coloured `rgb`, material 0.
    pub fn new(model: Mat4, rgb: Vec3) -> Self {
        Self {
            model,
            color: rgb.extend(1.0),
            material: 0,
            moves: 0,
            _pad: [0; 2],
        }
    }

    /// The same instance with material `material`.
    pub fn with_material(self, material: u32) -> Self {
        Self { material, ..self }
    }

    /// The most its model matrix stretches any length: its longest axis.
    pub fn max_scale(&self) -> f32 {
        let m = self.model;
        [m.x_axis, m.y_axis, m.z_axis]
            .map(|a| a.truncate().length())
            .into_iter()
            .fold(0.0, f32::max)
    }
}

/// All instances of one mesh: one instanced draw call.
#[derive(Clone, Debug, PartialEq)]
pub struct DrawBatch {
    /// Index into [`Scene::meshes`].
    pub mesh: usize,
    /// The mesh's placements.
    pub instances: Vec<Instance>,
}

/// A draw as the renderer records it: mesh, and a range of the flattened instance buffer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Draw {
    /// Index into [`Scene::meshes`].
    pub mesh: usize,
    /// The first instance, in the flattened instance buffer.
    pub first_instance: u32,
    /// How many instances from it.
    pub instance_count: u32,
}

/// Meshes, their instances and where the viewer's head is.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The meshes.
    pub meshes: Vec<Mesh>,
    /// Each mesh's instances: one batch per mesh drawn.
    pub batches: Vec<DrawBatch>,
    /// World pose of the head (the point between the eyes).
    pub head: Mat4,
    /// Direction the light travels (world space, normalised).
    pub light_dir: Vec3,
    /// Lit materials (PBR metallic-roughness); empty for a flat-shaded scene.
    pub materials: Vec<Material>,
    /// Point lights of a lit scene (at most [`materials::MAX_POINT_LIGHTS`]), besides the sun
    /// along `light_dir` and the ambient sky.
    pub lights: Vec<PointLight>,
    /// How far the far plane must reach to show all of the scene, when the default far plane
    /// might not (a file's scene, in whatever units it was made); `None` for the built-in
    /// scenes, which fit it.
    pub reach: Option<f32>,
}

impl Scene {
    /// Nothing to draw, the head at the origin: for measuring what a frame costs by itself
    /// (masks, the coverage probe).
    pub fn empty() -> Scene {
        Scene {
            meshes: vec![],
            batches: vec![],
            head: Mat4::IDENTITY,
            light_dir: Vec3::NEG_Y,
            materials: Vec::new(),
            lights: Vec::new(),
            reach: None,
        }
    }

    /// How the scene is shaded: lit when it has materials.
    pub fn shading(&self) -> Shading {
        if self.materials.is_empty() {
            Shading::Flat
        } else {
            Shading::Lit
        }
    }

    /// The scene shaded as asked: flat drops its materials and lights; lit keeps a lit scene's
    /// and gives a flat one the built-in material palette (each instance's colour tints its
    /// material) and a light rig.
    pub fn with_shading(mut self, shading: Shading) -> Scene {
        match (shading, self.shading()) {
            (Shading::Flat, _) => {
                self.materials.clear();
                self.lights.clear();
            }
            (Shading::Lit, Shading::Lit) => {}
            (Shading::Lit, Shading::Flat) => materials::light_up(&mut self),
        }
        self
    }

    /// Instances over all batches.
    pub fn instance_count(&self) -> usize {
        self.batches.iter().map(|b| b.instances.len()).sum()
    }

    /// Triangles submitted per view.
    pub fn triangle_count(&self) -> usize {
        self.batches
            .iter()
            .map(|b| self.meshes[b.mesh].triangle_count() * b.instances.len())
            .sum()
    }

    /// The draws in order, each naming its slice of [`Scene::flat_instances`]; empty batches
    /// are skipped.
    pub fn draws(&self) -> impl Iterator<Item = Draw> + '_ {
        let mut first = 0u32;
        self.batches
            .iter()
            .filter(|b| !b.instances.is_empty())
            .map(move |b| {
                let draw = Draw {
                    mesh: b.mesh,
                    first_instance: first,
                    instance_count: b.instances.len() as u32,
                };
                first += draw.instance_count;
                draw
            })
    }

    /// The scene with `spare` instances of each mesh appended as one batch per mesh, after the
    /// scene's own instances (which keep their numbers): the room a plan's
    /// `RenderConfig::spare_instances` makes for instances added while rendering. The renderer keeps them absent until one is added.
    pub fn with_spare_instances(&self, spare: u32) -> Scene {
        let mut scene = self.clone();
        if spare > 0 {
            let instance = Instance::new(Mat4::IDENTITY, Vec3::ONE);
            scene
                .batches
                .extend((0..self.meshes.len()).map(|mesh| DrawBatch {
                    mesh,
                    instances: vec![instance; spare as usize],
                }));
        }
        scene
    }

    /// Each instance's bounding sphere, in [`Scene::flat_instances`] order.
    pub fn instance_spheres(&self) -> Vec<Sphere> {
        let mesh_spheres: Vec<Sphere> = self.meshes.iter().map(Mesh::bounding_sphere).collect();
        self.batches
            .iter()
            .flat_map(|b| {
                let s = mesh_spheres[b.mesh];
                b.instances.iter().map(move |i| {
                    Sphere::new(i.model.transform_point3(s.center), s.radius * i.max_scale())
                })
            })
            .collect()
    }

    /// How far a viewer anywhere inside the scene's bounding box (its head position included)
    /// can see scene content: the box's diagonal. `0` for an empty scene.
    pub fn content_reach(&self) -> f32 {
        if self.instance_count() == 0 {
            return 0.0;
        }
        let head = self.head.transform_point3(Vec3::ZERO);
        let bounds = self
            .instance_spheres()
            .iter()
            .fold(Aabb::new(head, head), |b, s| b.union(&Aabb::of_sphere(s)));
        bounds.extents().length() * 2.0
    }

    /// Every instance, batch after batch, in the order [`Scene::draws`] indexes them.
    pub fn flat_instances(&self) -> Vec<Instance> {
        self.batches
            .iter()
            .flat_map(|b| b.instances.iter().copied())
            .collect()
    }
}
