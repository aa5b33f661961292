//! Radial density masking on the GPU: the skipped quads are the ones the pattern names (counted
//! by the coverage probe against a CPU count), the kept pixels are the full-quality frame's, and
//! the reconstruction fills the skipped ones far better than leaving them.

use foveate::metrics::RgbaImage;
use foveate::plan::{CountedStep, RadialDensity, RadialDensityGeometry, RenderConfig, Resolution};
use foveate::scene::{default_scene, Scene};
use foveate::view::Eye;
use foveate_tests::{gpu, render, render_plan};

/// Whether the pattern skips `quad` (2×2 pixels) of `eye`, as `shaders/radial_density.glsl`
/// decides; `None` for a quad whose radius lies within rounding of a threshold.
fn skipped(g: &RadialDensityGeometry, eye: Eye, quad: (u32, u32)) -> Option<bool> {
    let lens = g.lens[eye.index()];
    let centre = |q: u32, size: u32| (q * 2 + 1) as f32 / size as f32 * 2.0 - 1.0;
    let (x, y) = (centre(quad.0, g.view.width), centre(quad.1, g.view.height));
    let r = ((x - lens.x) / lens.z).hypot((y - lens.y) / lens.w);
    let (inner, outer) = (g.config.inner, g.config.outer);
    if (r - inner).abs() < 1e-4 || (r - outer).abs() < 1e-4 {
        return None;
    }
    Some(if r < inner {
        false
    } else if r < outer {
        (quad.0 + quad.1) % 2 == 1
    } else {
        !quad.0.is_multiple_of(2) || !quad.1.is_multiple_of(2)
    })
}

fn config(size: u32) -> RenderConfig {
    RenderConfig {
        resolution: Some(Resolution::square(size)),
        msaa: 4,
        ..RenderConfig::default()
    }
}

/// The probe counts, per eye, exactly the pixels of kept quads (ambiguous quads at a threshold
/// either way). Mutation: radii in pixels instead of lens units, or one quad in four skipped
/// everywhere, fails it (the other checkerboard colour counts the same: the next test catches
/// that).
#[test]
fn the_probe_counts_exactly_the_kept_quads() {
    let gpu = gpu();
    let empty = Scene::empty();
    let c = RenderConfig {
        msaa: 1,
        coverage_probe: true,
        count_fragments: true,
        radial_density: Some(RadialDensity::default()),
        ..config(128)
    };
    let plan = foveate::plan(&empty, &c, gpu.caps()).unwrap();
    let g = plan.radial_density.unwrap();
    let (_, stats) = render_plan(&gpu, &empty, &plan, 1);
    let probe = stats.per_view(CountedStep::Probe);
    for eye in Eye::BOTH {
        let (mut kept, mut unsure, mut skips) = (0u64, 0u64, 0u64);
        for qy in 0..g.view.height / 2 {
            for qx in 0..g.view.width / 2 {
                match skipped(&g, eye, (qx, qy)) {
                    Some(false) => kept += 4,
                    Some(true) => skips += 4,
                    None => unsure += 4,
                }
            }
        }
        assert!(skips > 0, "the pattern skips something");
        let measured = probe[eye.index()];
        assert!(
            (kept..=kept + unsure).contains(&measured),
            "{eye:?}: probe {measured}, kept {kept} (+{unsure} at a threshold)"
        );
    }
}

/// Kept pixels equal the full-quality frame's (their samples are shaded exactly as without the
/// mask); skipped quads, reconstructed, are far closer to it than the sky the scene pass leaves
/// there. Negative control: the frame with its skipped quads left as sky scores ≥ 10 dB lower.
/// Mutation: the CPU pattern's checkerboard on the other colour fails the kept-pixel check.
#[test]
fn kept_pixels_are_exact_and_skipped_quads_reconstructed() {
    let gpu = gpu();
    let scene = default_scene();
    let (reference, _) = render(&gpu, &scene, &config(128));
    let c = RenderConfig {
        radial_density: Some(RadialDensity::default()),
        ..config(128)
    };
    let g = foveate::plan(&scene, &c, gpu.caps())
        .unwrap()
        .radial_density
        .unwrap();
    let (image, _) = render(&gpu, &scene, &c);
    let sky = foveate::plan::SKY.map(|v| (v.powf(1.0 / 2.2) * 255.0).round() as u8);
    for eye in Eye::BOTH {
        let (a, b) = (reference.eye(eye), image.eye(eye));
        let state = |x: u32, y: u32| skipped(&g, eye, (x / 2, y / 2));
        let mut off = 0;
        for y in 0..a.height {
            for x in 0..a.width {
                if state(x, y) == Some(false) {
                    let (p, q) = (a.pixel(x, y), b.pixel(x, y));
                    off += (0..3).any(|c| p[c].abs_diff(q[c]) > 1) as u32;
                }
            }
        }
        assert_eq!(off, 0, "{eye:?}: kept pixels differ from the reference");
        let is_skipped = |x, y| state(x, y) == Some(true);
        let reconstructed = a.psnr_where(b, is_skipped).unwrap().unwrap();
        let mut holes: RgbaImage = b.clone();
        for y in 0..a.height {
            for x in 0..a.width {
                if is_skipped(x, y) {
                    holes.set_pixel(x, y, [sky[0], sky[1], sky[2], 255]);
                }
            }
        }
        let left_as_sky = a.psnr_where(&holes, is_skipped).unwrap().unwrap();
        assert!(
            reconstructed >= left_as_sky + 10.0,
            "{eye:?}: reconstructed {reconstructed:.1} dB vs {left_as_sky:.1} dB left as sky"
        );
    }
}
