//! An engine's mistakes with a `FoveationLayer`, each caught where it happens as an error that
//! names it, not drawn as a wrong frame or a crash: a frame's views recorded for another gaze
//! or twice, a slot whose frame has not finished, a layer dropped with its frame running, a head
//! pose that is not one, the judge on a layer with no frame or with an acuity that is none.
//! A device found lost makes every later call an error naming it. Validation is on; any
//! message fails the test. The engine draws nothing (its draws are not
//! what is checked): the layer's masks and output stage run as ever.

use foveate::ash::vk;
use foveate::foveation::FoveationConfig;
use foveate::glam::{Mat4, Vec2, Vec3};
use foveate::gpu::{Gpu, GpuError, GpuOptions};
use foveate::judge::GpuFlip;
use foveate::metrics::perceptual::Maps;
use foveate::metrics::{Acuity, EyePixels, JudgeError};
use foveate::plan::{OutputStage, RenderConfig, Resolution};
use foveate::render::{FoveationLayer, FrameInput, FrameViewSet};

fn gpu() -> Gpu {
    let options = GpuOptions {
        validation: true,
        device: std::env::var("FOVEATE_DEVICE").ok(),
        pipeline_cache: None,
        display: None,
    };
    Gpu::new(&options).expect("a Vulkan device with VK_LAYER_KHRONOS_validation (see README)")
}

/// A small foveated frame through the lens, two slots.
fn layer(gpu: &Gpu) -> FoveationLayer {
    let config = RenderConfig {
        hmd: "quest-pro".into(),
        resolution: Some(Resolution::square(64)),
        foveation: Some(FoveationConfig::single_frame()),
        output: OutputStage::Lens,
        frames_in_flight: 2,
        ..RenderConfig::default()
    };
    FoveationLayer::new(gpu, &config).unwrap()
}

fn head() -> Mat4 {
    Mat4::from_translation(Vec3::new(0.0, 1.6, 0.0))
}

/// The engine's own command buffers (raw Vulkan, a pool of its own), a fence and the queue.
struct Commands {
    device: foveate::ash::Device,
    queue: vk::Queue,
    pool: vk::CommandPool,
    fence: vk::Fence,
}

impl Commands {
    fn new(gpu: &Gpu) -> Self {
        let device = gpu.device().clone();
        let raw = gpu.raw_handles();
        unsafe {
            let info = vk::CommandPoolCreateInfo::default().queue_family_index(raw.queue_family);
            Commands {
                queue: device.get_device_queue(raw.queue_family, raw.queue_index),
                pool: device.create_command_pool(&info, None).unwrap(),
                fence: device
                    .create_fence(&vk::FenceCreateInfo::default(), None)
                    .unwrap(),
                device,
            }
        }
    }

    /// A new command buffer, begun.
    fn begun(&self) -> vk::CommandBuffer {
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.pool)
            .command_buffer_count(1);
        unsafe {
            let cmd = self.device.allocate_command_buffers(&info).unwrap()[0];
            let begin = vk::CommandBufferBeginInfo::default();
            self.device.begin_command_buffer(cmd, &begin).unwrap();
            cmd
        }
    }

    /// Ends and submits `cmd`, signalling the fence.
    fn submit(&self, cmd: vk::CommandBuffer) {
        unsafe {
            self.device.end_command_buffer(cmd).unwrap();
            let cmds = [cmd];
            let submit = vk::SubmitInfo::default().command_buffers(&cmds);
            (self.device)
                .queue_submit(self.queue, &[submit], self.fence)
                .unwrap();
        }
    }

    /// Waits for the last submission.
    fn wait(&self) {
        unsafe {
            let fences = [self.fence];
            self.device
                .wait_for_fences(&fences, true, u64::MAX)
                .unwrap();
            self.device.reset_fences(&fences).unwrap();
        }
    }
}

impl Drop for Commands {
    fn drop(&mut self) {
        unsafe {
            self.device.device_wait_idle().unwrap();
            self.device.destroy_fence(self.fence, None);
            self.device.destroy_command_pool(self.pool, None);
        }
    }
}

/// Records the frame of `set` into `cmd`, the engine drawing nothing.
fn record(
    layer: &mut FoveationLayer,
    cmd: vk::CommandBuffer,
    set: &FrameViewSet,
) -> Result<foveate::render::FrameRecord, GpuError> {
    unsafe { layer.record(cmd, set, &mut |_| {}) }
}

/// The views of the next frame (the head at rest), recorded into `cmd`.
fn next_frame(
    layer: &mut FoveationLayer,
    cmd: vk::CommandBuffer,
) -> Result<foveate::render::FrameRecord, GpuError> {
    let set = layer.views(&FrameInput::new(head()))?;
    record(layer, cmd, &set)
}

/// The field an error names (a refused value's).
fn field(error: &GpuError) -> &str {
    match error {
        GpuError::Config(c) => c.field,
        other => panic!("not a refused value: {other}"),
    }
}

/// Views placed for one gaze and recorded after the layer's gaze moved (`set_gaze` between the
/// calls) are refused, naming the gaze; the same set recorded twice is refused, naming the
/// frame; and neither refusal records or changes anything: the next frame records. Negative
/// controls (run): without the gaze check, or without the frame check, the call is `Ok`.
#[test]
fn views_of_another_gaze_or_frame_are_refused() {
    let gpu = gpu();
    let mut layer = layer(&gpu);
    let commands = Commands::new(&gpu);
    let set = layer.views(&FrameInput::new(head())).unwrap();
    layer.set_gaze([Vec2::new(0.4, 0.0); 2]).unwrap();
    let cmd = commands.begun();
    let refused = record(&mut layer, cmd, &set).unwrap_err();
    assert_eq!(field(&refused), "gaze", "{refused}");
    assert_eq!(layer.frames_recorded(), 0);

    let set = layer.views(&FrameInput::new(head())).unwrap();
    record(&mut layer, cmd, &set).unwrap();
    let twice = record(&mut layer, cmd, &set).unwrap_err();
    assert_eq!(field(&twice), "FrameViewSet::frame", "{twice}");
    assert!(twice.to_string().contains("next frame, 1"), "{twice}");
    commands.submit(cmd);
    commands.wait();
    assert_eq!(layer.frames_recorded(), 1);
    drop(layer);
    gpu.check_validation().unwrap();
}

/// A frame recorded into a slot whose last frame has not run (recorded, not yet submitted) is
/// refused naming that frame and slot, nothing recorded; once it has run the slot takes the
/// frame. Negative control (run): without the slot's check the third frame records.
#[test]
fn a_slot_whose_frame_has_not_run_is_refused() {
    let gpu = gpu();
    let mut layer = layer(&gpu);
    let commands = Commands::new(&gpu);
    let first = commands.begun();
    next_frame(&mut layer, first).unwrap();
    let second = commands.begun();
    next_frame(&mut layer, second).unwrap();

    let third = commands.begun();
    let set = layer.views(&FrameInput::new(head())).unwrap();
    match record(&mut layer, third, &set) {
        Err(GpuError::SlotInFlight { frame: 0, slot: 0 }) => {}
        other => panic!("slot 0's frame 0 has not run, yet: {other:?}"),
    }
    assert_eq!(layer.frames_recorded(), 2, "a refused frame is not counted");
    commands.submit(first);
    commands.wait();
    record(&mut layer, third, &set).unwrap();
    commands.submit(second);
    commands.wait();
    commands.submit(third);
    commands.wait();
    drop(layer);
    gpu.check_validation().unwrap();
}

/// foveate's own renderer refuses the same way, before it writes anything of the slot (its
/// culled ids, its moving instances). Negative control (run): without `Renderer::record`'s slot
/// check the third frame records.
#[test]
fn a_renderers_slot_whose_frame_has_not_run_is_refused() {
    let gpu = gpu();
    let scene = foveate::scene::default_scene();
    let config = RenderConfig {
        resolution: Some(Resolution::square(64)),
        frames_in_flight: 2,
        ..RenderConfig::default()
    };
    let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
    let mut renderer = foveate::render::Renderer::new(&gpu, &plan, &scene).unwrap();
    let commands = Commands::new(&gpu);
    let input = FrameInput::new(scene.head);
    let cmds = [commands.begun(), commands.begun(), commands.begun()];
    for &cmd in &cmds[..2] {
        unsafe { renderer.record(cmd, &input) }.unwrap();
    }
    match unsafe { renderer.record(cmds[2], &input) } {
        Err(GpuError::SlotInFlight { frame: 0, slot: 0 }) => {}
        other => panic!("slot 0's frame 0 has not run, yet: {other:?}"),
    }
    for cmd in cmds {
        commands.submit(cmd);
        commands.wait();
    }
    drop(renderer);
    gpu.check_validation().unwrap();
}

/// A layer dropped while its frame runs on the GPU waits for it: no validation message, no
/// crash. Negative control (run): without the wait on drop the test process dies of SIGSEGV
/// (the driver's worker runs the frame on freed objects).
#[test]
fn a_layer_dropped_with_its_frame_running_waits_for_it() {
    let gpu = gpu();
    let mut layer = layer(&gpu);
    let commands = Commands::new(&gpu);
    let cmd = commands.begun();
    next_frame(&mut layer, cmd).unwrap();
    commands.submit(cmd);
    drop(layer);
    commands.wait();
    drop(commands);
    gpu.check_validation().unwrap();
}

/// A head pose that is not one — the zero matrix, a flattened one — is refused by `views`
/// (before any frame records), naming `world_from_head`. Negative control (run): with the
/// finite check alone the zero matrix is accepted.
#[test]
fn a_head_pose_that_is_not_invertible_is_refused() {
    let gpu = gpu();
    let layer = layer(&gpu);
    let flat = head() * Mat4::from_scale(Vec3::new(1.0, 0.0, 1.0));
    for pose in [Mat4::ZERO, flat] {
        let refused = layer.views(&FrameInput::new(pose)).unwrap_err();
        assert_eq!(field(&refused), "world_from_head", "{refused}");
    }
    layer.views(&FrameInput::new(head())).unwrap();
    drop(layer);
    gpu.check_validation().unwrap();
}

/// The judge refuses a layer that has rendered no frame (it would judge a blank image as
/// perfect) and an acuity that is not finite and positive (which judges every frame
/// perfect), each naming what it refused. Negative controls (run): without either check the
/// judgement is `Ok` with an eFLIP of 0.
#[test]
fn the_judge_refuses_a_layer_with_no_frame_and_an_acuity_that_is_none() {
    let gpu = gpu();
    let mut layer = layer(&gpu);
    let reference = self::layer(&gpu);
    let mut flip = GpuFlip::new(&gpu);
    let plan = layer.plan().clone();
    let gaze = Vec2::ZERO;
    let pixels = EyePixels::both(&plan, gaze, plan.foveation.as_ref());
    let acuity = Acuity::default();
    let judged = flip.frame_errors(&reference, &layer, &pixels, acuity, Maps::Drop);
    match judged {
        Err(JudgeError::Gpu(GpuError::Config(c))) => {
            assert_eq!(c.field, "reference's output", "{c}")
        }
        other => panic!("a layer with no frame judged: {other:?}"),
    }

    let mut reference = reference;
    for l in [&mut layer, &mut reference] {
        let set = l.views(&FrameInput::new(head())).unwrap();
        l.render(&set, &mut |_| {}).unwrap();
    }
    for (bad, name) in [
        (f64::NAN, "acuity.mar0_arcmin"),
        (0.0, "acuity.mar0_arcmin"),
        (-1.0, "acuity.slope_arcmin_per_deg"),
    ] {
        let acuity = match name {
            "acuity.mar0_arcmin" => Acuity {
                mar0_arcmin: bad,
                ..acuity
            },
            _ => Acuity {
                slope_arcmin_per_deg: bad,
                ..acuity
            },
        };
        let judged = flip.frame_errors(&reference, &layer, &pixels, acuity, Maps::Drop);
        match judged {
            Err(JudgeError::Gpu(GpuError::Config(c))) => assert_eq!(c.field, name, "{c}"),
            other => panic!("acuity {acuity:?} judged: {other:?}"),
        }
    }
    flip.frame_errors(&reference, &layer, &pixels, Acuity::default(), Maps::Drop)
        .unwrap();
    drop((layer, reference, flip));
    gpu.check_validation().unwrap();
}

/// A device lost (through the seam, as if `vkQueueSubmit` had said so) makes each of the layer's
/// later calls an error naming the call that found it — views, record, render, the last
/// frame's figures, readback — with no panic, and the layer drops without waiting on it.
/// Negative control (run): without the check in the slot's check, `record` is `Ok`.
#[test]
fn a_lost_device_makes_every_later_call_an_error_naming_it() {
    let gpu = gpu();
    let mut layer = layer(&gpu);
    let set = layer.views(&FrameInput::new(head())).unwrap();
    layer.render(&set, &mut |_| {}).unwrap();
    let commands = Commands::new(&gpu);
    let cmd = commands.begun();
    let set = layer.views(&FrameInput::new(head())).unwrap();
    gpu.simulate_device_lost("vkQueueSubmit");
    let lost = |e: GpuError| match e {
        GpuError::DeviceLost {
            call: "vkQueueSubmit",
        } => {}
        other => panic!("not the lost device: {other}"),
    };
    lost(record(&mut layer, cmd, &set).unwrap_err());
    lost(layer.render(&set, &mut |_| {}).unwrap_err());
    lost(layer.views(&FrameInput::new(head())).unwrap_err());
    let first = foveate::render::FrameRecord { frame: 0, slot: 0 };
    lost(layer.frame_stats(first).unwrap_err());
    lost(layer.readback().unwrap_err());
    assert!(GpuError::DeviceLost {
        call: "vkQueueSubmit"
    }
    .to_string()
    .contains("make a new Gpu"));
    drop(layer);
    drop(commands);
    gpu.check_validation().unwrap();
}
