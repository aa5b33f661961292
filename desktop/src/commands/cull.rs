use std::path::PathBuf;
use std::time::Instant;

use anyhow::Result;
use clap::Args;
use foveate::cull::{batch_kernel, CullHierarchy, HierarchyParams, Strategy};
use foveate::measure::{hale_tables, rails_bench, RailsParams};
use foveate::scene::ThesisScene;
use foveate::view::{Eye, HmdProfile, LensRegion, DEFAULT_IPD_M};

use crate::csv_out::{opt, CsvTable};

#[derive(Args)]
pub struct CullBenchArgs {
    /// Size of the thesis scene: 1 is the full 711 × 22 × 711 (11.1 M instances).
    #[arg(long, default_value_t = 1.0)]
    scale: f32,
    /// Frames along the rails (spread over two rail loops).
    #[arg(long, default_value_t = 200)]
    frames: u64,
    /// Draw distance (thesis: 320).
    #[arg(long, default_value_t = 320.0)]
    draw_distance: f32,
    /// Headset profile for the eyes and lens regions.
    #[arg(long, default_value = "index")]
    hmd: String,
    /// Strategies, comma-separated: per-eye, superfrustum, dual-cone, dual-elliptical-cone, round-robin.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "per-eye,superfrustum,dual-cone,dual-elliptical-cone,round-robin"
    )]
    strategies: Vec<String>,
    /// Measure false positives and misses against the exact f64 reference every N frames (0: off).
    #[arg(long, default_value_t = 20)]
    reference_every: u64,
    /// Objects per side for the intersection tables (Hale: 64, i.e. 64³ objects).
    #[arg(long, default_value_t = 64)]
    micro_side: usize,
    /// Passes over the objects for the intersection tables (Hale: 10).
    #[arg(long, default_value_t = 10)]
    micro_passes: usize,
    /// Skip the intersection tables.
    #[arg(long)]
    skip_micro: bool,
    /// Skip the thesis-scene run.
    #[arg(long)]
    skip_scene: bool,
    /// Also write the tables as CSV to this file.
    #[arg(long)]
    csv: Option<PathBuf>,
}

fn strategy(name: &str) -> Result<Strategy> {
    Strategy::by_name(name).ok_or_else(|| {
        let names: Vec<_> = Strategy::ALL.iter().map(|s| s.name()).collect();
        anyhow::anyhow!("invalid strategies = {name}: one of {}", names.join(", "))
    })
}

pub fn cull_bench(args: &CullBenchArgs) -> Result<()> {
    crate::outputs::files(&[args.csv.as_deref()])?;
    let strategies = args
        .strategies
        .iter()
        .map(|s| strategy(s))
        .collect::<Result<Vec<_>>>()?;
    anyhow::ensure!(args.frames >= 1, "invalid frames = 0: at least 1");
    anyhow::ensure!(
        args.draw_distance.is_finite() && args.draw_distance > 0.0,
        "invalid draw_distance = {}: a finite distance > 0",
        args.draw_distance
    );
    let mut csv = CsvTable::new(&[
        "table",
        "name",
        "ns_per_test_or_ms_median",
        "ratio_or_p95",
        "visible_or_hits",
        "false_positive_rate",
        "miss_rate",
    ])?;
    println!(
        "cull-bench on {} threads (rayon), batch kernel: {}",
        rayon::current_num_threads(),
        batch_kernel()
    );

    if !args.skip_micro {
        micro_tables(args, &mut csv)?;
    }
    if !args.skip_scene {
        rails_table(args, &strategies, &mut csv)?;
    }
    csv.save(args.csv.as_deref())
}

/// Hale's intersection tests, timed in this run (Hale 2018, Tables 4.1–4.4 in form).
fn micro_tables(args: &CullBenchArgs, csv: &mut CsvTable) -> Result<()> {
    anyhow::ensure!(
        args.micro_side >= 2 && args.micro_passes >= 1,
        "invalid micro_side/micro_passes: at least 2 and 1"
    );
    let n = args.micro_side.pow(3);
    println!(
        "\nIntersection tests (Hale, Tables 4.1-4.4 in form): {n} objects x {} passes, one thread",
        args.micro_passes
    );
    println!(
        "{:<6} {:<52} {:>10} {:>9} {:>10} {:>8}",
        "table", "test", "total ms", "ns/test", "hits", "ratio"
    );
    for r in hale_tables(args.micro_side, args.micro_passes) {
        println!(
            "{:<6} {:<52} {:>10.2} {:>9.2} {:>10} {:>8.2}",
            r.table, r.name, r.total_ms, r.ns_per_test, r.hits, r.ratio
        );
        csv.row(&[
            &r.table,
            &r.name,
            &format!("{:.4}", r.ns_per_test),
            &format!("{:.4}", r.ratio),
            &r.hits,
            &"",
            &"",
        ])?;
    }
    println!("(ratio: time per test relative to sphere-frustum, this run)");
    Ok(())
}

/// Each strategy along the thesis scene's rails: time, what it keeps, and its errors against
/// the exact per-eye reference.
fn rails_table(args: &CullBenchArgs, strategies: &[Strategy], csv: &mut CsvTable) -> Result<()> {
    let hmd = HmdProfile::by_name(&args.hmd).ok_or_else(|| {
        anyhow::anyhow!(
            "invalid hmd = {}: one of {}",
            args.hmd,
            HmdProfile::names().join(", ")
        )
    })?;
    let eyes = hmd.eyes(DEFAULT_IPD_M);
    let regions = Eye::BOTH.map(|e| {
        LensRegion::with_hidden_fraction(eyes.fov(e), hmd.hidden_area_fraction.unwrap_or(0.0))
    });
    let t = Instant::now();
    let count = ThesisScene::instance_count(args.scale)?;
    eprintln!("generating the thesis scene ({count} instances) ...");
    let scene = ThesisScene::new(args.scale)?;
    let bounds = scene.bounds();
    let generated = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let hierarchy = CullHierarchy::build(&bounds, HierarchyParams::default());
    drop(bounds);
    println!(
        "\nThesis scene: {} instances (scale {}), generated in {generated:.1} s; {} chunks, hierarchy built in {:.1} s",
        scene.len(),
        args.scale,
        hierarchy.chunk_count(),
        t.elapsed().as_secs_f64()
    );
    let params = RailsParams {
        eyes: &eyes,
        lens_regions: &regions,
        frames: args.frames,
        draw_distance: args.draw_distance,
        near: 0.05,
        reference_every: args.reference_every,
        extent: scene.extent(),
    };
    let bar = crate::progress::bar("culling", 0);
    let reports = rails_bench(&hierarchy, strategies, &params, &mut |d, t| {
        bar.set_length(t);
        bar.set_position(d);
    });
    bar.finish_and_clear();
    let base = reports[0].time_ms.median;
    println!(
        "Stereo culling along the rails: {} frames, draw distance {}, {} ({})",
        args.frames, args.draw_distance, hmd.display_name, hmd.name
    );
    println!(
        "{:<22} {:>10} {:>8} {:>8} {:>11} {:>11} {:>12} {:>9} {:>9}",
        "strategy",
        "median ms",
        "p95 ms",
        "ratio",
        "visible",
        "node tests",
        "object tests",
        "false +",
        "misses"
    );
    let pct = |x: Option<f64>| x.map_or("n/a".to_string(), |v| format!("{:.2}%", v * 100.0));
    for r in &reports {
        println!(
            "{:<22} {:>10.3} {:>8.3} {:>8.2} {:>11.0} {:>11.0} {:>12.0} {:>9} {:>9}",
            r.strategy.name(),
            r.time_ms.median,
            r.time_ms.p95,
            r.time_ms.median / base,
            r.visible.median,
            r.node_tests.median,
            r.object_tests.median,
            pct(r.false_positive_rate),
            pct(r.miss_rate)
        );
        csv.row(&[
            &"rails",
            &r.strategy.name(),
            &format!("{:.4}", r.time_ms.median),
            &format!("{:.4}", r.time_ms.p95),
            &format!("{:.0}", r.visible.median),
            &opt(r.false_positive_rate, 6),
            &opt(r.miss_rate, 6),
        ])?;
    }
    println!(
        "(medians per frame; ratio to {}; false + and misses against the exact f64 per-eye reference on every {}th frame; dual-cone misses are objects only in the lens-hidden corners)",
        reports[0].strategy.name(),
        args.reference_every
    );
    Ok(())
}
