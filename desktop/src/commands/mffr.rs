use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::metrics::perceptual::Maps;
use foveate::metrics::Acuity;
use foveate::metrics::RgbaImage;
use foveate::mffr::{MffrConfig, MffrVariant, SplitDistance};
use foveate::plan::RenderConfig;
use foveate::plan::SKY;
use foveate::scene::named_scene;
use glam::Vec2;

use crate::csv_out::CsvTable;
use crate::frame_args::ClusterArgs;
use crate::side_by_side::{sweep, Group};

#[derive(Args)]
pub struct MffrArgs {
    /// Screen resolution per eye: N (square), WxH or `native` (the headset's panel).
    #[arg(long, default_value = "1024")]
    res: String,
    /// Headset profile.
    #[arg(long, default_value = "index")]
    hmd: String,
    /// Scene: city (far-heavy), default or fill.
    #[arg(long, default_value = "city")]
    scene: String,
    /// Split distances: disparities (`1px`) or metres (`40m`).
    #[arg(long, value_delimiter = ',', default_value = "0.5px,1px,2px,4px")]
    splits: Vec<String>,
    /// Variants: far-first, near-first, alternate-eye, depth-shift.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "far-first,near-first,alternate-eye,depth-shift"
    )]
    variants: Vec<String>,
    /// MSAA samples.
    #[arg(long, default_value_t = 4)]
    msaa: u32,
    /// The far pass's MSAA samples to compare, each 1 or 4 (default: the frame's `--msaa`).
    #[arg(long, value_delimiter = ',')]
    far_msaa: Vec<u32>,
    /// The far image's pixel densities to compare, fractions of the eyes' in 0.25..=1 (default:
    /// the library's, 0.8).
    #[arg(long, value_delimiter = ',')]
    far_density: Vec<f32>,
    /// Frames per configuration, rendered in interleaved rounds (the first is a warm-up).
    #[arg(long, default_value_t = 6)]
    frames: u32,
    /// Also write the table as CSV to this file.
    #[arg(long)]
    csv: Option<PathBuf>,
    #[command(flatten)]
    clusters: ClusterArgs,
}

/// The sky's clear colour as the sRGB image stores it.
fn sky_srgb() -> [u8; 3] {
    let encode = |c: f32| {
        let s = if c <= 0.003_130_8 {
            12.92 * c
        } else {
            1.055 * c.powf(1.0 / 2.4) - 0.055
        };
        (s * 255.0).round() as u8
    };
    [encode(SKY[0]), encode(SKY[1]), encode(SKY[2])]
}

/// Pixels showing sky where the reference shows something else: cracks at the split.
fn sky_through(image: &RgbaImage, reference: &RgbaImage) -> u64 {
    let sky = sky_srgb();
    let is_sky = |p: [u8; 4]| (0..3).all(|i| p[i].abs_diff(sky[i]) <= 8);
    let mut n = 0;
    for y in 0..image.height {
        for x in 0..image.width {
            n += (is_sky(image.pixel(x, y)) && !is_sky(reference.pixel(x, y))) as u64;
        }
    }
    n
}

pub fn mffr(options: &GpuOptions, args: &MffrArgs) -> Result<()> {
    crate::outputs::files(&[args.csv.as_deref()])?;
    let scene = args.clusters.apply(named_scene(&args.scene)?)?;
    let gpu = Gpu::new(options)?;
    let base = RenderConfig {
        hmd: crate::frame_args::profile(&args.hmd)?.name.to_string(),
        resolution: Some(crate::frame_args::screen(&args.hmd, &args.res)?),
        msaa: args.msaa,
        lod: args.clusters.lod()?,
        ..RenderConfig::default()
    };
    println!(
        "device: {}; scene {} ({} instances), {}, MSAA {}x; each split's rows measured side by side, {} interleaved rounds",
        gpu.info().name,
        args.scene,
        scene.instance_count(),
        crate::frame_args::headset_line(&foveate::plan(&scene, &base, gpu.caps())?),
        args.msaa,
        args.frames
    );
    print_columns();
    let mut csv = mffr_csv()?;
    for split_text in &args.splits {
        let split: SplitDistance = split_text.parse()?;
        let configs = split_configs(args, &base, split)?;
        let label = format!("split {split}");
        let group = Group {
            scene: &scene,
            configs: &configs,
            gaze: Vec2::ZERO,
            rounds: args.frames,
            label: &label,
        };
        let judged = sweep(&gpu, &group, Acuity::default(), Maps::Drop)?.whole()?;
        let reference = &judged[0].measured;
        let reference_both = reference.image.side_by_side();
        for (i, j) in judged.iter().enumerate() {
            let row = VariantRow {
                index: i,
                judged: j,
                reference,
                reference_both: &reference_both,
                split_text,
            };
            row.report(&mut csv)?;
        }
        println!();
    }
    println!("(far×, dens: the far pass's MSAA samples and its pixel density as a fraction of the eyes'; ratio: frame time to the stereo row of the same split, measured in the same rounds; PSNR/SSIM, FLIP (mean) and eFLIP (the eccentricity-aware FLIP's 99th percentile, gaze ahead): both eyes against that stereo reference, over the pixels the lens shows; bound: the disparity error the variant allows at the split, in eye pixels; matched: pixels equal to a reference pixel at most `bound` away along the row; sky px: pixels showing sky where the reference does not — a crack at the split would show here, as do silhouettes moved by up to `bound`)");
    gpu.check_validation()?;
    csv.save(args.csv.as_deref())
}

/// The columns `mffr` prints.
fn print_columns() {
    println!(
        "\n{:<14} {:>9} {:>7} {:>4} {:>5} {:>9} {:>6} {:>8} {:>8} {:>10} {:>10} {:>10} {:>6} {:>6} {:>7} {:>7} {:>7} {:>8} {:>7}",
        "variant",
        "split",
        "disp px",
        "far×",
        "dens",
        "frame ms",
        "ratio",
        "far ms",
        "eyes ms",
        "far frags",
        "eye frags",
        "all frags",
        "PSNR",
        "SSIM",
        "FLIP",
        "eFLIP",
        "bound",
        "matched",
        "sky px"
    );
}

/// The CSV `mffr` writes, one row per variant and split.
fn mffr_csv() -> Result<CsvTable> {
    CsvTable::new(&[
        "variant",
        "split",
        "split_m",
        "disparity_px",
        "far_msaa",
        "far_density",
        "frame_ms",
        "ratio",
        "gpu_far_ms",
        "gpu_eyes_ms",
        "far_fragments",
        "eye_fragments",
        "total_fragments",
        "psnr",
        "ssim",
        "flip_mean",
        "eccentric_flip_p99",
        "bound_px",
        "matched_within_bound",
        "sky_through_px",
    ])
}

/// The configurations one split measures: stereo (the reference), aliased stereo (MSAA 1, the
/// accuracy a far field's settings are held to) when the frame has more samples, then each
/// variant at each far sample count and density asked for.
fn split_configs(
    args: &MffrArgs,
    base: &RenderConfig,
    split: SplitDistance,
) -> Result<Vec<RenderConfig>> {
    let far_msaa: Vec<Option<u32>> = match args.far_msaa.as_slice() {
        [] => vec![MffrConfig::default().far_msaa],
        m => m.iter().copied().map(Some).collect(),
    };
    let far_density = match args.far_density.as_slice() {
        [] => vec![MffrConfig::default().far_density],
        d => d.to_vec(),
    };
    let mut configs = vec![base.clone()];
    if base.msaa > 1 {
        configs.push(RenderConfig {
            msaa: 1,
            ..base.clone()
        });
    }
    for name in &args.variants {
        for &msaa in &far_msaa {
            for &density in &far_density {
                configs.push(RenderConfig {
                    mffr: Some(MffrConfig {
                        far_msaa: msaa,
                        far_density: density,
                        ..MffrConfig::named(name, split)?
                    }),
                    ..base.clone()
                });
            }
        }
    }
    Ok(configs)
}

/// One judged variant of a split, against that split's stereo reference.
struct VariantRow<'a> {
    index: usize,
    judged: &'a crate::side_by_side::Judged,
    reference: &'a crate::side_by_side::Measured,
    reference_both: &'a RgbaImage,
    split_text: &'a str,
}

impl VariantRow<'_> {
    /// Prints the row and adds it to `csv`: time, fragments, accuracy, the disparity bound and
    /// how much of the image holds within it, and sky showing through.
    fn report(&self, csv: &mut CsvTable) -> Result<()> {
        let (i, j, reference, reference_both) =
            (self.index, self.judged, self.reference, self.reference_both);
        let (m, plan, accuracy) = (&j.measured, &j.measured.plan, &j.accuracy);
        let image = m.image.side_by_side();
        let (name, split_m, disparity, bound) = match &plan.mffr {
            Some(g) => {
                let bound = match g.config.variant {
                    MffrVariant::AlternateEye => g.disparity_at_split_px,
                    _ => g.disparity_at_split_px / 2.0,
                };
                (g.config.name(), g.split_m, g.disparity_at_split_px, bound)
            }
            None if i == 0 => ("stereo", f32::NAN, f32::NAN, 0.0),
            None if plan.samples < reference.plan.samples => {
                ("stereo, MSAA 1", f32::NAN, f32::NAN, 0.0)
            }
            None => ("(no far field)", f32::NAN, f32::NAN, 0.0),
        };
        let (far_samples, far_density) = plan.mffr.map_or((0, f32::NAN), |g| {
            (
                g.config.far_msaa.unwrap_or(plan.samples),
                g.config.far_density,
            )
        });
        let psnr = accuracy.psnr.unwrap_or(f64::NAN);
        let ssim = accuracy.ssim.unwrap_or(f64::NAN);
        let e = &accuracy.perceptual;
        let (flip, eflip) = (
            e.flip.map_or(f64::NAN, |s| s.mean),
            e.eccentric.map_or(f64::NAN, |s| s.p99),
        );
        let radius = bound.ceil() as u32;
        let matched = m
            .image
            .left
            .matched_within(&reference.image.left, radius, 24)?
            * 0.5
            + m.image
                .right
                .matched_within(&reference.image.right, radius, 24)?
                * 0.5;
        let cracks = sky_through(&image, reference_both);
        let (far_ms, eyes_ms) = if plan.far_pass().is_some() {
            (m.gpu_pass_ms[0], m.gpu_pass_ms[1..].iter().sum::<f64>())
        } else {
            (0.0, m.gpu_pass_ms.iter().sum())
        };
        let ratio = m.frame_ms / reference.frame_ms;
        println!(
                "{:<14} {:>9} {:>7.2} {:>4} {:>5.2} {:>9.2} {:>6.3} {:>8.2} {:>8.2} {:>10} {:>10} {:>10} {:>6} {:>6.4} {:>7.4} {:>7.3} {:>7.2} {:>7.2}% {:>7}",
                name,
                if plan.mffr.is_none() { "-".to_string() } else { format!("{split_m:.1}m") },
                disparity,
                far_samples,
                far_density,
                m.frame_ms,
                ratio,
                far_ms,
                eyes_ms,
                m.far_fragments,
                m.eye_fragments,
                m.total_fragments,
                if psnr.is_infinite() { "inf".to_string() } else { format!("{psnr:.1}") },
                ssim,
                flip,
                eflip,
                bound,
                100.0 * matched,
                cracks
            );
        csv.row(&[
            &name,
            &self.split_text,
            &split_m,
            &disparity,
            &far_samples,
            &far_density,
            &format!("{:.3}", m.frame_ms),
            &format!("{ratio:.4}"),
            &format!("{far_ms:.3}"),
            &format!("{eyes_ms:.3}"),
            &m.far_fragments,
            &m.eye_fragments,
            &m.total_fragments,
            &format!("{psnr:.3}"),
            &format!("{ssim:.5}"),
            &format!("{flip:.5}"),
            &format!("{eflip:.5}"),
            &bound,
            &format!("{matched:.5}"),
            &cracks,
        ])?;
        Ok(())
    }
}
