//! A renderer driven as an engine drives it: frames recorded into command buffers the test owns
//! and submits with its own fences, up to three in flight, each frame's output copied into the
//! test's own buffer in the same command buffer — against the same frames rendered one at a
//! time by `render_frame`. Validation, synchronization validation included, must stay clean.

use ash::vk;
use foveate::foveation::{FoveationConfig, TemporalConfig};
use foveate::gpu::{Buffer, CommandPool, Fence, Gpu, MemoryLocation};
use foveate::metrics::RgbaImage;
use foveate::mffr::MffrConfig;
use foveate::plan::{RenderConfig, Resolution, MAX_FRAMES_IN_FLIGHT};
use foveate::render::{FrameInput, FramesInFlight, Renderer, StereoImage};
use foveate::scene::{default_scene, Scene};
use foveate_tests::{assert_validation_clean, gpu, mesh_of, visible_instance};
use glam::{Mat4, Vec2, Vec3};

/// 64² per eye, the instances moving, one spare instance per mesh.
fn small(config: RenderConfig) -> RenderConfig {
    RenderConfig {
        resolution: Some(Resolution::square(64)),
        moving_instances: true,
        spare_instances: 1,
        ..config
    }
}

/// What changes in the scene before frame `i`: the visible instance slides a little (frames
/// 0 and 1), stays (2), is removed (3), stays away (4), is added again into its mesh's spare
/// place (5) and slides on from there.
fn change_scene(renderer: &mut Renderer, scene: &Scene, i: usize) {
    let index = visible_instance(scene);
    let original = scene.flat_instances()[index];
    let slid = |i: usize| Mat4::from_translation(Vec3::new(0.05 * i as f32, 0.02, 0.0));
    match i {
        // No change: each slot must hold the instances as they stand, not as it last saw
        // them.
        2 | 4 => {}
        3 => renderer.remove_instance(index).unwrap(),
        5 => {
            let mut added = original;
            added.model = slid(i) * original.model;
            let at = scene.instance_count() + mesh_of(scene, index);
            let k = renderer.add_instance(mesh_of(scene, index), added).unwrap();
            assert_eq!(k, at, "the mesh's spare");
        }
        6.. => {
            let at = scene.instance_count() + mesh_of(scene, index);
            renderer
                .move_instance(at, slid(i) * original.model)
                .unwrap();
        }
        _ => renderer
            .move_instance(index, slid(i) * original.model)
            .unwrap(),
    }
}

/// Stereo, foveated with temporal accumulation (history carried from frame to frame), MFFR.
fn configs() -> [RenderConfig; 3] {
    [
        RenderConfig::default(),
        RenderConfig {
            foveation: Some(FoveationConfig {
                periphery_density: Some(0.5),
                periphery_temporal: Some(TemporalConfig::default()),
                ..FoveationConfig::single_frame()
            }),
            msaa: 1,
            hmd_mask: true,
            ..RenderConfig::default()
        },
        RenderConfig {
            mffr: Some(MffrConfig::default()),
            ..RenderConfig::default()
        },
    ]
    .map(small)
}

/// A walk: the head moves a little each frame and the gaze wanders.
fn inputs(scene: &Scene, frames: usize) -> Vec<FrameInput> {
    (0..frames)
        .map(|i| {
            let t = i as f32;
            let head = scene.head * Mat4::from_translation(Vec3::new(0.03 * t, 0.0, -0.05 * t));
            FrameInput::new(head).with_gaze([Vec2::new(0.1 * t.sin(), -0.05 * t); 2])
        })
        .collect()
}

/// The frames rendered one at a time (record, submit, wait), read back after each.
fn rendered_alone(
    gpu: &Gpu,
    scene: &Scene,
    config: &RenderConfig,
    inputs: &[FrameInput],
) -> Vec<StereoImage> {
    let alone = RenderConfig {
        frames_in_flight: 1,
        ..config.clone()
    };
    let plan = foveate::plan(scene, &alone, gpu.caps()).unwrap();
    let mut renderer = Renderer::new(gpu, &plan, scene).unwrap();
    inputs
        .iter()
        .enumerate()
        .map(|(i, input)| {
            change_scene(&mut renderer, scene, i);
            renderer.render(input).unwrap();
            renderer.readback().unwrap()
        })
        .collect()
}

/// An engine's side of a frame slot: its command buffer and fence, and a buffer the frame's
/// output is copied into.
struct EngineFrame {
    _pool: CommandPool,
    cmd: vk::CommandBuffer,
    fence: Fence,
    submitted: bool,
    copy: Buffer,
}

/// Records every frame into the engine's command buffers, `in_flight` at once (a slot's fence
/// is waited on only when the slot comes round again), copying each frame's output into its
/// own buffer; returns each frame's images.
fn engine_loop(
    gpu: &Gpu,
    scene: &Scene,
    config: &RenderConfig,
    inputs: &[FrameInput],
    in_flight: u32,
) -> Vec<StereoImage> {
    let config = RenderConfig {
        frames_in_flight: in_flight,
        ..config.clone()
    };
    let plan = foveate::plan(scene, &config, gpu.caps()).unwrap();
    let mut renderer = Renderer::new(gpu, &plan, scene).unwrap();
    assert_eq!(renderer.frame_slots(), in_flight as usize);
    let (w, h) = (plan.eye_resolution.width, plan.eye_resolution.height);
    let bytes = 2 * (w * h * 4) as u64;
    let mut frames: Vec<EngineFrame> = (0..in_flight)
        .map(|_| {
            let pool = gpu
                .command_pool(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER)
                .unwrap();
            EngineFrame {
                cmd: gpu.allocate_command_buffer(&pool).unwrap(),
                _pool: pool,
                fence: gpu.fence().unwrap(),
                submitted: false,
                copy: copy_buffer(gpu, bytes),
            }
        })
        .collect();
    let mut images = Vec::new();
    let mut records = Vec::new();
    for (i, input) in inputs.iter().enumerate() {
        let frame = &mut frames[i % in_flight as usize];
        if frame.submitted {
            gpu.wait(&frame.fence).unwrap();
            images.push(read_copy(&mut frame.copy, w, h));
            let done = records[i - in_flight as usize];
            assert!(
                renderer.frame_stats(done).unwrap().is_some(),
                "frame {i}'s figures"
            );
        }
        change_scene(&mut renderer, scene, i);
        let device = gpu.device();
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        unsafe { device.begin_command_buffer(frame.cmd, &begin) }.unwrap();
        // SAFETY: the engine's buffer is recording; the slot's previous frame was waited on.
        let record = unsafe { renderer.record(frame.cmd, input) }.unwrap();
        assert_eq!(record.slot, i % in_flight as usize, "slots taken in turn");
        copy_output(&renderer, frame.cmd, frame.copy.raw);
        unsafe { device.end_command_buffer(frame.cmd) }.unwrap();
        // SAFETY: ended above; the renderer, pool and buffers outlive the wait below.
        unsafe { gpu.submit(frame.cmd, &frame.fence) }.unwrap();
        frame.submitted = true;
        records.push(record);
    }
    // The frames still in flight, oldest first.
    let n = inputs.len();
    for i in n.saturating_sub(in_flight as usize)..n {
        let frame = &mut frames[i % in_flight as usize];
        gpu.wait(&frame.fence).unwrap();
        images.push(read_copy(&mut frame.copy, w, h));
    }
    images
}

fn copy_buffer(gpu: &Gpu, bytes: u64) -> Buffer {
    Buffer::new(
        gpu,
        "engine copy",
        bytes,
        vk::BufferUsageFlags::TRANSFER_DST,
        MemoryLocation::GpuToCpu,
    )
    .unwrap()
}

/// Copies the frame's two eye layers into `buffer`, in the engine's command buffer, after the
/// frame: the plan's last pass leaves its output ready for a transfer read.
fn copy_output(renderer: &Renderer, cmd: vk::CommandBuffer, buffer: vk::Buffer) {
    let sources = renderer.present_sources().unwrap();
    let device = renderer.gpu().device();
    let mut offset = 0;
    for s in sources {
        let region = vk::BufferImageCopy::default()
            .buffer_offset(offset)
            .image_subresource(vk::ImageSubresourceLayers {
                aspect_mask: vk::ImageAspectFlags::COLOR,
                mip_level: 0,
                base_array_layer: s.layer,
                layer_count: 1,
            })
            .image_offset(vk::Offset3D {
                x: s.x as i32,
                y: 0,
                z: 0,
            })
            .image_extent(vk::Extent3D {
                width: s.width,
                height: s.height,
                depth: 1,
            });
        unsafe {
            device.cmd_copy_image_to_buffer(
                cmd,
                s.image,
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                buffer,
                &[region],
            )
        };
        offset += (s.width * s.height * 4) as u64;
    }
    let barrier = [vk::MemoryBarrier::default()
        .src_access_mask(vk::AccessFlags::TRANSFER_WRITE)
        .dst_access_mask(vk::AccessFlags::HOST_READ)];
    unsafe {
        device.cmd_pipeline_barrier(
            cmd,
            vk::PipelineStageFlags::TRANSFER,
            vk::PipelineStageFlags::HOST,
            vk::DependencyFlags::empty(),
            &barrier,
            &[],
            &[],
        )
    };
}

fn read_copy(buffer: &mut Buffer, w: u32, h: u32) -> StereoImage {
    let eye = (w * h * 4) as usize;
    let data = buffer.mapped();
    let image = |i: usize| RgbaImage {
        width: w,
        height: h,
        data: data[i * eye..(i + 1) * eye].to_vec(),
    };
    StereoImage {
        left: image(0),
        right: image(1),
    }
}

/// Each frame recorded into the test's command buffer and submitted by the test, one at a
/// time, equals the frame `render_frame` makes, pixel for pixel: stereo, foveated with
/// temporal accumulation, MFFR. Mutation: `record` writing the uniforms of another slot than
/// the one it binds (or skipping the executors' update) changes the foveated frames.
#[test]
fn a_frame_recorded_into_the_callers_buffer_is_the_frame_render_frame_makes() {
    let gpu = gpu();
    let scene = default_scene();
    let inputs = inputs(&scene, 4);
    for config in configs() {
        let alone = rendered_alone(&gpu, &scene, &config, &inputs);
        let recorded = engine_loop(&gpu, &scene, &config, &inputs, 1);
        for (i, (a, r)) in alone.iter().zip(&recorded).enumerate() {
            assert!(a == r, "frame {i} of {:?} differs", config.stereo);
        }
    }
    assert_validation_clean(&gpu);
}

/// Three frames in flight (two and three slots), the head and gaze moving, an instance
/// moving, removed and added again: synchronization validation clean, and each frame's pixels
/// those of the same frame rendered alone. Mutations: one shared uniform buffer instead of one
/// per slot (frame N+1's views written while frame N runs), or one shared instance buffer,
/// makes frames differ where the queue lets them overlap; dropping the plan's barriers into
/// the next frame fails synchronization validation.
#[test]
fn frames_in_flight_are_each_the_frame_rendered_alone() {
    let gpu = gpu();
    let scene = default_scene();
    let inputs = inputs(&scene, 7);
    for config in configs() {
        let alone = rendered_alone(&gpu, &scene, &config, &inputs);
        for in_flight in [2, 3] {
            let overlapped = engine_loop(&gpu, &scene, &config, &inputs, in_flight);
            assert_eq!(overlapped.len(), alone.len());
            for (i, (a, o)) in alone.iter().zip(&overlapped).enumerate() {
                assert!(a == o, "frame {i}, {in_flight} in flight, differs");
            }
            assert_validation_clean(&gpu);
        }
    }
}

/// A frame's figures are not ready before it ran, come back once its fence signalled, and
/// asking after its slot was used again is an error naming the frame — not another frame's
/// figures. (The renderer resets new query pools so that the early read is valid usage; the
/// validation layers here do not flag reading never-reset queries, so no test sees that reset.)
#[test]
fn a_frames_figures_are_its_own() {
    let gpu = gpu();
    let scene = default_scene();
    let config = small(RenderConfig::default());
    let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
    let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
    let inputs = inputs(&scene, 3);
    let pool = gpu
        .command_pool(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER)
        .unwrap();
    let cmd = gpu.allocate_command_buffer(&pool).unwrap();
    let fence = gpu.fence().unwrap();
    let mut records = Vec::new();
    for input in &inputs {
        let begin = vk::CommandBufferBeginInfo::default();
        unsafe { gpu.device().begin_command_buffer(cmd, &begin) }.unwrap();
        let record = unsafe { renderer.record(cmd, input) }.unwrap();
        if records.is_empty() {
            // Recorded, not yet run: its figures are not ready (and reading them is valid).
            assert_eq!(renderer.frame_stats(record).unwrap(), None);
        }
        records.push(record);
        unsafe { gpu.device().end_command_buffer(cmd) }.unwrap();
        unsafe { gpu.submit(cmd, &fence) }.unwrap();
        gpu.wait(&fence).unwrap();
    }
    let last = renderer.frame_stats(records[2]).unwrap().unwrap();
    assert!(last.gpu_ms.unwrap() > 0.0 && last.draw_calls > 0);
    // Each pass's time comes with the plan's name for it.
    let named: Vec<_> = last.gpu_pass_times().collect();
    assert_eq!(named.len(), plan.passes.len());
    for ((name, ms), pass) in named.iter().zip(&plan.passes) {
        assert!(*name == pass.name && *ms > 0.0, "{name}: {ms}");
        assert_eq!(last.gpu_pass_ms_of(pass.name), Some(*ms));
    }
    // Frame 0's slot (of 2) held frame 2 since.
    let error = renderer.frame_stats(records[0]).unwrap_err().to_string();
    assert!(
        error.contains("frame 0") && error.contains("slot 0"),
        "{error}"
    );
    assert_validation_clean(&gpu);
}

/// The library's own loop (`view`, `xr` and the Android demo use it): three frames in flight,
/// each frame's figures returned when its slot comes round (none while the slots fill), the
/// last frame's image the frame rendered alone; a frame recorded into another slot's buffer is
/// refused. Mutations: `begin` not waiting for the slot's fence (a figure not ready, or a
/// synchronization message), figures from the wrong record, each fail.
#[test]
fn the_librarys_frame_loop_returns_each_frames_figures_one_round_later() {
    let gpu = gpu();
    let scene = default_scene();
    let [_, foveated, _] = configs();
    let config = RenderConfig {
        frames_in_flight: 3,
        ..foveated
    };
    let plan = foveate::plan(&scene, &config, gpu.caps()).unwrap();
    let inputs = inputs(&scene, 7);
    let alone = rendered_alone(&gpu, &scene, &config, &inputs);
    let mut renderer = Renderer::new(&gpu, &plan, &scene).unwrap();
    let mut frames = FramesInFlight::new(&renderer).unwrap();
    assert_eq!(frames.len(), 3);
    let mut figures = Vec::new();
    for (i, input) in inputs.iter().enumerate() {
        change_scene(&mut renderer, &scene, i);
        figures.push(frames.render(&mut renderer, input).unwrap());
    }
    // Frames 0..3 fill the slots; frames 3..7 each return the figures of the frame 3 before.
    assert!(figures[..3].iter().all(Option::is_none));
    for stats in &figures[3..] {
        let stats = stats.as_ref().expect("the slot's earlier frame finished");
        assert!(stats.gpu_ms.unwrap() > 0.0 && stats.draw_calls > 0);
    }
    frames.wait_last().unwrap();
    assert!(renderer.readback().unwrap() == alone[6], "the last frame");

    // A record from one slot handed in with another slot's buffer.
    let (first, _) = frames.begin(&mut renderer).unwrap();
    let record = unsafe { renderer.record(first.cmd, &inputs[0]) }.unwrap();
    let (second, _) = frames.begin(&mut renderer).unwrap();
    let error = unsafe { frames.submit(second, record, &[], &[]) }
        .unwrap_err()
        .to_string();
    assert!(error.contains("slot"), "{error}");
    assert_validation_clean(&gpu);
}

/// More frames in flight than a renderer keeps is refused by the plan, naming the field.
#[test]
fn too_many_frames_in_flight_are_refused() {
    let gpu = gpu();
    let scene = default_scene();
    for bad in [0, MAX_FRAMES_IN_FLIGHT + 1] {
        let config = RenderConfig {
            frames_in_flight: bad,
            ..small(RenderConfig::default())
        };
        let error = foveate::plan(&scene, &config, gpu.caps())
            .unwrap_err()
            .to_string();
        assert!(error.contains("frames_in_flight"), "{error}");
    }
}
