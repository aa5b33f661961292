use anyhow::Result;
use clap::{Parser, Subcommand};
use foveate::gpu::{Gpu, GpuOptions};

use crate::commands::render::RenderArgs;
use crate::frame_args::ConfigArgs;

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
    /// Where frames are judged (FLIP, and flicker): gpu (compute passes on the rendering
    /// device) or cpu (NVIDIA's reference FLIP and the CPU flicker measure, the oracles; slow).
    #[arg(long, global = true, value_enum, default_value_t)]
    metric: crate::metric::Metric,
}

#[derive(Subcommand)]
enum Command {
    /// Render the default scene, write a side-by-side PNG, print plan, frame times and pixel counts.
    Render(RenderArgs),
    /// Print the frame plan: passes, attachments, load/store ops, transient images, bytes.
    Plan(PlanArgs),
    /// The frame in a window: eyes side by side, the mouse as the gaze, keys toggle foveation
    /// and the other effects, frame and GPU times and fragments in the title once a second.
    View(crate::commands::view::ViewArgs),
    /// List Vulkan devices with what foveate cares about.
    Devices,
    /// What the device's own compiler made of every pipeline of the frame, per pass and step
    /// (instructions, registers, waves, ...), where the device reports it (Adreno's turnip
    /// through scripts/adreno.sh, RADV, NVIDIA); compiling them all is the check that the
    /// driver accepts them.
    Shaders(crate::commands::shaders::ShadersArgs),
    /// A frame's price on a tile GPU (a formula: counted fragments and vertices x its own
    /// compiler's instructions, the plan's bytes at its bandwidth) beside its time on the
    /// rendering device, with stereo 4x and aliased stereo as yardsticks; two devices in one
    /// run (scripts/adreno.sh price).
    Price(crate::commands::price::PriceArgs),
    /// Write docs/results.md and the README's verdict table from the committed run files
    /// (docs/results/index.csv); `--check` compares instead (scripts/results.sh, CI).
    #[command(hide = true)]
    Results(crate::commands::results::ResultsArgs),
    /// Culling benchmarks: Hale's intersection tables, and stereo strategies on the thesis scene.
    CullBench(crate::commands::cull::CullBenchArgs),
    /// Arm's foveation pixel tables 2-4, every cell measured on the GPU beside the formula.
    Pixels(crate::commands::pixels::PixelsArgs),
    /// What accuracy costs: a full-quality stereo reference against foveation ratios x MSAA,
    /// blend bands and periphery sharpening: frame time beside PSNR and SSIM per region, FLIP and
    /// the eccentricity-aware FLIP; `--recommend` picks within an error budget.
    Compare(Box<crate::commands::compare::CompareArgs>),
    /// Temporal stability: flicker of each approximation beyond the reference's own change,
    /// along a saccade trace and with the head walking.
    Flicker(crate::commands::flicker::FlickerArgs),
    /// Monoscopic far-field rendering: every variant at a list of splits against a stereo
    /// reference, frame time beside image error, disparity bound and seam check.
    Mffr(crate::commands::mffr::MffrArgs),
    /// The HMD stencil mask per headset: fraction hidden (published, analytic, measured) beside
    /// the frame time it saves.
    Mask(crate::commands::mask::MaskArgs),
    /// The thesis' benchmark on its scene along the rails: 16 permutations of superfrustum,
    /// multiview, stencil mask and MFFR (and the multiview ones foveated), its tables with
    /// ratios to the baseline, memory and traffic, accuracy against time, and plots.
    Bench(crate::commands::bench::BenchArgs),
    /// What judging a frame costs: eFLIP of a foveated frame against its reference at a
    /// headset's panel on the GPU, and with --cpu on the CPU beside it, with both maps compared.
    Judge(crate::commands::judge::JudgeArgs),
    /// The frame on an OpenXR runtime's headset (Monado's simulated one in CI): the runtime
    /// makes the Vulkan device, places the eyes each frame and takes the output stage's images.
    Xr(crate::commands::xr::XrArgs),
    /// Renderers kept rendering for minutes or hours (lit and flat, stereo and foveated, frames
    /// in flight, an instance moving): resident memory and frame times sampled throughout; fails
    /// when memory grows beyond a bound after the warm-up.
    Soak(crate::commands::soak::SoakArgs),
}

impl Cli {
    fn gpu_options(&self) -> GpuOptions {
        let env = GpuOptions::from_env();
        GpuOptions {
            validation: self.validation || env.validation,
            device: self.device.clone().or(env.device),
            pipeline_cache: pipeline_cache_path(),
            display: None,
        }
    }

    pub fn run(&self) -> Result<()> {
        crate::metric::choose(self.metric);
        match &self.command {
            Command::Devices => devices(),
            Command::Results(args) => crate::commands::results::results(args),
            Command::Plan(PlanArgs {
                config: args,
                engine,
            }) => {
                // The scene first: a bad file is refused before the device starts.
                let scene = args.scene()?;
                let gpu = Gpu::new(&self.gpu_options())?;
                for mode in args.stereo_modes()? {
                    let config = args.config(mode)?;
                    let plan = match engine {
                        true => foveate::plan::plan_for_engine(&config, gpu.caps())?,
                        false => foveate::plan(&scene, &config, gpu.caps())?,
                    };
                    println!("{plan}\n");
                }
                let tracked: Vec<&str> = foveate::view::HMD_PROFILES
                    .iter()
                    .filter(|p| p.eye_tracker.is_some())
                    .map(|p| p.name)
                    .collect();
                println!(
                    "headsets with eye tracking (eye-tracked foveation): {}; the others ({}) only fixed foveation",
                    tracked.join(", "),
                    foveate::view::HMD_PROFILES
                        .iter()
                        .filter(|p| p.eye_tracker.is_none())
                        .map(|p| p.name)
                        .collect::<Vec<_>>()
                        .join(", ")
                );
                Ok(())
            }
            Command::Render(args) => crate::commands::render::render(&self.gpu_options(), args),
            Command::Price(args) => crate::commands::price::price(&self.gpu_options(), args),
            Command::Shaders(args) => crate::commands::shaders::shaders(&self.gpu_options(), args),
            Command::View(args) => crate::commands::view::view(&self.gpu_options(), args),
            Command::CullBench(args) => crate::commands::cull::cull_bench(args),
            Command::Pixels(args) => crate::commands::pixels::pixels(&self.gpu_options(), args),
            Command::Compare(args) => crate::commands::compare::compare(&self.gpu_options(), args),
            Command::Flicker(args) => crate::commands::flicker::flicker(&self.gpu_options(), args),
            Command::Mffr(args) => crate::commands::mffr::mffr(&self.gpu_options(), args),
            Command::Mask(args) => crate::commands::mask::mask(&self.gpu_options(), args),
            Command::Bench(args) => crate::commands::bench::bench(&self.gpu_options(), args),
            Command::Xr(args) => crate::commands::xr::xr(&self.gpu_options(), args),
            Command::Judge(args) => crate::commands::judge::judge(&self.gpu_options(), args),
            Command::Soak(args) => crate::commands::soak::soak(&self.gpu_options(), args),
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
            "    fragment density map: {}; fragment shading rate (VRS): {}; lazily allocated memory: {}; stencil masks (D32_SFLOAT_S8_UINT): {}",
            yes(d.fragment_density_map),
            yes(d.fragment_shading_rate),
            yes(d.lazily_allocated_memory),
            yes(d.depth_stencil)
        );
        let applying: Vec<_> = d
            .quirks
            .listing()
            .into_iter()
            .filter(|(_, applies, _)| *applies)
            .collect();
        if applying.is_empty() {
            println!("    driver quirks: none known");
        } else {
            println!("    driver quirks (and what foveate does about them):");
            for (name, _, workaround) in applying {
                println!("      {name}: {workaround}");
            }
        }
        if let Some(why) = d.unusable {
            println!("    unusable by foveate: {why}");
        }
    }
    Ok(())
}

/// Where the CLI keeps compiled pipelines between runs: `FOVEATE_PIPELINE_CACHE` (a path, or
/// `off`), else `$XDG_CACHE_HOME/foveate/pipelines.bin`, else `~/.cache/foveate/pipelines.bin`
/// (each device's file named after it: `GpuOptions::pipeline_cache`).
fn pipeline_cache_path() -> Option<std::path::PathBuf> {
    match std::env::var("FOVEATE_PIPELINE_CACHE") {
        Ok(v) if v == "off" || v.is_empty() => None,
        Ok(v) => Some(v.into()),
        Err(_) => std::env::var_os("XDG_CACHE_HOME")
            .map(std::path::PathBuf::from)
            .or_else(|| std::env::var_os("HOME").map(|h| std::path::Path::new(&h).join(".cache")))
            .map(|dir| dir.join("foveate").join("pipelines.bin")),
    }
}

/// `foveate plan`: the frame's configuration, and whose draws its scene steps are.
#[derive(clap::Args)]
pub struct PlanArgs {
    #[command(flatten)]
    config: ConfigArgs,
    /// Plan the frame a `FoveationLayer` records around an engine's own draws (the scene steps
    /// the engine's, nothing of `--scene` drawn): what foveate does in the engine's frame.
    #[arg(long)]
    engine: bool,
}
