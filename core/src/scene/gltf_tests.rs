//! The glTF loader on files built here, byte by byte: what it reads, what it refuses, and that
//! mutated files never panic it.

use base64::Engine;
use proptest::prelude::*;
use serde_json::{json, Value};

use super::*;

const FLOAT: u32 = 5126;
const U16: u32 = 5123;
const U32: u32 = 5125;

/// A glTF asset under construction: JSON and its binary buffer.
struct Asset {
    json: Value,
    bin: Vec<u8>,
}

impl Asset {
    fn new() -> Self {
        Asset {
            json: json!({
                "asset": {"version": "2.0"},
                "buffers": [], "bufferViews": [], "accessors": [],
                "meshes": [], "nodes": [], "materials": [],
                "scenes": [{"nodes": []}], "scene": 0
            }),
            bin: Vec::new(),
        }
    }

    fn push(&mut self, key: &str, v: Value) -> usize {
        let a = self.json[key].as_array_mut().unwrap();
        a.push(v);
        a.len() - 1
    }

    /// An accessor over `bytes` (a view of its own).
    fn accessor(&mut self, bytes: &[u8], component: u32, count: usize, ty: &str) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        let view = self.push(
            "bufferViews",
            json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": bytes.len()}),
        );
        self.bin.extend_from_slice(bytes);
        self.push(
            "accessors",
            json!({"bufferView": view, "componentType": component, "count": count, "type": ty}),
        )
    }

    fn floats(&mut self, v: &[f32], per: usize, ty: &str) -> usize {
        let bytes: Vec<u8> = v.iter().flat_map(|f| f.to_le_bytes()).collect();
        let a = self.accessor(&bytes, FLOAT, v.len() / per, ty);
        if ty == "VEC3" {
            let column = |k: usize| v.iter().skip(k).step_by(3).copied();
            let min: Vec<f32> = (0..3).map(|k| column(k).fold(f32::MAX, f32::min)).collect();
            let max: Vec<f32> = (0..3).map(|k| column(k).fold(f32::MIN, f32::max)).collect();
            self.json["accessors"][a]["min"] = json!(min);
            self.json["accessors"][a]["max"] = json!(max);
        }
        a
    }

    /// A unit quad in the xy plane facing +z (two triangles), indices of `index_type`, with
    /// normals and UVs unless told otherwise; returns the mesh index.
    fn quad(&mut self, index_type: u32, normals: bool, material: Option<usize>) -> usize {
        let p = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 1.0, 0.0];
        let position = self.floats(&p, 3, "VEC3");
        let uv = self.floats(&[0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0], 2, "VEC2");
        let idx = [0u32, 1, 2, 0, 2, 3];
        let bytes: Vec<u8> = match index_type {
            U16 => idx.iter().flat_map(|&i| (i as u16).to_le_bytes()).collect(),
            _ => idx.iter().flat_map(|&i| i.to_le_bytes()).collect(),
        };
        let indices = self.accessor(&bytes, index_type, 6, "SCALAR");
        let mut attributes = json!({"POSITION": position, "TEXCOORD_0": uv});
        if normals {
            let n = self.floats(&[0.0, 0.0, 1.0].repeat(4), 3, "VEC3");
            attributes["NORMAL"] = json!(n);
        }
        let mut primitive = json!({"attributes": attributes, "indices": indices});
        if let Some(m) = material {
            primitive["material"] = json!(m);
        }
        self.push("meshes", json!({"primitives": [primitive]}))
    }

    /// A node (a root when `root`); returns its index.
    fn node(&mut self, v: Value, root: bool) -> usize {
        let n = self.push("nodes", v);
        if root {
            self.json["scenes"][0]["nodes"]
                .as_array_mut()
                .unwrap()
                .push(json!(n));
        }
        n
    }

    /// The binary file (.glb).
    fn glb(&self) -> Vec<u8> {
        let mut json = self.json.clone();
        if json["buffers"].as_array().is_some_and(|b| b.is_empty()) {
            json["buffers"] = json!([{"byteLength": self.bin.len()}]);
        }
        let mut text = serde_json::to_vec(&json).unwrap();
        while !text.len().is_multiple_of(4) {
            text.push(b' ');
        }
        let mut bin = self.bin.clone();
        while !bin.len().is_multiple_of(4) {
            bin.push(0);
        }
        let total = 12 + 8 + text.len() + 8 + bin.len();
        let mut out = Vec::new();
        out.extend(b"glTF");
        out.extend(2u32.to_le_bytes());
        out.extend((total as u32).to_le_bytes());
        out.extend((text.len() as u32).to_le_bytes());
        out.extend(b"JSON");
        out.extend(text);
        out.extend((bin.len() as u32).to_le_bytes());
        out.extend(b"BIN\0");
        out.extend(bin);
        out
    }

    fn load(&self) -> Result<Scene, String> {
        gltf_from_slice(&self.glb(), None)
    }
}

/// One quad drawn by two nodes, one of them a child of a scaled, translated parent.
fn two_quads() -> Asset {
    let mut a = Asset::new();
    let mesh = a.quad(U16, true, None);
    let child = a.node(json!({"mesh": mesh, "translation": [1.0, 0.0, 0.0]}), false);
    a.node(
        json!({"children": [child], "translation": [0.0, 0.0, -5.0], "scale": [2.0, 2.0, 2.0]}),
        true,
    );
    a.node(json!({"mesh": mesh}), true);
    a
}

#[test]
fn repeated_meshes_are_instanced_under_their_parents_transforms() {
    let scene = two_quads().load().unwrap();
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.batches.len(), 1);
    assert_eq!(scene.instance_count(), 2);
    let origins: Vec<Vec3> = scene.batches[0]
        .instances
        .iter()
        .map(|i| i.model.transform_point3(Vec3::ZERO))
        .collect();
    // The child: its own translation, scaled by the parent, then the parent's translation.
    assert!(origins.contains(&Vec3::new(2.0, 0.0, -5.0)), "{origins:?}");
    assert!(origins.contains(&Vec3::ZERO), "{origins:?}");
    // The default material, lit, and a head that sees it; a reach for the far plane.
    assert_eq!(scene.shading(), crate::scene::Shading::Lit);
    assert_eq!(scene.materials.len(), 1);
    assert!(scene.reach.is_some_and(|r| r > 0.0));
}

#[test]
fn u16_and_u32_indices_read_the_same_triangles() {
    let load = |t| {
        let mut a = Asset::new();
        let mesh = a.quad(t, true, None);
        a.node(json!({"mesh": mesh}), true);
        a.load().unwrap().meshes.remove(0)
    };
    let (short, long) = (load(U16), load(U32));
    assert_eq!(short.indices, vec![0, 1, 2, 0, 2, 3]);
    assert_eq!(short.indices, long.indices);
}

#[test]
fn missing_normals_are_flat_and_tangents_are_generated() {
    let mut a = Asset::new();
    let mesh = a.quad(U16, false, None);
    a.node(json!({"mesh": mesh}), true);
    let mesh = a.load().unwrap().meshes.remove(0);
    for v in &mesh.vertices {
        assert_eq!(v.normal, [0.0, 0.0, 1.0]);
        let t = Vec3::new(v.tangent[0], v.tangent[1], v.tangent[2]);
        assert!((t.length() - 1.0).abs() < 1e-3, "unit tangent {t}");
        assert!(t.dot(Vec3::Z).abs() < 1e-3, "tangent in the surface {t}");
        // u grows along +x: MikkTSpace's tangent follows it.
        assert!(t.x > 0.99, "tangent along +u {t}");
        assert_eq!(v.tangent[3].abs(), 1.0);
    }
}

#[test]
fn materials_map_factors_alpha_mask_and_double_sides() {
    let mut a = Asset::new();
    a.push(
        "materials",
        json!({
            "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.25, 1.0, 0.5],
                                     "metallicFactor": 0.0, "roughnessFactor": 0.3},
            "alphaMode": "MASK", "alphaCutoff": 0.25, "doubleSided": true
        }),
    );
    let mesh = a.quad(U16, true, Some(0));
    a.node(json!({"mesh": mesh}), true);
    let scene = a.load().unwrap();
    let m = &scene.materials[0];
    assert_eq!(m.base_color, Vec3::new(0.5, 0.25, 1.0));
    assert_eq!((m.metallic, m.roughness), (0.0, 0.3));
    // alpha × 0.5 < 0.25 ⇔ alpha < 0.5.
    assert_eq!(m.alpha_cutoff, Some(0.5));
    // Double-sided: the back faces added, wound the other way with flipped normals.
    let mesh = &scene.meshes[0];
    assert_eq!(mesh.triangle_count(), 4);
    assert_eq!(&mesh.indices[6..9], &[4, 6, 5]);
    assert_eq!(mesh.vertices[4].normal, [0.0, 0.0, -1.0]);
}

/// Each refusal names what is wrong.
#[test]
fn bad_files_are_refused_with_the_reason() {
    let refused = |a: &Asset, expected: &str| {
        let e = a.load().expect_err(expected);
        assert!(e.contains(expected), "{e:?} should say {expected:?}");
    };
    let mut a = two_quads();
    a.json["accessors"][0]["count"] = json!(400);
    refused(&a, "accessor 0 (POSITION) is out of range");

    let mut a = two_quads();
    a.json["extensionsRequired"] = json!(["KHR_draco_mesh_compression"]);
    a.json["extensionsUsed"] = json!(["KHR_draco_mesh_compression"]);
    refused(&a, "requires extension KHR_draco_mesh_compression");

    let mut a = two_quads();
    a.bin[0..4].copy_from_slice(&f32::NAN.to_le_bytes());
    refused(&a, "POSITION holds NaN or infinite values");

    let mut a = two_quads();
    let indices = a.json["meshes"][0]["primitives"][0]["indices"]
        .as_u64()
        .unwrap() as usize;
    let view = a.json["accessors"][indices]["bufferView"].as_u64().unwrap() as usize;
    let at = a.json["bufferViews"][view]["byteOffset"].as_u64().unwrap() as usize;
    a.bin[at..at + 2].copy_from_slice(&9u16.to_le_bytes());
    refused(&a, "index 9 is out of range (vertices: 4)");

    let mut a = two_quads();
    a.json["accessors"][0]["componentType"] = json!(U16);
    refused(&a, "not what POSITION allows");

    let mut a = two_quads();
    a.json["meshes"][0]["primitives"][0]["mode"] = json!(1);
    refused(&a, "its scene draws no triangles");

    let e = gltf_from_slice(b"{\"asset\": ", None).unwrap_err();
    assert!(e.starts_with("not valid glTF 2.0"), "{e}");

    let json =
        br#"{"asset": {"version": "2.0"}, "buffers": [{"uri": "gone.bin", "byteLength": 4}]}"#;
    let dir = std::env::temp_dir();
    let e = gltf_from_slice(json, Some(&dir)).unwrap_err();
    assert!(
        e.contains("buffer 0: cannot read") && e.contains("gone.bin"),
        "{e}"
    );
}

#[test]
fn a_missing_file_is_named() {
    let e = load_gltf(Path::new("/nonexistent/scene.glb")).unwrap_err();
    assert_eq!(e.path, Path::new("/nonexistent/scene.glb"));
    assert!(
        e.to_string()
            .contains("cannot read /nonexistent/scene.glb: No such file"),
        "{e}"
    );
}

#[test]
fn embedded_and_external_buffers_load_like_the_binary_file() {
    let a = two_quads();
    let mut json = a.json.clone();
    let data = base64::engine::general_purpose::STANDARD.encode(&a.bin);
    json["buffers"] = json!([{"uri": format!("data:application/octet-stream;base64,{data}"),
                              "byteLength": a.bin.len()}]);
    let embedded = gltf_from_slice(&serde_json::to_vec(&json).unwrap(), None).unwrap();
    let dir = std::env::temp_dir().join(format!("foveate-gltf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("quad data.bin"), &a.bin).unwrap();
    json["buffers"] = json!([{"uri": "quad%20data.bin", "byteLength": a.bin.len()}]);
    std::fs::write(dir.join("quads.gltf"), serde_json::to_vec(&json).unwrap()).unwrap();
    let external = load_gltf(&dir.join("quads.gltf")).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    let binary = a.load().unwrap();
    assert_eq!(embedded, binary);
    assert_eq!(external, binary);
}

/// A scene folder holding `quads.gltf`, whose buffer is the URI `uri` declared as the real
/// buffer's length; `prepare` sets up the folder (and around it) first.
fn scene_with_buffer_uri(name: &str, uri: &str, prepare: impl FnOnce(&Path, &[u8])) -> String {
    let a = two_quads();
    let root = std::env::temp_dir().join(format!("foveate-uri-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    let dir = root.join("scene");
    std::fs::create_dir_all(&dir).unwrap();
    prepare(&dir, &a.bin);
    let mut json = a.json.clone();
    json["buffers"] = json!([{"uri": uri, "byteLength": a.bin.len()}]);
    std::fs::write(dir.join("quads.gltf"), serde_json::to_vec(&json).unwrap()).unwrap();
    let loaded = load_gltf(&dir.join("quads.gltf"));
    std::fs::remove_dir_all(&root).unwrap();
    loaded.err().map_or_else(String::new, |e| e.to_string())
}

/// URIs resolve inside the scene's folder: `..`, an absolute path and a link that leads out
/// are refused naming the rule; the same bytes inside the folder load (the negative control:
/// reading `..` as before would load the first case).
#[test]
fn a_scene_reads_only_files_in_its_folder() {
    let outside = |dir: &Path, bin: &[u8]| {
        std::fs::write(dir.parent().unwrap().join("outside.bin"), bin).unwrap();
    };
    let e = scene_with_buffer_uri("dotdot", "../outside.bin", outside);
    assert!(e.contains("outside the scene's folder"), "{e}");
    let e = scene_with_buffer_uri("link", "link.bin", |dir, bin| {
        outside(dir, bin);
        std::os::unix::fs::symlink(
            dir.parent().unwrap().join("outside.bin"),
            dir.join("link.bin"),
        )
        .unwrap();
    });
    assert!(e.contains("outside the scene's folder"), "{e}");
    let e = scene_with_buffer_uri("absolute", "/etc/hostname", |_, _| {});
    assert!(e.contains("an absolute path"), "{e}");
    let e = scene_with_buffer_uri("inside", "sub/inside.bin", |dir, bin| {
        std::fs::create_dir_all(dir.join("sub")).unwrap();
        std::fs::write(dir.join("sub/inside.bin"), bin).unwrap();
    });
    assert_eq!(e, "", "a buffer inside the folder loads");
}

/// The peak resident memory of this process (`VmHWM`), in bytes.
fn peak_memory() -> u64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap();
    let kb = status
        .lines()
        .find_map(|l| l.strip_prefix("VmHWM:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
        .unwrap();
    kb * 1024
}

/// Reads are bounded by the declared length: a device file and a sparse 4 GB file declared as
/// the real buffer's length are refused at once, naming both sizes, from their size before any
/// byte is read; a named pipe is refused without being opened (opening it would wait for a
/// writer for ever). The process's peak memory stays far from the 4 GB an unbounded read takes
/// (under 1 GiB here, where other tests run beside it; `desktop/tests/faults.rs` holds the CLI
/// to 100 MB of address space).
#[test]
fn buffers_are_read_no_further_than_declared() {
    let before = peak_memory();
    let start = std::time::Instant::now();
    let e = scene_with_buffer_uri("zero", "zero.bin", |dir, _| {
        std::os::unix::fs::symlink("/dev/zero", dir.join("zero.bin")).unwrap();
    });
    assert!(e.contains("outside the scene's folder"), "{e}");
    assert!(read_bounded(Path::new("/dev/zero"), 36, "at most")
        .unwrap_err()
        .contains("not a regular file"),);
    let e = scene_with_buffer_uri("sparse", "sparse.bin", |dir, _| {
        let f = std::fs::File::create(dir.join("sparse.bin")).unwrap();
        f.set_len(4 << 30).unwrap();
    });
    assert!(
        e.contains("buffer 0") && e.contains("holds 4294967296 bytes, more than the"),
        "{e}"
    );
    assert!(start.elapsed().as_secs_f64() < 2.0, "{:?}", start.elapsed());
    assert!(peak_memory() - before < 1 << 30);
    // A pipe, loaded on a thread of its own so that a loader that opens it fails by timing out.
    let (done, finished) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let e = scene_with_buffer_uri("fifo", "pipe.bin", |dir, _| {
            let made = std::process::Command::new("mkfifo")
                .arg(dir.join("pipe.bin"))
                .status();
            assert!(made.unwrap().success());
        });
        done.send(e).unwrap();
    });
    let e = finished
        .recv_timeout(std::time::Duration::from_secs(10))
        .expect("a named pipe refused, not waited on");
    assert!(e.contains("not a regular file"), "{e}");
}

/// Every number in `v`, as a mutable reference.
fn numbers(v: &mut Value) -> Vec<&mut Value> {
    match v {
        Value::Number(_) => vec![v],
        Value::Array(a) => a.iter_mut().flat_map(numbers).collect(),
        Value::Object(o) => o.values_mut().flat_map(numbers).collect(),
        _ => Vec::new(),
    }
}

/// Values that break assumptions: zero, negatives, just past a length, huge.
fn hostile_number() -> impl Strategy<Value = Value> {
    prop_oneof![
        Just(json!(0)),
        Just(json!(-1)),
        Just(json!(1)),
        Just(json!(7)),
        Just(json!(4294967295u64)),
        Just(json!(9007199254740991u64)),
        Just(json!(1e30)),
        (0u32..200).prop_map(|n| json!(n)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]
    /// Mutated .glb bytes (flipped bytes anywhere or only in the binary chunk, overwritten
    /// words, truncation) load or are refused; never a panic, which fails the case. Mutation:
    /// drop the degenerate-triangle filter and it finds MikkTSpace's out-of-bounds index.
    #[test]
    fn mutated_bytes_never_panic(
        flips in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 1..8),
        binary_only in any::<bool>(),
        words in prop::collection::vec((any::<prop::sample::Index>(), any::<u32>()), 0..3),
        cut in prop::option::of(any::<prop::sample::Index>()),
    ) {
        let asset = two_quads();
        let mut bytes = asset.glb();
        let first = if binary_only { bytes.len() - asset.bin.len() } else { 0 };
        for (at, b) in flips {
            let i = first + at.index(bytes.len() - first);
            bytes[i] ^= b;
        }
        for (at, w) in words {
            let i = at.index(bytes.len() - 4);
            bytes[i..i + 4].copy_from_slice(&w.to_le_bytes());
        }
        if let Some(c) = cut {
            bytes.truncate(c.index(bytes.len()));
        }
        let _ = gltf_from_slice(&bytes, None);
    }

    /// The JSON's numbers (indices, offsets, counts, strides, types) replaced by hostile ones:
    /// still loads or is refused, never a panic. Mutation: drop `dangling_accessors` and the
    /// `gltf` crate's validation panics on a POSITION accessor index past the end.
    #[test]
    fn mutated_numbers_never_panic(
        changes in prop::collection::vec((any::<prop::sample::Index>(), hostile_number()), 1..4),
    ) {
        let mut asset = two_quads();
        asset.json["buffers"] = json!([{"byteLength": asset.bin.len()}]);
        for (at, value) in changes {
            let mut all = numbers(&mut asset.json);
            let n = all.len();
            *all[at.index(n)] = value;
        }
        let _ = asset.load();
    }
}
