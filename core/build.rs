//! Compiles the GLSL in `shaders/` to SPIR-V with `glslc`.
//!
//! Each entry is (source, output name, extra defines); the SPIR-V lands in `OUT_DIR` and is
//! embedded by `src/shaders.rs`.
use std::path::{Path, PathBuf};
use std::process::Command;

const SHADERS: &[(&str, &str, &[&str])] = &[
    ("scene.vert", "scene.vert.spv", &[]),
    (
        "scene.vert",
        "scene_indirect.vert.spv",
        &["INDIRECT_INSTANCES"],
    ),
    ("scene.frag", "scene.frag.spv", &[]),
    (
        "scene.frag",
        "scene_counting.frag.spv",
        &["COUNT_FRAGMENTS"],
    ),
    ("scene.frag", "scene_lit.frag.spv", &["LIT"]),
    (
        "scene.frag",
        "scene_lit_counting.frag.spv",
        &["LIT", "COUNT_FRAGMENTS"],
    ),
    (
        "scene.frag",
        "scene_masked.frag.spv",
        &["LIT", "ALPHA_MASK"],
    ),
    (
        "scene.frag",
        "scene_masked_counting.frag.spv",
        &["LIT", "ALPHA_MASK", "COUNT_FRAGMENTS"],
    ),
    ("mask.vert", "mask.vert.spv", &[]),
    ("mask.frag", "mask.frag.spv", &[]),
    ("mask.frag", "mask_counting.frag.spv", &["COUNT_FRAGMENTS"]),
    ("coverage.vert", "coverage.vert.spv", &[]),
    ("coverage.frag", "coverage.frag.spv", &[]),
    ("composite.vert", "composite.vert.spv", &[]),
    ("output.frag", "output.frag.spv", &[]),
    ("output.frag", "output_temporal.frag.spv", &["TEMPORAL"]),
    (
        "output.frag",
        "output_temporal_counting.frag.spv",
        &["TEMPORAL", "COUNT_FRAGMENTS"],
    ),
    (
        "output.frag",
        "output_counting.frag.spv",
        &["COUNT_FRAGMENTS"],
    ),
    ("radial_mask.frag", "radial_mask.frag.spv", &[]),
    (
        "radial_mask.frag",
        "radial_mask_counting.frag.spv",
        &["COUNT_FRAGMENTS"],
    ),
    ("layer_copy.frag", "layer_copy.frag.spv", &[]),
    (
        "layer_copy.frag",
        "layer_copy_counting.frag.spv",
        &["COUNT_FRAGMENTS"],
    ),
    ("reconstruct.frag", "reconstruct.frag.spv", &[]),
    (
        "reconstruct.frag",
        "reconstruct_counting.frag.spv",
        &["COUNT_FRAGMENTS"],
    ),
    ("flip_prepare.comp", "flip_prepare.comp.spv", &[]),
    ("flip_reduce.comp", "flip_reduce.comp.spv", &[]),
    ("flip_horizontal.comp", "flip_horizontal.comp.spv", &[]),
    ("flip_vertical.comp", "flip_vertical.comp.spv", &[]),
    ("flip_resample.comp", "flip_resample.comp.spv", &[]),
    ("flip_combine.comp", "flip_combine.comp.spv", &[]),
    ("flip_histogram.comp", "flip_histogram.comp.spv", &[]),
    ("flip_gather.comp", "flip_gather.comp.spv", &[]),
    ("flicker.comp", "flicker.comp.spv", &[]),
    ("far_composite.frag", "far_composite.frag.spv", &[]),
    (
        "far_composite.frag",
        "far_composite_counting.frag.spv",
        &["COUNT_FRAGMENTS"],
    ),
];

/// The `bring_your_own_draws` example's engine's own shaders (its vertex layout, its
/// uniforms): not foveate's, compiled here only because the example cannot build anything
/// itself. Each is (source under `examples/bring_your_own_draws/`, output name).
const EXAMPLE_SHADERS: &[(&str, &str)] = &[
    ("engine.vert", "byod_engine.vert.spv"),
    ("engine.frag", "byod_engine.frag.spv"),
];

fn main() {
    let manifest = Path::new(env!("CARGO_MANIFEST_DIR"));
    let src_dir = manifest.join("shaders");
    let example_dir = manifest.join("examples").join("bring_your_own_draws");
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    println!("cargo:rerun-if-changed={}", src_dir.display());
    println!("cargo:rerun-if-changed={}", example_dir.display());
    println!("cargo:rerun-if-env-changed=GLSLC");
    let glslc = std::env::var("GLSLC").unwrap_or_else(|_| "glslc".to_string());
    for (source, output, defines) in SHADERS {
        compile(
            &glslc,
            &src_dir.join(source),
            &out_dir.join(output),
            defines,
        );
    }
    // A package that leaves the examples out builds without them.
    if example_dir.is_dir() {
        for (source, output) in EXAMPLE_SHADERS {
            compile(
                &glslc,
                &example_dir.join(source),
                &out_dir.join(output),
                &[],
            );
        }
    }
}

/// Compiles `src` to `out` with `glslc`, with `defines`; exits with what to install when
/// `glslc` is missing.
fn compile(glslc: &str, src: &Path, out: &Path, defines: &[&str]) {
    println!("cargo:rerun-if-changed={}", src.display());
    let mut cmd = Command::new(glslc);
    cmd.arg("--target-env=vulkan1.1").arg("-O").arg("-Werror");
    for d in defines {
        cmd.arg(format!("-D{d}"));
    }
    cmd.arg(src).arg("-o").arg(out);
    let status = match cmd.status() {
        Ok(s) => s,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            eprintln!(
                "error: `{glslc}` was not found, and foveate compiles its shaders with it.\n\
                 Install it: `sudo apt-get install glslc` (Debian/Ubuntu), or use the \
                 Vulkan SDK / Android NDK copy and point GLSLC at it."
            );
            std::process::exit(1);
        }
        Err(e) => panic!("could not run {glslc}: {e}"),
    };
    if !status.success() {
        eprintln!("error: glslc failed on {}", src.display());
        std::process::exit(1);
    }
}
