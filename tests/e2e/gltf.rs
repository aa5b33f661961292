//! glTF scenes on the GPU: the alpha mask discards what it should, and every glTF 2.0 model of
//! Debian's `assimp-testmodels` (files nobody here wrote) either renders validation-clean or is
//! refused with the reason `docs/scenes.md` lists.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use foveate::foveation::FoveationConfig;
use foveate::plan::{RenderConfig, Resolution};
use foveate::scene::{
    ground_quad, load_gltf, DrawBatch, Instance, Material, MaterialTextures, Scene, Surface,
    TEXTURE_SIZE,
};
use foveate_tests::{gpu, render};
use glam::{Mat4, Vec3};

/// A quad 1 m ahead whose base colour texture is transparent on its left half, masked at
/// `cutoff` (or opaque).
fn half_transparent_quad(cutoff: Option<f32>) -> Scene {
    let n = TEXTURE_SIZE as usize;
    let base: Vec<u8> = (0..n * n)
        .flat_map(|i| [255, 255, 255, if i % n < n / 2 { 0 } else { 255 }])
        .collect();
    let textures = MaterialTextures::new(
        base,
        [128, 128, 255, 255].repeat(n * n),
        [255; 4].repeat(n * n),
    )
    .unwrap();
    let model = Mat4::from_translation(Vec3::new(0.0, 0.0, -1.0))
        * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    Scene {
        meshes: vec![ground_quad()],
        batches: vec![DrawBatch {
            mesh: 0,
            instances: vec![Instance::new(model, Vec3::ONE)],
        }],
        materials: vec![Material {
            name: "half transparent".into(),
            surface: Surface::Images(Arc::new(textures)),
            base_color: Vec3::ONE,
            metallic: 0.0,
            roughness: 1.0,
            world_uv_scale: 0.0,
            alpha_cutoff: cutoff,
        }],
        ..Scene::empty()
    }
}

/// The masked half shows the background, the other half the surface. Mutations: the masked
/// shader without its discard, the plan not picking it, or mip levels with alpha 1 (the quad
/// is small enough to sample level 3: found this way) fail the left-half check; the opaque
/// run is the control that the left half is surface when nothing masks it.
#[test]
fn alpha_mask_discards_below_the_cutoff() {
    let gpu = gpu();
    let config = RenderConfig {
        resolution: Some(Resolution::square(64)),
        msaa: 1,
        ..RenderConfig::default()
    };
    let left_eye = |cutoff| render(&gpu, &half_transparent_quad(cutoff), &config).0.left;
    let masked = left_eye(Some(0.5));
    let opaque = left_eye(None);
    let background = masked.pixel(1, 1);
    // Quarter-way into the quad from its centre, either side (the quad spans about a third of
    // the view's width around its centre).
    let (cx, cy) = (masked.width / 2, masked.height / 2);
    let (left, right) = (cx - masked.width / 12, cx + masked.width / 12);
    assert_eq!(
        masked.pixel(left, cy),
        background,
        "the masked half shows the background"
    );
    assert_ne!(
        masked.pixel(right, cy),
        background,
        "the kept half shows the surface"
    );
    assert_ne!(
        opaque.pixel(left, cy),
        background,
        "opaque, the left half is surface"
    );
    assert_eq!(masked.pixel(right, cy), opaque.pixel(right, cy));
}

/// What each assimp glTF 2.0 test model gives: `None` renders, `Some(reason)` is refused with
/// an error containing `reason`. The table in `docs/scenes.md` is this one.
const ASSIMP_MODELS: &[(&str, Option<&str>)] = &[
    ("2CylinderEngine-glTF-Binary/2CylinderEngine.glb", None),
    ("BoxBadNormals-glTF-Binary/BoxBadNormals.glb", None),
    ("BoxTexcoords-glTF/boxTexcoords.gltf", None),
    ("BoxTextured-glTF-Binary/BoxTextured.glb", None),
    ("BoxTextured-glTF-Embedded/BoxTextured.gltf", None),
    (
        "BoxTextured-glTF-pbrSpecularGlossiness/BoxTextured.gltf",
        None,
    ),
    (
        "BoxTextured-glTF-techniqueWebGL/BoxTextured.gltf",
        Some("requires extension KHR_technique_webgl"),
    ),
    ("BoxTextured-glTF/BoxTextured.gltf", None),
    (
        "BoxWithInfinites-glTF-Binary/BoxWithInfinites.glb",
        Some("POSITION\"].min: Missing data"),
    ),
    ("ClearCoat-glTF/ClearCoatTest.gltf", None),
    ("IncorrectVertexArrays/Cube.gltf", Some("min: Missing data")),
    (
        "IndexOutOfRange/AllIndicesOutOfRange.gltf",
        Some("index 65535 is out of range"),
    ),
    (
        "IndexOutOfRange/IndexOutOfRange.gltf",
        Some("index 255 is out of range"),
    ),
    (
        "MissingBin/BoxTextured.gltf",
        Some("BoxTextured0.bin: No such file"),
    ),
    (
        "RecursiveNodes/RecursiveNodes.gltf",
        Some("or the hierarchy is cyclic"),
    ),
    (
        "SchemaFailures/sceneWrongType.gltf",
        Some("invalid type: string \"hello\""),
    ),
    (
        "TestNoRootNode/NoScene.gltf",
        Some("scene: Index out of bounds"),
    ),
    (
        "TestNoRootNode/SceneWithoutNodes.gltf",
        Some("missing field `nodes`"),
    ),
    ("cameras/Cameras.gltf", None),
    (
        "draco/2CylinderEngine.gltf",
        Some("requires extension KHR_draco_mesh_compression"),
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_00.gltf",
        Some("no triangles"),
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_01.gltf",
        Some("no triangles"),
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_02.gltf",
        Some("no triangles"),
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_03.gltf",
        Some("no triangles"),
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_04.gltf",
        None,
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_05.gltf",
        None,
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_06.gltf",
        None,
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_07.gltf",
        Some("no triangles"),
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_08.gltf",
        Some("no triangles"),
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_09.gltf",
        Some("no triangles"),
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_10.gltf",
        Some("no triangles"),
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_11.gltf",
        None,
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_12.gltf",
        None,
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_13.gltf",
        None,
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_14.gltf",
        None,
    ),
    (
        "glTF-Asset-Generator/Mesh_PrimitiveMode/Mesh_PrimitiveMode_15.gltf",
        None,
    ),
    (
        "glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf",
        None,
    ),
    ("issue_3269/texcoord_crash.gltf", None),
    ("simple_skin/simple_skin.gltf", None),
    ("textureTransform/TextureTransformTest.gltf", None),
    (
        "wrongTypes/badArray.gltf",
        Some("invalid type: map, expected a sequence"),
    ),
    ("wrongTypes/badExtension.gltf", None),
    (
        "wrongTypes/badNumber.gltf",
        Some("invalid type: string \"not a number\""),
    ),
    (
        "wrongTypes/badObject.gltf",
        Some("invalid type: string \"not an object\""),
    ),
    (
        "wrongTypes/badString.gltf",
        Some("invalid type: integer `42`"),
    ),
    (
        "wrongTypes/badUint.gltf",
        Some("invalid type: integer `-1`"),
    ),
];

const ASSIMP_GLTF2: &str = "/usr/share/assimp/models/glTF2";

fn gltf_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            gltf_files(&path, out);
        } else if foveate::scene::is_scene_file(&path.to_string_lossy()) {
            out.push(path);
        }
    }
}

/// Every model loads and renders foveated (4 views, MSAA, lens output) validation-clean, or
/// is refused with its listed reason; a model the table does not list fails the test, so a
/// new package version cannot slip past `docs/scenes.md`.
#[test]
fn assimp_test_models_render_or_are_refused_clearly() {
    let root = Path::new(ASSIMP_GLTF2);
    assert!(
        root.is_dir(),
        "{ASSIMP_GLTF2} is missing: install Debian's assimp-testmodels (scripts/setup.sh does)"
    );
    let mut files = Vec::new();
    gltf_files(root, &mut files);
    files.sort();
    let gpu = gpu();
    let config = RenderConfig {
        resolution: Some(Resolution::square(48)),
        foveation: Some(FoveationConfig {
            ratio: 0.5,
            ..FoveationConfig::single_frame()
        }),
        output: foveate::plan::OutputStage::Lens,
        ..RenderConfig::default()
    };
    let mut rendered = 0;
    for file in &files {
        let name = file
            .strip_prefix(root)
            .unwrap()
            .to_string_lossy()
            .into_owned();
        let expected = ASSIMP_MODELS
            .iter()
            .find(|(n, _)| *n == name)
            .unwrap_or_else(|| panic!("{name} is not in the table (and docs/scenes.md)"))
            .1;
        match (load_gltf(file), expected) {
            (Ok(scene), None) => {
                // Renders, validation-clean (render() checks) and with something drawn.
                let (_, stats) = render(&gpu, &scene, &config);
                assert!(stats.draw_calls > 0, "{name} recorded no draws");
                rendered += 1;
            }
            (Err(e), Some(reason)) => {
                let message = e.to_string();
                assert!(
                    message.contains(reason),
                    "{name}: {message:?} lacks {reason:?}"
                );
                assert!(message.contains(&name), "{name}: the error names the file");
            }
            (Ok(_), Some(reason)) => panic!("{name} loaded, but should be refused: {reason}"),
            (Err(e), None) => panic!("{name} should load: {e}"),
        }
    }
    assert_eq!(
        files.len(),
        ASSIMP_MODELS.len(),
        "every listed model is there"
    );
    assert_eq!(
        rendered,
        ASSIMP_MODELS.iter().filter(|(_, e)| e.is_none()).count()
    );
}
