//! Materials: flat shading (an instance colour, one light) or lit PBR metallic-roughness with
//! base colour, normal and occlusion-roughness-metallic textures, a sun, point lights and an
//! ambient sky. Built-in scenes get their textures procedurally at load (`textures`); glTF
//! files map their materials onto the same model (`gltf_file`).

use std::borrow::Cow;
use std::sync::Arc;

use glam::Vec3;

use super::{MaterialTextures, Scene};
use crate::vocab::named_enum;

/// Point lights a lit frame shades with, at most (`shaders/lighting.glsl`).
pub const MAX_POINT_LIGHTS: usize = 4;

/// How a scene is shaded.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Shading {
    /// Vertex colour and one light: almost no per-fragment work.
    Flat,
    /// PBR metallic-roughness with three textures per material, lights and ambient: the
    /// per-pixel work mobile VR content is dominated by.
    Lit,
}

named_enum!(Shading, "shading", [Shading::Flat => "flat", Shading::Lit => "lit"]);

/// The procedural texture set a material is generated with.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Pattern {
    /// Dressed stone blocks in mortar courses.
    Stone,
    /// Veined marble tiles with grout.
    Marble,
    /// A woven cloth: threads in two directions.
    Fabric,
    /// Wood grain in planks.
    Wood,
    /// Scratched, tarnished metal.
    Bronze,
    /// Rough lime plaster.
    Plaster,
}

/// Where a material's textures come from.
#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    /// Generated at load (the built-in scenes).
    Pattern(Pattern),
    /// Decoded from a scene file, already at the texture arrays' size with their mip chains.
    Images(Arc<MaterialTextures>),
}

/// A PBR metallic-roughness material.
#[derive(Clone, Debug, PartialEq)]
pub struct Material {
    /// Its name (the glTF material's, or the built-in one's).
    pub name: Cow<'static, str>,
    /// Its textures: a procedural pattern or a glTF's images.
    pub surface: Surface,
    /// Multiplies the base colour texture (as does each instance's colour).
    pub base_color: Vec3,
    /// Multiply the texture's metallic and roughness.
    pub metallic: f32,
    /// Multiplies the texture's roughness.
    pub roughness: f32,
    /// Texture repeats per metre with world-space box mapping (each face textured along its
    /// dominant axis, so scaled boxes tile evenly); 0 uses the mesh's texture coordinates.
    pub world_uv_scale: f32,
    /// An alpha mask: fragments whose base colour texture's alpha falls below this are
    /// discarded (the glTF loader folds the material's alpha factor in); `None` is opaque.
    pub alpha_cutoff: Option<f32>,
}

/// A point light: position, colour times intensity, and the range where it fades to nothing.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    /// World position.
    pub position: Vec3,
    /// Linear colour times intensity.
    pub color: Vec3,
    /// Distance in metres where it fades to nothing.
    pub range: f32,
}

/// The palette `Scene::with_shading(Lit)` gives a flat scene: each instance takes one of these
/// by its index, tinted by its own colour.
pub(super) const PALETTE: [Material; 4] = [
    Material {
        name: Cow::Borrowed("plaster"),
        surface: Surface::Pattern(Pattern::Plaster),
        base_color: Vec3::ONE,
        metallic: 0.0,
        roughness: 1.0,
        world_uv_scale: 1.0,
        alpha_cutoff: None,
    },
    Material {
        name: Cow::Borrowed("stone"),
        surface: Surface::Pattern(Pattern::Stone),
        base_color: Vec3::ONE,
        metallic: 0.0,
        roughness: 1.0,
        world_uv_scale: 0.5,
        alpha_cutoff: None,
    },
    Material {
        name: Cow::Borrowed("bronze"),
        surface: Surface::Pattern(Pattern::Bronze),
        base_color: Vec3::ONE,
        metallic: 1.0,
        roughness: 1.0,
        world_uv_scale: 1.0,
        alpha_cutoff: None,
    },
    Material {
        name: Cow::Borrowed("wood"),
        surface: Surface::Pattern(Pattern::Wood),
        base_color: Vec3::ONE,
        metallic: 0.0,
        roughness: 1.0,
        world_uv_scale: 1.0,
        alpha_cutoff: None,
    },
];

/// Lights a flat scene: the palette, instance `i` taking material `i mod 4`, and two warm
/// point lights near the head.
pub(super) fn light_up(scene: &mut Scene) {
    scene.materials = PALETTE.to_vec();
    let mut i = 0u32;
    for batch in &mut scene.batches {
        for instance in &mut batch.instances {
            instance.material = i % PALETTE.len() as u32;
            i += 1;
        }
    }
    let head = scene.head.transform_point3(Vec3::ZERO);
    scene.lights = [(-2.0, 1.0), (2.5, 0.5)]
        .map(|(x, y)| PointLight {
            position: head + Vec3::new(x, y, -3.0),
            color: Vec3::new(1.0, 0.8, 0.6) * 6.0,
            range: 12.0,
        })
        .to_vec();
}
