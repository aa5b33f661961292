//! What `foveate bench` measured, summarised in the thesis' table forms (Tables 6.1–6.3) with
//! ratios to the baseline, and written as Markdown, CSV, JSON and plots.

use std::fmt::Write as _;
use std::path::Path;

use anyhow::Result;
use foveate::gpu::Gpu;
use foveate::metrics::Stats;
use foveate::plan::{FramePlan, PassKind, RenderConfig};
use foveate::render::FrameStats;
use foveate::scene::{Instance, Scene, Vertex};
use serde::Serialize;

use super::accuracy::AccuracyPoint;
use super::{BenchArgs, Settings, Toggles};
use crate::counts::mib;
use crate::csv_out::{opt, CsvTable};

/// One measured configuration.
pub struct Row {
    pub name: String,
    /// `None` for the zero-cost check rows.
    pub toggles: Option<Toggles>,
    pub config: RenderConfig,
}

impl Row {
    pub fn new(name: String, toggles: Option<Toggles>, config: RenderConfig) -> Self {
        Row {
            name,
            toggles,
            config,
        }
    }
}

/// One measured frame.
#[derive(Clone, Debug, Serialize)]
pub struct FrameSample {
    /// Index of the row.
    pub config: usize,
    /// Frame number along the rails (the pose).
    pub rail_frame: u64,
    /// Culling, recording, submission and the wait for the GPU.
    pub frame_ms: f64,
    /// Culling, recording and submission.
    pub cpu_ms: f64,
    pub cull_ms: f64,
    /// First to last timestamp of the frame.
    pub gpu_ms: f64,
    pub draw_calls: u64,
    pub triangles: u64,
    /// Triangles the MFFR far pass submitted (0 without one).
    pub far_triangles: u64,
    /// Fragments the scene draws shaded, all views (on the counted frames).
    pub pixels: Option<u64>,
    /// Fragments every pass shaded: masks, composites and probes too (on the counted frames).
    pub total_pixels: Option<u64>,
}

impl FrameSample {
    pub fn new(config: usize, rail_frame: u64, s: &FrameStats, plan: &FramePlan) -> Self {
        let far_triangles = plan
            .passes
            .iter()
            .zip(&s.pass_triangles)
            .filter(|(p, _)| p.kind == PassKind::FarField)
            .map(|(_, &t)| t)
            .sum();
        FrameSample {
            config,
            rail_frame,
            frame_ms: s.frame_ms,
            cpu_ms: s.cpu_cull_ms + s.cpu_record_ms + s.cpu_submit_ms,
            cull_ms: s.cpu_cull_ms,
            gpu_ms: s.gpu_ms.unwrap_or(f64::NAN),
            draw_calls: s.draw_calls,
            triangles: s.triangles,
            far_triangles,
            pixels: None,
            total_pixels: None,
        }
    }
}

/// Median, mean and spread of one metric.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Summary {
    pub median: f64,
    pub mean: f64,
    pub p95: f64,
    pub min: f64,
    pub max: f64,
}

impl Summary {
    fn of(values: impl Iterator<Item = f64>) -> Summary {
        let s = Stats::of(&values.collect::<Vec<_>>()).unwrap_or_default();
        Summary {
            median: s.median,
            mean: s.mean,
            p95: s.p95,
            min: s.min,
            max: s.max,
        }
    }
}

/// Bytes a configuration needs (thesis Table 6.3 in form) and what its frame moves.
#[derive(Clone, Debug, Serialize)]
pub struct Memory {
    /// Attachments that must be backed by memory.
    pub resident_bytes: u64,
    /// Attachments that can live on tile only (lazily allocated where offered).
    pub transient_bytes: u64,
    /// Buffers only an effect asked for (instance ids, stencil shapes, …).
    pub effect_buffer_bytes: u64,
    /// Device memory the renderer allocated, measured from the allocator.
    pub allocated_bytes: u64,
    /// The plan's estimate of external memory traffic per frame on a tile GPU.
    pub traffic_bytes: u64,
    /// Attachments, by name, this configuration has and the baseline has not.
    pub added: Vec<String>,
    /// Planned exactly as the baseline.
    pub plan_is_baseline: bool,
}

/// One row's summary.
#[derive(Clone, Debug, Serialize)]
pub struct RowSummary {
    pub name: String,
    pub toggles: Option<Toggles>,
    pub frame_ms: Summary,
    pub cpu_ms: Summary,
    pub cull_ms: Summary,
    pub gpu_ms: Summary,
    pub draw_calls: Summary,
    pub triangles: Summary,
    pub far_triangles: Summary,
    /// Fragments the scene draws shaded, and every pass (composition included).
    pub pixels: Option<Summary>,
    pub total_pixels: Option<Summary>,
    /// Median and mean frame time over the baseline's, measured in the same run.
    pub ratio_median: f64,
    pub ratio_mean: f64,
    pub memory: Memory,
}

/// One resource of the baseline frame (Table 6.3's rows).
#[derive(Clone, Debug, Serialize)]
pub struct Resource {
    pub name: String,
    pub description: String,
    pub bytes: u64,
    pub kind: &'static str,
}

#[derive(Serialize)]
pub struct Report {
    pub device: String,
    pub driver: String,
    pub scale: f32,
    pub instances: usize,
    pub resolution: String,
    pub msaa: u32,
    pub hmd: String,
    pub draw_distance: f32,
    pub foveation_ratio: f32,
    pub mffr: String,
    pub frames: u64,
    pub warmup: u64,
    /// Rows rendered frame by frame in turn (else one after another).
    pub interleaved: bool,
    pub rows: Vec<RowSummary>,
    pub baseline_resources: Vec<Resource>,
    pub accuracy: Vec<AccuracyPoint>,
    pub samples: Vec<FrameSample>,
}

impl Report {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        gpu: &Gpu,
        settings: &Settings,
        scale: f32,
        scene: &Scene,
        args: &BenchArgs,
        interleaved: bool,
        rows: Vec<super::report::Row>,
        plans: Vec<FramePlan>,
        allocated: Vec<u64>,
        samples: Vec<FrameSample>,
        accuracy: Vec<AccuracyPoint>,
    ) -> Report {
        let of = |i: usize, f: &dyn Fn(&FrameSample) -> f64| {
            Summary::of(samples.iter().filter(|s| s.config == i).map(f))
        };
        let base = 0;
        let base_frame = of(base, &|s| s.frame_ms);
        let names = |p: &FramePlan| -> Vec<String> {
            p.attachments
                .iter()
                .map(|a| format!("{} ({:?}, {}x)", a.name, a.format, a.samples))
                .collect()
        };
        let base_names = names(&plans[base]);
        let summaries = rows
            .iter()
            .enumerate()
            .map(|(i, row)| {
                let plan = &plans[i];
                let frame = of(i, &|s| s.frame_ms);
                let counted = |f: fn(&FrameSample) -> Option<u64>| {
                    let values: Vec<f64> = samples
                        .iter()
                        .filter(|s| s.config == i)
                        .filter_map(|s| f(s).map(|p| p as f64))
                        .collect();
                    (!values.is_empty()).then(|| Summary::of(values.into_iter()))
                };
                RowSummary {
                    name: row.name.clone(),
                    toggles: row.toggles,
                    frame_ms: frame,
                    cpu_ms: of(i, &|s| s.cpu_ms),
                    cull_ms: of(i, &|s| s.cull_ms),
                    gpu_ms: of(i, &|s| s.gpu_ms),
                    draw_calls: of(i, &|s| s.draw_calls as f64),
                    triangles: of(i, &|s| s.triangles as f64),
                    far_triangles: of(i, &|s| s.far_triangles as f64),
                    pixels: counted(|s| s.pixels),
                    total_pixels: counted(|s| s.total_pixels),
                    ratio_median: frame.median / base_frame.median,
                    ratio_mean: frame.mean / base_frame.mean,
                    memory: Memory {
                        resident_bytes: plan.resident_bytes(),
                        transient_bytes: plan.transient_bytes(),
                        effect_buffer_bytes: plan.buffers.iter().map(|b| b.bytes).sum(),
                        allocated_bytes: allocated[i],
                        traffic_bytes: plan.external_traffic_bytes(),
                        added: names(plan)
                            .into_iter()
                            .filter(|n| !base_names.contains(n))
                            .collect(),
                        plan_is_baseline: *plan == plans[base],
                    },
                }
            })
            .collect();
        let info = gpu.info();
        Report {
            device: info.name.clone(),
            driver: info.driver.clone(),
            scale,
            instances: scene.instance_count(),
            resolution: settings.resolution.to_string(),
            msaa: settings.msaa,
            hmd: settings.hmd.clone(),
            draw_distance: settings.draw_distance,
            foveation_ratio: settings.foveation.ratio,
            mffr: format!("{} at {}", settings.mffr.name(), settings.mffr.split),
            frames: args.frames,
            warmup: args.warmup,
            interleaved,
            rows: summaries,
            baseline_resources: resources(&plans[base], scene),
            accuracy,
            samples,
        }
    }

    /// Prints the tables and writes every file into `out` (and `csv`/`json` where asked).
    pub fn write(&self, out: &Path, csv: Option<&Path>, json: Option<&Path>) -> Result<()> {
        let tables = self.tables();
        print!("{tables}");
        let write = |name: &str, text: &str| -> Result<()> {
            let path = out.join(name);
            foveate::write_atomic(&path, text.as_bytes()).map_err(anyhow::Error::from)
        };
        write("tables.md", &tables)?;
        let frames_csv = self.frames_csv()?;
        write("frames.csv", &frames_csv)?;
        write("summary.csv", &self.summary_csv()?)?;
        write("accuracy.csv", &super::accuracy::csv(&self.accuracy)?)?;
        let json_text = serde_json::to_string_pretty(self)?;
        write("bench.json", &json_text)?;
        for (path, text) in [(csv, &frames_csv), (json, &json_text)] {
            match path {
                Some(p) if p == Path::new("-") => println!("{text}"),
                Some(p) => foveate::write_atomic(p, text.as_bytes())?,
                None => {}
            }
        }
        super::plots::all(self, out)?;
        eprintln!(
            "wrote tables.md, frames.csv, summary.csv, accuracy.csv, bench.json and plots to {}",
            out.display()
        );
        Ok(())
    }

    fn tables(&self) -> String {
        let mut t = String::new();
        let _ = writeln!(
            t,
            "# foveate bench\n\n{} ({}); thesis scene at scale {} ({} instances), {} per eye, {}x MSAA, {} profile, draw distance {}, foveation ratio {}, MFFR {}; {} frames along the rails per configuration after {} warm-up frames{}.\n",
            self.device,
            self.driver,
            self.scale,
            self.instances,
            self.resolution,
            self.msaa,
            self.hmd,
            self.draw_distance,
            self.foveation_ratio,
            self.mffr,
            self.frames,
            self.warmup,
            if self.interleaved {
                ", configurations interleaved frame by frame"
            } else {
                ", one configuration after another"
            }
        );
        self.time_tables(&mut t);
        self.per_frame_table(&mut t);
        self.memory_tables(&mut t);
        if !self.accuracy.is_empty() {
            t.push('\n');
            t.push_str(&super::accuracy::table(&self.accuracy));
        }
        if let Some(best) = self
            .rows
            .iter()
            .filter(|r| r.toggles.is_some())
            .min_by(|a, b| a.ratio_median.total_cmp(&b.ratio_median))
        {
            let _ = writeln!(
                t,
                "\nBest configuration: {} at {:.3}x the baseline's median frame time ({:.2} ms against {:.2} ms).",
                best.name, best.ratio_median, best.frame_ms.median, self.rows[0].frame_ms.median
            );
        }
        t
    }

    /// The time tables, one per group of configurations.
    fn time_tables(&self, t: &mut String) {
        type Keep<'a> = &'a dyn Fn(&RowSummary) -> bool;
        let groups: [(&str, Keep); 4] = [
            ("Individual optimisations (thesis Table 6.1 form)", &|r| {
                r.toggles
                    .is_some_and(|t| !t.foveate && t.thesis_switches() <= 1)
            }),
            ("Combined optimisations (thesis Table 6.2 form)", &|r| {
                r.toggles
                    .is_some_and(|t| !t.foveate && t.thesis_switches() > 1)
            }),
            ("With foveation", &|r| r.toggles.is_some_and(|t| t.foveate)),
            (
                "Switched-off effects cost nothing (against the baseline)",
                &|r| r.toggles.is_none(),
            ),
        ];
        for (title, keep) in groups {
            let rows: Vec<&RowSummary> = self.rows.iter().filter(|r| keep(r)).collect();
            if rows.is_empty() {
                continue;
            }
            let _ = writeln!(t, "## {title}\n\nTimes in ms; ratio: frame time over the baseline's, measured in the same run.\n");
            let _ = writeln!(t, "| config | frame median | frame avg | gpu median | gpu avg | cull median | cull avg | ratio median | ratio avg |");
            let _ = writeln!(t, "|---|---|---|---|---|---|---|---|---|");
            for r in rows {
                let _ = writeln!(
                    t,
                    "| {} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.2} | {:.3} | {:.3} |",
                    r.name,
                    r.frame_ms.median,
                    r.frame_ms.mean,
                    r.gpu_ms.median,
                    r.gpu_ms.mean,
                    r.cull_ms.median,
                    r.cull_ms.mean,
                    r.ratio_median,
                    r.ratio_mean
                );
            }
            t.push('\n');
        }
    }

    /// Per frame: CPU time, draw calls, triangles, pixels shaded.
    fn per_frame_table(&self, t: &mut String) {
        let _ = writeln!(
            t,
            "## Per frame: CPU time, draw calls, triangles, pixels shaded (medians)\n"
        );
        let _ = writeln!(t, "Timed frames run one at a time (each recorded, submitted and waited for: one frame in flight), so a frame time is one frame's whole cost. CPU: culling, recording and submission. Draw calls and triangles: as recorded by the timed frames (a multiview draw counts once). Pixels: fragments shaded, counted on every sampled frame by a separate counting renderer (timed frames carry no counters) — by the scene draws in all views, and by every pass (mask fans, MFFR far composite, foveated composition included).\n");
        let _ = writeln!(
            t,
            "| config | cpu ms | draw calls | triangles | scene pixels | vs baseline | all passes' pixels | vs baseline |"
        );
        let _ = writeln!(t, "|---|---|---|---|---|---|---|---|");
        let base_pixels = self.rows[0].pixels.map(|p| p.median);
        let base_total = self.rows[0].total_pixels.map(|p| p.median);
        let cells = |px: Option<f64>, base: Option<f64>| {
            (
                px.map_or("–".into(), |p| format!("{p:.0}")),
                px.zip(base)
                    .map_or("–".into(), |(p, b)| format!("{:.3}", p / b)),
            )
        };
        for r in &self.rows {
            let (scene, scene_ratio) = cells(r.pixels.map(|p| p.median), base_pixels);
            let (total, total_ratio) = cells(r.total_pixels.map(|p| p.median), base_total);
            let _ = writeln!(
                t,
                "| {} | {:.2} | {:.0} | {:.0} | {scene} | {scene_ratio} | {total} | {total_ratio} |",
                r.name, r.cpu_ms.median, r.draw_calls.median, r.triangles.median,
            );
        }
    }

    /// The baseline's resources, and each configuration's memory and traffic.
    fn memory_tables(&self, t: &mut String) {
        let _ = writeln!(t, "\n## Memory and traffic (thesis Table 6.3 in form)\n");
        let _ = writeln!(t, "The baseline frame's resources:\n");
        let _ = writeln!(t, "| resource | what | MiB | kind |");
        let _ = writeln!(t, "|---|---|---|---|");
        for r in &self.baseline_resources {
            let _ = writeln!(
                t,
                "| {} | {} | {:.2} | {} |",
                r.name,
                r.description,
                mib(r.bytes),
                r.kind
            );
        }
        let _ = writeln!(t, "\nPer configuration: attachments resident and transient (planned), effect-only buffers, device memory the renderer allocated (measured from the allocator, scene buffers included) and the plan's estimate of external memory traffic per frame on a tile GPU.\n");
        let _ = writeln!(
            t,
            "| config | resident MiB | transient MiB | effect buffers KiB | allocated MiB | traffic MiB/frame | adds to the baseline |"
        );
        let _ = writeln!(t, "|---|---|---|---|---|---|---|");
        for r in &self.rows {
            let m = &r.memory;
            let added = if m.plan_is_baseline {
                "nothing: planned exactly as the baseline".to_string()
            } else if m.added.is_empty() {
                "no attachment".to_string()
            } else {
                m.added.join(", ")
            };
            let _ = writeln!(
                t,
                "| {} | {:.2} | {:.2} | {:.1} | {:.2} | {:.2} | {} |",
                r.name,
                mib(m.resident_bytes),
                mib(m.transient_bytes),
                m.effect_buffer_bytes as f64 / 1024.0,
                mib(m.allocated_bytes),
                mib(m.traffic_bytes),
                added
            );
        }
    }

    fn frames_csv(&self) -> Result<String> {
        let mut csv = CsvTable::new(&[
            "config",
            "rail_frame",
            "frame_ms",
            "cpu_ms",
            "cull_ms",
            "gpu_ms",
            "draw_calls",
            "triangles",
            "far_triangles",
            "pixels",
            "total_pixels",
        ])?;
        let count = |c: Option<u64>| c.map_or(String::new(), |p| p.to_string());
        for s in &self.samples {
            csv.row(&[
                &self.rows[s.config].name,
                &s.rail_frame,
                &format!("{:.4}", s.frame_ms),
                &format!("{:.4}", s.cpu_ms),
                &format!("{:.4}", s.cull_ms),
                &format!("{:.4}", s.gpu_ms),
                &s.draw_calls,
                &s.triangles,
                &s.far_triangles,
                &count(s.pixels),
                &count(s.total_pixels),
            ])?;
        }
        csv.into_string()
    }

    fn summary_csv(&self) -> Result<String> {
        let mut csv = CsvTable::new(&[
            "config",
            "frame_median_ms",
            "frame_mean_ms",
            "gpu_median_ms",
            "gpu_mean_ms",
            "cull_median_ms",
            "cull_mean_ms",
            "cpu_median_ms",
            "draw_calls",
            "triangles",
            "far_triangles",
            "pixels",
            "total_pixels",
            "ratio_median",
            "ratio_mean",
            "resident_bytes",
            "transient_bytes",
            "effect_buffer_bytes",
            "allocated_bytes",
            "traffic_bytes",
        ])?;
        let f4 = |v: f64| format!("{v:.4}");
        let median = |s: Option<Summary>| opt(s.map(|p| p.median), 0);
        for r in &self.rows {
            let m = &r.memory;
            csv.row(&[
                &r.name,
                &f4(r.frame_ms.median),
                &f4(r.frame_ms.mean),
                &f4(r.gpu_ms.median),
                &f4(r.gpu_ms.mean),
                &f4(r.cull_ms.median),
                &f4(r.cull_ms.mean),
                &f4(r.cpu_ms.median),
                &format!("{:.0}", r.draw_calls.median),
                &format!("{:.0}", r.triangles.median),
                &format!("{:.0}", r.far_triangles.median),
                &median(r.pixels),
                &median(r.total_pixels),
                &f4(r.ratio_median),
                &f4(r.ratio_mean),
                &m.resident_bytes,
                &m.transient_bytes,
                &m.effect_buffer_bytes,
                &m.allocated_bytes,
                &m.traffic_bytes,
            ])?;
        }
        csv.into_string()
    }
}

/// The baseline's attachments and buffers, as the thesis lists its VRAM (Table 6.3).
fn resources(plan: &FramePlan, scene: &Scene) -> Vec<Resource> {
    let mut out: Vec<Resource> = plan
        .attachments
        .iter()
        .map(|a| Resource {
            name: a.name.to_string(),
            description: format!(
                "{:?} {}x, {} layer(s) of {}x{}",
                a.format, a.samples, a.layers, a.width, a.height
            ),
            bytes: a.bytes(),
            kind: if a.transient {
                "transient attachment"
            } else {
                "resident attachment"
            },
        })
        .collect();
    let vertices: usize = scene.meshes.iter().map(|m| m.vertices.len()).sum();
    let indices: usize = scene.meshes.iter().map(|m| m.indices.len()).sum();
    let size = std::mem::size_of::<Instance>();
    out.push(Resource {
        name: "vertices + indices".into(),
        description: format!("{} meshes", scene.meshes.len()),
        bytes: (vertices * std::mem::size_of::<Vertex>() + indices * 4) as u64,
        kind: "scene buffer",
    });
    out.push(Resource {
        name: "instances".into(),
        description: format!("model matrix + colour, {size} B per instance"),
        bytes: (scene.instance_count() * size) as u64,
        kind: "scene buffer",
    });
    out.extend(plan.buffers.iter().map(|b| Resource {
        name: b.name.to_string(),
        description: "per frame".into(),
        bytes: b.bytes,
        kind: "effect buffer",
    }));
    out
}
