//! Helpers for the end-to-end tests: a validated GPU, one-call rendering, golden images.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

use foveate::gpu::{Gpu, GpuOptions};
use foveate::metrics::RgbaImage;
use foveate::plan::{FramePlan, RenderConfig};
use foveate::render::{FrameStats, Renderer, StereoImage};
use foveate::scene::Scene;
use glam::{Mat4, Vec2};

/// The test GPU: validation always on (`FOVEATE_DEVICE` may pick the device).
/// Linear light of an 8-bit sRGB level (IEC 61966-2-1).
pub fn linear(v: u8) -> f64 {
    let c = v as f64 / 255.0;
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

pub fn gpu() -> Gpu {
    gpu_with(None)
}

/// The test GPU, able to present to windows of `display` when given.
pub fn gpu_with(display: Option<raw_window_handle::RawDisplayHandle>) -> Gpu {
    let options = GpuOptions {
        validation: true,
        device: std::env::var("FOVEATE_DEVICE").ok(),
        pipeline_cache: None,
        display,
    };
    Gpu::new(&options).expect("a Vulkan device with VK_LAYER_KHRONOS_validation (see README)")
}

/// Fails the test if validation reported anything.
pub fn assert_validation_clean(gpu: &Gpu) {
    if let Err(e) = gpu.check_validation() {
        panic!("{e}");
    }
}

/// Plans, renders `frames` frames and reads the last one back; validation must stay silent.
pub fn render_plan(
    gpu: &Gpu,
    scene: &Scene,
    plan: &FramePlan,
    frames: u32,
) -> (StereoImage, FrameStats) {
    let mut renderer = Renderer::new(gpu, plan, scene).expect("renderer");
    let mut stats = FrameStats::default();
    for _ in 0..frames {
        stats = renderer.render_frame(scene.head).expect("frame");
    }
    let image = renderer.readback().expect("readback");
    drop(renderer);
    assert_validation_clean(gpu);
    (image, stats)
}

/// Renders `motion` (head pose, gaze) frame by frame with one renderer, reading back the frames
/// `read` asks for; validation must stay silent.
pub fn render_motion(
    gpu: &Gpu,
    scene: &Scene,
    plan: &FramePlan,
    motion: &[(Mat4, Vec2)],
    read: impl Fn(usize) -> bool,
) -> Vec<StereoImage> {
    let mut renderer = Renderer::new(gpu, plan, scene).expect("renderer");
    let mut images = Vec::new();
    for (frame, &(pose, gaze)) in motion.iter().enumerate() {
        renderer.set_gaze([gaze; 2]).expect("gaze in -1..1");
        renderer.render_frame(pose).expect("frame");
        if read(frame) {
            images.push(renderer.readback().expect("readback"));
        }
    }
    drop(renderer);
    assert_validation_clean(gpu);
    images
}

/// One frame of `config` with both eyes gazing at `gaze`; validation must stay silent.
pub fn render_at(gpu: &Gpu, scene: &Scene, config: &RenderConfig, gaze: Vec2) -> StereoImage {
    let plan = foveate::plan(scene, config, gpu.caps()).unwrap();
    let mut renderer = Renderer::new(gpu, &plan, scene).unwrap();
    renderer.set_gaze([gaze; 2]).expect("gaze in -1..1");
    renderer.render_frame(scene.head).unwrap();
    let image = renderer.readback().unwrap();
    drop(renderer);
    assert_validation_clean(gpu);
    image
}

pub fn render(gpu: &Gpu, scene: &Scene, config: &RenderConfig) -> (StereoImage, FrameStats) {
    let plan = foveate::plan(scene, config, gpu.caps()).expect("valid config");
    render_plan(gpu, scene, &plan, 1)
}

fn golden_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("golden")
}

/// Where failing comparisons leave the actual image and a diff picture.
pub fn failure_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../target/golden-failures")
}

/// Compares `actual` with `tests/golden/<name>.png` by SSIM. With `FOVEATE_BLESS=1` the
/// reference is (re)written instead. On failure the actual image and a diff are written to
/// `target/golden-failures/`.
pub fn assert_matches_golden(name: &str, actual: &RgbaImage, min_ssim: f64) {
    let path = golden_dir().join(format!("{name}.png"));
    if std::env::var("FOVEATE_BLESS").is_ok_and(|v| v == "1") {
        actual.save(&path).expect("write golden image");
        eprintln!("blessed {}", path.display());
        return;
    }
    let expected = RgbaImage::load_png(&path).unwrap_or_else(|e| {
        panic!("{e}\n(create it with FOVEATE_BLESS=1 cargo test -p foveate-tests)")
    });
    let ssim = expected.ssim(actual).unwrap_or(f64::NEG_INFINITY);
    let differing = (0..actual.height.min(expected.height))
        .flat_map(|y| (0..actual.width.min(expected.width)).map(move |x| (x, y)))
        .filter(|&(x, y)| expected.pixel(x, y) != actual.pixel(x, y))
        .count();
    eprintln!(
        "{name}: SSIM {ssim:.6} against the golden image (at least {min_ssim}); {differing} pixels differ"
    );
    if ssim < min_ssim {
        let dir = failure_dir();
        std::fs::create_dir_all(&dir).expect("create failure dir");
        let actual_path = dir.join(format!("{name}-actual.png"));
        actual.save(&actual_path).expect("write actual");
        if let Ok(diff) = expected.diff_image(actual) {
            diff.save(&dir.join(format!("{name}-diff.png")))
                .expect("write diff");
        }
        panic!(
            "{name}: SSIM {ssim:.4} < {min_ssim} against {}; actual and diff written to {}",
            path.display(),
            dir.display()
        );
    }
}

/// Centroid (x, y) of the pixels that differ from `background` by more than `threshold` in any
/// channel, or `None` if there are none.
pub fn centroid_of_non_background(
    img: &RgbaImage,
    background: [u8; 4],
    threshold: u8,
) -> Option<(f64, f64)> {
    let (mut sx, mut sy, mut n) = (0.0, 0.0, 0u64);
    for y in 0..img.height {
        for x in 0..img.width {
            let p = img.pixel(x, y);
            if (0..3).any(|c| p[c].abs_diff(background[c]) > threshold) {
                sx += x as f64 + 0.5;
                sy += y as f64 + 0.5;
                n += 1;
            }
        }
    }
    (n > 0).then(|| (sx / n as f64, sy / n as f64))
}

/// A virtual X server on a free display, killed when dropped.
pub struct Xvfb {
    child: Child,
    pub display: String,
}

impl Xvfb {
    pub fn start() -> Xvfb {
        let mut child = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                "640x480x24",
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb (apt xvfb; scripts/setup.sh installs it)");
        let mut line = String::new();
        BufReader::new(child.stdout.take().unwrap())
            .read_line(&mut line)
            .unwrap();
        let display = format!(":{}", line.trim());
        Xvfb { child, display }
    }

    /// Runs `program` against this display (60 s at most), its stdout; fails the test if it fails.
    pub fn run(&self, program: &str, args: &[&str]) -> String {
        let out = Command::new("timeout")
            .arg("60")
            .arg(program)
            .args(args)
            .env("DISPLAY", &self.display)
            .output()
            .unwrap_or_else(|e| panic!("{program}: {e} (apt xdotool x11-apps)"));
        assert!(
            out.status.success(),
            "{program} {args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout).into_owned()
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// The instance nearest the head in front of it, by its number.
pub fn visible_instance(scene: &Scene) -> usize {
    let head = scene.head.inverse();
    let spheres = scene.instance_spheres();
    (0..spheres.len())
        .filter(|&i| head.transform_point3(spheres[i].center).z < -1.0)
        .min_by(|&a, &b| {
            let d = |i: usize| head.transform_point3(spheres[i].center).length();
            d(a).total_cmp(&d(b))
        })
        .expect("something in front of the head")
}

/// The mesh of instance `index`.
pub fn mesh_of(scene: &Scene, index: usize) -> usize {
    let mut left = index;
    for batch in &scene.batches {
        if left < batch.instances.len() {
            return batch.mesh;
        }
        left -= batch.instances.len();
    }
    panic!("no instance {index}");
}
