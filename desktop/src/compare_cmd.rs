use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use foveate::foveation::{fovea_centre_px, fovea_views, gaze_tangent, FoveationConfig};
use foveate::gpu::{Gpu, GpuOptions};
use foveate::metrics::flip;
use foveate::metrics::{RgbaImage, Stats};
use foveate::plan::{FramePlan, RadialDensity, RenderConfig, Resolution, StereoMode};
use foveate::render::{counting_frame, Renderer, StereoImage};
use foveate::scene::{named_scene, Scene, Shading};
use foveate::view::Eye;
use glam::Vec2;

use crate::csv_out::{opt, CsvTable};
use crate::fovea_table::{self, TableSettings};

#[derive(Args)]
pub struct CompareArgs {
    /// Screen resolution per eye.
    #[arg(long, default_value_t = 1024)]
    res: u32,
    /// Scene: default, fill, city, thesis or atrium.
    #[arg(long, default_value = "default")]
    scene: String,
    /// Shading: flat or lit (default: the scene's own).
    #[arg(long)]
    shading: Option<String>,
    /// What the frame's last pass writes: lens (pre-distorted, the display's image) or
    /// undistorted. Accuracy is measured on it.
    #[arg(long, default_value = "lens")]
    output: String,
    /// Fovea layout of the foveated rows: auto, one-pass or two-pass.
    #[arg(long, default_value = "auto")]
    fovea_layout: String,
    /// Foveation ratios to compare (default 0.7,0.5,0.35; with --table 0.35,0.5).
    #[arg(long, value_delimiter = ',')]
    ratios: Option<Vec<f32>>,
    /// The foveation table instead: stereo against each ratio in both fovea layouts, on every
    /// scene of --scenes, flat and lit, MSAA 4 (the first of --msaa), side by side in one run.
    #[arg(long)]
    table: bool,
    /// Scenes of the table.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "default,fill,city,thesis,atrium"
    )]
    scenes: Vec<String>,
    /// Shadings of the table's scenes.
    #[arg(long, value_delimiter = ',', default_value = "flat,lit")]
    shadings: Vec<String>,
    /// MSAA sample counts to compare (the table uses the last).
    #[arg(long, value_delimiter = ',', default_value = "1,4")]
    msaa: Vec<u32>,
    /// Gaze of both eyes, normalised X,Y in -1..1.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        default_value = "0,0"
    )]
    gaze: Vec<f32>,
    /// Blend band in screen pixels (default: an eighth of the fovea).
    #[arg(long)]
    blend_band: Option<f32>,
    /// Also price radial density masking (its default radii) at each MSAA count.
    #[arg(long)]
    radial_density: bool,
    /// Frames per configuration (the first is a warm-up).
    #[arg(long, default_value_t = 5)]
    frames: u32,
    /// Also write the table as CSV to this file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// One configuration's measurements.
struct Run {
    frame_ms: f64,
    /// Fragments the scene draws shaded, and every pass together (a separate counting frame).
    scene_fragments: u64,
    total_fragments: u64,
    image: StereoImage,
}

fn run(gpu: &Gpu, scene: &Scene, config: &RenderConfig, gaze: Vec2, frames: u32) -> Result<Run> {
    let plan = foveate::plan(scene, config, gpu.caps())?;
    let mut renderer = Renderer::new(gpu, &plan, scene)?;
    renderer.set_gaze([gaze; 2]);
    let mut times = Vec::new();
    for i in 0..frames {
        let stats = renderer.render_frame(scene.head)?;
        if i > 0 || frames == 1 {
            times.push(stats.frame_ms);
        }
    }
    let counts = counting_frame(gpu, scene, config, [gaze; 2], scene.head)?;
    Ok(Run {
        frame_ms: Stats::of(&times).map_or(f64::NAN, |s| s.median),
        scene_fragments: counts.scene_fragments(),
        total_fragments: counts.total_fragments(),
        image: renderer.readback()?,
    })
}

/// PSNR and SSIM of both eyes over the pixels a region predicate selects (by distance from each
/// eye's fovea centre in rendered pixels; through the lens, where each display pixel shows the
/// rendered image, and display pixels beyond the rendered field in no region).
fn region_error(
    reference: &StereoImage,
    image: &StereoImage,
    centres: [Vec2; 2],
    plan: &FramePlan,
    inside: impl Fn(f32) -> bool,
) -> (Option<f64>, Option<f64>) {
    let both = |img: &StereoImage| RgbaImage::side_by_side(&img.left, &img.right);
    let (a, b) = (both(reference), both(image));
    let w = reference.left.width;
    let region = |x: u32, y: u32| {
        let eye = Eye::BOTH[(x >= w) as usize];
        let (x, y) = (x % w, y);
        let at = match &plan.lens {
            Some(lens) => lens.rendered_px(eye, plan.eyes.fov(eye), plan.eye_resolution, x, y),
            None => Some(Vec2::new(x as f32 + 0.5, y as f32 + 0.5)),
        };
        at.is_some_and(|p| inside(p.distance(centres[eye.index()])))
    };
    (
        a.psnr_where(&b, region).ok().flatten(),
        a.ssim_where(&b, region).ok().flatten(),
    )
}

pub fn compare(options: &GpuOptions, args: &CompareArgs) -> Result<()> {
    anyhow::ensure!(args.frames >= 1, "invalid frames = 0: at least 1");
    if args.table {
        return table(options, args);
    }
    let ratios = args.ratios.clone().unwrap_or(vec![0.7, 0.5, 0.35]);
    let gaze = crate::gaze_arg::gaze_from(&args.gaze)?;
    let scene = crate::frame_args::scene_from(&args.scene, args.shading.as_deref())?;
    let gpu = Gpu::new(options)?;
    let screen = Resolution::square(args.res);
    let base = RenderConfig {
        resolution: Some(screen),
        stereo: StereoMode::Multiview,
        output: args.output.parse()?,
        fovea_layout: args.fovea_layout.parse()?,
        ..RenderConfig::default()
    };
    let total = 1 + args.msaa.len() * (1 + args.radial_density as usize + ratios.len());
    let bar = crate::progress::bar("compare", total as u64);
    let step = |what: &str| {
        bar.set_message(what.to_string());
        bar.inc(1);
    };
    step("reference: stereo, MSAA 4");
    let reference = run(
        &gpu,
        &scene,
        &RenderConfig {
            msaa: 4,
            ..base.clone()
        },
        gaze,
        args.frames,
    )?;
    println!(
        "device: {}; scene {}, {}x{} per eye, gaze {gaze}",
        gpu.info().name,
        args.scene,
        args.res,
        args.res
    );
    println!(
        "reference: stereo multiview, MSAA 4: {:.2} ms, {} scene fragments, {} in all passes",
        reference.frame_ms, reference.scene_fragments, reference.total_fragments
    );
    let mut csv = CsvTable::new(&[
        "config",
        "msaa",
        "ratio",
        "frame_ms",
        "time_ratio",
        "scene_fragments",
        "total_fragments",
        "psnr_fovea",
        "psnr_band",
        "psnr_periphery",
        "ssim_fovea",
        "ssim_band",
        "ssim_periphery",
        "flip_mean",
        "eccentric_flip_p99",
    ])?;
    let mut rows = Vec::new();
    for &msaa in &args.msaa {
        step(&format!("stereo, MSAA {msaa}"));
        let stereo = run(
            &gpu,
            &scene,
            &RenderConfig {
                msaa,
                ..base.clone()
            },
            gaze,
            args.frames,
        )?;
        rows.push((format!("stereo, MSAA {msaa}"), msaa, None, stereo, None));
        if args.radial_density {
            let name = format!("radial density, MSAA {msaa}");
            step(&name);
            let config = RenderConfig {
                msaa,
                radial_density: Some(RadialDensity::default()),
                ..base.clone()
            };
            let masked = run(&gpu, &scene, &config, gaze, args.frames)?;
            rows.push((name, msaa, None, masked, None));
        }
        for &ratio in &ratios {
            step(&format!("foveated {ratio}, MSAA {msaa}"));
            let foveation = FoveationConfig {
                ratio,
                blend_band_px: args.blend_band.unwrap_or(-1.0),
                ..Default::default()
            };
            let geometry = foveation.geometry(screen)?;
            let config = RenderConfig {
                msaa,
                views: 4,
                foveation: Some(foveation),
                ..base.clone()
            };
            let foveated = run(&gpu, &scene, &config, gaze, args.frames)?;
            rows.push((
                format!("foveated {ratio}, MSAA {msaa}"),
                msaa,
                Some(ratio),
                foveated,
                Some(geometry),
            ));
        }
    }
    bar.finish_and_clear();
    println!(
        "\n{:<24} {:>10} {:>7} {:>12} {:>12} {:>15} {:>15} {:>15} {:>9} {:>9}",
        "configuration",
        "frame ms",
        "ratio",
        "scene frags",
        "total frags",
        "fovea dB/SSIM",
        "band dB/SSIM",
        "perif. dB/SSIM",
        "FLIP",
        "eFLIP p99"
    );
    let base_plan = foveate::plan(&scene, &base, gpu.caps())?;
    let eyes = base_plan.eyes;
    for (name, msaa, ratio, r, geometry) in rows {
        // Regions: the fovea circle (less the band), the band, and the rest.
        let (centres, radius, band) = match geometry {
            Some(g) => {
                let fovea = fovea_views(&eyes, g.ratio, [gaze; 2], (args.res, args.res));
                let centres = Eye::BOTH
                    .map(|e| fovea_centre_px(eyes.fov(e), fovea[e.index()], (args.res, args.res)));
                (centres, g.fovea_screen_px / 2.0, g.blend_band_px)
            }
            None => ([Vec2::splat(args.res as f32 / 2.0); 2], 0.0, 0.0),
        };
        let error = |inside: &dyn Fn(f32) -> bool| {
            region_error(&reference.image, &r.image, centres, &base_plan, inside)
        };
        let regions = [
            error(&|d| d < radius - band),
            error(&|d| d >= radius - band && d <= radius),
            error(&|d| d > radius),
        ];
        let psnr = |p: Option<f64>| {
            p.map_or("-".to_string(), |v| {
                if v.is_infinite() {
                    "inf".into()
                } else {
                    format!("{v:.1}")
                }
            })
        };
        let ssim = |s: Option<f64>| s.map_or("-".to_string(), |v| format!("{v:.3}"));
        let cells: Vec<String> = regions
            .iter()
            .map(|(p, s)| format!("{} / {}", psnr(*p), ssim(*s)))
            .collect();
        let ratio_to_reference = r.frame_ms / reference.frame_ms;
        let (flip_mean, eflip_p99) = flip_errors(&reference.image, &r.image, &base_plan, gaze)?;
        println!(
            "{:<24} {:>10.2} {:>7.3} {:>12} {:>12} {:>15} {:>15} {:>15} {:>9.4} {:>9.4}",
            name,
            r.frame_ms,
            ratio_to_reference,
            r.scene_fragments,
            r.total_fragments,
            cells[0],
            cells[1],
            cells[2],
            flip_mean,
            eflip_p99
        );
        csv.row(&[
            &name,
            &msaa,
            &ratio.map_or(String::new(), |v: f32| v.to_string()),
            &format!("{:.3}", r.frame_ms),
            &format!("{ratio_to_reference:.4}"),
            &r.scene_fragments,
            &r.total_fragments,
            &opt(regions[0].0, 4),
            &opt(regions[1].0, 4),
            &opt(regions[2].0, 4),
            &opt(regions[0].1, 4),
            &opt(regions[1].1, 4),
            &opt(regions[2].1, 4),
            &format!("{flip_mean:.5}"),
            &format!("{eflip_p99:.5}"),
        ])?;
    }
    println!(
        "(ratio: frame time to the reference, this run, frames without counters; fragments from a separate counting frame: the scene draws, and every pass (the output stage included); PSNR in dB / SSIM per region against the reference, both eyes, on the output image ({}); stereo rows: the periphery column is the whole image; FLIP: mean at the display's pixels per degree; eFLIP p99: the eccentricity-aware FLIP's 99th percentile for the eye at the gaze, see metrics::flip)",
        base.output
    );
    gpu.check_validation()?;
    csv.save(args.csv.as_deref())
}

/// FLIP over both eyes' output images (mean, at the display's ppd at the lens axis) and the
/// eccentricity-aware FLIP's 99th percentile (`metrics::flip`), with the eye looking at `gaze`;
/// display pixels beyond the rendered field are left out.
fn flip_errors(
    reference: &StereoImage,
    image: &StereoImage,
    plan: &FramePlan,
    gaze: Vec2,
) -> Result<(f64, f64)> {
    let (mut plain, mut eccentric) = (Vec::new(), Vec::new());
    for eye in Eye::BOTH {
        let fov = plan.eyes.fov(eye);
        let screen = plan.eye_resolution;
        let field = plan.lens.map_or(fov, |l| l.display[eye.index()]);
        let ppd = flip::pixels_per_degree((field.left + field.right) as f64, screen.width);
        let g = gaze_tangent(fov, gaze);
        let gaze_dir = glam::DVec3::new(g.x as f64, g.y as f64, -1.0).normalize();
        let tangent = |x: u32, y: u32| -> Option<glam::DVec3> {
            let p = match &plan.lens {
                Some(lens) => lens.rendered_px(eye, fov, screen, x, y)?,
                None => Vec2::new(x as f32 + 0.5, y as f32 + 0.5),
            };
            let tx = -fov.left + p.x / screen.width as f32 * (fov.left + fov.right);
            let ty = fov.up - p.y / screen.height as f32 * (fov.up + fov.down);
            Some(glam::DVec3::new(tx as f64, ty as f64, -1.0).normalize())
        };
        let eccentricity =
            |x: u32, y: u32| tangent(x, y).map(|d| d.angle_between(gaze_dir).to_degrees());
        let (a, b) = (reference.eye(eye), image.eye(eye));
        let inside = |x: u32, y: u32| tangent(x, y).is_some();
        plain.extend(flip::select(&flip::flip_map(a, b, ppd)?, a.width, &inside));
        eccentric.extend(flip::select(
            &flip::eccentric_flip_map(a, b, ppd, &eccentricity)?,
            a.width,
            &inside,
        ));
    }
    let summary = |v: &[f32]| flip::ErrorSummary::of(v).map_or(f64::NAN, |s| s.mean);
    let p99 = |v: &[f32]| flip::ErrorSummary::of(v).map_or(f64::NAN, |s| s.p99);
    Ok((summary(&plain), p99(&eccentric)))
}

/// `compare --table`: the foveation table (see `fovea_table`).
fn table(options: &GpuOptions, args: &CompareArgs) -> Result<()> {
    let gpu = Gpu::new(options)?;
    let mut scenes = Vec::new();
    for name in &args.scenes {
        for shading in &args.shadings {
            scenes.push((name.clone(), shading.parse::<Shading>()?));
        }
    }
    let settings = TableSettings {
        scenes,
        ratios: args.ratios.clone().unwrap_or(vec![0.35, 0.5]),
        resolution: Resolution::square(args.res),
        msaa: *args.msaa.last().unwrap_or(&4),
        output: args.output.parse()?,
        frames: args.frames,
    };
    println!(
        "device: {}; {}x{} per eye, MSAA {}, output {}, gaze centred; {} timed frames per row, rows interleaved",
        gpu.info().name,
        args.res,
        args.res,
        settings.msaa,
        settings.output,
        settings.frames
    );
    let rows = fovea_table::measure(&gpu, &settings, &|name, shading| {
        Ok(named_scene(name)?.with_shading(shading))
    })?;
    fovea_table::print(&rows);
    println!(
        "(x stereo: frame time to the same scene's stereo row in this run; fragments and primitives from separate counting frames; (auto): the layout `--fovea-layout auto` picks on this device)"
    );
    fovea_table::csv(&rows)?.save(args.csv.as_deref())
}
