//! `foveate flicker`: temporal stability (`metrics::temporal`). Each approximation runs frame by
//! frame beside the full-quality reference (stereo, 4× MSAA) through the motions asked for —
//! head and gaze still, the gaze jumping along saccade traces with the head still, the head
//! walking with the gaze at rest (ahead, or `--gaze`) — and reports how much more its output
//! changes between frames than the reference's does.

use std::cell::Cell;
use std::path::PathBuf;
use std::time::Instant;

use anyhow::Result;
use clap::Args;
use foveate::foveation::{large_saccade_trace, simulated_trace, FoveationConfig, GazeSpace};
use foveate::gpu::{Gpu, GpuOptions};
use foveate::judge::{GpuFlicker, GpuFlip};
use foveate::metrics::perceptual::{perceptual_error, Maps};
use foveate::metrics::temporal::{Flicker, FlickerSummary};
use foveate::metrics::Acuity;
use foveate::metrics::{ErrorSummary, Stats};
use foveate::plan::RenderConfig;
use foveate::render::{HistoryOutcomes, Renderer};
use foveate::scene::{walking_pose, Walker};
use glam::{Mat4, Vec2};

use crate::commands::motion_frontier::{self, plot_stem, MotionPoint};
use crate::counts::mib;
use crate::csv_out::{opt, CsvTable};
use crate::frame_args::ComparedFrame;
use crate::history_table::OutcomesAlong;
use crate::region_maps::RegionMaps;
use crate::side_by_side::settle;
use crate::variants::{with_temporal, with_view_sets, Accumulation};

#[derive(Args)]
pub struct FlickerArgs {
    /// Screen resolution per eye: N (square), WxH, or `native` (the headset's panel).
    #[arg(long, default_value = "512")]
    res: String,
    /// Scene: default, fill, city, thesis or atrium.
    #[arg(long, default_value = "atrium")]
    scene: String,
    #[command(flatten)]
    frame: ComparedFrame,
    /// Foveation ratios to measure (the fovea at `--fovea-msaa`).
    #[arg(long, value_delimiter = ',', default_value = "0.35,0.5")]
    ratios: Vec<f32>,
    /// Each foveated row once per sample count of its fovea views (the frame's MSAA), 1 or 4.
    /// An accumulated periphery stays at its own (1×), a single-frame one follows the fovea's.
    #[arg(long, value_delimiter = ',', default_value = "4")]
    fovea_msaa: Vec<u32>,
    /// Also each ratio with the periphery sharpened at these strengths.
    #[arg(long, value_delimiter = ',')]
    sharpen: Vec<f32>,
    /// Also each foveated row with the periphery at these densities (fractions of the screen's
    /// pixels per side, independent of the fovea's ratio), one row each.
    #[arg(long, value_delimiter = ',')]
    densities: Vec<f32>,
    /// Also each plain foveated row (every density) with its periphery accumulated over frames
    /// (1x, jittered; the fovea at `--fovea-msaa`). Its history first settles on the motion's
    /// first frame (two jitter cycles, not measured).
    #[arg(long)]
    temporal: bool,
    #[command(flatten)]
    accumulation: Accumulation,
    /// Also judge frames against the reference's frame in eccentricity-aware FLIP at that
    /// frame's gaze: every frame, or with a number N every Nth (FLIP is slow at a headset's
    /// native resolution). Per motion: the mean over the judged frames of the mean and of the
    /// 99th percentile, and the worst frame's.
    #[arg(long, num_args = 0..=1, default_missing_value = "1", value_name = "EVERY")]
    flip: Option<u32>,
    /// Frames of each motion, at 90 Hz.
    #[arg(long, default_value_t = 45)]
    frames: u32,
    /// Seed of the simulated saccade traces.
    #[arg(long, default_value_t = 3)]
    seed: u32,
    /// Gaze of both eyes where it rests (`still`, `walking`), normalised X,Y in -1..1. The
    /// saccade traces start at the centre and move on their own.
    #[arg(
        long,
        value_delimiter = ',',
        allow_hyphen_values = true,
        default_value = "0,0"
    )]
    gaze: Vec<f32>,
    /// The motions, in order: `still` (head and gaze still: the jitter's shimmer alone),
    /// `saccades` (a simulated trace, head still), `large-saccades` (15–30° each, head still),
    /// `walking` (gaze at rest, `--gaze`).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "still,saccades,large-saccades,walking"
    )]
    motions: Vec<MotionKind>,
    /// A walker crosses the view in every motion (a person-sized box 4 m ahead, 1.4 m/s), so
    /// accumulation meets a surface moving on its own: ghosting and what it uncovers.
    #[arg(long)]
    walker: bool,
    /// Also count, every frame, what became of each accumulated pixel's history (kept,
    /// clipped, taken from the fovea, or dropped: reset, off-screen, disoccluded, empty), per
    /// region: the accumulated rows run as counting frames. With a file, every frame's counts
    /// are written to it as CSV.
    #[arg(long, num_args = 0..=1, value_name = "CSV")]
    history_outcomes: Option<Option<PathBuf>>,
    /// Also plot each motion's eFLIP p99 against frame time (× the reference's), stereo and
    /// foveated points marked and the Pareto frontier joined, to `<STEM>-<motion>.png` and
    /// `.svg`, and print the points. Needs `--flip`. A configuration's time is the median of
    /// its frames along the motion (every configuration's frames interleaved, as `compare`
    /// times them); rows counting `--history-outcomes` are not timed.
    #[arg(long, value_name = "STEM")]
    pareto: Option<PathBuf>,
    /// Also write the table as CSV to this file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// Frame rate the motions are sampled at.
const RATE_HZ: f64 = 90.0;

/// One motion: per frame, the head pose and the gaze.
struct Motion {
    kind: MotionKind,
    frames: Vec<(Mat4, Vec2)>,
}

/// The motions `foveate flicker` measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum MotionKind {
    Still,
    Saccades,
    LargeSaccades,
    Walking,
}

pub fn flicker(options: &GpuOptions, args: &FlickerArgs) -> Result<()> {
    crate::interrupt::install();
    let history_csv = check_args(args)?;
    let gaze = crate::gaze_arg::gaze_from(&args.gaze)?;
    let mut scene = args.frame.scene(&args.scene)?;
    let walker = args.walker.then(|| Walker::add(&mut scene, 4.0));
    let screen = args.frame.screen(&args.res)?;
    let base = args.frame.base(&args.res)?;
    let base = RenderConfig {
        moving_instances: args.walker,
        ..base
    };
    let configs = flicker_configs(args, &base, screen)?;
    let reference = RenderConfig {
        msaa: 4,
        ..base.clone()
    };
    let gpu = Gpu::new(options)?;
    // With --history-outcomes the accumulated rows count (their frames show the same image).
    let accumulates =
        |c: &RenderConfig| (c.foveation.as_ref()).is_some_and(|f| f.periphery_temporal.is_some());
    let plans = std::iter::once(&reference)
        .chain(configs.iter().map(|(_, c)| c))
        .map(
            |c| match args.history_outcomes.is_some() && accumulates(c) {
                true => foveate::plan(&scene, &c.counting(), gpu.caps()),
                false => foveate::plan(&scene, c, gpu.caps()),
            },
        )
        .collect::<Result<Vec<_>, _>>()?;
    let space = GazeSpace {
        fov: plans[0].eyes.fov(foveate::view::Eye::Left),
    };
    let motions = motions(args, gaze, &scene, space);
    println!(
        "device: {}; scene {}{}, {}, output {}; {} frames at {RATE_HZ} Hz per motion: {}",
        gpu.info().name,
        args.scene,
        if args.walker {
            " with a walker crossing 4 m ahead"
        } else {
            ""
        },
        crate::frame_args::headset_line(&plans[0]),
        base.output,
        args.frames,
        motions
            .iter()
            .map(|m| m.describe(args))
            .collect::<Vec<_>>()
            .join(", ")
    );
    let bar = crate::progress::bar("flicker", (motions.len() as u32 * args.frames) as u64);
    let spent = Spent::default();
    let mut results = Vec::new();
    // Ctrl-C or SIGTERM: the motions finished so far are printed and written.
    let mut interrupted = false;
    for motion in &motions {
        let measured = MotionRun {
            gpu: &gpu,
            scene: &scene,
            plans: &plans,
            configs: &configs,
            walker,
            flip: args.flip,
            bar: &bar,
            spent: &spent,
        }
        .measure(motion)?;
        match measured {
            Some(rows) => results.extend(rows),
            None => {
                interrupted = true;
                break;
            }
        }
    }
    bar.finish_and_clear();
    print_table(&results);
    if let Some(stem) = &args.pareto {
        report_frontiers(stem, &motions, &results, &plans[0])?;
    }
    let outcomes: Vec<_> = results
        .iter_mut()
        .filter_map(|r| r.history.take())
        .collect();
    crate::history_table::print(&outcomes);
    println!("{}", spent.describe());
    gpu.check_validation()?;
    write_csv(&results, args.csv.as_deref())?;
    if let Some(path) = &history_csv {
        crate::history_table::write_csv(&outcomes, path)?;
    }
    if interrupted {
        return Err(crate::interrupt::stopped(&format!(
            "flicker stopped during a motion; the {} motions finished before it are in the table above{}",
            results.len() / configs.len().max(1),
            if args.csv.is_some() { " and the CSV" } else { "" }
        )));
    }
    Ok(())
}

/// The arguments checked, and every output path writable, before any work: the history
/// outcomes' CSV path, if asked for.
fn check_args(args: &FlickerArgs) -> Result<Option<PathBuf>> {
    let history_csv = args.history_outcomes.clone().flatten();
    crate::outputs::files(&[args.csv.as_deref(), history_csv.as_deref()])?;
    anyhow::ensure!(
        args.frames >= 2,
        "invalid frames = {}: at least 2 (flicker is a change between frames)",
        args.frames
    );
    if let Some(m) = args.fovea_msaa.iter().find(|m| !matches!(m, 1 | 4)) {
        anyhow::bail!("invalid fovea-msaa = {m}: each sample count 1 or 4");
    }
    anyhow::ensure!(
        args.flip != Some(0),
        "invalid flip = 0: judge every Nth frame, N ≥ 1 (leave it out for none)"
    );
    anyhow::ensure!(
        args.pareto.is_none() || args.flip.is_some(),
        "invalid pareto without flip: the frontier is eFLIP p99 against time, so --pareto needs --flip [N]"
    );
    if let Some(stem) = &args.pareto {
        for motion in &args.motions {
            crate::outputs::plot(&plot_stem(stem, motion.name()))?;
        }
    }
    Ok(history_csv)
}

/// Each motion's frontier (`--pareto`): its judged rows against their times, printed and
/// plotted to `stem`'s file for the motion.
fn report_frontiers(
    stem: &std::path::Path,
    motions: &[Motion],
    results: &[Row],
    plan: &foveate::plan::FramePlan,
) -> Result<()> {
    let headset = format!("{}, {}/eye", plan.hmd.display_name, plan.eye_resolution);
    for motion in motions {
        let points: Vec<MotionPoint> = (results.iter())
            .filter(|r| r.motion == motion.name())
            .filter_map(|r| r.point())
            .collect();
        // A motion an interruption cut short has no points: no empty plot.
        if points.is_empty() {
            continue;
        }
        motion_frontier::report(motion.name(), &points, &headset, stem)?;
    }
    Ok(())
}

/// The rows compared: aliased stereo, then every foveated variant the arguments ask for (each
/// checked against the screen), at 4× MSAA.
fn flicker_configs(
    args: &FlickerArgs,
    base: &RenderConfig,
    screen: foveate::plan::Resolution,
) -> Result<Vec<(String, RenderConfig)>> {
    let mut variants = Vec::new();
    for &ratio in &args.ratios {
        for sharpen in std::iter::once(0.0).chain(args.sharpen.iter().copied()) {
            let name = match sharpen {
                0.0 => format!("foveated {ratio}"),
                s => format!("foveated {ratio}, sharpen {s}"),
            };
            let foveation = FoveationConfig {
                ratio,
                periphery_sharpen: sharpen,
                ..Default::default()
            };
            variants.push((name, foveation));
        }
    }
    variants = with_view_sets(variants, &args.densities, &[]);
    if args.temporal {
        variants = with_temporal(variants, &args.accumulation)?;
    }
    let mut configs = vec![(
        "stereo, MSAA 1".to_string(),
        RenderConfig {
            msaa: 1,
            ..base.clone()
        },
    )];
    for (name, foveation) in variants {
        foveation.geometry(screen)?;
        for &msaa in &args.fovea_msaa {
            let config = RenderConfig {
                msaa,
                foveation: Some(foveation),
                ..base.clone()
            };
            configs.push((format!("{name}, MSAA {msaa}"), config));
        }
    }
    Ok(configs)
}

/// The motions asked for: head and gaze still; saccades with the head still (a simulated
/// trace); large saccades (15–30°) with the head still; a walk with the gaze at rest (`gaze`).
fn motions(
    args: &FlickerArgs,
    gaze: Vec2,
    scene: &foveate::scene::Scene,
    space: GazeSpace,
) -> Vec<Motion> {
    let seconds = args.frames as f64 / RATE_HZ;
    let head = |gazes: Vec<Vec2>| gazes.into_iter().map(|g| (scene.head, g)).collect();
    args.motions
        .iter()
        .map(|kind| match kind {
            MotionKind::Still => Motion {
                kind: *kind,
                frames: vec![(scene.head, gaze); args.frames as usize],
            },
            MotionKind::Saccades => Motion {
                kind: *kind,
                frames: head(
                    simulated_trace(seconds, RATE_HZ, args.seed)
                        .iter()
                        .map(|s| s.left)
                        .collect(),
                ),
            },
            MotionKind::LargeSaccades => Motion {
                kind: *kind,
                frames: head(large_saccade_trace(
                    space,
                    seconds,
                    RATE_HZ,
                    (15.0, 30.0),
                    args.seed,
                )),
            },
            MotionKind::Walking => Motion {
                kind: *kind,
                frames: (0..args.frames)
                    .map(|i| {
                        let t = i as f32 / RATE_HZ as f32;
                        (walking_pose(scene.head, t), gaze)
                    })
                    .collect(),
            },
        })
        .collect()
}

impl MotionKind {
    /// How the table's rows name it.
    fn name(self) -> &'static str {
        match self {
            MotionKind::Still => "still",
            MotionKind::Saccades => "saccades",
            MotionKind::LargeSaccades => "large saccades",
            MotionKind::Walking => "walking",
        }
    }
}

impl Motion {
    /// How the table's rows name it.
    fn name(&self) -> &'static str {
        self.kind.name()
    }

    /// How the header line names it.
    fn describe(&self, args: &FlickerArgs) -> String {
        match self.kind {
            MotionKind::Still => format!("still (head, gaze {})", self.resting_gaze()),
            MotionKind::Saccades => format!("saccades (seed {}, head still)", args.seed),
            MotionKind::LargeSaccades => {
                format!("large saccades (15–30°, seed {}, head still)", args.seed)
            }
            MotionKind::Walking => format!(
                "walking ({} m/s, turning {}°/s, gaze {})",
                foveate::scene::WALK_SPEED_M_S,
                foveate::scene::TURN_DEG_S,
                self.resting_gaze()
            ),
        }
    }

    /// Where the gaze rests (the still and walking motions keep their first frame's), as the
    /// header line says it.
    fn resting_gaze(&self) -> String {
        match self.frames.first().map(|&(_, gaze)| gaze) {
            Some(g) if g != Vec2::ZERO => format!("at ({}, {})", g.x, g.y),
            _ => "ahead".to_string(),
        }
    }
}

/// One configuration's flicker along a motion: measured on the GPU where the frames lie (the
/// default), or on frames read back, by the CPU measure (`--metric cpu`, its oracle).
enum Meter {
    Gpu(Box<GpuFlicker>),
    Cpu(Flicker),
}

impl Meter {
    fn new(gpu: &Gpu) -> Result<Self> {
        Ok(match crate::metric::chosen() {
            crate::metric::Metric::Gpu => Meter::Gpu(Box::new(GpuFlicker::new(gpu)?)),
            crate::metric::Metric::Cpu => Meter::Cpu(Flicker::default()),
        })
    }

    fn summary(&self) -> FlickerSummary {
        match self {
            Meter::Gpu(m) => m.summary(),
            Meter::Cpu(m) => m.summary(),
        }
    }
}

/// What measuring one motion needs: every configuration's renderer is made from these.
struct MotionRun<'a> {
    gpu: &'a Gpu,
    scene: &'a foveate::scene::Scene,
    /// The reference's plan, then each configuration's.
    plans: &'a [foveate::plan::FramePlan],
    configs: &'a [(String, RenderConfig)],
    /// The walker crossing the view, when there is one: every renderer moves it each frame.
    walker: Option<Walker>,
    /// Judge every Nth frame with eFLIP.
    flip: Option<u32>,
    bar: &'a indicatif::ProgressBar,
    spent: &'a Spent,
}

/// Where a run's wall time went: rendering the frames (and, with `--metric cpu`, reading them
/// back), mapping the regions at each new gaze (on the CPU), measuring flicker, judging with
/// eFLIP (and how many judgements).
#[derive(Default)]
struct Spent {
    rendering_s: Cell<f64>,
    maps_s: Cell<f64>,
    flicker_s: Cell<f64>,
    judging_s: Cell<f64>,
    judgements: Cell<u64>,
}

impl Spent {
    fn add(cell: &Cell<f64>, since: Instant) {
        cell.set(cell.get() + since.elapsed().as_secs_f64());
    }

    fn describe(&self) -> String {
        let judged = match self.judgements.get() {
            0 => String::new(),
            n => format!(
                ", judging {:.0} s ({n} judgements of both eyes, {:.2} s each)",
                self.judging_s.get(),
                self.judging_s.get() / n as f64
            ),
        };
        format!(
            "time: rendering {:.0} s, region maps {:.0} s, flicker {:.0} s{judged}",
            self.rendering_s.get(),
            self.maps_s.get(),
            self.flicker_s.get()
        )
    }
}

impl MotionRun<'_> {
    /// Every configuration along `motion`, frames interleaved with the reference's: one row
    /// each; `None` when interrupted.
    fn measure(&self, motion: &Motion) -> Result<Option<Vec<Row>>> {
        let mut rows = Vec::new();
        let (first_pose, first_gaze) = motion.frames[0];
        let mut renderers = Vec::new();
        for plan in self.plans {
            let mut renderer = Renderer::new(self.gpu, plan, self.scene)?;
            renderer.set_gaze([first_gaze; 2])?;
            if let Some(w) = self.walker {
                renderer.move_instance(w.instance, w.model(0.0))?;
            }
            settle(&mut renderer, first_pose)?;
            renderers.push(renderer);
        }
        let mut meters = (self.configs.iter())
            .map(|_| Meter::new(self.gpu))
            .collect::<Result<Vec<_>>>()?;
        let on_cpu = meters.iter().any(|m| matches!(m, Meter::Cpu(_)));
        let mut judged: Vec<Vec<Judged>> = self.configs.iter().map(|_| Vec::new()).collect();
        let mut history: Vec<Vec<HistoryOutcomes>> =
            self.configs.iter().map(|_| Vec::new()).collect();
        // Every renderer's frame times, the reference's first (counting renderers: none).
        let mut times: Vec<Vec<f64>> = renderers.iter().map(|_| Vec::new()).collect();
        // On the GPU both measures read the frames where they lie; on the CPU (`--metric cpu`)
        // every frame is read back.
        let mut in_place = GpuFlip::new(self.gpu);
        let mut on_host = crate::metric::flip_mapper(self.gpu);
        let mut maps = RegionMaps::default();
        for (frame, &(pose, gaze)) in motion.frames.iter().enumerate() {
            if crate::interrupt::requested() {
                return Ok(None);
            }
            // Frames of every configuration interleaved, the reference first; read back only
            // for the measures on the host.
            self.bar
                .set_message(format!("{}: rendering", motion.name()));
            let rendering = Instant::now();
            let judge_now = self.flip.is_some_and(|every| frame % every as usize == 0);
            let mut images = Vec::new();
            for (r, renderer) in renderers.iter_mut().enumerate() {
                renderer.set_gaze([gaze; 2])?;
                if let Some(w) = self.walker {
                    renderer.move_instance(w.instance, w.model(frame as f32 / RATE_HZ as f32))?;
                }
                let stats = renderer.render_frame(pose)?;
                if !renderer.plan().count_fragments() {
                    times[r].push(stats.frame_ms);
                }
                if let (Some(outcomes), Some(r)) = (stats.history, r.checked_sub(1)) {
                    history[r].push(outcomes);
                }
                if on_cpu {
                    images.push(renderer.readback()?);
                }
            }
            Spent::add(&self.spent.rendering_s, rendering);
            let mapping = Instant::now();
            maps.look_at(gaze, &self.plans[1..]);
            Spent::add(&self.spent.maps_s, mapping);
            for (i, meter) in meters.iter_mut().enumerate() {
                let pixels = maps.of(i);
                let measuring = Instant::now();
                match meter {
                    Meter::Gpu(m) => m.push(&renderers[0], &renderers[i + 1], pixels)?,
                    Meter::Cpu(m) => m.push(images[0].eyes(), images[i + 1].eyes(), pixels)?,
                }
                Spent::add(&self.spent.flicker_s, measuring);
                if judge_now {
                    self.bar.set_message(format!("{}: judging", motion.name()));
                    let judging = Instant::now();
                    let (reference, approximation) = (&renderers[0], &renderers[i + 1]);
                    let acuity = Acuity::default();
                    let error = match on_cpu {
                        false => in_place.frame_errors(
                            reference,
                            approximation,
                            pixels,
                            acuity,
                            Maps::Drop,
                        )?,
                        true => perceptual_error(
                            images[0].eyes(),
                            images[i + 1].eyes(),
                            pixels,
                            acuity,
                            &mut *on_host,
                            Maps::Drop,
                        )?,
                    };
                    Spent::add(&self.spent.judging_s, judging);
                    self.spent.judgements.set(self.spent.judgements.get() + 1);
                    judged[i].extend(error.eccentric.map(|all| (all, error.regions)));
                }
            }
            self.bar.inc(1);
        }
        let median = |t: &[f64]| Stats::of(t).map(|s| s.median);
        let reference_ms = median(&times[0]);
        let along = self.configs.iter().zip(&meters).zip(&judged).zip(history);
        for (i, ((((name, config), meter), frames), history)) in along.enumerate() {
            let frame_ms = median(&times[i + 1]);
            rows.push(Row {
                motion: motion.name(),
                name: name.clone(),
                foveated: config.foveation.is_some(),
                frame_ms,
                ratio: frame_ms.zip(reference_ms).map(|(t, r)| t / r),
                traffic_bytes: self.plans[i + 1].external_traffic_bytes(),
                flicker: meter.summary(),
                accuracy: AlongMotion::of(frames),
                history: (!history.is_empty()).then(|| OutcomesAlong {
                    motion: motion.name(),
                    config: name.clone(),
                    frames: history,
                }),
            });
        }
        Ok(Some(rows))
    }
}

/// The rows as CSV, to `path` or stdout.
fn write_csv(results: &[Row], path: Option<&std::path::Path>) -> Result<()> {
    let mut csv = CsvTable::new(&[
        "motion",
        "config",
        "frame_ms",
        "x_ref",
        "external_traffic_bytes",
        "changes",
        "flicker_mean",
        "flicker_p99",
        "flicker_mean_fovea",
        "flicker_mean_band",
        "flicker_mean_periphery",
        "eflip_mean",
        "eflip_p99",
        "eflip_p99_worst",
        "eflip_p99_fovea",
        "eflip_p99_band",
        "eflip_p99_periphery",
    ])?;
    for row in results {
        let (s, a) = (&row.flicker, row.accuracy);
        let mean = |e: Option<ErrorSummary>| opt(e.map(|e| e.mean), 6);
        csv.row(&[
            &row.motion,
            &row.name,
            &opt(row.frame_ms, 3),
            &opt(row.ratio, 4),
            &row.traffic_bytes,
            &s.changes,
            &mean(s.all),
            &opt(s.all.map(|e| e.p99), 6),
            &mean(s.regions[0]),
            &mean(s.regions[1]),
            &mean(s.regions[2]),
            &opt(a.map(|a| a.mean), 6),
            &opt(a.map(|a| a.p99), 6),
            &opt(a.map(|a| a.worst_p99), 6),
            &opt(a.and_then(|a| a.region_p99[0]), 6),
            &opt(a.and_then(|a| a.region_p99[1]), 6),
            &opt(a.and_then(|a| a.region_p99[2]), 6),
        ])?;
    }
    csv.save(path)
}

/// One configuration along one motion.
struct Row {
    motion: &'static str,
    name: String,
    flicker: FlickerSummary,
    accuracy: Option<AlongMotion>,
    /// What became of the history, frame by frame (`--history-outcomes`, accumulated rows).
    history: Option<OutcomesAlong>,
    foveated: bool,
    /// The median frame time along the motion, and over the reference's (counting rows: none).
    frame_ms: Option<f64>,
    ratio: Option<f64>,
    /// What a tile GPU would move per frame by the plan's rule (a formula, not a measurement).
    traffic_bytes: u64,
}

impl Row {
    /// The row as a point of its motion's frontier, when judged.
    fn point(&self) -> Option<MotionPoint> {
        let accuracy = self.accuracy?;
        Some(MotionPoint {
            name: self.name.clone(),
            foveated: self.foveated,
            frame_ms: self.frame_ms,
            ratio: self.ratio,
            eflip_mean: accuracy.mean,
            eflip_p99: accuracy.p99,
        })
    }
}

/// A judged frame's eccentricity-aware FLIP: over every pixel the lens shows, and per region
/// at the frame's gaze (`Region::ALL`'s order; none where the region has no pixel).
type Judged = (ErrorSummary, [Option<ErrorSummary>; 3]);

/// The eccentricity-aware FLIP of a configuration's frames along a motion: the means over the
/// frames of each frame's mean and 99th percentile, the largest 99th percentile, and the mean
/// of each region's 99th percentile over the frames where it has pixels (where the error is).
#[derive(Clone, Copy)]
struct AlongMotion {
    mean: f64,
    p99: f64,
    worst_p99: f64,
    region_p99: [Option<f64>; 3],
}

impl AlongMotion {
    /// `None` when no frame was judged.
    fn of(frames: &[Judged]) -> Option<Self> {
        let average = |values: Vec<f64>| {
            let n = values.len() as f64;
            (!values.is_empty()).then(|| values.iter().sum::<f64>() / n)
        };
        let region = |r: usize| {
            average(
                frames
                    .iter()
                    .filter_map(|f| f.1[r])
                    .map(|e| e.p99)
                    .collect(),
            )
        };
        (!frames.is_empty()).then(|| AlongMotion {
            mean: average(frames.iter().map(|f| f.0.mean).collect()).unwrap_or(0.0),
            p99: average(frames.iter().map(|f| f.0.p99).collect()).unwrap_or(0.0),
            worst_p99: frames.iter().map(|f| f.0.p99).fold(0.0, f64::max),
            region_p99: [0, 1, 2].map(region),
        })
    }
}

fn print_table(rows: &[Row]) {
    let width = super::name_column_width(rows.iter().map(|r| r.name.as_str()));
    let judged = rows.iter().any(|r| r.accuracy.is_some());
    let eflip = match judged {
        true => format!(
            " {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
            "eFLIP mean", "eFLIP p99", "worst p99", "p99 fovea", "p99 band", "p99 periph"
        ),
        false => String::new(),
    };
    println!(
        "\n{:<10} {:<width$} {:>9} {:>6} {:>7} {:>10} {:>8} {:>10} {:>10} {:>10}{eflip}",
        "motion",
        "configuration",
        "frame ms",
        "x ref",
        "MiB",
        "mean",
        "p99",
        "fovea",
        "band",
        "periphery"
    );
    let mean = |e: Option<ErrorSummary>| e.map_or("-".to_string(), |e| format!("{:.5}", e.mean));
    for row in rows {
        let s = &row.flicker;
        let eflip = match row.accuracy {
            Some(a) => {
                let region = |r: Option<f64>| r.map_or("-".to_string(), |p| format!("{p:.4}"));
                format!(
                    " {:>10.4} {:>10.4} {:>10.4} {:>10} {:>10} {:>10}",
                    a.mean,
                    a.p99,
                    a.worst_p99,
                    region(a.region_p99[0]),
                    region(a.region_p99[1]),
                    region(a.region_p99[2])
                )
            }
            None => String::new(),
        };
        let time =
            |t: Option<f64>, digits: usize| t.map_or("-".to_string(), |t| format!("{t:.digits$}"));
        println!(
            "{:<10} {:<width$} {:>9} {:>6} {:>7.1} {:>10} {:>8} {:>10} {:>10} {:>10}{eflip}",
            row.motion,
            row.name,
            time(row.frame_ms, 1),
            time(row.ratio, 3),
            mib(row.traffic_bytes),
            mean(s.all),
            s.all.map_or("-".to_string(), |e| format!("{:.4}", e.p99)),
            mean(s.regions[0]),
            mean(s.regions[1]),
            mean(s.regions[2]),
        );
    }
    let untimed = match rows.iter().any(|r| r.frame_ms.is_none()) {
        true => "; -: its frames count --history-outcomes, so they are no timing",
        false => "",
    };
    println!(
        "(time: the median frame time along the motion, every configuration's frames interleaved with the reference's (stereo, MSAA 4), none carrying an instrument; x ref: over the reference's median{untimed}; MiB: what a tile GPU moves per frame by the plan's rule, attachment loads and stores, sampling and readback, a formula as `foveate plan` prints it)"
    );
    println!(
        "(flicker: per pixel and frame, how much more the output's luma (0..1) changed from the previous frame than the reference's (stereo, MSAA 4) did — max(0, |ΔT| − |ΔR|) — over the pixels the lens shows, both eyes; mean and 99th percentile, then the mean per region at each frame's gaze (a stereo row's regions: where the first foveated row puts its fovea); metrics::temporal)"
    );
    if judged {
        println!(
            "(eFLIP: each frame against the reference's frame, the eccentricity-aware FLIP for the eye at that frame's gaze (metrics::flip); the mean over the frames of each frame's mean and 99th percentile, and the worst frame's 99th percentile; then each region's 99th percentile at the frame's gaze, its mean over the frames; a stereo row's regions: where the first foveated row puts its fovea)"
        );
    }
}
