//! What accuracy costs in time, across every approximation foveate has (DESIGN rule 2): each
//! one rendered at the same rails pose beside a full-quality reference (multiview, 4× MSAA,
//! per-eye culling, nothing approximated), in interleaved rounds; error over the pixels the
//! lens shows, time as the ratio to the reference measured in the same rounds.

use std::fmt::Write as _;

use anyhow::Result;
use foveate::cull::Strategy;
use foveate::foveation::FoveationConfig;
use foveate::gpu::Gpu;
use foveate::metrics::RgbaImage;
use foveate::mffr::MffrConfig;
use foveate::plan::{CullConfig, RadialDensity, RenderConfig};
use foveate::scene::Scene;
use foveate::view::{Eye, LensRegion};
use glam::Mat4;
use serde::Serialize;

use super::{BenchArgs, Settings, Toggles};
use crate::csv_out::CsvTable;
use crate::side_by_side::measure_group;

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
    for ratio in [0.25, 0.35, 0.5, 0.7] {
        let foveation = FoveationConfig {
            ratio,
            ..settings.foveation
        };
        out.push((
            "foveation",
            format!("foveation {ratio}"),
            with(&|c| {
                c.foveation = Some(foveation);
                c.views = 4;
            }),
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
    let measured = measure_group(
        gpu,
        &scene,
        &configs,
        args.accuracy_rounds.max(2),
        "accuracy sweep",
    )?;
    let plan = foveate::plan(&scene, &reference, gpu.caps())?;
    let lens = Eye::BOTH.map(|e| plan.hmd.lens_region(plan.eyes.fov(e)));
    let base = &measured[0];
    points
        .into_iter()
        .zip(&measured[1..])
        .map(|((family, name, _), m)| {
            let (psnr, ssim) = error(
                &lens,
                &m.image.left,
                &base.image.left,
                &m.image.right,
                &base.image.right,
            )?;
            Ok(AccuracyPoint {
                family,
                name,
                frame_ms: m.frame_ms,
                ratio: m.frame_ms / base.frame_ms,
                psnr_db: psnr.is_finite().then_some(psnr),
                ssim,
            })
        })
        .collect()
}

/// PSNR and SSIM of both eyes over the pixels wholly inside each eye's lens region.
fn error(
    lens: &[LensRegion; 2],
    left: &RgbaImage,
    left_ref: &RgbaImage,
    right: &RgbaImage,
    right_ref: &RgbaImage,
) -> Result<(f64, f64)> {
    let (w, h) = (left.width, left.height);
    let mut psnr = Vec::new();
    let mut ssim = Vec::new();
    for (eye, (a, b)) in [(left, left_ref), (right, right_ref)]
        .into_iter()
        .enumerate()
    {
        let visible = |x, y| lens[eye].contains_pixel(x, y, w, h);
        // SSIM's 8-pixel windows, by their centre: only those wholly inside the lens region.
        let window = |x: u32, y: u32| {
            [(0, 0), (8, 0), (0, 8), (8, 8)]
                .iter()
                .all(|&(dx, dy)| visible((x + dx).saturating_sub(4), (y + dy).saturating_sub(4)))
        };
        psnr.push(a.psnr_where(b, visible)?.unwrap_or(f64::INFINITY));
        ssim.push(a.ssim_where(b, window)?.unwrap_or(1.0));
    }
    // Mean squared error of both eyes together, back to dB.
    let mse: f64 = psnr.iter().map(|p| 10f64.powf(-p / 10.0)).sum::<f64>() / 2.0;
    Ok((-10.0 * mse.log10(), (ssim[0] + ssim[1]) / 2.0))
}

pub fn table(points: &[AccuracyPoint]) -> String {
    let mut t = String::from("## What accuracy costs in time\n\nEach approximation at one rails pose against the full-quality reference (multiview, 4x MSAA, per-eye culling), measured in interleaved rounds; PSNR and SSIM over the pixels the lens shows, both eyes.\n\n| family | approximation | frame ms | time vs reference | PSNR dB | SSIM |\n|---|---|---|---|---|---|\n");
    for p in points {
        let _ = writeln!(
            t,
            "| {} | {} | {:.2} | {:.3} | {} | {:.4} |",
            p.family,
            p.name,
            p.frame_ms,
            p.ratio,
            p.psnr_db.map_or("identical".into(), |d| format!("{d:.1}")),
            p.ssim
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
    ])?;
    for p in points {
        csv.row(&[
            &p.family,
            &p.name,
            &format!("{:.4}", p.frame_ms),
            &format!("{:.4}", p.ratio),
            &p.psnr_db.map_or("inf".into(), |d| format!("{d:.3}")),
            &format!("{:.5}", p.ssim),
        ])?;
    }
    csv.into_string()
}
