//! `foveate bench`: the thesis' benchmark (Preißner 2020 §5–6) on its scene along its rails — every
//! permutation of superfrustum, multiview, stencil mask and MFFR, each multiview one also
//! foveated — per-frame times and counts, the thesis' tables with ratios to the baseline,
//! memory and traffic per configuration, the accuracy-vs-time curve, and plots.

pub(crate) mod accuracy;
mod matrix;
pub(crate) mod plots;
mod report;

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Args;
use foveate::foveation::FoveationConfig;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::mffr::{MffrConfig, SplitDistance};
use foveate::plan::{FramePlan, OutputStage, Resolution};
use foveate::render::Renderer;
use foveate::scene::{rail_pose, Instance, Shading, ThesisScene, RAIL_LOOP_FRAMES};

use crate::fovea_table::TableSettings;

pub use matrix::{Settings, Toggles};
use report::{FrameSample, Report, Row};

#[derive(Args)]
pub struct BenchArgs {
    /// Size of the thesis scene: tiny (1 k instances), small (29 k), medium (444 k), full
    /// (11.1 M, as in the thesis) or a factor 0 < s ≤ 1 of its horizontal counts.
    #[arg(long, default_value = "small")]
    pub scale: String,
    /// Frames measured per configuration, spread evenly over two loops of the rails.
    #[arg(long, default_value_t = 24)]
    pub frames: u64,
    /// Warm-up frames rendered first by every configuration and dropped.
    #[arg(long, default_value_t = 2)]
    pub warmup: u64,
    /// Headset profile (its FOV, IPD and lens mask; with `--res native`, its panel).
    #[arg(long, default_value = "index")]
    pub hmd: String,
    /// Per-eye resolution: N (square), WxH or `native` (the headset's panel).
    #[arg(long, default_value = "512")]
    pub res: String,
    /// MSAA samples: 1 or 4 (the thesis: 4).
    #[arg(long, default_value_t = 4)]
    pub msaa: u32,
    /// Distance culling radius (the thesis: 320 units).
    #[arg(long, default_value_t = 320.0)]
    pub draw_distance: f32,
    /// Foveation ratio of the foveated rows.
    #[arg(long, default_value_t = 0.35)]
    pub ratio: f32,
    /// MFFR variant of the MFFR rows: far-first, near-first, alternate-eye, depth-shift.
    #[arg(long, default_value = "near-first")]
    pub mffr: String,
    /// MFFR split of the MFFR rows: a disparity (`1px`) or metres (`20m`).
    #[arg(long, default_value = "1px")]
    pub split: String,
    /// Count pixels shaded on every Nth measured frame, with a separate counting renderer so the
    /// counter's atomics never touch a timed frame (0: never).
    #[arg(long, default_value_t = 4)]
    pub pixels_every: u64,
    /// Only the rows whose name contains one of these (e.g. `MVIEW,SMASK`); the baseline is
    /// always measured.
    #[arg(long, value_delimiter = ',')]
    pub only: Vec<String>,
    /// Rounds per point of the accuracy-vs-time sweep (the first is a warm-up; 0: skip it).
    #[arg(long, default_value_t = 3)]
    pub accuracy_rounds: u32,
    /// Directory for tables.md, the CSVs, bench.json and the plots (PNG and SVG).
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// Also write the per-frame samples as CSV to this file (`-`: standard output).
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Also write the whole report as JSON to this file (`-`: standard output).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Per-eye resolution of the foveation table (stereo against foveation 0.35 and 0.5 in
    /// both fovea layouts on every built-in scene, flat and lit, lens output on every row),
    /// written as foveation-table.md and .csv; 0 skips it.
    #[arg(long, default_value_t = 1024)]
    pub foveation_res: u32,
    /// Timed frames per row of the foveation table.
    #[arg(long, default_value_t = 3)]
    pub foveation_frames: u32,
}

/// Scene scale by name or factor.
pub fn parse_scale(s: &str) -> Result<f32> {
    let scale = match s {
        "tiny" => 0.01,
        "small" => 0.05,
        "medium" => 0.2,
        "full" => 1.0,
        _ => s.parse::<f32>().map_err(|_| {
            anyhow::anyhow!("invalid scale = {s}: tiny, small, medium, full or a factor 0 < s ≤ 1")
        })?,
    };
    ThesisScene::counts(scale)?;
    Ok(scale)
}

/// Instance buffers of all configurations alive together above this: measure one
/// configuration after another instead of interleaving them frame by frame.
const INTERLEAVE_LIMIT_BYTES: u64 = 2 << 30;

pub fn bench(options: &GpuOptions, args: &BenchArgs) -> Result<()> {
    crate::interrupt::install();
    let scale = parse_scale(&args.scale)?;
    anyhow::ensure!(
        args.frames >= 1,
        "invalid frames = {}: at least 1",
        args.frames
    );
    let resolution = crate::frame_args::screen(&args.hmd, &args.res)?;
    let split: SplitDistance = args.split.parse()?;
    crate::outputs::folder(&args.out)?;
    crate::outputs::files(&[args.csv.as_deref(), args.json.as_deref()])?;
    let settings = Settings {
        hmd: args.hmd.clone(),
        resolution,
        msaa: args.msaa,
        draw_distance: args.draw_distance,
        foveation: FoveationConfig {
            ratio: args.ratio,
            ..FoveationConfig::single_frame()
        },
        mffr: MffrConfig::named(&args.mffr, split)?,
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;

    eprintln!(
        "thesis scene at scale {scale}: {} instances",
        ThesisScene::instance_count(scale)?
    );
    let thesis = ThesisScene::new(scale)?;
    let extent = thesis.extent();
    let scene = thesis.to_scene();
    drop(thesis);
    let gpu = Gpu::new(options)?;

    let rows = rows(&settings, &args.only);
    // Every row is planned before anything renders, so a bad setting fails at once.
    let plans = rows
        .iter()
        .map(|r| foveate::plan(&scene, &r.config, gpu.caps()).with_context(|| r.name.clone()))
        .collect::<Result<Vec<FramePlan>>>()?;
    let step = (2 * RAIL_LOOP_FRAMES / args.frames).max(1);
    let rail_frames: Vec<u64> = (0..args.frames).map(|i| i * step).collect();
    let pose = |frame: u64| rail_pose(frame, extent);

    let instance_bytes = (scene.instance_count() * std::mem::size_of::<Instance>()) as u64;
    let interleave = instance_bytes * rows.len() as u64 <= INTERLEAVE_LIMIT_BYTES;
    let groups: Vec<Vec<usize>> = if interleave {
        vec![(0..rows.len()).collect()]
    } else {
        (0..rows.len()).map(|i| vec![i]).collect()
    };
    let counted: Vec<u64> = rail_frames
        .iter()
        .enumerate()
        .filter(|(i, _)| args.pixels_every > 0 && (*i as u64).is_multiple_of(args.pixels_every))
        .map(|(_, &f)| f)
        .collect();
    let total = rows.len() as u64 * (args.warmup + args.frames + counted.len() as u64);
    let bar = crate::progress::bar("bench", total);
    let tick = |label: &str| {
        bar.set_message(label.to_string());
        bar.inc(1);
    };
    let allocated = allocated_bytes(&gpu, &plans, &scene)?;
    let rails = Rails {
        gpu: &gpu,
        scene: &scene,
        plans: &plans,
        frames: &rail_frames,
        warmup: args.warmup,
        pose: &pose,
        tick: &tick,
    };
    let (mut samples, complete) = rails.measure(&groups)?;
    // Ctrl-C or SIGTERM stop each stage early; what was measured until then is the report
    // (the error at the end says so), and nothing is written when no frame was timed.
    if samples.is_empty() {
        return Err(crate::interrupt::stopped(
            "bench stopped before any timed frame: nothing written",
        ));
    }
    if complete {
        rails.count_pixels(&rows, &counted, &mut samples)?;
    }
    gpu.check_validation()?;
    let accuracy = match args.accuracy_rounds {
        0 => Vec::new(),
        _ if crate::interrupt::requested() => Vec::new(),
        _ => match accuracy::sweep(&gpu, &scene, &settings, pose(RAIL_LOOP_FRAMES / 4), args) {
            Err(_) if crate::interrupt::requested() => Vec::new(),
            accuracy => accuracy?,
        },
    };
    gpu.check_validation()?;
    bar.finish_and_clear();
    let report = Report::new(
        &gpu, &settings, scale, &scene, args, interleave, rows, plans, allocated, samples, accuracy,
    );
    report.write(&args.out, args.csv.as_deref(), args.json.as_deref())?;
    if args.foveation_res > 0 && !crate::interrupt::requested() {
        foveation_table(&gpu, args)?;
    }
    if crate::interrupt::requested() {
        return Err(crate::interrupt::stopped(&format!(
            "bench stopped early; {} holds what was measured until then ({})",
            args.out.display(),
            if complete {
                "every frame along the rails; pixel counts, accuracy or the foveation table cut short"
            } else {
                "the frames along the rails so far; no pixel counts, no accuracy"
            }
        )));
    }
    Ok(())
}

/// What each plan's renderer allocates, measured with no other renderer alive (alignment
/// padding depends on what else the allocator holds).
fn allocated_bytes(
    gpu: &Gpu,
    plans: &[FramePlan],
    scene: &foveate::scene::Scene,
) -> Result<Vec<u64>> {
    plans
        .iter()
        .map(|plan| {
            let before = gpu.allocated_bytes();
            let renderer = Renderer::new(gpu, plan, scene)?;
            let bytes = gpu.allocated_bytes().saturating_sub(before);
            drop(renderer);
            Ok(bytes)
        })
        .collect()
}

/// What the timed frames along the rails need.
struct Rails<'a> {
    gpu: &'a Gpu,
    scene: &'a foveate::scene::Scene,
    plans: &'a [FramePlan],
    frames: &'a [u64],
    warmup: u64,
    pose: &'a dyn Fn(u64) -> glam::Mat4,
    tick: &'a dyn Fn(&str),
}

impl Rails<'_> {
    /// Each group's rows rendered side by side along the rails (after their warm-up), every
    /// frame a sample; false beside the samples when Ctrl-C or SIGTERM stopped it early.
    fn measure(&self, groups: &[Vec<usize>]) -> Result<(Vec<FrameSample>, bool)> {
        let mut samples: Vec<FrameSample> = Vec::new();
        for group in groups {
            let mut renderers = Vec::new();
            for &i in group {
                renderers.push((i, Renderer::new(self.gpu, &self.plans[i], self.scene)?));
            }
            for _ in 0..self.warmup {
                if crate::interrupt::requested() {
                    return Ok((samples, false));
                }
                for (_, r) in &mut renderers {
                    r.render_frame((self.pose)(0))?;
                    (self.tick)("bench (warm-up)");
                }
            }
            for &frame in self.frames {
                if crate::interrupt::requested() {
                    return Ok((samples, false));
                }
                for (i, r) in &mut renderers {
                    let stats = r.render_frame((self.pose)(frame))?;
                    samples.push(FrameSample::new(*i, frame, &stats, &self.plans[*i]));
                    (self.tick)("bench");
                }
            }
        }
        Ok((samples, true))
    }

    /// Pixels shaded, by a counting twin of each row on the `counted` frames, into their
    /// samples (untimed frames: their times are no measurement).
    fn count_pixels(
        &self,
        rows: &[Row],
        counted: &[u64],
        samples: &mut [FrameSample],
    ) -> Result<()> {
        for (i, row) in rows.iter().enumerate() {
            if counted.is_empty() || crate::interrupt::requested() {
                break;
            }
            let plan = foveate::plan(self.scene, &row.config.counting(), self.gpu.caps())?;
            let mut twin = Renderer::new(self.gpu, &plan, self.scene)?;
            for &frame in counted {
                let stats = twin.render_frame((self.pose)(frame))?;
                if let Some(s) = samples
                    .iter_mut()
                    .find(|s| s.config == i && s.rail_frame == frame)
                {
                    s.pixels = Some(stats.scene_fragments());
                    s.total_pixels = Some(stats.total_fragments());
                }
                (self.tick)("bench (pixel counts)");
            }
        }
        Ok(())
    }
}

/// The foveation table (see `fovea_table`), into the output directory.
fn foveation_table(gpu: &Gpu, args: &BenchArgs) -> Result<()> {
    let mut scenes = Vec::new();
    for name in foveate::scene::SCENE_NAMES {
        for shading in [Shading::Flat, Shading::Lit] {
            scenes.push((name.to_string(), shading));
        }
    }
    let settings = TableSettings {
        scenes,
        ratios: vec![0.35, 0.5],
        resolution: Resolution::square(args.foveation_res),
        hmd: args.hmd.clone(),
        msaa: args.msaa,
        output: OutputStage::Lens,
        frames: args.foveation_frames,
        lod: None,
    };
    let rows = crate::fovea_table::measure(gpu, &settings, &|name, shading| {
        Ok(foveate::scene::named_scene(name)?.with_shading(shading))
    })?;
    crate::fovea_table::print(&rows);
    let md = args.out.join("foveation-table.md");
    let header = format!(
        "Foveation table: {} ({}x{} per eye, MSAA {}, lens output on every row, gaze centred, {} timed frames per row, rows interleaved; x stereo = frame time / the same scene's stereo row in this run; fragments and primitives from separate counting frames; (auto) = the layout `--fovea-layout auto` picks on this device).\n\n",
        gpu.info().name,
        args.foveation_res,
        args.foveation_res,
        args.msaa,
        args.foveation_frames
    );
    foveate::write_atomic(
        &md,
        (header + &crate::fovea_table::markdown(&rows)).as_bytes(),
    )?;
    println!("wrote {}", md.display());
    crate::fovea_table::csv(&rows)?.save(Some(&args.out.join("foveation-table.csv")))
}

/// The rows measured: the matrix (or the rows `only` names, with the baseline), then two
/// zero-cost checks — the baseline again (the noise between identical runs) and MFFR switched
/// off by a split past the far plane (planned exactly as the baseline).
fn rows(settings: &Settings, only: &[String]) -> Vec<Row> {
    let mut rows: Vec<Row> = Toggles::matrix()
        .into_iter()
        .filter(|t| t.is_baseline() || only.is_empty() || only.iter().any(|o| t.name().contains(o)))
        .map(|t| Row::new(t.name(), Some(t), settings.config(t)))
        .collect();
    let baseline = settings.config(Toggles::default());
    rows.push(Row::new(
        "baseline again (noise)".into(),
        None,
        baseline.clone(),
    ));
    let mut mffr_off = baseline;
    mffr_off.mffr = Some(MffrConfig {
        split: SplitDistance::Metres(mffr_off.far * 2.0),
        ..settings.mffr
    });
    rows.push(Row::new("MFFR off (split past far)".into(), None, mffr_off));
    rows
}
