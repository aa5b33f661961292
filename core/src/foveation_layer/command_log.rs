//! A [`Recorder`] that keeps what a frame records as a list of commands: the recording of any
//! plan, read without a GPU (tests, and anyone checking what a configuration records).

use super::record::record_frame;
use super::recorder::{FrameDraws, Recorder, Rect};
use crate::plan::{Barrier, ClearValue, FramePlan, Step};
use crate::scene::{Draw, Scene};

/// One recorded command, in the renderer's terms.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    ResetQueries(u32),
    Timestamp(u32),
    ClearCounters,
    BeginStatistics(usize),
    EndStatistics(usize),
    CountersBarrier,
    CountersToHost,
    /// A pass begins once what it waits on is done.
    BeginPass {
        pass: usize,
        clears: Vec<ClearValue>,
        wait: Vec<Barrier>,
    },
    /// A pass ends; what touches its images next waits on `signal`.
    EndPass {
        pass: usize,
        signal: Vec<Barrier>,
    },
    /// A step's pipeline and resources bound (the step as the plan has it).
    BindStep {
        pass: usize,
        step: Step,
    },
    BindGeometry,
    SetViewport {
        area: Rect,
        guard_band: u32,
    },
    PushVertex(u32),
    PushFragment(u32),
    StencilReference(u32),
    Draw(u32),
    DrawIndexed {
        mesh: usize,
        instance_count: u32,
        first_instance: u32,
    },
    /// The engine draws its own world into a pass's views (a `FoveationLayer`'s frame).
    EngineDraws {
        pass: usize,
    },
}

/// The commands one frame of a plan records.
pub struct CommandLog<'p> {
    plan: &'p FramePlan,
    pub commands: Vec<Command>,
}

impl<'p> CommandLog<'p> {
    /// Records one frame of `plan` over `scene`'s draws. Culled steps draw every instance (the
    /// log shows what is recorded, not what a cull would keep).
    pub fn record(plan: &'p FramePlan, scene: &Scene) -> Self {
        let all: Vec<Draw> = scene.draws().collect();
        let culled = vec![all.clone(); plan.cull_slots.len()];
        let mut log = CommandLog {
            plan,
            commands: Vec::new(),
        };
        record_frame(
            plan,
            &FrameDraws::Scene {
                all: &all,
                culled: &culled,
            },
            &mut log,
        );
        log
    }

    /// Records one frame of `plan` whose scene steps an engine draws.
    pub fn record_engine(plan: &'p FramePlan) -> Self {
        let mut log = CommandLog {
            plan,
            commands: Vec::new(),
        };
        record_frame(plan, &FrameDraws::Engine, &mut log);
        log
    }
}

impl Recorder for CommandLog<'_> {
    fn reset_queries(&mut self, count: u32) {
        self.commands.push(Command::ResetQueries(count));
    }
    fn timestamp(&mut self, index: u32) {
        self.commands.push(Command::Timestamp(index));
    }
    fn clear_counters(&mut self, _statistics: u32) {
        self.commands.push(Command::ClearCounters);
    }
    fn begin_statistics(&mut self, pass: usize) {
        self.commands.push(Command::BeginStatistics(pass));
    }
    fn end_statistics(&mut self, pass: usize) {
        self.commands.push(Command::EndStatistics(pass));
    }
    fn counters_barrier(&mut self) {
        self.commands.push(Command::CountersBarrier);
    }
    fn counters_to_host(&mut self) {
        self.commands.push(Command::CountersToHost);
    }
    fn begin_pass(&mut self, pass: usize, clears: &[ClearValue], wait: &[Barrier]) {
        self.commands.push(Command::BeginPass {
            pass,
            clears: clears.to_vec(),
            wait: wait.to_vec(),
        });
    }
    fn end_pass(&mut self, pass: usize, signal: &[Barrier]) {
        self.commands.push(Command::EndPass {
            pass,
            signal: signal.to_vec(),
        });
    }
    fn bind_step(&mut self, pass: usize, step: usize) {
        self.commands.push(Command::BindStep {
            pass,
            step: self.plan.passes[pass].steps[step],
        });
    }
    fn bind_geometry(&mut self) {
        self.commands.push(Command::BindGeometry);
    }
    fn set_viewport(&mut self, area: Rect, guard_band: u32) {
        self.commands
            .push(Command::SetViewport { area, guard_band });
    }
    fn push_vertex(&mut self, value: u32) {
        self.commands.push(Command::PushVertex(value));
    }
    fn push_fragment(&mut self, value: u32) {
        self.commands.push(Command::PushFragment(value));
    }
    fn stencil_reference(&mut self, reference: u32) {
        self.commands.push(Command::StencilReference(reference));
    }
    fn draw(&mut self, vertices: u32) {
        self.commands.push(Command::Draw(vertices));
    }
    fn draw_indexed(&mut self, mesh: usize, instance_count: u32, first_instance: u32) {
        self.commands.push(Command::DrawIndexed {
            mesh,
            instance_count,
            first_instance,
        });
    }
    fn engine_draws(&mut self, pass: usize, _step: usize) {
        self.commands.push(Command::EngineDraws { pass });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::foveation::FoveationConfig;
    use crate::mffr::{MffrConfig, MffrOrder};
    use crate::plan::{
        DeviceCaps, FoveaLayout, OutputStage, RenderConfig, Resolution, StereoMode, SKY,
    };
    use crate::scene::default_scene;

    fn log_of(config: &RenderConfig) -> (FramePlan, Vec<Command>) {
        let scene = default_scene();
        let plan = crate::plan(&scene, config, &DeviceCaps::generic()).unwrap();
        let commands = CommandLog::record(&plan, &scene).commands;
        (plan, commands)
    }

    fn base() -> RenderConfig {
        RenderConfig {
            resolution: Some(Resolution::square(64)),
            timestamps: false,
            ..RenderConfig::default()
        }
    }

    /// The commands with draws and state left out: passes and steps in order.
    fn outline(commands: &[Command]) -> Vec<String> {
        commands
            .iter()
            .filter_map(|c| match c {
                Command::BeginPass { pass, .. } => Some(format!("begin {pass}")),
                Command::EndPass { pass, .. } => Some(format!("end {pass}")),
                Command::BindStep { step, .. } => {
                    Some(step.to_string().split(" [").next().unwrap().to_string())
                }
                Command::ClearCounters => Some("clear counters".into()),
                Command::CountersBarrier => Some("counters barrier".into()),
                Command::CountersToHost => Some("counters to host".into()),
                Command::Timestamp(i) => Some(format!("timestamp {i}")),
                _ => None,
            })
            .collect()
    }

    /// Step order per configuration. Mutation: the executor recording the far composite
    /// before the scene in near-first, the probe before the scene, the composition in the
    /// scene pass, or the fovea pass drawing the periphery's set fails it.
    #[test]
    fn steps_are_recorded_in_the_plans_order() {
        let (_, plain) = log_of(&base());
        assert_eq!(outline(&plain), ["begin 0", "scene", "end 0"]);
        let (_, lens) = log_of(&RenderConfig {
            output: OutputStage::Lens,
            ..base()
        });
        assert_eq!(
            outline(&lens),
            [
                "begin 0",
                "scene",
                "end 0",
                "begin 1",
                "output (eye images, lens-distorted)",
                "end 1"
            ]
        );
        let foveated = |fovea_layout| RenderConfig {
            foveation: Some(FoveationConfig::single_frame()),
            hmd_mask: true,
            fovea_layout,
            ..base()
        };
        let (_, log) = log_of(&foveated(FoveaLayout::OnePass));
        assert_eq!(
            outline(&log),
            [
                "begin 0",
                "mask fans",
                "scene (cull slot 0)",
                "end 0",
                "begin 1",
                "output (fovea over periphery, undistorted)",
                "end 1"
            ]
        );
        let (_, log) = log_of(&foveated(FoveaLayout::TwoPass));
        assert_eq!(
            outline(&log),
            [
                "begin 0",
                "mask fans",
                "scene",
                "end 0",
                "begin 1",
                "mask fans",
                "scene (cull slot 0)",
                "end 1",
                "begin 2",
                "output (fovea over periphery, undistorted)",
                "end 2"
            ]
        );
        for (order, expected) in [
            (MffrOrder::NearFirst, ["scene", "far composite"]),
            (MffrOrder::FarFirst, ["far composite", "scene"]),
        ] {
            let (_, log) = log_of(&RenderConfig {
                mffr: Some(MffrConfig {
                    order,
                    ..MffrConfig::default()
                }),
                ..base()
            });
            let outline = outline(&log);
            assert_eq!(outline[..3], ["begin 0", "scene (cull slot 0)", "end 0"]);
            let eye: Vec<&str> = outline[4..6]
                .iter()
                .map(|s| s.split(" (").next().unwrap())
                .collect();
            assert_eq!(eye, expected, "{order:?}");
        }
    }

    /// A switched-off effect records nothing: no stencil reference, no mask fans, no push for
    /// a composite, no counter, no timestamp in the plain frame; switched on, each appears.
    /// Mutation: an executor clearing counters or writing timestamps unconditionally fails it.
    #[test]
    fn effects_that_are_off_record_nothing() {
        let (_, plain) = log_of(&base());
        let has = |log: &[Command], f: &dyn Fn(&Command) -> bool| log.iter().any(f);
        assert!(!has(&plain, &|c| matches!(
            c,
            Command::StencilReference(_)
                | Command::PushFragment(_)
                | Command::ClearCounters
                | Command::CountersBarrier
                | Command::CountersToHost
                | Command::Timestamp(_)
                | Command::ResetQueries(_)
                | Command::Draw(_)
        )));
        let (_, masked) = log_of(&RenderConfig {
            hmd_mask: true,
            ..base()
        });
        assert!(has(&masked, &|c| matches!(c, Command::StencilReference(1))));
        let (plan, timed) = log_of(&RenderConfig {
            timestamps: true,
            ..base()
        });
        assert_eq!(timed.first(), Some(&Command::ResetQueries(2)));
        assert_eq!(timed.last(), Some(&Command::Timestamp(1)));
        // Where queries after a multiview pass span its views, the whole pool is reset, its
        // spare slots too (lavapipe 25 writes them).
        let scene = default_scene();
        let mut quirky = DeviceCaps::generic();
        quirky.quirks.queries_after_multiview_span_views = true;
        let config = RenderConfig {
            timestamps: true,
            ..base()
        };
        let spanning = crate::plan(&scene, &config, &quirky).unwrap();
        let commands = CommandLog::record(&spanning, &scene).commands;
        assert_eq!(commands.first(), Some(&Command::ResetQueries(2 + 1)));
        assert_eq!(plan.timestamp_queries, spanning.timestamp_queries);
    }

    /// Counting frames: the counters cleared before the first pass, a barrier after every
    /// pass (one pass's atomics before the next's), made visible to the host at the end.
    /// Mutation: a missing barrier between the scene and the composition fails it.
    #[test]
    fn counting_frames_fence_their_counters() {
        let (_, log) = log_of(
            &RenderConfig {
                foveation: Some(FoveationConfig::single_frame()),
                fovea_layout: FoveaLayout::OnePass,
                ..base()
            }
            .counting(),
        );
        assert_eq!(
            outline(&log),
            [
                "clear counters",
                "begin 0",
                "mask fans",
                "scene (cull slot 0)",
                "end 0",
                "counters barrier",
                "begin 1",
                "output (fovea over periphery, undistorted)",
                "end 1",
                "counters barrier",
                "counters to host"
            ]
        );
    }

    /// Each pass begins with the plan's clear values: the scene pass clears colour to the sky
    /// and depth to the far plane; composition, which overwrites every pixel, clears nothing.
    /// Mutation: clear values handed to a pass that loads or overwrites fails it.
    #[test]
    fn passes_begin_with_the_plans_clears() {
        let (_, log) = log_of(&RenderConfig {
            foveation: Some(FoveationConfig::single_frame()),
            fovea_layout: FoveaLayout::OnePass,
            msaa: 1,
            ..base()
        });
        let clears: Vec<&Vec<ClearValue>> = log
            .iter()
            .filter_map(|c| match c {
                Command::BeginPass { clears, .. } => Some(clears),
                _ => None,
            })
            .collect();
        assert_eq!(
            clears,
            [
                &vec![
                    ClearValue::Color(SKY),
                    ClearValue::DepthStencil {
                        depth: 0.0,
                        stencil: 0
                    }
                ],
                &Vec::new()
            ]
        );
    }

    /// Per-object stereo draws every instance twice, once per eye's half of the image with the
    /// eye's index pushed; instanced stereo doubles instance counts. Mutation: per-object
    /// drawing each object once, or instanced not doubling, fails it.
    #[test]
    fn submissions_record_as_their_strategy_says() {
        let scene = default_scene();
        let instances: u32 = scene.draws().map(|d| d.instance_count).sum();
        let drawn = |log: &[Command]| -> (u32, usize) {
            let mut total = 0;
            let mut calls = 0;
            for c in log {
                if let Command::DrawIndexed { instance_count, .. } = c {
                    total += instance_count;
                    calls += 1;
                }
            }
            (total, calls)
        };
        let (_, per_object) = log_of(&RenderConfig {
            stereo: StereoMode::PerObject,
            ..base()
        });
        assert_eq!(drawn(&per_object), (2 * instances, 2 * instances as usize));
        let pushes: Vec<u32> = per_object
            .iter()
            .filter_map(|c| match c {
                Command::PushVertex(v) => Some(*v),
                _ => None,
            })
            .take(4)
            .collect();
        assert_eq!(pushes, [0, 1, 0, 1], "left and right eye alternate");
        let (_, instanced) = log_of(&RenderConfig {
            stereo: StereoMode::Instanced,
            ..base()
        });
        assert_eq!(drawn(&instanced).0, 2 * instances);
        let (_, two_pass) = log_of(&RenderConfig {
            stereo: StereoMode::TwoPass,
            ..base()
        });
        assert_eq!(
            drawn(&two_pass).0,
            2 * instances,
            "the scene once per eye pass"
        );
    }

    /// Radial density masking records its mask before the scene and its reconstruction as a
    /// pass of its own. Mutation: the mask recorded after the scene fails it.
    #[test]
    fn radial_density_masks_before_the_scene_and_reconstructs_after() {
        let (_, log) = log_of(&RenderConfig {
            radial_density: Some(crate::plan::RadialDensity::default()),
            ..base()
        });
        assert_eq!(
            outline(&log),
            [
                "begin 0",
                "radial mask",
                "scene",
                "end 0",
                "begin 1",
                "reconstruct",
                "end 1"
            ]
        );
    }

    /// Each pass's barriers as recorded where it begins and ends.
    fn barriers(commands: &[Command]) -> (Vec<Vec<Barrier>>, Vec<Vec<Barrier>>) {
        let (mut waits, mut signals) = (Vec::new(), Vec::new());
        for c in commands {
            match c {
                Command::BeginPass { wait, .. } => waits.push(wait.clone()),
                Command::EndPass { signal, .. } => signals.push(signal.clone()),
                _ => {}
            }
        }
        (waits, signals)
    }

    /// A foveated frame: the output pass samples the scene pass's resolve only after the scene
    /// pass ends, the readback follows the output pass, and the on-tile MSAA image only waits on
    /// its own previous frame. Mutation: the sampled touch left out of `derive_barriers`, or
    /// barriers recorded with the wrong pass, fails it (and synchronization validation fails
    /// the Vulkan tests).
    #[test]
    fn each_pass_records_the_barriers_its_images_need() {
        use crate::plan::Touch::*;
        let (plan, commands) = log_of(&RenderConfig {
            msaa: 4,
            foveation: Some(FoveationConfig::single_frame()),
            fovea_layout: FoveaLayout::OnePass,
            output: OutputStage::Lens,
            ..base()
        });
        let (waits, signals) = barriers(&commands);
        for (i, pass) in plan.passes.iter().enumerate() {
            assert_eq!(
                (&waits[i], &signals[i]),
                (&pass.barriers.wait, &pass.barriers.signal)
            );
        }
        let barrier = |attachment, from, to| Barrier {
            attachment,
            from,
            to,
        };
        let (msaa, depth) = (
            plan.passes[0].color.attachment,
            plan.passes[0].depth.unwrap(),
        );
        let views = plan.passes[0].resolve.unwrap().attachment;
        let output = plan.passes[1].color.attachment;
        assert_eq!(
            signals[0],
            [
                barrier(msaa, ColourAttachment, ColourAttachment),
                barrier(depth.attachment, DepthAttachment, DepthAttachment),
                barrier(views, ColourAttachment, Sampled),
            ]
        );
        assert_eq!(
            waits[1],
            [
                barrier(views, ColourAttachment, Sampled),
                barrier(output, ReadAfterFrame, ColourAttachment),
            ]
        );
        assert_eq!(
            signals[1],
            [
                barrier(views, Sampled, ColourAttachment),
                barrier(output, ColourAttachment, ReadAfterFrame),
            ]
        );
    }

    /// Two-pass stereo: the eye passes share the on-tile scratch images, so the second waits on
    /// the first; each resolves into its own layer of the eye image, so neither waits on the
    /// other's resolve. Mutation: touches compared without their layers fails it.
    #[test]
    fn two_pass_eyes_wait_on_each_other_only_for_the_images_they_share() {
        use crate::plan::Touch::*;
        let (plan, commands) = log_of(&RenderConfig {
            stereo: StereoMode::TwoPass,
            msaa: 4,
            ..base()
        });
        let (waits, _) = barriers(&commands);
        let (left, right) = (&plan.passes[0], &plan.passes[1]);
        let eyes = right.resolve.unwrap().attachment;
        assert_eq!(left.resolve.unwrap().attachment, eyes, "one layered image");
        assert_eq!(
            waits[1],
            [
                Barrier {
                    attachment: right.color.attachment,
                    from: ColourAttachment,
                    to: ColourAttachment
                },
                Barrier {
                    attachment: right.depth.unwrap().attachment,
                    from: DepthAttachment,
                    to: DepthAttachment
                },
                Barrier {
                    attachment: eyes,
                    from: ReadAfterFrame,
                    to: ColourAttachment
                },
            ]
        );
    }
}
