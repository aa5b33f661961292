use std::path::PathBuf;

use anyhow::Result;
use clap::Args;
use foveate::gpu::{Gpu, GpuOptions};
use foveate::metrics::perceptual::Maps;
use foveate::metrics::Acuity;
use foveate::plan::RenderConfig;
use foveate::scene::named_scene;
use foveate::view::HMD_PROFILES;
use glam::Vec2;

use crate::csv_out::CsvTable;
use crate::side_by_side::{sweep, Group};

#[derive(Args)]
pub struct MaskArgs {
    /// Screen resolution per eye: N (square), WxH or `native` (each headset's own panel).
    #[arg(long, default_value = "1024")]
    res: String,
    /// Scene: fill (fill-bound), default or city.
    #[arg(long, default_value = "fill")]
    scene: String,
    /// Frames per configuration, rendered in interleaved rounds (the first is a warm-up).
    #[arg(long, default_value_t = 6)]
    frames: u32,
    /// Also write the table as CSV to this file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

/// The fraction of both eyes the mask hides, measured by the coverage probe.
fn measured_hidden(gpu: &Gpu, config: &RenderConfig) -> Result<f64> {
    let shaded: u64 = crate::commands::pixels::coverage(gpu, config)?.iter().sum();
    let pixels = 2 * config.resolution.map_or(0, |r| r.pixels());
    Ok(1.0 - shaded as f64 / pixels as f64)
}

pub fn mask(options: &GpuOptions, args: &MaskArgs) -> Result<()> {
    crate::outputs::files(&[args.csv.as_deref()])?;
    let scene = named_scene(&args.scene)?;
    let gpu = Gpu::new(options)?;
    println!(
        "device: {}; scene {}, {} per eye, MSAA 4x; each profile's pair measured side by side, {} interleaved rounds",
        gpu.info().name,
        args.scene,
        args.res,
        args.frames
    );
    println!(
        "\n{:<10} {:>10} {:>9} {:>9} {:>10} {:>10} {:>8} {:>13} {:>12} {:>9}",
        "profile",
        "published",
        "analytic",
        "measured",
        "off ms",
        "on ms",
        "saved",
        "saved/masked",
        "visible PSNR",
        "eFLIP p99"
    );
    let mut csv = CsvTable::new(&[
        "profile",
        "published_hidden",
        "analytic_hidden",
        "measured_hidden",
        "off_ms",
        "on_ms",
        "saved",
        "saved_over_masked",
        "visible_psnr",
        "visible_eccentric_flip_p99",
    ])?;
    for profile in HMD_PROFILES {
        let off = RenderConfig {
            hmd: profile.name.into(),
            resolution: Some(crate::frame_args::screen(profile.name, &args.res)?),
            ..RenderConfig::default()
        };
        let on = RenderConfig {
            hmd_mask: true,
            ..off.clone()
        };
        let plan = foveate::plan(&scene, &on, gpu.caps())?;
        let lens = plan.hmd_mask.expect("planned with the mask");
        let analytic = lens[0].hidden_fraction();
        let hidden = measured_hidden(&gpu, &on)?;
        // The mask may cost no accuracy where the lens shows the image.
        let group = Group {
            scene: &scene,
            configs: &[off, on],
            gaze: Vec2::ZERO,
            rounds: args.frames,
            label: profile.name,
        };
        let judged = sweep(&gpu, &group, Acuity::default(), Maps::Drop)?.whole()?;
        let (m, accuracy) = (
            [&judged[0].measured, &judged[1].measured],
            &judged[1].accuracy,
        );
        let saved = 1.0 - m[1].frame_ms / m[0].frame_ms;
        let psnr = accuracy.psnr.unwrap_or(f64::NAN);
        let eflip = accuracy.perceptual.eccentric.map_or(f64::NAN, |s| s.p99);
        let published = profile
            .hidden_area_fraction
            .map_or("-".to_string(), |f| format!("{:.1} %", 100.0 * f));
        println!(
            "{:<10} {:>10} {:>7.1} % {:>7.1} % {:>10.2} {:>10.2} {:>6.1} % {:>13.2} {:>12} {:>9.4}",
            profile.name,
            published,
            100.0 * analytic,
            100.0 * hidden,
            m[0].frame_ms,
            m[1].frame_ms,
            100.0 * saved,
            saved / hidden,
            if psnr.is_infinite() {
                "inf".to_string()
            } else {
                format!("{psnr:.1}")
            },
            eflip
        );
        csv.row(&[
            &profile.name,
            &profile
                .hidden_area_fraction
                .map_or(String::new(), |f| f.to_string()),
            &format!("{analytic:.5}"),
            &format!("{hidden:.5}"),
            &format!("{:.3}", m[0].frame_ms),
            &format!("{:.3}", m[1].frame_ms),
            &format!("{saved:.5}"),
            &format!("{:.4}", saved / hidden),
            &psnr,
            &format!("{eflip:.5}"),
        ])?;
    }
    println!("(published: the hidden-area mesh's area where the headset's is on record, else the circular fallback; measured: the coverage probe; saved: frame time saved by the mask, visible PSNR and eFLIP p99 (the eccentricity-aware FLIP's 99th percentile, gaze ahead): both eyes' pixels the lens shows against the unmasked frame — inf and 0: the mask costs no accuracy)");
    gpu.check_validation()?;
    csv.save(args.csv.as_deref())
}
