use std::path::PathBuf;

use anyhow::Result;
use clap::{Args, Parser, Subcommand};
use foveate::foveation::FoveationConfig;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::mffr::MffrConfig;
use foveate::plan::{RenderConfig, Resolution, StereoMode};
use foveate::scene::named_scene;

#[derive(Parser)]
#[command(
    name = "foveate",
    version,
    about = "Stereo and foveated VR rendering on Vulkan, measured"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
    /// Vulkan device to use: index or part of its name (default: the best; env FOVEATE_DEVICE).
    #[arg(long, global = true)]
    device: Option<String>,
    /// Enable VK_LAYER_KHRONOS_validation and fail on any message (env FOVEATE_VALIDATION=1).
    #[arg(long, global = true)]
    validation: bool,
}

#[derive(Subcommand)]
enum Command {
    /// Render the default scene, write a side-by-side PNG, print plan, frame times and pixel counts.
    Render(RenderArgs),
    /// Print the frame plan: passes, attachments, load/store ops, transient images, bytes.
    Plan(ConfigArgs),
    /// List Vulkan devices with what foveate cares about.
    Devices,
    /// Culling benchmarks: Hale's intersection tables, and stereo strategies on the thesis scene.
    CullBench(crate::cull_cmd::CullBenchArgs),
    /// Arm's foveation pixel tables 2-4, every cell measured on the GPU beside the formula.
    Pixels(crate::pixels_cmd::PixelsArgs),
    /// What accuracy costs: a full-quality stereo reference against foveation ratios x MSAA,
    /// frame time beside PSNR per region (fovea, band, periphery) and SSIM.
    Compare(crate::compare_cmd::CompareArgs),
    /// Monoscopic far-field rendering: every variant at a list of splits against a stereo
    /// reference, frame time beside image error, disparity bound and seam check.
    Mffr(crate::mffr_cmd::MffrArgs),
    /// The HMD stencil mask per headset: fraction hidden (published, analytic, measured) beside
    /// the frame time it saves.
    Mask(crate::mask_cmd::MaskArgs),
    /// The thesis' benchmark on its scene along the rails: 16 permutations of superfrustum,
    /// multiview, stencil mask and MFFR (and the multiview ones foveated), its tables with
    /// ratios to the baseline, memory and traffic, accuracy against time, and plots.
    Bench(crate::bench::BenchArgs),
}

/// Frame configuration shared by `render` and `plan`.
#[derive(Args, Clone)]
pub struct ConfigArgs {
    /// Headset profile: index, vive, rift-cv1, quest2.
    #[arg(long, default_value = "index")]
    pub hmd: String,
    /// Stereo submission: multiview, two-pass, per-object, instanced (`render` also takes `all`).
    #[arg(long, default_value = "multiview")]
    pub stereo: String,
    /// MSAA samples on the scene pass: 1 or 4.
    #[arg(long, default_value_t = 4)]
    pub msaa: u32,
    /// Per-eye resolution: N (square), WxH, or `native` for the headset's panel.
    #[arg(long, default_value = "1024")]
    pub res: String,
    /// Views per pass (2 for stereo).
    #[arg(long, default_value_t = 2)]
    pub views: u32,
    /// Interpupillary distance in millimetres (default 64).
    #[arg(long)]
    pub ipd_mm: Option<f32>,
    /// Outward cant of each eye in degrees (default: the headset's).
    #[arg(long)]
    pub cant: Option<f32>,
    /// Foveated rendering at this ratio (e.g. 0.35): four views, composed per eye.
    #[arg(long)]
    pub foveate: Option<f32>,
    /// Pixels per side of the four foveated views (default: resolution × ratio).
    #[arg(long)]
    pub view_res: Option<u32>,
    /// Fixed fovea diameter on screen in pixels (default: the whole fovea window).
    #[arg(long)]
    pub fovea_size: Option<u32>,
    /// Blend band in screen pixels at the fovea's edge (smoothstep); default: an eighth of the
    /// fovea's diameter.
    #[arg(long)]
    pub blend_band: Option<f32>,
    /// Foveation without the inset/outset stencil masks.
    #[arg(long)]
    pub no_stencil: bool,
    /// Gaze of both eyes, normalised: X,Y in -1..1 (x right, y up).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub gaze: Option<Vec<f32>>,
    /// Tint the composed image: fovea green, band yellow, periphery blue.
    #[arg(long)]
    pub tint: bool,
    /// The HMD stencil mask: no fragment is shaded where the lens hides the image.
    #[arg(long)]
    pub hmd_mask: bool,
    /// Monoscopic far-field rendering: far-first, near-first, alternate-eye or depth-shift.
    #[arg(long)]
    pub mffr: Option<String>,
    /// Where MFFR splits near from far: a disparity (`1px`: z = IPD x focal / 1 px) or metres
    /// (`40m`).
    #[arg(long, default_value = "1px")]
    pub split: String,
    /// Scene: `default` (lit cubes and spheres, near and far), `fill` (24 full-view walls drawn
    /// back to front: a fill-bound frame) or `city` (blocks from 28 m to 400 m: far-heavy).
    #[arg(long, default_value = "default")]
    pub scene: String,
}

impl ConfigArgs {
    /// The config for one stereo mode (`stereo` may be `all`; the caller picks the mode).
    pub fn config(&self, stereo: StereoMode) -> Result<RenderConfig> {
        let resolution = match self.res.as_str() {
            "native" => None,
            r => Some(r.parse::<Resolution>()?),
        };
        let foveation = self.foveate.map(|ratio| FoveationConfig {
            ratio,
            view_resolution: self.view_res,
            stencil: !self.no_stencil,
            fovea_size: self.fovea_size,
            blend_band_px: self.blend_band.unwrap_or(-1.0),
            debug_tint: self.tint,
        });
        let mffr = self
            .mffr
            .as_deref()
            .map(|name| MffrConfig::named(name, self.split.parse()?))
            .transpose()?;
        Ok(RenderConfig {
            hmd: self.hmd.clone(),
            hmd_mask: self.hmd_mask,
            mffr,
            resolution,
            stereo,
            // Foveation renders four views unless the user asked for something else.
            views: if foveation.is_some() && self.views == 2 {
                4
            } else {
                self.views
            },
            foveation,
            msaa: self.msaa,
            ipd_m: self.ipd_mm.map(|mm| mm / 1000.0),
            cant_deg: self.cant,
            ..RenderConfig::default()
        })
    }

    /// The stereo modes asked for: one, or all four for `all`.
    pub fn stereo_modes(&self) -> Result<Vec<StereoMode>> {
        if self.stereo == "all" {
            Ok(StereoMode::ALL.to_vec())
        } else {
            Ok(vec![self.stereo.parse()?])
        }
    }
}

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub config: ConfigArgs,
    /// Drive the gaze from a trace: a CSV file (`time,left_x,left_y,right_x,right_y,valid`) or
    /// `sim` for simulated fixations and saccades; frame i uses the sample at i / 90 s, filtered
    /// (bad samples keep the last good gaze, then return to the centre).
    #[arg(long)]
    pub gaze_trace: Option<String>,
    /// Frames to render (the first is a warm-up and not counted in the statistics).
    #[arg(long, default_value_t = 10)]
    pub frames: u32,
    /// Where to write the side-by-side PNG (with `--stereo all`, one file per mode is written,
    /// the mode's name inserted before the extension).
    #[arg(long, default_value = "frame.png")]
    pub out: PathBuf,
}

impl Cli {
    fn gpu_options(&self) -> GpuOptions {
        let env = GpuOptions::from_env();
        GpuOptions {
            validation: self.validation || env.validation,
            device: self.device.clone().or(env.device),
        }
    }

    pub fn run(&self) -> Result<()> {
        match &self.command {
            Command::Devices => devices(),
            Command::Plan(args) => {
                let gpu = Gpu::new(&self.gpu_options())?;
                let scene = named_scene(&args.scene)?;
                for mode in args.stereo_modes()? {
                    let plan = foveate::plan(&scene, &args.config(mode)?, gpu.caps())?;
                    println!("{plan}\n");
                }
                Ok(())
            }
            Command::Render(args) => crate::render_cmd::render(&self.gpu_options(), args),
            Command::CullBench(args) => crate::cull_cmd::cull_bench(args),
            Command::Pixels(args) => crate::pixels_cmd::pixels(&self.gpu_options(), args),
            Command::Compare(args) => crate::compare_cmd::compare(&self.gpu_options(), args),
            Command::Mffr(args) => crate::mffr_cmd::mffr(&self.gpu_options(), args),
            Command::Mask(args) => crate::mask_cmd::mask(&self.gpu_options(), args),
            Command::Bench(args) => crate::bench::bench(&self.gpu_options(), args),
        }
    }
}

fn devices() -> Result<()> {
    let devices = Gpu::list_devices()?;
    if devices.is_empty() {
        println!("no Vulkan devices found (install mesa-vulkan-drivers for lavapipe)");
    }
    for d in devices {
        let yes = |b: bool| if b { "yes" } else { "no" };
        println!("[{}] {} ({})", d.index, d.name, d.device_type);
        println!("    Vulkan {}; driver {}", d.api_version, d.driver);
        println!(
            "    multiview: max {} views; MSAA sample counts: {:?}",
            d.max_multiview_views, d.sample_counts
        );
        println!(
            "    fragment density map: {}; fragment shading rate (VRS): {}; lazily allocated memory: {}",
            yes(d.fragment_density_map),
            yes(d.fragment_shading_rate),
            yes(d.lazily_allocated_memory)
        );
        if let Some(why) = d.unusable {
            println!("    unusable by foveate: {why}");
        }
    }
    Ok(())
}

/// A `--gaze X,Y` argument: two finite numbers, clamped to −1…1.
pub fn gaze_from(values: &[f32]) -> Result<glam::Vec2> {
    anyhow::ensure!(
        values.len() == 2,
        "invalid gaze = {values:?}: two numbers X,Y in -1..1"
    );
    let gaze = glam::Vec2::new(values[0], values[1]);
    anyhow::ensure!(
        gaze.is_finite(),
        "invalid gaze = {},{}: finite numbers in -1..1",
        values[0],
        values[1]
    );
    Ok(gaze.clamp(glam::Vec2::NEG_ONE, glam::Vec2::ONE))
}
