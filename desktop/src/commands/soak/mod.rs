//! `foveate soak`: renderers kept rendering for minutes or hours, the way a headset app runs
//! them, with the process's resident memory and each configuration's frame time sampled
//! throughout; the run fails when memory grows beyond a bound after its warm-up. A driver that
//! leaks per frame (lavapipe 22.3 did, per lit scene pass) or a leak of foveate's own shows as
//! growth here long before a machine swaps.
//!
//! Every configuration renders through the public path an engine takes (`Renderer` over the
//! foveation layer), two frames in flight, one instance of the scene moving every frame, the
//! head swaying and, foveated, the gaze sweeping; the configurations take turns frame by frame,
//! so all of them are alive for the whole run.

mod curves;
mod log;
mod rounds;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use clap::Args;
use foveate::gpu::{Gpu, GpuOptions};

use self::log::{Limits, SoakLog};
use self::rounds::{SoakConfig, Soaked};

#[derive(Args)]
pub struct SoakArgs {
    /// The scene: a built-in name or a glTF file (`flat` configurations drop its materials,
    /// `lit` ones light a flat scene with the built-in palette).
    #[arg(long, default_value = "atrium")]
    pub scene: String,
    /// Headset profile (as `render --hmd`).
    #[arg(long, default_value = "index")]
    pub hmd: String,
    /// Per-eye resolution: N (square), WxH, or `native`.
    #[arg(long, default_value = "128")]
    pub res: String,
    /// MSAA samples on the scene passes: 1 or 4.
    #[arg(long, default_value_t = 4)]
    pub msaa: u32,
    /// The configurations, comma-separated, each alive for the whole run: `lit-stereo`,
    /// `lit-foveated`, `flat-stereo`, `flat-foveated` (foveated: the library's default
    /// foveation).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "lit-stereo,lit-foveated,flat-stereo,flat-foveated"
    )]
    pub configs: Vec<String>,
    /// Run this many frames of each configuration (the default: 300, unless --minutes).
    #[arg(long, conflicts_with = "minutes")]
    pub frames: Option<u64>,
    /// Run for this many minutes instead of a number of frames.
    #[arg(long)]
    pub minutes: Option<f64>,
    /// The warm-up, a percentage of the run: memory is judged against its level at the
    /// warm-up's end (pipelines, caches and the allocator's pools settle there).
    #[arg(long, default_value_t = 10.0)]
    pub warm_up: f64,
    /// The most resident memory may grow after the warm-up, in percent of its level then.
    #[arg(long, default_value_t = 5.0)]
    pub max_growth: f64,
    /// The most any configuration's frame time p99 may be over its median in a window after the
    /// warm-up (GPU time from timestamps); 0 reports it without failing on it.
    #[arg(long, default_value_t = 1.5)]
    pub max_p99: f64,
    /// Seconds per window: a line of progress and a CSV row per configuration each window.
    #[arg(long, default_value_t = 60.0)]
    pub window: f64,
    /// Write each window's figures as CSV: elapsed time, resident memory, each configuration's
    /// frames and frame time (median, p99).
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Draw the curves (resident memory, frame times) as `<PLOT>.png` and `<PLOT>.svg`.
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// The negative control: keep this many KiB per round of frames on purpose, a leak the run
    /// must catch.
    #[arg(long, hide = true, default_value_t = 0)]
    pub leak_kib_per_round: u64,
}

/// How long the run goes on.
#[derive(Clone, Copy)]
enum Length {
    Frames(u64),
    Time(Duration),
}

impl Length {
    /// Whether the run is over after `rounds` rounds begun `elapsed` ago.
    fn reached(self, rounds: u64, elapsed: Duration) -> bool {
        match self {
            Length::Frames(n) => rounds >= n,
            Length::Time(t) => elapsed >= t,
        }
    }

    /// How far into the run `rounds` at `elapsed` are, 0 to 1.
    fn progress(self, rounds: u64, elapsed: Duration) -> f64 {
        match self {
            Length::Frames(n) => rounds as f64 / n as f64,
            Length::Time(t) => elapsed.as_secs_f64() / t.as_secs_f64(),
        }
    }
}

/// The arguments checked before the device starts.
fn checked(args: &SoakArgs) -> Result<(Vec<SoakConfig>, Length, Limits)> {
    let configs = args
        .configs
        .iter()
        .map(|c| c.parse::<SoakConfig>())
        .collect::<Result<Vec<_>>>()?;
    anyhow::ensure!(
        !configs.is_empty(),
        "invalid configs = (none): at least one"
    );
    let length = match (args.frames, args.minutes) {
        (_, Some(m)) => {
            anyhow::ensure!(
                m.is_finite() && m > 0.0 && m <= 24.0 * 60.0,
                "invalid minutes = {m}: more than 0, at most a day (1440)"
            );
            Length::Time(Duration::from_secs_f64(m * 60.0))
        }
        (frames, None) => {
            let n = frames.unwrap_or(300);
            anyhow::ensure!(n >= 10, "invalid frames = {n}: at least 10");
            Length::Frames(n)
        }
    };
    let bounded = |name: &str, v: f64, lo: f64, hi: f64| {
        anyhow::ensure!(
            v.is_finite() && (lo..=hi).contains(&v),
            "invalid {name} = {v}: {lo} to {hi}"
        );
        Ok(v)
    };
    let limits = Limits {
        warm_up: bounded("warm-up", args.warm_up, 0.0, 90.0)? / 100.0,
        max_growth: bounded("max-growth", args.max_growth, 0.0, 1000.0)? / 100.0,
        max_p99: bounded("max-p99", args.max_p99, 0.0, 100.0)?,
        window: Duration::from_secs_f64(bounded("window", args.window, 0.1, 3600.0)?),
    };
    crate::frame_args::profile(&args.hmd)?;
    crate::frame_args::parse_res(&args.res)?;
    anyhow::ensure!(
        matches!(args.msaa, 1 | 4),
        "invalid msaa = {}: 1 or 4",
        args.msaa
    );
    crate::outputs::files(&[args.csv.as_deref()])?;
    if let Some(stem) = &args.plot {
        crate::outputs::plot(stem)?;
    }
    Ok((configs, length, limits))
}

pub fn soak(options: &GpuOptions, args: &SoakArgs) -> Result<()> {
    let (configs, length, limits) = checked(args)?;
    let scene = foveate::scene::named_scene(&args.scene)?;
    let gpu = Gpu::new(options)?;
    let mut soaked = configs
        .iter()
        .map(|&c| Soaked::new(&gpu, &scene, c, args))
        .collect::<Result<Vec<_>>>()?;
    println!("device: {}; driver: {}", gpu.info().name, gpu.info().driver);
    println!(
        "soak: {}, {} per eye on {}, MSAA {}x, two frames in flight, an instance moving; {}; memory judged after a {} % warm-up against +{} %, windows of {} s",
        args.scene,
        args.res,
        args.hmd,
        args.msaa,
        match length {
            Length::Frames(n) => format!("{n} frames of each configuration"),
            Length::Time(t) => format!("{} minutes", t.as_secs_f64() / 60.0),
        },
        args.warm_up,
        args.max_growth,
        args.window
    );
    crate::interrupt::install();
    let names: Vec<String> = soaked.iter().map(|s| s.config.to_string()).collect();
    let mut log = SoakLog::new(names, limits, options.validation);
    let failed = run(&gpu, &mut soaked, &mut log, length, args.leak_kib_per_round);
    for s in &mut soaked {
        s.finish()?;
    }
    drop(soaked);
    let validation = gpu.check_validation();
    let report = log.finish();
    println!("{report}");
    if let Some(csv) = &args.csv {
        report.csv()?.save(Some(csv))?;
    }
    if let Some(stem) = &args.plot {
        curves::draw(&report, stem).context("the soak's curves")?;
    }
    if let Some(e) = failed {
        return Err(crate::interrupt::stopped_by(
            Some(e),
            "the soak stopped early",
        ));
    }
    validation?;
    if crate::interrupt::requested() {
        return Err(crate::interrupt::stopped(
            "the soak's figures so far are above",
        ));
    }
    report.verdict()
}

/// Rounds of one frame of each configuration until the run's length or a signal; returns the
/// error that ended it early, if one did. `leak_kib` KiB are kept each round on purpose (the
/// negative control).
fn run(
    gpu: &Gpu,
    soaked: &mut [Soaked],
    log: &mut SoakLog,
    length: Length,
    leak_kib: u64,
) -> Option<anyhow::Error> {
    let mut kept: Vec<Vec<u8>> = Vec::new();
    let start = Instant::now();
    let mut rounds = 0;
    while !length.reached(rounds, start.elapsed()) && !crate::interrupt::requested() {
        let warming = length.progress(rounds, start.elapsed()) < log.limits().warm_up;
        let round = Instant::now();
        for (k, s) in soaked.iter_mut().enumerate() {
            match s.frame(rounds) {
                Ok(Some(ms)) => log.frame(k, ms),
                Ok(None) => {}
                Err(e) => return Some(e.context(format!("{} frame {rounds}", s.config))),
            }
        }
        if leak_kib > 0 {
            kept.push(vec![1u8; leak_kib as usize * 1024]);
        }
        let resident = match resident_bytes() {
            Ok(bytes) => bytes,
            Err(e) => return Some(e),
        };
        log.round(start.elapsed(), round.elapsed(), resident, warming);
        if let Some(line) = log.window_done(start.elapsed()) {
            println!("{line}");
            if let Err(e) = gpu.check_validation() {
                return Some(e.into());
            }
        }
        rounds += 1;
    }
    None
}

/// The process's resident memory (`VmRSS` in `/proc/self/status`), in bytes.
fn resident_bytes() -> Result<u64> {
    let status = std::fs::read_to_string("/proc/self/status")
        .context("reading resident memory from /proc/self/status (the soak needs Linux)")?;
    let kib = status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse::<u64>().ok())
        .context("no VmRSS line in /proc/self/status")?;
    Ok(kib * 1024)
}
