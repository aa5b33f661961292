//! The results page's sections and the README's table, each from its runs: a table, the
//! command that made each run, its build, date and device. A verdict column says, from the
//! figures, whether a row beats the yardstick the section names.

use anyhow::Result;

use super::runs::{num, Run, Runs};

pub(super) use super::sections_more::{table, yes};

/// The rows of the foveation verdict: aliased stereo, single frames at the ratio's density, the
/// periphery at 0.6 single-frame and accumulated at the output's pixels (the library's default
/// and the demo's, and with a 1× fovea), then accumulated at the periphery's own texels at 0.35
/// and 0.6.
const FOVEATION_ROWS: [(&str, &str); 7] = [
    ("stereo, MSAA 1", "stereo, no MSAA (aliased): the yardstick"),
    (
        "foveated 0.35, MSAA 4",
        "foveated 0.35, 4×, one periphery frame (single frames)",
    ),
    (
        "foveated 0.35, periphery 0.6, MSAA 4",
        "foveated 0.35, periphery 0.6, one frame, 4×",
    ),
    (
        "foveated 0.35, periphery 0.6, temporal, MSAA 4",
        "foveated 0.35, periphery 0.6 accumulated at the output's pixels, fovea 4× (the default, the demo's)",
    ),
    (
        "foveated 0.35, periphery 0.6, temporal, MSAA 1",
        "foveated 0.35, periphery 0.6 accumulated at the output's pixels, fovea 1×",
    ),
    (
        "foveated 0.35, temporal (history at the periphery's pixels), MSAA 4",
        "foveated 0.35, periphery 0.35 accumulated at its own texels, fovea 4×",
    ),
    (
        "foveated 0.35, periphery 0.6, temporal (history at the periphery's pixels), MSAA 4",
        "foveated 0.35, periphery 0.6 accumulated at its own texels, fovea 4×",
    ),
];

/// The rows the motion runs measured every frame of (the first four), and the rows measured
/// later with every third frame judged (the periphery accumulated at its own texels).
const EVERY_FRAME_ROWS: usize = 4;

/// The README's verdict table: the still frame at the Quest Pro's panel, both gazes.
pub(super) fn readme_table(runs: &Runs) -> Result<String> {
    let body = still_table(runs, "")?;
    Ok(format!("{body}\n"))
}

/// The still frame at both gazes: × the stereo 4× frame, eFLIP p99, the tile GPU's figures,
/// and whether a row is as accurate as, and cheaper than, aliased stereo at both gazes.
fn still_table(runs: &Runs, from_dir: &str) -> Result<String> {
    let (ahead, gaze) = (
        runs.get("foveation-still-ahead")?,
        runs.get("foveation-still-gaze")?,
    );
    let stereo = |run: &Run| -> Result<(f64, f64)> {
        let row = run.row("config", FOVEATION_ROWS[0].0)?;
        Ok((num(row, "time_ratio")?, num(row, "eccentric_flip_p99")?))
    };
    let yardstick = [stereo(ahead)?, stereo(gaze)?];
    // The price on the Adreno 650 (a formula), × the stereo 4× frame's on that chip.
    let price = |run: &Run, config: &str| num(run.row("config", config)?, "price_ratio");
    let price_yardstick = [
        price(ahead, FOVEATION_ROWS[0].0)?,
        price(gaze, FOVEATION_ROWS[0].0)?,
    ];
    // The stereo 4× frame timed against itself: a row is cheaper, or dearer, only by more
    // than the run's own noise.
    let noise = |run: &Run| -> Result<f64> {
        Ok((num(run.row("config", "stereo, MSAA 4")?, "time_ratio")? - 1.0).abs())
    };
    let noise = [noise(ahead)?, noise(gaze)?];
    let mut rows = Vec::new();
    for (config, label) in FOVEATION_ROWS {
        let (a, g) = (ahead.row("config", config)?, gaze.row("config", config)?);
        let figures = [a, g].map(|r| (num(r, "time_ratio"), num(r, "eccentric_flip_p99")));
        let [(ta, pa), (tg, pg)] = figures;
        let (ta, pa, tg, pg) = (ta?, pa?, tg?, pg?);
        let accurate = pa <= yardstick[0].1 && pg <= yardstick[1].1;
        let cheaper =
            ta < yardstick[0].0 * (1.0 - noise[0]) && tg < yardstick[1].0 * (1.0 - noise[1]);
        let dearer =
            ta > yardstick[0].0 * (1.0 + noise[0]) || tg > yardstick[1].0 * (1.0 + noise[1]);
        let is_yardstick = config == FOVEATION_ROWS[0].0;
        let verdict = |v: bool| {
            if is_yardstick {
                "–".to_string()
            } else {
                yes(v)
            }
        };
        let (price_a, price_g) = (price(ahead, config)?, price(gaze, config)?);
        let priced_cheaper = price_a < price_yardstick[0] && price_g < price_yardstick[1];
        rows.push(vec![
            label.to_string(),
            format!("{ta:.2}×, {tg:.2}×"),
            format!("{price_a:.3}×, {price_g:.3}×"),
            format!("{pa:.3}, {pg:.3}"),
            format!("{:.1}", num(g, "resolved_samples")? / 1e6),
            format!(
                "{:.0}",
                num(g, "external_traffic_bytes")? / (1 << 20) as f64
            ),
            verdict(accurate),
            match (is_yardstick, cheaper, dearer) {
                (false, false, false) => "within the noise".to_string(),
                _ => verdict(cheaper),
            },
            verdict(priced_cheaper),
        ]);
    }
    let header = [
        "configuration",
        "time × stereo 4× (ahead, gaze)",
        "Adreno 650 price × stereo 4× (ahead, gaze)",
        "eFLIP p99 (ahead, gaze)",
        "M samples resolved",
        "MiB moved",
        "as accurate as aliased stereo (both gazes)?",
        "cheaper (both gazes)?",
        "cheaper on the Adreno 650's price?",
    ];
    let mut out = table(&header, &rows);
    out += &format!(
        "\nThe lit atrium at the Meta Quest Pro's panel (1800×1920 per eye, 19.5 px/°), through the lens, a still frame with the gaze ahead and at (0.3, −0.2); every row measured side by side with the full-quality reference (stereo, 4×) in one run; a row is cheaper only by more than that reference timed against itself strayed ({:.0} % ahead, {:.0} % at the gaze). eFLIP p99: the eccentricity-aware FLIP's 99th percentile for the eye at the gaze, lower is better. Samples resolved and MiB moved: what a tile GPU pays, by the plan's formula. The Adreno 650's price (the Quest Pro's GPU): a formula, not a measurement — the fragments and vertices each step's counting frame counted × the instructions Adreno's own compiler (Mesa's turnip) made of its shaders, the plan's bytes at the chip's bandwidth, per pass the larger ([how]({})); cheaper only below aliased stereo's at both gazes. Ahead: {}. At (0.3, −0.2): {}.\n",
        noise[0] * 100.0,
        noise[1] * 100.0,
        // The page's link to the Adreno page: the README's from the root, the results page's
        // from docs/.
        if from_dir.is_empty() {
            "docs/adreno.md"
        } else {
            "adreno.md"
        },
        ahead.provenance(from_dir),
        gaze.provenance(from_dir)
    );
    Ok(out)
}

/// Each motion, every frame judged: eFLIP p99 over the frame (and in the periphery alone for
/// the walks) and the walk's flicker.
fn motion_table(runs: &Runs, from_dir: &str) -> Result<String> {
    let walk = runs.get("foveation-walk-ahead")?;
    let gaze_walk = runs.get("foveation-walk-gaze")?;
    let saccades = runs.get("foveation-saccades")?;
    let p99 = |run: &Run, motion: &str, config: &str, column: &str| -> Result<f64> {
        let row = (run.rows_where("motion", motion))
            .find(|r| r.get("config").map(String::as_str) == Some(config))
            .ok_or_else(|| anyhow::anyhow!("{}: no {motion} row {config}", run.file.display()))?;
        num(row, column)
    };
    let texels = [
        runs.get("texels-walk-ahead")?,
        runs.get("texels-walk-gaze")?,
        runs.get("texels-saccades")?,
    ];
    let mut rows = Vec::new();
    // The motion runs measured every row but the 1× fovea's; the texels' runs, their rows.
    let every_frame = FOVEATION_ROWS.into_iter().take(EVERY_FRAME_ROWS);
    let every_third = FOVEATION_ROWS.into_iter().skip(EVERY_FRAME_ROWS + 1);
    let measured = (every_frame.map(|r| (r, [walk, gaze_walk, saccades], "")))
        .chain(every_third.map(|r| (r, texels, " (every third frame judged)")));
    for ((config, label), [walk, gaze_walk, saccades], judged) in measured {
        rows.push(vec![
            format!("{label}{judged}"),
            format!(
                "{:.4}, {:.4}",
                p99(walk, "walking", config, "eflip_p99")?,
                p99(gaze_walk, "walking", config, "eflip_p99")?
            ),
            format!(
                "{:.4}, {:.4}",
                p99(walk, "walking", config, "eflip_p99_periphery")?,
                p99(gaze_walk, "walking", config, "eflip_p99_periphery")?
            ),
            format!("{:.4}", p99(saccades, "saccades", config, "eflip_p99")?),
            format!(
                "{:.4}",
                p99(saccades, "large saccades", config, "eflip_p99")?
            ),
            format!(
                "{:.5}, {:.5}",
                p99(walk, "walking", config, "flicker_mean")?,
                p99(gaze_walk, "walking", config, "flicker_mean")?
            ),
        ]);
    }
    let header = [
        "configuration",
        "walk: eFLIP p99 (ahead, gaze)",
        "walk: the periphery's p99",
        "saccade trace: p99",
        "large saccades: p99",
        "walk: flicker (ahead, gaze)",
    ];
    let mut out = table(&header, &rows);
    out += &format!(
        "\n45 frames at 90 Hz per motion, every frame judged against the reference's frame (every third for the rows that say so); the walk at 1.4 m/s turning 20°/s with the gaze at rest, the saccade traces with the head still. Flicker: how much more the output's luma changed from one frame to the next than the reference's did (mean). Walk, ahead: {}. Walk at (0.3, −0.2): {}. Both saccade traces: {}. The periphery at its own texels, walk ahead: {}; at (0.3, −0.2): {}; both saccade traces: {}.\n",
        walk.provenance(from_dir),
        gaze_walk.provenance(from_dir),
        saccades.provenance(from_dir),
        texels[0].provenance(from_dir),
        texels[1].provenance(from_dir),
        texels[2].provenance(from_dir)
    );
    Ok(out)
}

/// The whole results page.
pub(super) fn page(runs: &Runs) -> Result<String> {
    let mut out = String::from(
        "# Results\n\nThe current result of each technique, generated by `scripts/results.sh` from the run files \
         `docs/results/index.csv` lists (CI fails when this page and its runs disagree). Each \
         table names the command that made its run, the build, the date and the device; a \
         verdict column reads the figures against the section's yardstick. How accuracy is \
         measured: [what the eye sees](what-the-eye-sees.md). The investigations behind these \
         results, dated with their builds: [the notebook](../BENCHMARKS.md#the-notebook).\n",
    );
    out += "\n## Foveation on an eye-tracked headset\n\nA still frame:\n\n";
    out += &still_table(runs, "docs")?;
    out += "\nIn motion:\n\n";
    out += &motion_table(runs, "docs")?;
    out += "\n![eFLIP p99 against time along the walk at the Quest Pro's panel](frontier/quest-pro-periphery-0.6-walking.svg)\n";
    out += &super::sections_more::mffr(runs)?;
    out += &super::sections_more::masks(runs)?;
    out += &super::sections_more::thesis(runs)?;
    out += &super::sections_more::latency(runs)?;
    Ok(out)
}
