//! What accuracy costs in time, across every approximation foveate has (DESIGN rule 2): each
//! one rendered at the same rails pose beside a full-quality reference (multiview, 4× MSAA,
//! per-eye culling, nothing approximated), in interleaved rounds; error over the pixels the
//! lens shows (PSNR, SSIM, FLIP and the eccentricity-aware FLIP for the eye looking ahead), time
//! as the ratio to the reference measured in the same rounds.

use std::fmt::Write as _;

use anyhow::Result;
use foveate::cull::Strategy;
use foveate::foveation::FoveationConfig;
use foveate::gpu::Gpu;
use foveate::metrics::perceptual::Maps;
use foveate::metrics::Acuity;
use foveate::mffr::MffrConfig;
use foveate::plan::{CullConfig, RadialDensity, RenderConfig};
use foveate::scene::Scene;
use glam::{Mat4, Vec2};
use serde::Serialize;

use super::{BenchArgs, Settings, Toggles};
use crate::csv_out::CsvTable;
use crate::side_by_side;

/// One approximation: its time and its error against the reference.
#[derive(Clone, Debug, Serialize)]
pub struct AccuracyPoint {
    /// What is approximated: foveation, MSAA, stencil mask, MFFR, culling, combined.
    pub family: &'static str,
    pub name: String,
    pub frame_ms: f64,
    /// Frame time over the reference's, measured in the same rounds.
    pub ratio: f64,
    /// PSNR over the lens-visible pixels of both eyes; `None`: identical to the reference.
    pub psnr_db: Option<f64>,
    pub ssim: f64,
    /// FLIP's mean at the display's ppd, and the eccentricity-aware FLIP's mean and 99th
    /// percentile (`metrics::flip`), gaze ahead.
    pub flip_mean: f64,
    pub eccentric_flip_mean: f64,
    pub eccentric_flip_p99: f64,
}

/// The approximations swept, each as a change to the reference configuration.
fn points(
    settings: &Settings,
    reference: &RenderConfig,
) -> Vec<(&'static str, String, RenderConfig)> {
    let mut out = Vec::new();
    let with = |f: &dyn Fn(&mut RenderConfig)| {
        let mut c = reference.clone();
        f(&mut c);
        c
    };
    let foveated = |foveation: FoveationConfig| {
        with(&|c| {
            c.foveation = Some(foveation);
        })
    };
    for ratio in [0.25, 0.35, 0.5, 0.7] {
        let foveation = FoveationConfig {
            ratio,
            ..settings.foveation
        };
        out.push((
            "foveation",
            format!("foveation {ratio}"),
            foveated(foveation),
        ));
    }
    // The periphery's quality options, each priced at 0.35.
    let at_035 = FoveationConfig {
        ratio: 0.35,
        ..settings.foveation
    };
    // No band, and a wide one: a quarter of the fovea's diameter (twice the default).
    let fovea_px = at_035
        .geometry(settings.resolution)
        .map_or(0.0, |g| g.fovea_screen_px);
    for band in [0.0, (fovea_px / 4.0).floor()] {
        let foveation = FoveationConfig {
            blend_band_px: band,
            ..at_035
        };
        out.push((
            "blend band",
            format!("foveation 0.35, band {band} px"),
            foveated(foveation),
        ));
    }
    for sharpen in [0.5, 1.0] {
        let foveation = FoveationConfig {
            periphery_sharpen: sharpen,
            ..at_035
        };
        out.push((
            "sharpening",
            format!("foveation 0.35, sharpen {sharpen}"),
            foveated(foveation),
        ));
    }
    out.push(("MSAA", "MSAA 1x".into(), with(&|c| c.msaa = 1)));
    out.push((
        "radial density",
        "radial density masking".into(),
        with(&|c| c.radial_density = Some(RadialDensity::default())),
    ));
    out.push((
        "stencil mask",
        "HMD stencil mask".into(),
        with(&|c| c.hmd_mask = true),
    ));
    for split in ["1px", "2px", "4px"] {
        for (name, _, _) in MffrConfig::NAMED {
            let mffr = MffrConfig::named(name, split.parse().expect("a valid split"))
                .expect("a named variant");
            out.push((
                "MFFR",
                format!("MFFR {name} {split}"),
                with(&|c| c.mffr = Some(mffr)),
            ));
        }
    }
    for strategy in Strategy::ALL.into_iter().filter(|&s| s != Strategy::PerEye) {
        // Lens-region culling runs only under the HMD mask, which hides what it drops.
        let mask = strategy.culls_to_lens();
        out.push((
            "culling",
            format!(
                "culling {}{}",
                strategy.name(),
                if mask { " (with HMD mask)" } else { "" }
            ),
            with(&|c| {
                c.hmd_mask |= mask;
                c.culling = Some(CullConfig {
                    strategy,
                    draw_distance: settings.draw_distance,
                })
            }),
        ));
    }
    let all = Toggles {
        smask: true,
        sfrust: true,
        mview: true,
        mffr: true,
        foveate: true,
    };
    out.push(("combined", all.name(), settings.config(all)));
    out
}

/// Measures every approximation against the reference at the head pose `pose`.
pub fn sweep(
    gpu: &Gpu,
    scene: &Scene,
    settings: &Settings,
    pose: Mat4,
    args: &BenchArgs,
) -> Result<Vec<AccuracyPoint>> {
    let reference = RenderConfig {
        msaa: 4,
        ..settings.config(Toggles {
            mview: true,
            ..Toggles::default()
        })
    };
    let points = points(settings, &reference);
    let mut configs = vec![reference.clone()];
    configs.extend(points.iter().map(|(_, _, c)| c.clone()));
    let scene = Scene {
        head: pose,
        ..scene.clone()
    };
    let group = side_by_side::Group {
        scene: &scene,
        configs: &configs,
        gaze: Vec2::ZERO,
        rounds: args.accuracy_rounds.max(2),
        label: "accuracy sweep",
    };
    let judged = side_by_side::sweep(gpu, &group, Acuity::default(), Maps::Drop)?.whole()?;
    let base = &judged[0].measured;
    Ok(points
        .into_iter()
        .zip(&judged[1..])
        .map(|((family, name, _), j)| {
            let (m, a) = (&j.measured, &j.accuracy);
            let e = &a.perceptual;
            AccuracyPoint {
                family,
                name,
                frame_ms: m.frame_ms,
                ratio: m.frame_ms / base.frame_ms,
                psnr_db: a.psnr.filter(|p| p.is_finite()),
                ssim: a.ssim.unwrap_or(1.0),
                flip_mean: e.flip.map_or(0.0, |s| s.mean),
                eccentric_flip_mean: e.eccentric.map_or(0.0, |s| s.mean),
                eccentric_flip_p99: e.eccentric.map_or(0.0, |s| s.p99),
            }
        })
        .collect())
}

pub fn table(points: &[AccuracyPoint]) -> String {
    let mut t = String::from("## What accuracy costs in time\n\nEach approximation at one rails pose against the full-quality reference (multiview, 4x MSAA, per-eye culling), measured in interleaved rounds; over the pixels the lens shows, both eyes: PSNR, SSIM, FLIP (mean, at the display's ppd) and the eccentricity-aware FLIP (mean and 99th percentile, the eye looking ahead; see docs/what-the-eye-sees.md).\n\n| family | approximation | frame ms | time vs reference | PSNR dB | SSIM | FLIP | eFLIP | eFLIP p99 |\n|---|---|---|---|---|---|---|---|---|\n");
    for p in points {
        let _ = writeln!(
            t,
            "| {} | {} | {:.2} | {:.3} | {} | {:.4} | {:.4} | {:.4} | {:.3} |",
            p.family,
            p.name,
            p.frame_ms,
            p.ratio,
            p.psnr_db.map_or("identical".into(), |d| format!("{d:.1}")),
            p.ssim,
            p.flip_mean,
            p.eccentric_flip_mean,
            p.eccentric_flip_p99
        );
    }
    t
}

pub fn csv(points: &[AccuracyPoint]) -> Result<String> {
    let mut csv = CsvTable::new(&[
        "family",
        "approximation",
        "frame_ms",
        "ratio",
        "psnr_db",
        "ssim",
        "flip_mean",
        "eccentric_flip_mean",
        "eccentric_flip_p99",
    ])?;
    for p in points {
        csv.row(&[
            &p.family,
            &p.name,
            &format!("{:.4}", p.frame_ms),
            &format!("{:.4}", p.ratio),
            &p.psnr_db.map_or("inf".into(), |d| format!("{d:.3}")),
            &format!("{:.5}", p.ssim),
            &format!("{:.5}", p.flip_mean),
            &format!("{:.5}", p.eccentric_flip_mean),
            &format!("{:.5}", p.eccentric_flip_p99),
        ])?;
    }
    csv.into_string()
}
