//! The foveated variants a sweep measures beyond its plain rows (`compare`, `flicker`): the
//! periphery at its own density and sample count, and accumulated over frames.

use foveate::foveation::{
    ClipNeighbourhood, FoveationConfig, HistoryAt, HistoryClip, HistoryFilter, HistoryFormat,
    NewSample, PeripheryFilter, TemporalConfig,
};
use foveate::plan::RenderConfig;

/// Each foveated variant as it is, then with the periphery at each of `densities` and at each
/// of `periphery_msaa`'s sample counts (every combination), named after what changed.
pub fn with_view_sets(
    variants: Vec<(String, FoveationConfig)>,
    densities: &[f32],
    periphery_msaa: &[u32],
) -> Vec<(String, FoveationConfig)> {
    let densities = std::iter::once(None).chain(densities.iter().map(|&d| Some(d)));
    let densities: Vec<Option<f32>> = densities.collect();
    let msaa: Vec<Option<u32>> = std::iter::once(None)
        .chain(periphery_msaa.iter().map(|&m| Some(m)))
        .collect();
    let mut out = Vec::new();
    for (name, f) in variants {
        for &density in &densities {
            for &samples in &msaa {
                let mut name = name.clone();
                if let Some(d) = density {
                    name += &format!(", periphery {d}");
                }
                if let Some(m) = samples {
                    name += &format!(" at {m}x");
                }
                let config = FoveationConfig {
                    periphery_density: density,
                    periphery_msaa: samples,
                    ..f
                };
                out.push((name, config));
            }
        }
    }
    out
}

/// How the accumulated rows of `compare --temporal` and `flicker --temporal` accumulate.
#[derive(clap::Args)]
pub struct Accumulation {
    /// With --temporal: one accumulated row per way of holding the history to the periphery:
    /// `variance[:SIGMAS]` (Salvi's variance clipping), `range` (the min/max box), `moved` (the
    /// range only where the head's motion moved the point or a moving instance lies), `depth`
    /// (no clip, the frame before's depth test alone), `off` (neither) (default: the
    /// library's).
    #[arg(long, value_delimiter = ',')]
    pub clips: Vec<HistoryClip>,
    /// With --temporal: one accumulated row per way of reading the history where the point
    /// moved: `bilinear`, `catmull-rom` (default: the library's).
    #[arg(long, value_delimiter = ',')]
    pub history_filters: Vec<HistoryFilter>,
    /// With --temporal: one accumulated row per set of periphery texels making the clip's box:
    /// `3x3`, `cross` (default: the library's).
    #[arg(long, value_delimiter = ',')]
    pub neighbourhoods: Vec<ClipNeighbourhood>,
    /// With --temporal: one accumulated row per new sample: `nearest` (the nearest texel
    /// alone), `weighted` (where the point moved, the 3×3 texels, each by its distance)
    /// (default: the library's).
    #[arg(long, value_delimiter = ',')]
    pub new_samples: Vec<NewSample>,
    /// With --temporal: one accumulated row per place the history keeps its pixels: `output`
    /// (the output's pixels), `periphery` (the periphery's own texels) (default: the
    /// library's).
    #[arg(long, value_delimiter = ',')]
    pub histories: Vec<HistoryAt>,
    /// With --temporal: beside each accumulated row, one per density (of the screen's pixels
    /// per side) of a history kept in a pass of its own, between the periphery's texels and
    /// the output's pixels.
    #[arg(long, value_delimiter = ',')]
    pub history_densities: Vec<f32>,
    /// With --temporal: one accumulated row per history format: `colour` (32 bits a pixel),
    /// `luma` (one byte, the chroma from each frame's periphery) (default: the library's).
    #[arg(long, value_delimiter = ',')]
    pub history_formats: Vec<HistoryFormat>,
    /// With --temporal: one accumulated row per reach: the eccentricity (degrees) within which
    /// the periphery accumulates, each frame's periphery shown beyond it (default: everywhere).
    #[arg(long, value_delimiter = ',')]
    pub withins: Vec<f32>,
    /// With --temporal: a settled pixel's weight for a new sample (0 < w ≤ 1; default: the
    /// library's).
    #[arg(long)]
    pub temporal_blend: Option<f32>,
    /// With --temporal: the same weight where nothing moved (default: the library's).
    #[arg(long)]
    pub temporal_still_blend: Option<f32>,
    /// With --temporal: frames in the jitter cycle (1: no jitter; default: the library's).
    #[arg(long)]
    pub jitter_cycle: Option<u32>,
    /// With --temporal: one accumulated row per periphery sample count, 1 or 4 (default 1;
    /// 4 needs a device that resolves depth in a pass, VK_KHR_depth_stencil_resolve).
    #[arg(long, value_delimiter = ',')]
    pub temporal_msaa: Vec<u32>,
    /// With --temporal: only the foveated rows whose name contains this text (e.g. `periphery
    /// 0.6, temporal`; given again, either text); the stereo rows stay (default: every row).
    #[arg(long)]
    pub only: Vec<String>,
}

/// `variants` and, after them, each plain one (single-sample periphery, not sharpened,
/// bilinear, no band sweep) accumulated over frames as `accumulation` says: one row per clip.
pub fn with_temporal(
    variants: Vec<(String, FoveationConfig)>,
    accumulation: &Accumulation,
) -> anyhow::Result<Vec<(String, FoveationConfig)>> {
    let plain = |f: &FoveationConfig| {
        f.periphery_msaa.is_none()
            && f.periphery_sharpen == 0.0
            && f.periphery_filter == PeripheryFilter::Bilinear
    };
    let library = TemporalConfig::default();
    let default = TemporalConfig {
        blend: accumulation.temporal_blend.unwrap_or(library.blend),
        still_blend: accumulation
            .temporal_still_blend
            .unwrap_or(library.still_blend),
        jitter_cycle: accumulation.jitter_cycle.unwrap_or(library.jitter_cycle),
        ..library
    };
    // One way per combination, the clip varying slowest and the reach fastest.
    let mut ways = vec![default];
    ways = vary(ways, &accumulation.clips, |w, clip| TemporalConfig {
        clip,
        ..w
    });
    ways = vary(ways, &accumulation.history_filters, |w, filter| {
        TemporalConfig { filter, ..w }
    });
    ways = vary(ways, &accumulation.neighbourhoods, |w, neighbourhood| {
        TemporalConfig { neighbourhood, ..w }
    });
    ways = vary(ways, &accumulation.new_samples, |w, new_sample| {
        TemporalConfig { new_sample, ..w }
    });
    ways = vary(ways, &accumulation.history_formats, |w, history_format| {
        TemporalConfig {
            history_format,
            ..w
        }
    });
    ways = vary(ways, &accumulation.histories, |w, history_at| {
        TemporalConfig { history_at, ..w }
    });
    // Beside each way, the same with its history at each density (the rows compared with
    // the history where `--histories` keeps it).
    let at_densities = vary(
        ways.clone(),
        &accumulation.history_densities,
        |w, density| TemporalConfig {
            history_at: HistoryAt::Periphery,
            history_density: Some(density),
            ..w
        },
    );
    // Without densities `vary` gives the ways back unchanged: nothing new to add.
    for way in at_densities {
        if !ways.contains(&way) {
            ways.push(way);
        }
    }
    ways = vary(ways, &accumulation.withins, |w, within| TemporalConfig {
        within_deg: Some(within),
        ..w
    });
    for way in &ways {
        way.validate()?;
    }
    let samples = match &accumulation.temporal_msaa[..] {
        [] => &[1][..],
        given => given,
    };
    let ways: Vec<(TemporalConfig, u32)> = ways
        .iter()
        .flat_map(|&way| samples.iter().map(move |&m| (way, m)))
        .collect();
    let temporal: Vec<(String, FoveationConfig)> = variants
        .iter()
        .filter(|(name, f)| plain(f) && !name.contains(", band "))
        .flat_map(|(name, f)| {
            ways.iter().map(move |&(way, samples)| {
                let config = FoveationConfig {
                    periphery_msaa: Some(samples),
                    periphery_temporal: Some(way),
                    ..*f
                };
                let at = if samples == 1 {
                    String::new()
                } else {
                    format!(" at {samples}x")
                };
                (
                    format!("{name}, temporal{at}{}", way_words(way, default)),
                    config,
                )
            })
        })
        .collect();
    let wanted = |name: &String| {
        let only = &accumulation.only;
        only.is_empty() || only.iter().any(|text| name.contains(text.as_str()))
    };
    let rows = variants.into_iter().chain(temporal);
    let rows: Vec<_> = rows.filter(|(name, _)| wanted(name)).collect();
    anyhow::ensure!(
        !rows.is_empty(),
        "--only {:?}: no foveated row's name contains any of these",
        accumulation.only
    );
    Ok(rows)
}

/// Each of `ways` once per value in `values` (set by `set`), or `ways` as they are where no
/// value was given (the library's default stands).
fn vary<T: Copy>(
    ways: Vec<TemporalConfig>,
    values: &[T],
    set: impl Fn(TemporalConfig, T) -> TemporalConfig,
) -> Vec<TemporalConfig> {
    if values.is_empty() {
        return ways;
    }
    ways.into_iter()
        .flat_map(|w| values.iter().map(move |&v| (w, v)))
        .map(|(w, v)| set(w, v))
        .collect()
}

/// What sets `way` apart from the default accumulation in a row's name: "" or " (clip range,
/// catmull-rom, box cross)".
fn way_words(way: TemporalConfig, default: TemporalConfig) -> String {
    let mut words = Vec::new();
    if way.clip != default.clip {
        words.push(format!("clip {}", way.clip));
    }
    if way.filter != default.filter {
        words.push(way.filter.to_string());
    }
    if way.neighbourhood != default.neighbourhood {
        words.push(format!("box {}", way.neighbourhood));
    }
    if way.new_sample != default.new_sample {
        words.push(format!("{} sample", way.new_sample));
    }
    if way.history_format != default.history_format {
        words.push(format!("{} history", way.history_format));
    }
    match way.history_density {
        Some(density) => words.push(format!("history at density {density}")),
        None if way.history_at != default.history_at => {
            words.push(format!("history at the {}'s pixels", way.history_at))
        }
        None => {}
    }
    if let Some(within) = way
        .within_deg
        .filter(|_| way.within_deg != default.within_deg)
    {
        words.push(format!("within {within}°"));
    }
    match words.is_empty() {
        true => String::new(),
        false => format!(" ({})", words.join(", ")),
    }
}

/// `rows`, each single-frame foveated row followed by its twins: with the periphery's
/// highlights prefiltered when `prefilter` (`--prefilter`), and with a parafoveal ring of each
/// of `rings` wider than its fovea (`--rings`).
pub fn with_twins<T: Clone>(
    rows: Vec<(String, T, RenderConfig)>,
    prefilter: bool,
    rings: &[f32],
) -> Vec<(String, T, RenderConfig)> {
    let twins = |(name, t, config): &(String, T, RenderConfig)| {
        let Some(foveation) = config.foveation.filter(|f| f.periphery_temporal.is_none()) else {
            return Vec::new();
        };
        let twin = |suffix: String, foveation| {
            let config = RenderConfig {
                foveation: Some(foveation),
                ..config.clone()
            };
            (format!("{name}, {suffix}"), t.clone(), config)
        };
        let prefiltered = FoveationConfig {
            periphery_prefilter: true,
            ..foveation
        };
        let ringed = rings.iter().filter(|&&r| r > foveation.ratio).map(|&r| {
            let ring = FoveationConfig {
                ring_ratio: Some(r),
                ..foveation
            };
            twin(format!("ring {r}"), ring)
        });
        let prefiltered = prefilter.then(|| twin("prefiltered".into(), prefiltered));
        prefiltered.into_iter().chain(ringed).collect()
    };
    let mut twinned = Vec::with_capacity(rows.len());
    for row in rows {
        let with = twins(&row);
        twinned.push(row);
        twinned.extend(with);
    }
    twinned
}
