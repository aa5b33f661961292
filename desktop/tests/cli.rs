//! The `foveate` command line as a user runs it (validation on).

use std::process::{Command, Output};

fn foveate(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_foveate"))
        .arg("--validation")
        .args(args)
        .output()
        .expect("run foveate")
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Reads a CSV the CLI wrote with a CSV parser: every record has the header's `columns` fields
/// (a field with an unquoted comma would add one), and every field but the first parses as a
/// number where it is not empty.
fn read_csv(
    path: &std::path::Path,
    columns: usize,
) -> Vec<std::collections::HashMap<String, String>> {
    let mut reader = csv::Reader::from_path(path).unwrap();
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    assert_eq!(header.len(), columns, "{header:?}");
    reader
        .records()
        .map(|r| {
            let r = r.unwrap_or_else(|e| panic!("{}: {e}", path.display()));
            assert_eq!(r.len(), columns, "{r:?}");
            header
                .iter()
                .cloned()
                .zip(r.iter().map(String::from))
                .collect()
        })
        .collect()
}

/// Every field of a record that is not text names a number (or is empty, or `inf`).
fn assert_numeric(row: &std::collections::HashMap<String, String>, text: &[&str]) {
    for (k, v) in row {
        if text.contains(&k.as_str()) || v.is_empty() {
            continue;
        }
        assert!(
            v.parse::<f64>().is_ok(),
            "{k} = {v:?} is not a number in {row:?}"
        );
    }
}

#[test]
fn render_writes_a_stereo_png_and_prints_plan_times_and_counts() {
    let out = std::env::temp_dir().join(format!("foveate-cli-{}.png", std::process::id()));
    let o = foveate(&[
        "render",
        "--res",
        "64",
        "--frames",
        "3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for needle in [
        "frame plan:",
        "frame time median",
        "no counters",
        "CPU cull",
        "draw calls",
        "triangles recorded",
        "fragments (a separate counting frame): scene",
        "scene (multiview) / scene: left eye",
        "right eye",
        "wrote",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
    let image = foveate::metrics::RgbaImage::load_png(&out).unwrap();
    assert_eq!(
        (image.width, image.height),
        (128, 64),
        "left | right at 64 per eye"
    );
    let _ = std::fs::remove_file(out);
}

#[test]
fn render_all_modes_prints_ratios_to_multiview() {
    let dir = std::env::temp_dir().join(format!("foveate-cli-all-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("f.png");
    let o = foveate(&[
        "render",
        "--stereo",
        "all",
        "--msaa",
        "1",
        "--res",
        "32",
        "--frames",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(text.contains("ratios to multiview"), "{text}");
    for mode in ["multiview", "two-pass", "per-object", "instanced"] {
        assert!(dir.join(format!("f-{mode}.png")).exists(), "{mode} image");
    }
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn plan_prints_passes_and_derived_ops() {
    let o = foveate(&[
        "plan", "--stereo", "two-pass", "--msaa", "4", "--res", "256",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for needle in [
        "scene (left eye)",
        "scene (right eye)",
        "load CLEAR, store DONT_CARE",
        "store STORE",
        "transient",
        "MiB",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
}

/// `plan --engine`: the frame a `FoveationLayer` records around an engine's draws, its scene
/// steps the engine's pipelines; what needs foveate's scene refused by name.
#[test]
fn plan_for_an_engine_says_whose_draws() {
    let o = foveate(&["plan", "--engine", "--foveate", "0.35", "--res", "128"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for needle in [
        "frame plan around an engine's draws",
        "scene pipeline: the engine's own",
        "mask fans",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
    assert!(!text.contains("scene.vert"), "{text}");
    let o = foveate(&["plan", "--engine", "--mffr", "near-first", "--res", "128"]);
    assert!(
        !o.status.success() && stderr(&o).contains("mffr = near-first"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn devices_lists_multiview_and_sample_counts() {
    let o = foveate(&["devices"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    assert!(
        text.contains("multiview: max") && text.contains("sample counts"),
        "{text}"
    );
}

#[test]
fn bad_input_is_a_clear_error_not_a_panic() {
    for (args, needle) in [
        (&["render", "--msaa", "8", "--res", "32"][..], "msaa = 8"),
        (&["render", "--views", "5", "--res", "32"][..], "views = 5"),
        (&["render", "--res", "0"][..], "resolution = 0x0"),
        (&["plan", "--hmd", "pimax"][..], "hmd = pimax"),
        (&["plan", "--stereo", "mono"][..], "stereo = mono"),
        (
            &["plan", "--output", "warped"][..],
            "output = warped: one of undistorted, lens",
        ),
        (
            &["plan", "--foveate", "0.35", "--fovea-layout", "three"][..],
            "fovea layout = three: one of auto, one-pass, two-pass",
        ),
        (
            &["plan", "--shading", "pbr"][..],
            "shading = pbr: one of flat, lit",
        ),
        (
            &["render", "--res", "32", "--reference"][..],
            "reference = true: compares a foveated frame",
        ),
        (
            &["render", "--frames", "0", "--res", "32"][..],
            "frames = 0",
        ),
        (
            &["render", "--res", "32", "--out", "/nonexistent-dir/f.png"][..],
            "cannot write /nonexistent-dir/f.png: its folder /nonexistent-dir does not exist",
        ),
        (
            &["plan", "--foveate", "0.35", "--sharpen", "1.5"][..],
            "periphery_sharpen = 1.5: 0 (off) ≤ sharpen ≤ 1",
        ),
        (
            &["compare", "--res", "32", "--sharpen", "0"][..],
            "sharpen = 0: 0 < sharpen ≤ 1",
        ),
        (
            &["compare", "--res", "32", "--sharpen", "2"][..],
            "periphery_sharpen = 2",
        ),
        (&["compare", "--recommend=-1"][..], "recommend = -1"),
        (
            &["compare", "--res", "32", "--price-device", "nothing"][..],
            "invalid price-device = nothing: no such device (devices: ",
        ),
        (
            &["price", "--res", "32", "--price-device", "0"][..],
            "is none of the tile GPUs foveate prices (Adreno 650, Adreno 740)",
        ),
        (
            &["price", "--frames", "0"][..],
            "invalid frames = 0: 1 to 1000",
        ),
        (
            &["price", "--stereo", "all"][..],
            "invalid stereo = all: price takes one stereo mode",
        ),
        (&["compare", "--mar-slope", "0"][..], "mar-slope = 0"),
        (
            &["compare", "--res", "32", "--bands", "40"][..],
            "blend_band = 40",
        ),
        (
            &["render", "--res", "32", "--scene", "/nonexistent/scene.glb"][..],
            "scene file /nonexistent/scene.glb: cannot read /nonexistent/scene.glb: No such file",
        ),
        (
            &["plan", "--scene", "pyramid"][..],
            "scene = pyramid: one of default, fill, city, thesis, atrium, or a .gltf or .glb file",
        ),
        (&["plan", "--head", "1,nan,2"][..], "head = [1.0, NaN, 2.0]"),
        (
            &["plan", "--head", "0,1,0", "--look-at", "0,5,0"][..],
            "look-at = [0, 5, 0]: a point away from the head",
        ),
        (
            &["plan", "--foveate", "0.35", "--ring", "0.6"][..],
            "invalid --ring = 0.6: it sets a parameter of single frames",
        ),
        (
            &[
                "plan",
                "--foveate",
                "0.35",
                "--single-frame",
                "--ring",
                "0.3",
            ][..],
            "ring_ratio = 0.3: 0.35 (the fovea's ratio) < ring ratio ≤ 1",
        ),
        (&["view", "--frames", "0"][..], "frames = 0"),
        (&["view", "--window", "0x10"][..], "window = \"0x10\""),
        (
            &["view", "--frames-in-flight", "5"][..],
            "frames-in-flight = 5: 1 to 4",
        ),
    ] {
        let o = foveate(args);
        assert!(!o.status.success(), "{args:?} should fail");
        let err = stderr(&o);
        assert!(err.contains(needle), "{args:?}: `{needle}` not in\n{err}");
        assert!(!err.contains("panicked"), "{args:?} panicked:\n{err}");
    }
}

#[test]
fn cull_bench_prints_both_tables_and_writes_csv() {
    let csv = std::env::temp_dir().join(format!("foveate-cull-{}.csv", std::process::id()));
    let o = foveate(&[
        "cull-bench",
        "--scale",
        "0.02",
        "--frames",
        "4",
        "--reference-every",
        "2",
        "--micro-side",
        "8",
        "--micro-passes",
        "1",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for needle in [
        "sphere-frustum (baseline)",
        "triangle-cone",
        "superfrustum",
        "dual-elliptical-cone",
        "round-robin",
        "false +",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
    let rows = read_csv(&csv, 7);
    assert!(rows.len() > 15);
    assert!(rows
        .iter()
        .any(|r| r["table"] == "rails" && r["name"] == "per-eye"));
    for r in &rows {
        assert_numeric(r, &["table", "name"]);
    }
    let _ = std::fs::remove_file(&csv);
}

#[test]
fn cull_bench_rejects_bad_input() {
    for (args, needle) in [
        (
            &["cull-bench", "--strategies", "octree"][..],
            "strategies = octree",
        ),
        (
            &["cull-bench", "--scale", "0", "--skip-micro"][..],
            "scale = 0",
        ),
        (
            &["cull-bench", "--draw-distance=-5", "--skip-micro"][..],
            "draw_distance = -5",
        ),
    ] {
        let o = foveate(args);
        assert!(!o.status.success(), "{args:?} should fail");
        assert!(
            stderr(&o).contains(needle),
            "{args:?}: `{needle}` not in {}",
            stderr(&o)
        );
    }
}

#[test]
fn pixels_prints_arms_three_tables_measured_beside_the_formula() {
    let csv = std::env::temp_dir().join(format!("foveate-pixels-{}.csv", std::process::id()));
    let o = foveate(&[
        "pixels",
        "--res",
        "128",
        "--rows",
        "90:0.7,64:0.5",
        "--fovea-size",
        "32",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_csv(&csv, 13);
    assert_eq!(rows.len(), 3 * 2);
    for r in &rows {
        assert_numeric(r, &[]);
    }
    let _ = std::fs::remove_file(&csv);
    let text = stdout(&o);
    for needle in [
        "Table 2",
        "Table 3",
        "Table 4",
        "fixed fovea 32x32",
        "stereo 128x128 x 2 views: 32768 measured, 32768 analytic",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
    let o = foveate(&["pixels", "--rows", "512"]);
    assert!(
        !o.status.success() && stderr(&o).contains("rows = 512"),
        "{}",
        stderr(&o)
    );
    let o = foveate(&["pixels", "--res", "128", "--rows", "64:1.5"]);
    assert!(
        !o.status.success() && stderr(&o).contains("ratio = 1.5"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn render_foveated_with_gaze_tint_and_the_fill_scene() {
    let out = std::env::temp_dir().join(format!("foveate-fov-{}.png", std::process::id()));
    let o = foveate(&[
        "render",
        "--scene",
        "fill",
        "--res",
        "64",
        "--frames",
        "2",
        "--foveate",
        "0.5",
        "--gaze",
        "-0.4,-0.3", // a leading minus is a number, not a flag
        "--tint",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for needle in [
        "fovea layout: two-pass",
        "scene (fovea views)",
        "GPU output (periphery accumulated, fovea over it, lens-distorted)",
        "right fovea",
        "scene (fovea views) / mask",
        "(periphery accumulated, fovea over it, lens-distorted) / output: left eye 4096, right eye 4096",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
    let image = foveate::metrics::RgbaImage::load_png(&out).unwrap();
    assert_eq!(
        (image.width, image.height),
        (128, 64),
        "composed at full resolution, both eyes"
    );
    let _ = std::fs::remove_file(out);
    for (args, needle) in [
        (
            &["render", "--res", "32", "--foveate", "0"][..],
            "ratio = 0",
        ),
        (
            &["render", "--res", "32", "--scene", "mars"][..],
            "scene = mars",
        ),
        (
            &["render", "--res", "32", "--foveate", "0.5", "--gaze", "0.1"][..],
            "invalid gaze",
        ),
    ] {
        let o = foveate(args);
        assert!(
            !o.status.success() && stderr(&o).contains(needle),
            "{args:?}: {}",
            stderr(&o)
        );
    }
}

#[test]
fn compare_prints_time_and_error_per_region() {
    let csv = std::env::temp_dir().join(format!("foveate-compare-{}.csv", std::process::id()));
    let heatmaps = std::env::temp_dir().join(format!("foveate-heat-{}", std::process::id()));
    let o = foveate(&[
        "compare",
        "--res",
        "64",
        "--frames",
        "2",
        "--ratios",
        "0.5",
        "--msaa",
        "4",
        "--gaze",
        "-0.2,0.1",
        "--radial-density",
        "--sharpen",
        "1",
        "--bands",
        "0",
        "--recommend",
        "0.5",
        "--heatmaps",
        heatmaps.to_str().unwrap(),
        "--csv",
        csv.to_str().unwrap(),
        // Without a path: the frontier printed, nothing plotted.
        "--pareto",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for needle in [
        "Pareto frontier (eFLIP p99 against frame time",
        "reference: stereo multiview, MSAA 4",
        "foveated 0.5, MSAA 4",
        // The library's default beside the single frames (mutation: the row left out).
        "foveated 0.5, periphery 0.6, temporal (the default), MSAA 4",
        "foveated 0.5, sharpen 1, MSAA 4",
        "foveated 0.5, band 0, MSAA 4",
        "fovea dB/SSIM",
        "perif. dB/SSIM",
        "p99 fov/band/perif",
        "iso-error, the cheapest within eFLIP p99 ≤ 0.5: ",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
    let heat = foveate::metrics::RgbaImage::load_png(&heatmaps.join("foveated-0.5-msaa-4.png"))
        .expect("a heat map per row");
    assert_eq!(
        (heat.width, heat.height),
        (128, 64),
        "both eyes side by side"
    );
    let _ = std::fs::remove_dir_all(&heatmaps);
    let rows = read_csv(&csv, 32);
    // Without a tile GPU to price on, the price columns are empty, never a made-up figure.
    let price_columns = [
        "price_ms",
        "price_ratio",
        "price_alu_ms",
        "price_memory_ms",
        "price_instructions",
    ];
    assert!(rows
        .iter()
        .all(|r| price_columns.iter().all(|c| r[*c].is_empty())));
    let row = rows
        .iter()
        .find(|r| r["config"] == "foveated 0.5, MSAA 4")
        .expect("foveated row");
    // Each foveated row's output pass timed on its own (with and without accumulation, rows
    // apart). Mutation: the column left empty, or filtered to a pass kind the frame lacks. A
    // column timed from another pass that exists (a scene pass) would pass: which pass it times
    // is read from the plan's pass kinds, not checked here.
    for r in rows.iter().filter(|r| r["config"].starts_with("foveated")) {
        let ms: f64 = r["output_pass_ms"].parse().unwrap_or(-1.0);
        assert!(ms > 0.0, "{r:?}");
    }
    // FLIP beside PSNR/SSIM: 0 for the reference's own twin, above 0 for the foveated frame.
    let stereo4 = rows
        .iter()
        .find(|r| r["config"] == "stereo, MSAA 4")
        .expect("stereo row");
    let flip =
        |r: &std::collections::HashMap<String, String>, k: &str| -> f64 { r[k].parse().unwrap() };
    assert_eq!(flip(stereo4, "flip_mean"), 0.0, "{stereo4:?}");
    // A stereo row is judged region by region where the foveated rows put the fovea (a stereo
    // row placed by its own foveation, a mutation, has no fovea and an empty cell here).
    for key in [
        "psnr_fovea",
        "eccentric_flip_p99_fovea",
        "eccentric_flip_p99_band",
    ] {
        assert!(!stereo4[key].is_empty(), "{key} empty in {stereo4:?}");
    }
    assert!(flip(row, "flip_mean") > 0.0 && flip(row, "eccentric_flip_p99") > 0.0);
    // Radial density masking is priced like every other approximation.
    let masked = rows
        .iter()
        .find(|r| r["config"] == "radial density, MSAA 4")
        .expect("radial density row");
    let psnr: f64 = masked["psnr_periphery"].parse().unwrap();
    assert!(psnr.is_finite() && psnr > 20.0, "{masked:?}");
    // The fovea maps 1:1 and matches the reference there.
    let fovea_psnr: f64 = row["psnr_fovea"].parse().unwrap();
    assert!(fovea_psnr > 40.0, "{row:?}");
    for r in &rows {
        assert_numeric(r, &["config"]);
    }
    // Composition is counted: all passes shade more than the scene draws alone.
    let count = |k: &str| row[k].parse::<u64>().unwrap();
    assert!(
        count("total_fragments") >= count("scene_fragments") + 2 * 64 * 64,
        "{row:?}"
    );
    let _ = std::fs::remove_file(&csv);
    // The foveation table: stereo, then each ratio in both layouts, ratios to stereo.
    let o = foveate(&[
        "compare",
        "--table",
        "--res",
        "48",
        "--frames",
        "1",
        "--scenes",
        "fill",
        "--shadings",
        "flat,lit",
        "--ratios",
        "0.5",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_csv(&csv, 10);
    let names: Vec<(&str, &str)> = rows
        .iter()
        .map(|r| (r["shading"].as_str(), r["row"].as_str()))
        .collect();
    assert_eq!(
        names,
        [
            ("flat", "stereo"),
            ("flat", "foveated 0.5 one-pass"),
            ("flat", "foveated 0.5 two-pass"),
            ("lit", "stereo"),
            ("lit", "foveated 0.5 one-pass"),
            ("lit", "foveated 0.5 two-pass"),
        ]
    );
    assert_eq!(rows[0]["ratio_to_stereo"], "1.0000");
    assert!(rows.iter().any(|r| r["auto_pick"] == "true"));
    assert!(
        rows[2]["gpu_ms_per_pass"].contains("fovea"),
        "{:?}",
        rows[2]
    );
    let _ = std::fs::remove_file(&csv);
    let o = foveate(&["compare", "--res", "64", "--gaze", "2"]);
    assert!(
        !o.status.success() && stderr(&o).contains("invalid gaze"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn render_follows_a_gaze_trace_and_survives_bad_samples() {
    let dir = std::env::temp_dir().join(format!("foveate-trace-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let trace = dir.join("trace.csv");
    std::fs::write(&trace, "time,lx,ly,rx,ry,valid\n0,0.5,0.2,0.5,0.2,1\n0.011,NaN,0,0,0,1\n0.022,9,9,9,9,1\n0.033,0,0,0,0,0\n0.044,0.1,0.1,0.1,0.1,1\n").unwrap();
    let out = dir.join("f.png");
    for source in [trace.to_str().unwrap(), "sim"] {
        let o = foveate(&[
            "render",
            "--res",
            "48",
            "--frames",
            "5",
            "--foveate",
            "0.5",
            "--gaze-trace",
            source,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{source}: {}", stderr(&o));
    }
    let o = foveate(&[
        "render",
        "--res",
        "48",
        "--foveate",
        "0.5",
        "--gaze-trace",
        dir.join("missing.csv").to_str().unwrap(),
    ]);
    assert!(
        !o.status.success() && stderr(&o).contains("missing.csv"),
        "{}",
        stderr(&o)
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn mffr_prices_every_variant_against_stereo() {
    let csv = std::env::temp_dir().join(format!("foveate-mffr-{}.csv", std::process::id()));
    let o = foveate(&[
        "mffr",
        "--res",
        "48",
        "--frames",
        "2",
        "--splits",
        "2px,40m",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_csv(&csv, 20);
    assert_eq!(
        rows.len(),
        2 * 6,
        "stereo, aliased stereo and four variants per split"
    );
    for r in &rows {
        assert_numeric(r, &["variant", "split"]);
    }
    assert_eq!(
        rows[1]["variant"], "stereo, MSAA 1",
        "the accuracy yardstick"
    );
    assert_eq!(
        rows[2]["far_density"], "0.8",
        "without --far-density, the library's default"
    );
    let _ = std::fs::remove_file(&csv);
    let text = stdout(&o);
    for needle in [
        "stereo",
        "far-first",
        "near-first",
        "alternate-eye",
        "depth-shift",
        "matched",
        "40.0m",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
    let o = foveate(&[
        "mffr",
        "--res",
        "48",
        "--frames",
        "2",
        "--splits",
        "2px",
        "--variants",
        "near-first",
        "--far-msaa",
        "4,1",
        "--far-density",
        "1,0.5",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_csv(&csv, 20);
    let far: Vec<(&str, &str)> = rows[2..]
        .iter()
        .map(|r| (r["far_msaa"].as_str(), r["far_density"].as_str()))
        .collect();
    assert_eq!(
        far,
        [("4", "1"), ("4", "0.5"), ("1", "1"), ("1", "0.5")],
        "one row per far pass's samples and density"
    );
    let _ = std::fs::remove_file(&csv);
    let o = foveate(&["mffr", "--res", "48", "--frames", "2", "--splits", "0px"]);
    assert!(
        !o.status.success() && stderr(&o).contains("mffr split"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn mask_reports_each_profile_measured() {
    let csv = std::env::temp_dir().join(format!("foveate-mask-{}.csv", std::process::id()));
    let o = foveate(&[
        "mask",
        "--res",
        "32",
        "--frames",
        "2",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_csv(&csv, 10);
    assert_eq!(
        rows.len(),
        foveate::view::HMD_PROFILES.len(),
        "one row per profile"
    );
    for r in &rows {
        assert_numeric(r, &["profile"]);
    }
    let _ = std::fs::remove_file(&csv);
    let text = stdout(&o);
    for needle in ["index", "vive", "rift-cv1", "quest2", "saved/masked"] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
}

#[test]
fn bench_runs_the_whole_matrix_on_a_tiny_scene_and_writes_every_output() {
    let dir = std::env::temp_dir().join(format!("foveate-cli-bench-{}", std::process::id()));
    let json = dir.join("copy.json");
    let o = foveate(&[
        "bench",
        "--scale",
        "tiny",
        "--res",
        "48",
        "--frames",
        "2",
        "--warmup",
        "1",
        "--pixels-every",
        "1",
        "--accuracy-rounds",
        "2",
        "--foveation-res",
        "32",
        "--foveation-frames",
        "1",
        "--out",
        dir.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for needle in [
        "Table 6.1 form",
        "Table 6.2 form",
        "Table 6.3 in form",
        "| SMASK & SFRUST & MVIEW & MFFR |",
        "| SMASK & SFRUST & MVIEW & MFFR & FOV |",
        "| MFFR off (split past far) |",
        "nothing: planned exactly as the baseline",
        "What accuracy costs in time",
        "Best configuration:",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
    for file in [
        "tables.md",
        "frames.csv",
        "summary.csv",
        "accuracy.csv",
        "bench.json",
        "rails.png",
        "rails.svg",
        "rails-compare.png",
        "ratios.svg",
        "accuracy.png",
        "accuracy.svg",
        "foveation-table.md",
        "foveation-table.csv",
    ] {
        let path = dir.join(file);
        assert!(
            std::fs::metadata(&path).is_ok_and(|m| m.len() > 0),
            "{file}"
        );
    }
    // 24 matrix rows and 2 zero-cost rows, 2 frames each, every frame's pixels counted.
    let frames = read_csv(&dir.join("frames.csv"), 11);
    assert_eq!(frames.len(), 26 * 2);
    for (file, columns) in [("frames.csv", 11), ("summary.csv", 20), ("accuracy.csv", 9)] {
        for r in read_csv(&dir.join(file), columns) {
            assert_numeric(&r, &["config", "family", "approximation"]);
        }
    }
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let rows = report["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 26);
    assert_eq!(rows[0]["ratio_median"].as_f64(), Some(1.0));
    let row = |name: &str| {
        rows.iter()
            .find(|r| r["name"] == name)
            .unwrap_or_else(|| panic!("no row {name}"))
    };
    let median = |r: &serde_json::Value, key: &str| r[key]["median"].as_f64().unwrap();
    for r in rows {
        assert!(median(r, "frame_ms") > 0.0);
        assert!(median(r, "pixels") > 0.0);
        assert!(median(r, "total_pixels") >= median(r, "pixels"));
        assert!(median(r, "draw_calls") > 0.0);
        let name = r["name"].as_str().unwrap();
        // Foveation shades fewer scene fragments than its stereo twin, and pays for its
        // composition: every one of its output pixels is a counted fragment.
        if let Some(twin) = name.strip_suffix(" & FOV") {
            let twin = row(twin);
            assert!(median(r, "pixels") < median(twin, "pixels"), "{name}");
            assert!(
                median(r, "total_pixels") >= median(r, "pixels") + 2.0 * 48.0 * 48.0,
                "{name}: the composite is counted"
            );
        }
        // MFFR draws the far field once, in its far pass: the eye passes draw fewer triangles
        // than the twin's, and the far pass draws some. (Total triangles may not drop: objects
        // straddling the split are drawn on both sides.)
        let parts: Vec<&str> = name.split(" & ").collect();
        if parts.contains(&"MFFR") {
            let twin: Vec<&str> = parts.into_iter().filter(|&p| p != "MFFR").collect();
            let twin = row(&if twin.is_empty() {
                "baseline".to_string()
            } else {
                twin.join(" & ")
            });
            let far = median(r, "far_triangles");
            assert!(far > 0.0, "{name}: the far pass draws");
            assert!(
                median(r, "triangles") - far < median(twin, "triangles"),
                "{name}: eye passes {} vs {}",
                median(r, "triangles") - far,
                median(twin, "triangles")
            );
            assert_eq!(median(twin, "far_triangles"), 0.0);
        }
    }
    // The baseline again: the same work exactly, and a time within noise of the baseline.
    let (base, again) = (row("baseline"), row("baseline again (noise)"));
    for key in ["draw_calls", "triangles", "pixels", "total_pixels"] {
        assert_eq!(median(base, key), median(again, key), "{key}");
    }
    // Two frames of a 48-pixel frame under a parallel test run are noisy (0.24x seen): only a
    // gross difference, an order of magnitude, says something here.
    let noise = median(again, "frame_ms") / median(base, "frame_ms");
    assert!(
        (0.1..10.0).contains(&noise),
        "baseline again at {noise:.2}x"
    );
    let last = &rows[25];
    assert_eq!(last["memory"]["plan_is_baseline"], true);
    assert_eq!(
        last["memory"]["allocated_bytes"],
        rows[0]["memory"]["allocated_bytes"]
    );
    let _ = std::fs::remove_dir_all(dir);
}

#[test]
fn bench_rejects_a_bad_scale_naming_the_field() {
    let o = foveate(&["bench", "--scale", "2"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("scale"), "{}", stderr(&o));
}

/// A small `flicker` run: the flat scene at 48², four frames a motion, foveated 0.5 with its
/// accumulated twin.
const SMALL_FLICKER: [&str; 10] = [
    "flicker",
    "--scene",
    "default",
    "--res",
    "48",
    "--frames",
    "4",
    "--ratios",
    "0.5",
    "--temporal",
];

#[test]
fn flicker_measures_each_approximation_along_every_motion() {
    let csv = std::env::temp_dir().join(format!("foveate-flicker-{}.csv", std::process::id()));
    let mut args = SMALL_FLICKER.to_vec();
    args.extend([
        "--temporal-msaa",
        "1,4",
        "--flip",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    let o = foveate(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_csv(&csv, 17);
    // Four motions × (stereo MSAA 1, foveated 0.5, and accumulated at 1× and 4×), three
    // changes each.
    assert_eq!(rows.len(), 16, "{rows:?}");
    let motions: Vec<&str> = rows
        .iter()
        .step_by(4)
        .map(|r| r["motion"].as_str())
        .collect();
    assert_eq!(motions, ["still", "saccades", "large saccades", "walking"]);
    for r in &rows {
        assert_numeric(r, &["motion", "config"]);
        assert_eq!(r["changes"], "3");
        // Each row's time beside its error, as a ratio to the reference's in the same run.
        assert!(r["frame_ms"].parse::<f64>().unwrap() > 0.0, "{r:?}");
        assert!(r["x_ref"].parse::<f64>().unwrap() > 0.0, "{r:?}");
    }
    let at = |motion: &str, config: &str, column: &str| -> f64 {
        let r = rows
            .iter()
            .find(|r| r["motion"] == motion && r["config"] == config)
            .unwrap_or_else(|| panic!("no row {motion}, {config}: {rows:?}"));
        r[column].parse().unwrap()
    };
    // The stereo frame does not depend on the gaze: with the head still it cannot flicker;
    // with nothing moving, neither can a single-frame periphery (the accumulated one may:
    // its jitter).
    assert_eq!(at("saccades", "stereo, MSAA 1", "flicker_mean"), 0.0);
    assert_eq!(at("still", "foveated 0.5, MSAA 4", "flicker_mean"), 0.0);
    assert!(at("saccades", "foveated 0.5, MSAA 4", "flicker_mean") > 0.0);
    // The bytes beside the time: what each plan moves (a formula), the accumulated history
    // on top of the single-frame periphery's.
    let bytes = |config: &str| at("walking", config, "external_traffic_bytes");
    assert!(bytes("stereo, MSAA 1") > 0.0);
    assert!(bytes("foveated 0.5, temporal, MSAA 4") > bytes("foveated 0.5, MSAA 4"));
    // A 4× periphery's samples and depth stay on tile: it moves no more than at 1×.
    assert!(
        bytes("foveated 0.5, temporal at 4x, MSAA 4") <= bytes("foveated 0.5, temporal, MSAA 4")
    );
    // Every row is judged frame by frame; none equals the reference.
    for r in &rows {
        let name = r["config"].as_str();
        assert!(at(r["motion"].as_str(), name, "eflip_mean") > 0.0, "{r:?}");
        assert!(
            at(r["motion"].as_str(), name, "eflip_p99_worst")
                >= at(r["motion"].as_str(), name, "eflip_p99")
        );
    }
    assert!(rows
        .iter()
        .any(|r| r["config"] == "foveated 0.5, temporal, MSAA 4"));
    // Per region, every row: a stereo frame's regions are where the foveated row puts its
    // fovea, so its error there stands beside the foveated rows'.
    for r in &rows {
        let regions = ["fovea", "band", "periphery"].map(|g| &r[&format!("eflip_p99_{g}")]);
        assert!(regions.iter().all(|v| !v.is_empty()), "{r:?}");
    }
    // A walker crossing the view, moved in every renderer each frame.
    let o = foveate(&[
        "flicker",
        "--scene",
        "atrium",
        "--res",
        "48",
        "--frames",
        "4",
        "--ratios",
        "0.5",
        "--motions",
        "still",
        "--walker",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(
        stdout(&o).contains("with a walker crossing"),
        "{}",
        stdout(&o)
    );
    assert_eq!(read_csv(&csv, 17).len(), 2);
    // The gaze at rest moves the fovea of the still frames, and the judge's eye with it.
    let still_at = |gaze: &str| {
        let mut args = SMALL_FLICKER.to_vec();
        args.extend(["--motions", "still", "--flip", "--gaze", gaze]);
        args.extend(["--csv", csv.to_str().unwrap()]);
        let o = foveate(&args);
        assert!(o.status.success(), "{}", stderr(&o));
        let row = read_csv(&csv, 17).remove(1);
        assert_eq!(row["config"], "foveated 0.5, MSAA 4");
        (stdout(&o), row["eflip_mean"].parse::<f64>().unwrap())
    };
    let ((ahead, centred), (aside, moved)) = (still_at("0,0"), still_at("0.3,-0.2"));
    assert!(ahead.contains("still (head, gaze ahead)"), "{ahead}");
    assert!(
        aside.contains("still (head, gaze at (0.3, -0.2))"),
        "{aside}"
    );
    assert_ne!(centred, moved, "the gaze changed nothing");
    let _ = std::fs::remove_file(&csv);
    let o = foveate(&["flicker", "--frames", "1"]);
    assert!(
        !o.status.success() && stderr(&o).contains("frames = 1"),
        "{}",
        stderr(&o)
    );
}

/// `flicker --fovea-msaa 1,4` measures each foveated row at both of its fovea's sample counts,
/// the accumulated ones too: the aliased fovea is judged worse there than the 4× one, and so is
/// aliased stereo judged where the fovea lies. A count the frame is not built for is an error
/// naming the option and the value. Mutation runs: the count ignored (every row at 4×) makes
/// the two rows equal (0.016022 both) and fails; a stereo row placed by its own (absent) fovea
/// has no fovea figure and fails.
#[test]
fn flicker_measures_the_fovea_at_each_sample_count() {
    let csv = std::env::temp_dir().join(format!("foveate-fovea-msaa-{}.csv", std::process::id()));
    let mut args = SMALL_FLICKER.to_vec();
    args.extend(["--motions", "still", "--fovea-msaa", "1,4", "--flip"]);
    args.extend(["--csv", csv.to_str().unwrap()]);
    let o = foveate(&args);
    assert!(o.status.success(), "{}", stderr(&o));
    let rows = read_csv(&csv, 17);
    let _ = std::fs::remove_file(&csv);
    let configs: Vec<&str> = rows.iter().map(|r| r["config"].as_str()).collect();
    assert_eq!(
        configs,
        [
            "stereo, MSAA 1",
            "foveated 0.5, MSAA 1",
            "foveated 0.5, MSAA 4",
            "foveated 0.5, temporal, MSAA 1",
            "foveated 0.5, temporal, MSAA 4"
        ]
    );
    let fovea_p99 = |config: &str| -> f64 {
        let r = rows.iter().find(|r| r["config"] == config).unwrap();
        r["eflip_p99_fovea"].parse().unwrap()
    };
    for row in ["foveated 0.5", "foveated 0.5, temporal"] {
        let (aliased, multisampled) = (
            fovea_p99(&format!("{row}, MSAA 1")),
            fovea_p99(&format!("{row}, MSAA 4")),
        );
        assert!(
            aliased > multisampled,
            "{row}: {aliased} against {multisampled}"
        );
        // Aliased stereo, judged where the fovea lies, is as far from the reference there.
        let stereo = fovea_p99("stereo, MSAA 1");
        assert!(
            stereo > multisampled,
            "{row}: stereo {stereo} against {multisampled}"
        );
    }
    let o = foveate(&["flicker", "--fovea-msaa", "4,2"]);
    assert!(
        !o.status.success() && stderr(&o).contains("fovea-msaa = 2"),
        "{}",
        stderr(&o)
    );
}

/// `flicker --history-outcomes` counts every frame's history outcomes for the accumulated rows
/// (a CSV row per motion, configuration, frame and outcome) and `--pareto` plots each motion's
/// frontier (the counting row untimed, and said so) to a file of its own, even when the stem
/// holds a dot; `--pareto` without `--flip` is an error naming both.
#[test]
fn flicker_counts_history_outcomes_and_plots_frontiers_in_motion() {
    let dir = std::env::temp_dir().join(format!("foveate-history-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A stem with a dot, as a density names one: its motions' plots must not become one file.
    let (history, stem) = (dir.join("history.csv"), dir.join("frontier-0.5"));
    let run = |extra: &[&str]| {
        let mut args = SMALL_FLICKER.to_vec();
        args.extend(["--motions", "still,walking"]);
        args.extend(extra);
        foveate(&args)
    };
    let o = run(&[
        "--flip",
        "--history-outcomes",
        history.to_str().unwrap(),
        "--pareto",
        stem.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    assert!(
        out.contains("history (accumulated rows, counting frames)"),
        "{out}"
    );
    assert!(
        out.contains("not timed, counting frames: foveated 0.5, temporal, MSAA 4"),
        "{out}"
    );
    // Two motions × one accumulated row × four frames × nine outcomes.
    let rows = read_csv(&history, 7);
    assert_eq!(rows.len(), 72, "{rows:?}");
    for r in &rows {
        assert_numeric(r, &["motion", "config", "outcome"]);
    }
    for motion in ["still", "walking"] {
        for extension in ["png", "svg"] {
            let plot = dir.join(format!("frontier-0.5-{motion}.{extension}"));
            assert!(plot.exists(), "no {}", plot.display());
        }
        let said = format!("frontier-0.5-{motion}.png and .svg");
        assert!(out.contains(&said), "missing `{said}` in\n{out}");
    }
    // Untimed rows only without the outcomes: every row is on the plot then.
    let o = run(&["--flip", "--pareto", stem.to_str().unwrap()]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(!stdout(&o).contains("not timed"), "{}", stdout(&o));
    let o = run(&["--pareto", stem.to_str().unwrap()]);
    assert!(
        !o.status.success() && stderr(&o).contains("pareto without flip"),
        "{}",
        stderr(&o)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The latency sweep: every latency without prediction, the others with each prediction, one
/// row per configuration, judged frames after a saccade; a bad latency is an error naming it.
#[test]
fn compare_sweeps_the_trackers_latency() {
    let csv = std::env::temp_dir().join(format!("foveate-latency-{}.csv", std::process::id()));
    let frames_csv = csv.with_extension("frames.csv");
    let o = foveate(&[
        "compare",
        "--frames-csv",
        frames_csv.to_str().unwrap(),
        "--scene",
        "default",
        "--res",
        "48",
        "--ratios",
        "0.5",
        "--frames",
        "2",
        "--gaze-latency",
        "0,50",
        "--gaze-predict",
        "saccade-landing",
        "--trace-s",
        "2",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("the smallest fovea"), "{out}");
    let rows = read_csv(&csv, 11);
    let keys: Vec<(&str, &str)> = rows
        .iter()
        .map(|r| (r["latency_ms"].as_str(), r["prediction"].as_str()))
        .collect();
    assert_eq!(
        keys,
        [("0", "none"), ("50", "none"), ("50", "saccade-landing")]
    );
    for r in &rows {
        assert_numeric(r, &["prediction", "config"]);
        let worst: f64 = r["eflip_p99_worst_after_landing"].parse().unwrap();
        assert!(worst > 0.0 && worst <= 1.0, "{r:?}");
    }
    // Every judged frame of every row, with its eFLIP per region where the fovea was placed.
    let frames = read_csv(&frames_csv, 14);
    assert!(!frames.is_empty() && frames.len().is_multiple_of(rows.len()));
    for f in &frames {
        assert_numeric(f, &["prediction", "config"]);
    }
    let _ = std::fs::remove_file(&csv);
    let _ = std::fs::remove_file(&frames_csv);
    let o = foveate(&["compare", "--res", "48", "--gaze-latency", "-5"]);
    assert!(
        !o.status.success() && stderr(&o).contains("gaze-latency = -5"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn render_reference_stacks_both_frames_and_prices_the_foveated_one() {
    let out = std::env::temp_dir().join(format!("foveate-ref-{}.png", std::process::id()));
    let o = foveate(&[
        "render",
        "--foveate",
        "0.5",
        "--reference",
        "--res",
        "48",
        "--frames",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let text = stdout(&o);
    for needle in [
        "accuracy against the reference (output image, lens-visible pixels",
        "PSNR fovea",
        "eccentricity-aware FLIP mean",
    ] {
        assert!(text.contains(needle), "missing `{needle}` in\n{text}");
    }
    let image = foveate::metrics::RgbaImage::load_png(&out).unwrap();
    assert_eq!((image.width, image.height), (96, 96));
    let _ = std::fs::remove_file(&out);
}

/// Without a runtime (none installed on the host, or none running), `foveate xr` says what is
/// missing and exits non-zero; bad arguments are refused before any runtime is asked.
#[test]
fn xr_without_a_runtime_or_with_bad_arguments_is_a_clear_error() {
    let empty = std::env::temp_dir().join(format!("foveate-xr-{}", std::process::id()));
    std::fs::create_dir_all(&empty).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_foveate"))
        .args(["--validation", "xr", "--frames", "1"])
        .env("XDG_RUNTIME_DIR", &empty)
        .env("XR_RUNTIME_JSON", empty.join("no-runtime.json"))
        .output()
        .unwrap();
    let err = stderr(&out);
    assert!(!out.status.success() && !err.contains("panicked"), "{err}");
    assert!(
        err.contains("no OpenXR loader") || err.contains("no OpenXR runtime"),
        "{err}"
    );
    for (args, expected) in [
        (&["xr", "--frames", "0"][..], "invalid frames = 0"),
        (
            &["xr", "--save", "x.png"],
            "--save writes the checked frame",
        ),
        (
            &["xr", "--gaze-source", "sideways"],
            "invalid gaze-source = sideways",
        ),
        (&["xr", "--gaze", "0.2,0"], "add --gaze-source fixed"),
    ] {
        let out = foveate(args);
        let err = stderr(&out);
        assert!(
            !out.status.success() && err.contains(expected),
            "{args:?}: {err}"
        );
    }
    std::fs::remove_dir_all(&empty).unwrap();
}

/// Every headset profile is offered where a user looks for one: `--help` and the options
/// table of the command-line docs. Mutation: a profile added to the library and not to either
/// fails it.
#[test]
fn help_and_the_options_table_list_every_headset() {
    let help = stdout(&foveate(&["render", "--help"]));
    let table = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/commands/README.md"),
    )
    .unwrap();
    let row = table
        .lines()
        .find(|l| l.starts_with("| `--hmd`"))
        .expect("the --hmd row");
    for profile in foveate::view::HMD_PROFILES {
        assert!(help.contains(profile.name), "--help lacks {}", profile.name);
        assert!(
            row.contains(&format!("`{}`", profile.name)),
            "the options table lacks {}",
            profile.name
        );
    }
}

/// `shaders` on a device without the compiler's statistics (lavapipe): every mode's pipelines
/// and the judges' compiled, whole frames recorded without queries, and each absence said, not
/// filled in: no statistics, no driver trace, a CSV with its header alone. Mutation: a frame
/// that waits on a query it did not plan (the frames asked without timestamps) fails on a
/// device that runs nothing, not here; the absence lines and the header-only CSV fail if the
/// command printed or wrote a figure it did not get.
#[test]
fn shaders_compiles_every_mode_and_says_what_the_device_does_not_report() {
    let csv = std::env::temp_dir().join(format!("foveate-shaders-{}.csv", std::process::id()));
    let o = foveate(&[
        "shaders",
        "--res",
        "32",
        "--stereo",
        "all",
        "--frames",
        "2",
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = stdout(&o);
    for mode in ["multiview", "two-pass", "per-object", "instanced"] {
        assert!(out.contains(&format!("{mode}: ")), "{out}");
    }
    let modes = out
        .lines()
        .filter(|l| !l.contains("compute") && l.ends_with(" pipelines compiled"));
    assert_eq!(modes.count(), 4, "{out}");
    assert_eq!(
        out.matches("2 frames recorded and submitted, without queries")
            .count(),
        4,
        "{out}"
    );
    assert!(
        out.contains("does not report its compiler's statistics"),
        "{out}"
    );
    assert!(out.contains("the judges (eFLIP, flicker): 9 compute pipelines compiled"));
    assert!(out.contains("the driver wrote no trace"), "{out}");
    assert_eq!(
        std::fs::read_to_string(&csv).unwrap().lines().count(),
        1,
        "the header alone"
    );
    let _ = std::fs::remove_file(&csv);
}
