//! glTF 2.0 scenes (`.gltf` with external or embedded buffers, `.glb`): the default scene's node
//! hierarchy, each mesh primitive a [`Mesh`] drawn once per node that uses it (instanced), PBR
//! metallic-roughness materials mapped onto the lit material model.
//!
//! Every accessor is checked against its buffer before it is read, so a malformed file is an
//! error naming the file and what is wrong, never a panic (the loader is fuzzed, see the tests).
//! What the lit model lacks, the loader approximates and says so in the log: textures are
//! resampled to the texture arrays' [`TEXTURE_SIZE`]² with repeat wrapping, `BLEND` renders as a
//! mask at 0.5, double-sided materials get their back faces as extra triangles, emission,
//! texture transforms and UV sets other than 0 are ignored.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::{Mat4, Vec3};
use gltf::accessor::{DataType, Dimensions};
use gltf::mesh::Mode;

use super::gltf_geometry::{
    add_back_faces, finite_or_zero, framing_head, generate_tangents, triangle_list, with_normals,
};
use super::gltf_uri::{load_buffer, read_uri};
use super::textures::unorm8;
use super::TEXTURE_SIZE;
use super::{DrawBatch, Instance, Material, MaterialTextures, Mesh, Scene, Surface, Vertex};
use crate::vocab::read_bounded;

/// A scene file that could not be loaded: which file, and what is wrong with it.
#[derive(Debug, thiserror::Error)]
#[error("scene file {}: {problem}", path.display())]
pub struct SceneFileError {
    /// The file.
    pub path: PathBuf,
    /// What is wrong with it.
    pub problem: String,
}

/// Deepest node hierarchy followed (glTF forbids cycles; a malformed file must not recurse
/// without end).
const MAX_NODE_DEPTH: usize = 256;
/// Most node placements followed (a shared subtree is placed once per parent).
const MAX_NODE_VISITS: usize = 1 << 20;
/// Largest image decoded, per side and in bytes.
const MAX_IMAGE_SIDE: u32 = 16384;
const MAX_IMAGE_BYTES: u64 = 512 << 20;
/// Largest scene file read (a `.glb` holds its buffers; the largest sample models are ~100 MB).
const MAX_SCENE_FILE_BYTES: u64 = 2 << 30;

/// Whether `name` names a scene file rather than a built-in scene.
pub fn is_scene_file(name: &str) -> bool {
    let lower = name.to_ascii_lowercase();
    lower.ends_with(".gltf") || lower.ends_with(".glb")
}

/// Loads the glTF file at `path`.
pub fn load_gltf(path: &Path) -> Result<Scene, SceneFileError> {
    let fail = |problem: String| SceneFileError {
        path: path.to_path_buf(),
        problem,
    };
    let bytes =
        read_bounded(path, MAX_SCENE_FILE_BYTES, "foveate reads of a scene file").map_err(fail)?;
    gltf_from_slice(&bytes, path.parent()).map_err(fail)
}

/// Loads glTF from `bytes` (JSON or binary), external files relative to `base` (none: a file
/// that names one is an error).
pub fn gltf_from_slice(bytes: &[u8], base: Option<&Path>) -> Result<Scene, String> {
    // Required extensions first: a file that needs one (Draco, say) fails validation in ways
    // that only make sense once you know it.
    let unchecked = gltf::Gltf::from_slice_without_validation(bytes)
        .map_err(|e| format!("not valid glTF 2.0: {e}"))?;
    if let Some(ext) = unchecked.extensions_required().next() {
        return Err(format!(
            "requires extension {ext}, which foveate does not support (it supports no required extensions)"
        ));
    }
    dangling_accessors(unchecked.as_json())?;
    let gltf::Gltf { document, blob } = unchecked;
    let document = gltf::Document::from_json(document.into_json())
        .map_err(|e| format!("not valid glTF 2.0: {e}"))?;
    let buffers = document
        .buffers()
        .map(|b| load_buffer(&b, base, blob.as_deref()))
        .collect::<Result<Vec<_>, _>>()?;
    let mut loader = Loader {
        buffers,
        base,
        meshes: Vec::new(),
        mesh_of: HashMap::new(),
        materials: Vec::new(),
        material_of: HashMap::new(),
        images: HashMap::new(),
    };
    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next())
        .ok_or("has no scene")?;
    let mut placed: Vec<(usize, Mat4)> = Vec::new();
    let mut skipped = 0usize;
    let mut camera = None;
    let mut stack: Vec<(gltf::Node, Mat4, usize)> =
        scene.nodes().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    let mut visits = 0usize;
    while let Some((node, parent, depth)) = stack.pop() {
        visits += 1;
        if depth > MAX_NODE_DEPTH {
            return Err(format!(
                "node {} lies {depth} levels deep, more than the {MAX_NODE_DEPTH} foveate follows (or the hierarchy is cyclic)",
                node.index()
            ));
        }
        if visits > MAX_NODE_VISITS {
            return Err(format!(
                "its hierarchy places more than {MAX_NODE_VISITS} nodes (reached at node {}): cyclic, or subtrees shared too often",
                node.index()
            ));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if !world.is_finite() {
            return Err(format!("node {} has a non-finite transform", node.index()));
        }
        if camera.is_none() && node.camera().is_some() {
            camera = Some(world);
        }
        if let Some(mesh) = node.mesh() {
            for primitive in mesh.primitives() {
                match loader.primitive(&mesh, &primitive)? {
                    Some(m) => placed.push((m, world)),
                    None => skipped += 1,
                }
            }
        }
        stack.extend(node.children().map(|c| (c, world, depth + 1)));
    }
    if placed.is_empty() {
        return Err(format!(
            "its scene draws no triangles ({skipped} primitives without triangles: foveate draws no points or lines)"
        ));
    }
    let mut batches: Vec<DrawBatch> = (0..loader.meshes.len())
        .map(|mesh| DrawBatch {
            mesh,
            instances: Vec::new(),
        })
        .collect();
    for (mesh, model) in placed {
        let material = loader.meshes[mesh].1;
        batches[mesh]
            .instances
            .push(Instance::new(model, Vec3::ONE).with_material(material));
    }
    let meshes: Vec<Mesh> = loader.meshes.into_iter().map(|(m, _)| m).collect();
    let mut scene = Scene {
        meshes,
        batches,
        head: Mat4::IDENTITY,
        light_dir: Vec3::new(-0.35, -1.0, -0.45).normalize(),
        materials: loader.materials,
        lights: Vec::new(),
        reach: None,
    };
    scene.head = match camera {
        // A camera node's pose, without its scale.
        Some(c) => {
            let (_, rotation, translation) = c.to_scale_rotation_translation();
            Mat4::from_rotation_translation(rotation.normalize(), translation)
        }
        None => framing_head(&scene),
    };
    scene.reach = Some(scene.content_reach());
    Ok(scene)
}

/// Refuses a primitive naming an accessor that does not exist, before validation: the `gltf`
/// crate's validation indexes the POSITION accessor unchecked (found by the fuzz test).
fn dangling_accessors(root: &gltf::json::Root) -> Result<(), String> {
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let named = primitive.attributes.values().chain(&primitive.indices);
            if let Some(bad) = named
                .map(|i| i.value())
                .find(|&i| i >= root.accessors.len())
            {
                return Err(format!(
                    "mesh {m} primitive {p} names accessor {bad}, but there are {}",
                    root.accessors.len()
                ));
            }
        }
    }
    Ok(())
}

/// A primitive's vertices and triangle-list indices.
type Geometry = (Vec<Vertex>, Vec<u32>);

struct Loader<'a> {
    buffers: Vec<Vec<u8>>,
    base: Option<&'a Path>,
    /// Each loaded primitive and its material's index in `materials`.
    meshes: Vec<(Mesh, u32)>,
    /// (mesh, primitive) → index in `meshes`, `None` when it draws nothing.
    mesh_of: HashMap<(usize, usize), Option<usize>>,
    materials: Vec<Material>,
    /// glTF material (`None`: the default material) → index in `materials`.
    material_of: HashMap<Option<usize>, u32>,
    /// Decoded images, resampled to the texture size (RGBA8).
    images: HashMap<usize, Arc<Vec<u8>>>,
}

impl Loader<'_> {
    /// The mesh drawing `primitive` of `mesh`, loaded on first use.
    fn primitive(
        &mut self,
        mesh: &gltf::Mesh,
        primitive: &gltf::Primitive,
    ) -> Result<Option<usize>, String> {
        let key = (mesh.index(), primitive.index());
        if let Some(&m) = self.mesh_of.get(&key) {
            return Ok(m);
        }
        let what = format!(
            "mesh {} ({}) primitive {}",
            mesh.index(),
            mesh.name().unwrap_or("unnamed"),
            primitive.index()
        );
        let loaded = match self
            .geometry(primitive)
            .map_err(|e| format!("{what}: {e}"))?
        {
            None => {
                log::warn!(
                    "{what}: draws no triangles (mode {:?}); skipped",
                    primitive.mode()
                );
                None
            }
            Some((vertices, indices)) => {
                let material = primitive.material();
                let double_sided = material.double_sided();
                let material = self.material(&material)?;
                let mut mesh = Mesh {
                    name: what.clone(),
                    vertices,
                    indices,
                    clusters: Vec::new(),
                    lods: Vec::new(),
                };
                if double_sided {
                    add_back_faces(&mut mesh);
                }
                self.meshes.push((mesh, material));
                Some(self.meshes.len() - 1)
            }
        };
        self.mesh_of.insert(key, loaded);
        Ok(loaded)
    }

    /// A primitive's vertices and triangle-list indices (`None`: points, lines or no
    /// whole triangle).
    fn geometry(&self, primitive: &gltf::Primitive) -> Result<Option<Geometry>, String> {
        if matches!(
            primitive.mode(),
            Mode::Points | Mode::Lines | Mode::LineLoop | Mode::LineStrip
        ) {
            return Ok(None);
        }
        let (uvs, tangents) = self.check_attributes(primitive)?;
        let reader = primitive.reader(|b| self.buffers.get(b.index()).map(Vec::as_slice));
        let positions: Vec<[f32; 3]> = reader
            .read_positions()
            .ok_or("unreadable POSITION")?
            .collect();
        if positions.iter().flatten().any(|c| !c.is_finite()) {
            return Err("POSITION holds NaN or infinite values".into());
        }
        let count = positions.len();
        let same_count = |name: &str, n: usize| {
            if n == count {
                Ok(())
            } else {
                Err(format!("{name} has {n} items, POSITION {count}"))
            }
        };
        let raw: Vec<u32> = match reader.read_indices() {
            Some(i) => i.into_u32().collect(),
            None => (0..count as u32).collect(),
        };
        if let Some(&bad) = raw.iter().find(|&&i| i as usize >= count) {
            return Err(format!("index {bad} is out of range (vertices: {count})"));
        }
        // A triangle naming a vertex twice draws nothing (and trips MikkTSpace).
        let indices: Vec<u32> = triangle_list(primitive.mode(), &raw)
            .chunks_exact(3)
            .filter(|t| t[0] != t[1] && t[1] != t[2] && t[0] != t[2])
            .flatten()
            .copied()
            .collect();
        if indices.is_empty() {
            return Ok(None);
        }
        let uv: Vec<[f32; 2]> = match reader.read_tex_coords(0) {
            Some(t) => t.into_f32().collect(),
            None => vec![[0.0; 2]; count],
        };
        same_count("TEXCOORD_0", uv.len())?;
        let vertices: Vec<Vertex> = positions
            .iter()
            .zip(&uv)
            .map(|(&position, &uv)| Vertex {
                position,
                normal: [0.0; 3],
                uv: finite_or_zero(uv),
                tangent: [0.0; 4],
            })
            .collect();
        let normals = reader.read_normals().map(|n| n.collect::<Vec<[f32; 3]>>());
        if let Some(n) = &normals {
            same_count("NORMAL", n.len())?;
        }
        let (mut vertices, indices) = with_normals(vertices, indices, normals);
        match reader.read_tangents() {
            Some(t) if tangents => {
                let t: Vec<[f32; 4]> = t.collect();
                same_count("TANGENT", t.len())?;
                for (v, t) in vertices.iter_mut().zip(t) {
                    let t = finite_or_zero(t);
                    v.tangent = [t[0], t[1], t[2], if t[3] < 0.0 { -1.0 } else { 1.0 }];
                }
            }
            _ if uvs => generate_tangents(&mut vertices, &indices),
            _ => {}
        }
        Ok(Some((vertices, indices)))
    }

    /// Refuses a primitive whose attributes the reader would misread: no POSITION, or an
    /// attribute of a type or shape foveate does not read. Returns whether it has texture
    /// coordinates and tangents.
    fn check_attributes(&self, primitive: &gltf::Primitive) -> Result<(bool, bool), String> {
        let positions = primitive
            .get(&gltf::Semantic::Positions)
            .ok_or("has no POSITION attribute")?;
        self.check(
            &positions,
            "POSITION",
            &[Dimensions::Vec3],
            &[DataType::F32],
        )?;
        let normals = primitive.get(&gltf::Semantic::Normals);
        if let Some(a) = &normals {
            self.check(a, "NORMAL", &[Dimensions::Vec3], &[DataType::F32])?;
        }
        let uvs = primitive.get(&gltf::Semantic::TexCoords(0));
        if let Some(a) = &uvs {
            self.check(
                a,
                "TEXCOORD_0",
                &[Dimensions::Vec2],
                &[DataType::F32, DataType::U8, DataType::U16],
            )?;
        }
        let tangents = primitive.get(&gltf::Semantic::Tangents);
        if let Some(a) = &tangents {
            self.check(a, "TANGENT", &[Dimensions::Vec4], &[DataType::F32])?;
        }
        if let Some(a) = primitive.indices() {
            self.check(
                &a,
                "indices",
                &[Dimensions::Scalar],
                &[DataType::U8, DataType::U16, DataType::U32],
            )?;
        }
        Ok((uvs.is_some(), tangents.is_some()))
    }

    /// Refuses an accessor the reader would misread or read past its buffer: sparse, without
    /// a view, of another type than `semantic` allows, or reaching past its view or buffer.
    fn check(
        &self,
        accessor: &gltf::Accessor,
        semantic: &str,
        dimensions: &[Dimensions],
        types: &[DataType],
    ) -> Result<(), String> {
        let what = format!("accessor {} ({semantic})", accessor.index());
        if accessor.sparse().is_some() {
            return Err(format!("{what} is sparse, which foveate does not read"));
        }
        if !dimensions.contains(&accessor.dimensions()) || !types.contains(&accessor.data_type()) {
            return Err(format!(
                "{what} is {:?} of {:?}, not what {semantic} allows",
                accessor.dimensions(),
                accessor.data_type()
            ));
        }
        if accessor.count() == 0 {
            return Err(format!("{what} is empty"));
        }
        let view = accessor
            .view()
            .ok_or(format!("{what} has no buffer view"))?;
        let size = accessor.size();
        let stride = view.stride().unwrap_or(size);
        let buffer_len = self.buffers.get(view.buffer().index()).map_or(0, Vec::len);
        let end = stride
            .checked_mul(accessor.count() - 1)
            .and_then(|n| n.checked_add(size))
            .and_then(|n| n.checked_add(accessor.offset()));
        let view_end = view.offset().checked_add(view.length());
        match (end, view_end) {
            (_, None) => Err(format!("{what}: its buffer view overflows")),
            (None, _) => Err(format!("{what} is out of range: its size overflows")),
            (Some(end), Some(view_end)) if stride < size || end > view.length() || view_end > buffer_len => {
                Err(format!(
                    "{what} is out of range: {} items of {size} bytes at stride {stride} from byte {} need {end} bytes of buffer view {} ({} bytes at {} of a {buffer_len}-byte buffer)",
                    accessor.count(),
                    accessor.offset(),
                    view.index(),
                    view.length(),
                    view.offset(),
                ))
            }
            _ => Ok(()),
        }
    }

    /// The index in `materials` of glTF material `material`, mapped on first use.
    fn material(&mut self, material: &gltf::Material) -> Result<u32, String> {
        if let Some(&m) = self.material_of.get(&material.index()) {
            return Ok(m);
        }
        let what = format!(
            "material {} ({})",
            material
                .index()
                .map_or("default".to_string(), |i| i.to_string()),
            material.name().unwrap_or("unnamed")
        );
        let pbr = material.pbr_metallic_roughness();
        let [r, g, b, alpha] = pbr.base_color_factor();
        let textures = self
            .textures(material)
            .map_err(|e| format!("{what}: {e}"))?;
        let cutoff = match material.alpha_mode() {
            gltf::material::AlphaMode::Opaque => None,
            gltf::material::AlphaMode::Mask => Some(material.alpha_cutoff().unwrap_or(0.5)),
            gltf::material::AlphaMode::Blend => {
                log::warn!("{what}: alpha blending is drawn as a mask at 0.5");
                Some(0.5)
            }
        };
        if material.emissive_factor() != [0.0; 3] || material.emissive_texture().is_some() {
            log::info!("{what}: emission is not shaded");
        }
        let factor = |v: f32| if v.is_finite() { v.max(0.0) } else { 1.0 };
        self.materials.push(Material {
            name: Cow::Owned(what),
            surface: Surface::Images(Arc::new(textures)),
            base_color: Vec3::new(factor(r), factor(g), factor(b)),
            metallic: factor(pbr.metallic_factor()),
            roughness: factor(pbr.roughness_factor()),
            world_uv_scale: 0.0,
            // The texture's alpha times the factor against the cutoff, as the texture's alpha
            // against the cutoff over the factor.
            alpha_cutoff: cutoff.map(|c| c / factor(alpha).max(1e-6)),
        });
        let index = self.materials.len() as u32 - 1;
        self.material_of.insert(material.index(), index);
        Ok(index)
    }

    /// A material's three textures at the arrays' size: the base colour image (or white), the
    /// normal map scaled (or flat), occlusion from its image's red and roughness and metallic
    /// from theirs' green and blue (or 1: the factors alone).
    fn textures(&mut self, material: &gltf::Material) -> Result<MaterialTextures, String> {
        let pbr = material.pbr_metallic_roughness();
        let texels = (TEXTURE_SIZE * TEXTURE_SIZE) as usize;
        let base = match pbr.base_color_texture() {
            Some(info) => self.image(&info.texture())?.to_vec(),
            None => vec![255; 4 * texels],
        };
        let normal = match material.normal_texture() {
            Some(info) => {
                let scale = info.scale();
                let image = self.image(&info.texture())?;
                image
                    .chunks_exact(4)
                    .flat_map(|t| {
                        let n = Vec3::from([0, 1, 2].map(|c| t[c] as f32 / 255.0 * 2.0 - 1.0));
                        let n = (n * Vec3::new(scale, scale, 1.0)).normalize_or(Vec3::Z);
                        let [x, y, z] = (n * 0.5 + 0.5).to_array().map(unorm8);
                        [x, y, z, 255]
                    })
                    .collect()
            }
            None => [128, 128, 255, 255].repeat(texels),
        };
        let mut orm = vec![255u8; 4 * texels];
        if let Some(info) = pbr.metallic_roughness_texture() {
            let image = self.image(&info.texture())?;
            for (o, t) in orm.chunks_exact_mut(4).zip(image.chunks_exact(4)) {
                o[1] = t[1];
                o[2] = t[2];
            }
        }
        if let Some(info) = material.occlusion_texture() {
            let strength = info.strength().clamp(0.0, 1.0);
            let image = self.image(&info.texture())?;
            for (o, t) in orm.chunks_exact_mut(4).zip(image.chunks_exact(4)) {
                o[0] = unorm8(1.0 + strength * (t[0] as f32 / 255.0 - 1.0));
            }
        }
        MaterialTextures::new(base, normal, orm)
    }

    /// A texture's image, decoded and resampled to the arrays' size, RGBA8.
    fn image(&mut self, texture: &gltf::Texture) -> Result<Arc<Vec<u8>>, String> {
        let image = texture.source();
        if let Some(found) = self.images.get(&image.index()) {
            return Ok(found.clone());
        }
        let what = format!(
            "image {} ({})",
            image.index(),
            image.name().unwrap_or("unnamed")
        );
        let bytes = match image.source() {
            gltf::image::Source::View { view, .. } => {
                let buffer = self
                    .buffers
                    .get(view.buffer().index())
                    .ok_or(format!("{what}: no buffer"))?;
                view.offset()
                    .checked_add(view.length())
                    .and_then(|end| buffer.get(view.offset()..end))
                    .ok_or(format!("{what}: its buffer view is out of range"))?
                    .to_vec()
            }
            gltf::image::Source::Uri { uri, .. } => {
                read_uri(uri, self.base, MAX_IMAGE_BYTES, "foveate reads of an image")
                    .map_err(|e| format!("{what}: {e}"))?
            }
        };
        let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
            .with_guessed_format()
            .map_err(|e| format!("{what}: {e}"))?;
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(MAX_IMAGE_SIDE);
        limits.max_image_height = Some(MAX_IMAGE_SIDE);
        limits.max_alloc = Some(MAX_IMAGE_BYTES);
        reader.limits(limits);
        let decoded = reader
            .decode()
            .map_err(|e| format!("{what} cannot be decoded: {e}"))?
            .into_rgba8();
        let resized = image::imageops::resize(
            &decoded,
            TEXTURE_SIZE,
            TEXTURE_SIZE,
            image::imageops::FilterType::Triangle,
        );
        let texels = Arc::new(resized.into_raw());
        self.images.insert(image.index(), texels.clone());
        Ok(texels)
    }
}

#[cfg(test)]
#[path = "gltf_tests.rs"]
mod tests;
