//! One motion measured: every configuration's renderer frame by frame beside the reference's,
//! flicker on every frame and eFLIP on the judged ones.

use std::cell::Cell;
use std::time::Instant;

use anyhow::Result;
use foveate::gpu::Gpu;
use foveate::judge::{GpuFlicker, GpuFlip};
use foveate::metrics::perceptual::{perceptual_error, Maps};
use foveate::metrics::temporal::{Flicker, FlickerSummary};
use foveate::metrics::{Acuity, Stats};
use foveate::plan::RenderConfig;
use foveate::render::{HistoryOutcomes, Renderer};
use foveate::scene::Walker;

use super::motion::{Motion, RATE_HZ};
use super::rows::{AlongMotion, Judged, Row};
use crate::history_table::OutcomesAlong;
use crate::region_maps::RegionMaps;
use crate::side_by_side::settle;

/// One configuration's flicker along a motion: measured on the GPU where the frames lie (the
/// default), or on frames read back, by the CPU measure (`--metric cpu`, its oracle).
enum Meter {
    Gpu(Box<GpuFlicker>),
    Cpu(Flicker),
}

impl Meter {
    fn new(gpu: &Gpu) -> Result<Self> {
        Ok(match crate::metric::chosen() {
            crate::metric::Metric::Gpu => Meter::Gpu(Box::new(GpuFlicker::new(gpu)?)),
            crate::metric::Metric::Cpu => Meter::Cpu(Flicker::default()),
        })
    }

    fn summary(&self) -> FlickerSummary {
        match self {
            Meter::Gpu(m) => m.summary(),
            Meter::Cpu(m) => m.summary(),
        }
    }
}

/// What measuring one motion needs: every configuration's renderer is made from these.
pub(super) struct MotionRun<'a> {
    pub(super) gpu: &'a Gpu,
    pub(super) scene: &'a foveate::scene::Scene,
    /// The reference's plan, then each configuration's.
    pub(super) plans: &'a [foveate::plan::FramePlan],
    pub(super) configs: &'a [(String, RenderConfig)],
    /// The walker crossing the view, when there is one: every renderer moves it each frame.
    pub(super) walker: Option<Walker>,
    /// Judge every Nth frame with eFLIP.
    pub(super) flip: Option<u32>,
    pub(super) bar: &'a indicatif::ProgressBar,
    pub(super) spent: &'a Spent,
}

/// Where a run's wall time went: rendering the frames (and, with `--metric cpu`, reading them
/// back), mapping the regions at each new gaze (on the CPU), measuring flicker, judging with
/// eFLIP (and how many judgements).
#[derive(Default)]
pub(super) struct Spent {
    rendering_s: Cell<f64>,
    maps_s: Cell<f64>,
    flicker_s: Cell<f64>,
    judging_s: Cell<f64>,
    judgements: Cell<u64>,
}

impl Spent {
    fn add(cell: &Cell<f64>, since: Instant) {
        cell.set(cell.get() + since.elapsed().as_secs_f64());
    }

    pub(super) fn describe(&self) -> String {
        let judged = match self.judgements.get() {
            0 => String::new(),
            n => format!(
                ", judging {:.0} s ({n} judgements of both eyes, {:.2} s each)",
                self.judging_s.get(),
                self.judging_s.get() / n as f64
            ),
        };
        format!(
            "time: rendering {:.0} s, region maps {:.0} s, flicker {:.0} s{judged}",
            self.rendering_s.get(),
            self.maps_s.get(),
            self.flicker_s.get()
        )
    }
}

impl MotionRun<'_> {
    /// Every configuration along `motion`, frames interleaved with the reference's: one row
    /// each; `None` when interrupted.
    pub(super) fn measure(&self, motion: &Motion) -> Result<Option<Vec<Row>>> {
        let mut rows = Vec::new();
        let (first_pose, first_gaze) = motion.frames[0];
        let mut renderers = Vec::new();
        for plan in self.plans {
            let mut renderer = Renderer::new(self.gpu, plan, self.scene)?;
            renderer.set_gaze([first_gaze; 2])?;
            if let Some(w) = self.walker {
                renderer.move_instance(w.instance, w.model(0.0))?;
            }
            settle(&mut renderer, first_pose)?;
            renderers.push(renderer);
        }
        let mut meters = (self.configs.iter())
            .map(|_| Meter::new(self.gpu))
            .collect::<Result<Vec<_>>>()?;
        let on_cpu = meters.iter().any(|m| matches!(m, Meter::Cpu(_)));
        let mut judged: Vec<Vec<Judged>> = self.configs.iter().map(|_| Vec::new()).collect();
        let mut history: Vec<Vec<HistoryOutcomes>> =
            self.configs.iter().map(|_| Vec::new()).collect();
        // Every renderer's frame times, the reference's first (counting renderers: none).
        let mut times: Vec<Vec<f64>> = renderers.iter().map(|_| Vec::new()).collect();
        // On the GPU both measures read the frames where they lie; on the CPU (`--metric cpu`)
        // every frame is read back.
        let mut in_place = GpuFlip::new(self.gpu);
        let mut on_host = crate::metric::flip_mapper(self.gpu);
        let mut maps = RegionMaps::default();
        for (frame, &(pose, gaze)) in motion.frames.iter().enumerate() {
            if crate::interrupt::requested() {
                return Ok(None);
            }
            // Frames of every configuration interleaved, the reference first; read back only
            // for the measures on the host.
            self.bar
                .set_message(format!("{}: rendering", motion.name()));
            let rendering = Instant::now();
            let judge_now = self.flip.is_some_and(|every| frame % every as usize == 0);
            let mut images = Vec::new();
            for (r, renderer) in renderers.iter_mut().enumerate() {
                renderer.set_gaze([gaze; 2])?;
                if let Some(w) = self.walker {
                    renderer.move_instance(w.instance, w.model(frame as f32 / RATE_HZ as f32))?;
                }
                let stats = renderer.render_frame(pose)?;
                if !renderer.plan().count_fragments() {
                    times[r].push(stats.frame_ms);
                }
                if let (Some(outcomes), Some(r)) = (stats.history, r.checked_sub(1)) {
                    history[r].push(outcomes);
                }
                if on_cpu {
                    images.push(renderer.readback()?);
                }
            }
            Spent::add(&self.spent.rendering_s, rendering);
            let mapping = Instant::now();
            maps.look_at(gaze, &self.plans[1..]);
            Spent::add(&self.spent.maps_s, mapping);
            for (i, meter) in meters.iter_mut().enumerate() {
                let pixels = maps.of(i);
                let measuring = Instant::now();
                match meter {
                    Meter::Gpu(m) => m.push(&renderers[0], &renderers[i + 1], pixels)?,
                    Meter::Cpu(m) => m.push(images[0].eyes(), images[i + 1].eyes(), pixels)?,
                }
                Spent::add(&self.spent.flicker_s, measuring);
                if judge_now {
                    self.bar.set_message(format!("{}: judging", motion.name()));
                    let judging = Instant::now();
                    let (reference, approximation) = (&renderers[0], &renderers[i + 1]);
                    let acuity = Acuity::default();
                    let error = match on_cpu {
                        false => in_place.frame_errors(
                            reference,
                            approximation,
                            pixels,
                            acuity,
                            Maps::Drop,
                        )?,
                        true => perceptual_error(
                            images[0].eyes(),
                            images[i + 1].eyes(),
                            pixels,
                            acuity,
                            &mut *on_host,
                            Maps::Drop,
                        )?,
                    };
                    Spent::add(&self.spent.judging_s, judging);
                    self.spent.judgements.set(self.spent.judgements.get() + 1);
                    judged[i].extend(error.eccentric.map(|all| (all, error.regions)));
                }
            }
            self.bar.inc(1);
        }
        let median = |t: &[f64]| Stats::of(t).map(|s| s.median);
        let reference_ms = median(&times[0]);
        let along = self.configs.iter().zip(&meters).zip(&judged).zip(history);
        for (i, ((((name, config), meter), frames), history)) in along.enumerate() {
            let frame_ms = median(&times[i + 1]);
            rows.push(Row {
                motion: motion.name(),
                name: name.clone(),
                foveated: config.foveation.is_some(),
                frame_ms,
                ratio: frame_ms.zip(reference_ms).map(|(t, r)| t / r),
                traffic_bytes: self.plans[i + 1].external_traffic_bytes(),
                flicker: meter.summary(),
                accuracy: AlongMotion::of(frames),
                history: (!history.is_empty()).then(|| OutcomesAlong {
                    motion: motion.name(),
                    config: name.clone(),
                    frames: history,
                }),
            });
        }
        Ok(Some(rows))
    }
}
