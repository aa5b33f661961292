//! Android only, and thin: the logger, the GPU for Android's display, and `android-activity`'s
//! events turned into the host-tested [`App`]'s. Built by `scripts/apk.sh`; never run here.

use std::time::Duration;

use android_activity::input::{InputEvent, MotionAction};
use android_activity::{AndroidApp, InputStatus, MainEvent, PollEvent};
use foveate::gpu::{Gpu, GpuOptions};
use ndk::native_window::NativeWindow;
use raw_window_handle::{AndroidDisplayHandle, RawDisplayHandle};

use crate::app::{App, DemoError, Event};
use crate::vulkan::{demo_config, demo_scene, VulkanBackend};

#[no_mangle]
fn android_main(android: AndroidApp) {
    android_logger::init_once(
        android_logger::Config::default()
            .with_max_level(log::LevelFilter::Info)
            .with_tag("foveate"),
    );
    // Panics abort: say why in the log first (stderr goes nowhere on Android).
    std::panic::set_hook(Box::new(|info| log::error!("{info}")));
    if let Err(e) = run(&android) {
        log::error!("foveate: {e}");
    }
}

fn run(android: &AndroidApp) -> Result<(), DemoError> {
    let display = RawDisplayHandle::Android(AndroidDisplayHandle::new());
    let gpu = Gpu::new(&GpuOptions {
        display: Some(display),
        pipeline_cache: android
            .internal_data_path()
            .map(|p| p.join("pipeline-cache.bin")),
        ..GpuOptions::default()
    })?;
    log::info!("{}", gpu.info().name);
    let backend = VulkanBackend::<NativeWindow>::new(&gpu, display, demo_scene(), demo_config())?;
    let mut app = App::new(backend);
    loop {
        let timeout = app.wants_frames().then_some(Duration::ZERO);
        let mut handled: Result<(), DemoError> = Ok(());
        // Handled inside the callback: a terminated window goes back to Android when it returns.
        android.poll_events(timeout, |event| {
            if let PollEvent::Main(event) = event {
                // Android may end a paused app without a word: keep the compiled pipelines now.
                if matches!(event, MainEvent::Pause) {
                    if let Err(e) = gpu.save_pipeline_cache() {
                        log::warn!("pipeline cache not saved: {e}");
                    }
                }
                if let (Some(event), Ok(())) = (translate(android, event), &handled) {
                    handled = app.handle(event);
                }
            }
        });
        handled?;
        for (x, y) in touches(android) {
            app.handle(Event::Touch(x, y))?;
        }
        if !app.frame()? {
            break;
        }
    }
    drop(app);
    gpu.save_pipeline_cache()?;
    Ok(())
}

fn translate(android: &AndroidApp, event: MainEvent) -> Option<Event<NativeWindow>> {
    let size = |w: &NativeWindow| (w.width().max(0) as u32, w.height().max(0) as u32);
    Some(match event {
        MainEvent::Resume { .. } => Event::Resume,
        MainEvent::Pause => Event::Pause,
        MainEvent::InitWindow { .. } => {
            let window = android.native_window()?;
            let size = size(&window);
            Event::WindowCreated(window, size)
        }
        MainEvent::WindowResized { .. } | MainEvent::ConfigChanged { .. } => {
            Event::WindowResized(size(&android.native_window()?))
        }
        MainEvent::TerminateWindow { .. } => Event::WindowDestroyed,
        MainEvent::LowMemory => Event::LowMemory,
        MainEvent::Destroy => Event::Destroy,
        _ => return None,
    })
}

/// Where a finger went down or moved since the last turn, in window pixels.
fn touches(android: &AndroidApp) -> Vec<(f64, f64)> {
    let mut touches = Vec::new();
    if let Ok(mut events) = android.input_events_iter() {
        while events.next(|event| match event {
            InputEvent::MotionEvent(m)
                if matches!(m.action(), MotionAction::Down | MotionAction::Move) =>
            {
                let p = m.pointer_at_index(0);
                touches.push((p.x() as f64, p.y() as f64));
                InputStatus::Handled
            }
            _ => InputStatus::Unhandled,
        }) {}
    }
    touches
}
