//! The demo's `App` with its real Vulkan backend through Android's lifecycle, on X11 windows
//! under Xvfb (lavapipe, validation on): frames presented, a touch moving the gaze, a resize
//! reaching the swapchain, pause and resume, low memory, the window destroyed behind the
//! swapchain's back in the middle of the run (as Android may) and a new one given, destroy.
//! What differs on a device is only the surface type (`VK_KHR_android_surface`).

use std::time::{Duration, Instant};

use foveate::plan::Resolution;
use foveate_android::app::{App, Event, Phase};
use foveate_android::vulkan::{demo_config, demo_scene, VulkanBackend};
use foveate_tests::{assert_validation_clean, gpu_with, Xvfb};
use raw_window_handle::{HasDisplayHandle, HasWindowHandle, RawWindowHandle};
use winit::dpi::PhysicalSize;
use winit::event_loop::EventLoop;
use winit::platform::pump_events::EventLoopExtPumpEvents;
use winit::platform::x11::EventLoopBuilderExtX11;
use winit::window::Window;

type Demo<'g> = App<VulkanBackend<'g, Window>>;

fn main() {
    let x = Xvfb::start();
    // winit reads the display from the environment; this process has no other thread yet.
    std::env::set_var("DISPLAY", &x.display);
    let mut event_loop = EventLoop::builder()
        .with_x11()
        .build()
        .expect("an X11 event loop on Xvfb");
    let display = event_loop.display_handle().expect("display").as_raw();
    let gpu = gpu_with(Some(display));
    // Small eyes: this tests the lifecycle, not the picture (the viewer's test compares pixels).
    let config = foveate::plan::RenderConfig {
        resolution: Some(Resolution::square(64)),
        ..demo_config()
    };
    let backend = VulkanBackend::new(&gpu, display, demo_scene(), config).expect("the demo plans");
    let mut app = App::new(backend);
    let mut window = |size: (u32, u32)| {
        #[allow(deprecated)] // Creating windows outside `run_app` is what this test needs.
        let w = event_loop
            .create_window(
                Window::default_attributes()
                    .with_title("foveate demo")
                    .with_inner_size(PhysicalSize::new(size.0, size.1)),
            )
            .expect("a window");
        // Let the server map it.
        event_loop.pump_app_events(Some(Duration::from_millis(50)), &mut Idle);
        w
    };
    let frames = |app: &mut Demo, n: u64| {
        let before = app.presented();
        let deadline = Instant::now() + Duration::from_secs(60);
        while app.presented() < before + n && Instant::now() < deadline {
            assert!(app.frame().expect("frame"));
        }
        app.presented() - before
    };
    let step = |what: &str| println!("x11_lifecycle: {what}");

    step("resume, then a 200x100 window: frames are presented");
    app.handle(Event::Resume).unwrap();
    let first = window((200, 100));
    let first_id = x11_id(&first);
    app.handle(Event::WindowCreated(first, (200, 100))).unwrap();
    assert_eq!(app.phase(), Phase::Running);
    assert_eq!(frames(&mut app, 3), 3);
    assert_eq!(app.backend().extent(), Some((200, 100)));

    step("a touch on the right eye moves the gaze");
    app.handle(Event::Touch(150.0, 25.0)).unwrap();
    assert!(
        (app.gaze().x - 0.0).abs() < 0.05 && (app.gaze().y - 0.5).abs() < 0.05,
        "gaze {} (the right eye's square is centred at x 150)",
        app.gaze()
    );
    assert_eq!(frames(&mut app, 1), 1);

    step("resized to 300x120: the swapchain follows");
    x.run("xdotool", &["windowsize", &first_id, "300", "120"]);
    app.handle(Event::WindowResized((300, 120))).unwrap();
    assert_eq!(frames(&mut app, 2), 2);
    assert_eq!(app.backend().extent(), Some((300, 120)));

    step("paused: nothing drawn; resumed: drawing again");
    app.handle(Event::Pause).unwrap();
    assert_eq!(app.phase(), Phase::Paused);
    let before = app.presented();
    for _ in 0..3 {
        assert!(app.frame().unwrap());
    }
    assert_eq!(app.presented(), before);
    app.handle(Event::Resume).unwrap();
    assert_eq!(frames(&mut app, 1), 1);

    step("low memory: renderers dropped, made again for the next frame");
    app.handle(Event::LowMemory).unwrap();
    assert!(!app.backend().has_renderer());
    assert_eq!(frames(&mut app, 1), 1);
    assert!(app.backend().has_renderer());

    step("the window destroyed behind the swapchain's back, mid-run");
    assert_validation_clean(&gpu);
    x.run("xdotool", &["windowclose", &first_id]);
    let deadline = Instant::now() + Duration::from_secs(30);
    while app.phase() == Phase::Running && Instant::now() < deadline {
        app.frame().expect("a lost window is not an error");
    }
    assert_eq!(app.phase(), Phase::Lost, "the lost surface was noticed");
    // The one message allowed: best practices noting the error the loss returns.
    for m in gpu.take_validation_messages() {
        assert!(
            m.contains("BestPractices-Error-Result") && m.contains("VK_ERROR_SURFACE_LOST_KHR"),
            "{m}"
        );
    }
    assert!(!app.wants_frames());
    let before = app.presented();
    assert!(app.frame().unwrap());
    assert_eq!(app.presented(), before, "nothing drawn while lost");
    app.handle(Event::WindowDestroyed).unwrap();
    assert_eq!(app.phase(), Phase::Waiting);

    step("a new window: drawing again, renderers kept");
    let second = window((160, 90));
    app.handle(Event::WindowCreated(second, (160, 90))).unwrap();
    assert_eq!(app.phase(), Phase::Running);
    assert_eq!(frames(&mut app, 2), 2);
    assert_eq!(app.backend().extent(), Some((160, 90)));

    step("window taken away in the usual order (destroyed event first), then destroy");
    app.handle(Event::WindowDestroyed).unwrap();
    assert_eq!(app.backend().extent(), None);
    let third = window((100, 100));
    app.handle(Event::WindowCreated(third, (100, 100))).unwrap();
    assert_eq!(frames(&mut app, 1), 1);
    app.handle(Event::Destroy).unwrap();
    assert_eq!(app.phase(), Phase::Destroyed);
    assert!(!app.frame().unwrap());
    assert!(!app.backend().has_renderer());
    drop(app);
    assert_validation_clean(&gpu);
    // In the form the test script tallies.
    println!("test result: ok. 1 passed; 0 failed (x11_lifecycle)");
}

fn x11_id(window: &Window) -> String {
    match window.window_handle().expect("handle").as_raw() {
        RawWindowHandle::Xlib(h) => h.window.to_string(),
        RawWindowHandle::Xcb(h) => h.window.get().to_string(),
        other => panic!("not an X11 window: {other:?}"),
    }
}

/// An application that ignores every event: the test drives the windows itself.
struct Idle;

impl winit::application::ApplicationHandler for Idle {
    fn resumed(&mut self, _: &winit::event_loop::ActiveEventLoop) {}
    fn window_event(
        &mut self,
        _: &winit::event_loop::ActiveEventLoop,
        _: winit::window::WindowId,
        _: winit::event::WindowEvent,
    ) {
    }
}
