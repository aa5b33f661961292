//! The results page's other sections: MFFR, the HMD mask, the thesis' benchmark (culling,
//! multiview and their combinations) and the eye tracker's latency.

use anyhow::Result;

use super::runs::{num, Runs};

/// A Markdown table.
pub(crate) fn table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut out = format!("| {} |\n", header.join(" | "));
    out += &format!("|{}\n", "---|".repeat(header.len()));
    for row in rows {
        out += &format!("| {} |\n", row.join(" | "));
    }
    out
}

/// A verdict cell.
pub(crate) fn yes(v: bool) -> String {
    if v { "yes" } else { "**no**" }.to_string()
}

/// MFFR's far pass on the city, both drivers: the rows against the stereo 4× frame, and
/// whether each is as accurate as aliased stereo.
pub(super) fn mffr(runs: &Runs) -> Result<String> {
    let (old, new) = (runs.get("mffr-mesa22")?, runs.get("mffr-mesa25")?);
    let aliased = old.row("variant", "stereo, MSAA 1")?;
    let yardstick = num(aliased, "eccentric_flip_p99")?;
    let mut rows = vec![vec![
        "stereo, no MSAA (aliased): the yardstick".to_string(),
        format!("{:.3}", num(aliased, "ratio")?),
        format!(
            "{:.3}",
            num(new.row("variant", "stereo, MSAA 1")?, "ratio")?
        ),
        format!("{yardstick:.4}"),
        "–".to_string(),
        "–".to_string(),
    ]];
    let far = |r: &std::collections::HashMap<String, String>| {
        (r.get("far_msaa").cloned(), r.get("far_density").cloned())
    };
    for row in old.rows_where("variant", "near-first") {
        let twin = (new.rows_where("variant", "near-first"))
            .find(|r| far(r) == far(row))
            .ok_or_else(|| anyhow::anyhow!("{}: no row like {:?}", new.file.display(), far(row)))?;
        let p99 = num(row, "eccentric_flip_p99")?;
        rows.push(vec![
            format!(
                "near-first, far pass {}×, density {}",
                num(row, "far_msaa")?,
                num(row, "far_density")?
            ),
            format!("{:.3}", num(row, "ratio")?),
            format!("{:.3}", num(twin, "ratio")?),
            format!("{p99:.4}"),
            format!("{:.2} M", num(row, "far_fragments")? / 1e6),
            yes(p99 <= yardstick),
        ]);
    }
    let header = [
        "far pass",
        "Mesa 22.3: × stereo 4×",
        "Mesa 25.0: × stereo 4×",
        "eFLIP p99",
        "far fragments",
        "as accurate as aliased stereo?",
    ];
    Ok(format!(
        "\n## Monoscopic far field (MFFR)\n\nThe city at 1024² per eye (Index profile, MSAA 4), near-first at a 1 px split; the default far pass is the frame's samples at 0.8 of the eyes' density, the cheapest setting as accurate as aliased stereo.\n\n{}\nMesa 22.3: {}. Mesa 25.0: {}.\n",
        table(&header, &rows),
        old.provenance("docs"),
        new.provenance("docs")
    ))
}

/// The HMD mask per headset: what it hides, what it saves.
pub(super) fn masks(runs: &Runs) -> Result<String> {
    let run = runs.get("masks")?;
    let mut rows = Vec::new();
    for row in &run.rows {
        let saved = num(row, "saved")?;
        rows.push(vec![
            row.get("profile").cloned().unwrap_or_default(),
            format!("{:.1} %", 100.0 * num(row, "measured_hidden")?),
            format!("{:.2}", num(row, "off_ms")?),
            format!("{:.2}", num(row, "on_ms")?),
            format!("{:.1} %", 100.0 * saved),
            yes(saved > 0.0),
        ]);
    }
    let header = [
        "headset",
        "hidden (measured)",
        "ms, mask off",
        "ms, mask on",
        "saved",
        "pays?",
    ];
    Ok(format!(
        "\n## The HMD stencil mask\n\nA fill-bound frame (512² per eye, MSAA 4), each headset's pair measured side by side; the mask changes no pixel the lens shows.\n\n{}\n{}.\n",
        table(&header, &rows),
        run.provenance("docs")
    ))
}

/// The thesis' benchmark: each optimisation alone and the best combinations, against the
/// baseline in the same run.
pub(super) fn thesis(runs: &Runs) -> Result<String> {
    let run = runs.get("thesis")?;
    let configs = [
        ("MVIEW", "multiview"),
        ("SFRUST", "superfrustum culling"),
        ("SMASK", "HMD stencil mask"),
        ("MFFR", "monoscopic far field"),
        ("MVIEW & FOV", "multiview and foveation"),
        ("SMASK & SFRUST & MVIEW & MFFR", "all four"),
        (
            "SMASK & SFRUST & MVIEW & MFFR & FOV",
            "all four and foveation",
        ),
        ("baseline again (noise)", "the baseline again"),
    ];
    // The baseline measured against itself: a configuration is faster, or slower, only by more
    // than the run's own noise.
    let noise = (num(run.row("config", "baseline again (noise)")?, "ratio_median")? - 1.0).abs();
    let faster = |ratio: f64| match ratio {
        r if r < 1.0 - noise => "yes",
        r if r > 1.0 + noise => "**no**",
        _ => "within the noise",
    };
    let mut rows = Vec::new();
    for (config, label) in configs {
        let row = run.row("config", config)?;
        let ratio = num(row, "ratio_median")?;
        rows.push(vec![
            match config.starts_with("baseline") {
                true => format!("{label}: the run's noise"),
                false => format!("{label} (`{config}`)"),
            },
            format!("{ratio:.3}"),
            format!("{:.0}", num(row, "draw_calls")?),
            format!("{:.0}", num(row, "triangles")?),
            format!("{:.0}", num(row, "total_pixels")?),
            match config.starts_with("baseline") {
                true => "–".to_string(),
                false => faster(ratio).to_string(),
            },
        ]);
    }
    let header = [
        "configuration",
        "time × baseline",
        "draw calls",
        "triangles",
        "pixels shaded",
        "faster?",
    ];
    Ok(format!(
        "\n## Culling, multiview and the thesis' combinations\n\nThe Tachyon thesis' benchmark scene along its rails (Preißner 2020 §5–6), two-pass stereo without culling as the baseline, every configuration interleaved frame by frame in one run. Faster: by more than the baseline measured against itself in the same run.\n\n{}\n{}.\n\n![frame time over the baseline per configuration](bench-lavapipe/ratios.svg)\n",
        table(&header, &rows),
        run.provenance("docs")
    ))
}

/// The eye tracker's latency: per latency and prediction, the worst frame after each saccade
/// lands for each fovea ratio, and the smallest ratio within the budget (aliased stereo's worst).
pub(super) fn latency(runs: &Runs) -> Result<String> {
    let run = runs.get("latency")?;
    let mut ratios: Vec<String> = Vec::new();
    let mut trackings: Vec<(String, String)> = Vec::new();
    for row in &run.rows {
        let cell = |c: &str| row.get(c).cloned().unwrap_or_default();
        if !ratios.contains(&cell("ratio")) {
            ratios.push(cell("ratio"));
        }
        let tracking = (cell("latency_ms"), cell("prediction"));
        if !trackings.contains(&tracking) {
            trackings.push(tracking);
        }
    }
    let mut rows = Vec::new();
    for (latency, prediction) in &trackings {
        let mut cells = vec![format!("{latency} ms"), prediction.clone()];
        let mut pick: Option<(f64, f64, String)> = None;
        for ratio in &ratios {
            let row = (run.rows.iter())
                .find(|r| {
                    [
                        ("latency_ms", latency),
                        ("prediction", prediction),
                        ("ratio", ratio),
                    ]
                    .iter()
                    .all(|(c, v)| r.get(*c) == Some(*v))
                })
                .ok_or_else(|| anyhow::anyhow!("latency: no row {latency} {prediction} {ratio}"))?;
            let worst = num(row, "eflip_p99_worst_after_landing")?;
            let within = worst <= num(row, "budget")?;
            cells.push(format!("{worst:.3}{}", if within { "" } else { " ✗" }));
            let r: f64 = ratio.parse()?;
            if within && pick.as_ref().is_none_or(|p| r < p.0) {
                pick = Some((r, num(row, "time_ratio")?, ratio.clone()));
            }
        }
        cells.push(pick.as_ref().map_or("none".into(), |p| p.2.clone()));
        cells.push(pick.map_or("–".into(), |p| format!("{:.3}×", p.1)));
        rows.push(cells);
    }
    let budget = num(&run.rows[0], "budget")?;
    let mut header = vec!["latency".to_string(), "prediction".to_string()];
    header.extend(ratios.iter().map(|r| format!("fovea {r}")));
    header.extend([
        "smallest within budget".into(),
        "its time × stereo 4×".into(),
    ]);
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    Ok(format!(
        "\n## The eye tracker's latency\n\nThe lit atrium at a quarter of the Quest Pro's panel, foveated as the library's default foveates (the periphery at 0.6 of the screen's density, accumulated over the display frames, rendered in order) at each fovea ratio, the fovea placed where the tracker saw the gaze that long before (with the prediction named), judged at the eye's true gaze from each simulated saccade's onset to 150 ms after its landing. Each cell is the worst eFLIP p99 at or after a landing, ✗ over the budget: aliased stereo's worst frame, {budget:.3}.\n\n{}\n{}.\n",
        table(&header, &rows),
        run.provenance("docs")
    ))
}
