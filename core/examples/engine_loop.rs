//! An engine's frame loop: its own command buffers and fences, two frames in flight, each
//! frame recorded with `Renderer::record` between the engine's own commands and submitted by
//! the engine; an instance of the scene moving every frame; each frame's figures read when its
//! slot comes round again.
//!
//! ```text
//! cargo run -p foveate --example engine_loop
//! ```

use foveate::ash::vk;
use foveate::foveation::FoveationConfig;
use foveate::glam::{Mat4, Vec3};
use foveate::gpu::{Gpu, GpuOptions};
use foveate::plan::RenderConfig;
use foveate::plan::Resolution;
use foveate::render::{FrameInput, FrameRecord, Renderer};
use foveate::scene::default_scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // An engine lends its own device with `Gpu::from_engine`; here foveate opens one.
    let gpu = Gpu::new(&GpuOptions::default())?;
    let scene = default_scene();
    let config = RenderConfig {
        resolution: Some(Resolution::square(256)),
        foveation: Some(FoveationConfig::default()),
        frames_in_flight: 2,
        moving_instances: true,
        ..RenderConfig::default()
    };
    let plan = foveate::plan(&scene, &config, gpu.caps())?;
    let mut renderer = Renderer::new(&gpu, &plan, &scene)?;
    // The engine's side of each frame slot: a command buffer and a fence.
    let pool = gpu.command_pool(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER)?;
    let slots = (0..renderer.frame_slots())
        .map(|_| Ok((gpu.allocate_command_buffer(&pool)?, gpu.fence()?)))
        .collect::<Result<Vec<_>, foveate::gpu::GpuError>>()?;
    let mut in_flight: Vec<Option<FrameRecord>> = vec![None; slots.len()];
    let moving = 0; // the scene's first instance
    let start = scene.flat_instances()[moving].model;
    let device = gpu.device();
    for frame in 0..12 {
        let k = frame % slots.len();
        let (cmd, fence) = &slots[k];
        // The frame this slot held two frames ago: wait for it, then read its figures.
        if let Some(done) = in_flight[k].take() {
            gpu.wait(fence)?;
            let stats = renderer.frame_stats(done)?.expect("finished");
            println!(
                "frame {}: GPU {:.2} ms, {} instances drawn",
                done.frame,
                stats.gpu_ms.unwrap_or(0.0),
                stats.instances_drawn.iter().sum::<u64>()
            );
        }
        // The scene changes between frames: the instance slides sideways.
        let slide = Mat4::from_translation(Vec3::new(0.1 * frame as f32, 0.0, 0.0));
        renderer.move_instance(moving, slide * start)?;
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the slot's previous frame finished (its fence was waited on above); the
        // command buffer is this device's and recording; the renderer outlives the frames
        // (the device is idle before it drops).
        unsafe {
            device.reset_command_buffer(*cmd, vk::CommandBufferResetFlags::empty())?;
            device.begin_command_buffer(*cmd, &begin)?;
            // … the engine's commands before the frame …
            let record = renderer.record(*cmd, &FrameInput::new(scene.head))?;
            // … and after it (a copy of the output, its compositor) …
            device.end_command_buffer(*cmd)?;
            // The engine's own submission would add its semaphores here.
            gpu.submit(*cmd, fence)?;
            in_flight[k] = Some(record);
        }
    }
    gpu.wait_idle()?;
    drop(renderer);
    gpu.check_validation()?;
    Ok(())
}
