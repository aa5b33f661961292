//! Every transition of the demo's lifecycle against a backend that records what it is asked
//! and checks, on every call, that the window its swapchain presents to is still alive.

use std::cell::{Cell, RefCell};
use std::collections::VecDeque;
use std::rc::Rc;

use super::*;

/// A window that knows when Android has it back.
struct FakeWindow {
    id: u32,
    alive: Rc<Cell<bool>>,
}

impl FakeWindow {
    fn new(id: u32) -> (FakeWindow, Rc<Cell<bool>>) {
        let alive = Rc::new(Cell::new(true));
        (
            FakeWindow {
                id,
                alive: alive.clone(),
            },
            alive,
        )
    }
}

impl Drop for FakeWindow {
    fn drop(&mut self) {
        self.alive.set(false);
    }
}

#[derive(Default)]
struct Fake {
    calls: Rc<RefCell<Vec<String>>>,
    /// The window the swapchain presents to, while there is one.
    presenting_to: Option<(u32, Rc<Cell<bool>>)>,
    renderers: bool,
    /// What the next draws report (then Shown).
    next: VecDeque<Drawn>,
    refuse_open: bool,
}

impl Fake {
    fn call(&self, s: String) {
        self.calls.borrow_mut().push(s);
    }

    fn check_window(&self, what: &str) {
        if let Some((id, alive)) = &self.presenting_to {
            assert!(
                alive.get(),
                "{what}: window {id} was dropped under its swapchain"
            );
        }
    }
}

impl Backend for Fake {
    type Window = FakeWindow;

    unsafe fn open(&mut self, window: &FakeWindow, size: (u32, u32)) -> Result<(), DemoError> {
        assert!(self.presenting_to.is_none(), "a second swapchain");
        if self.refuse_open {
            return Err("no presentation".into());
        }
        self.call(format!("open {} {}x{}", window.id, size.0, size.1));
        self.presenting_to = Some((window.id, window.alive.clone()));
        Ok(())
    }

    fn close(&mut self) {
        self.check_window("close");
        let (id, _) = self
            .presenting_to
            .take()
            .expect("close without a swapchain");
        self.call(format!("close {id}"));
    }

    fn resize(&mut self, size: (u32, u32)) {
        self.check_window("resize");
        self.call(format!("resize {}x{}", size.0, size.1));
    }

    fn release_memory(&mut self) {
        self.renderers = false;
        self.call("release".into());
    }

    fn draw(&mut self, gaze: Vec2) -> Result<Drawn, DemoError> {
        self.check_window("draw");
        let (id, _) = self
            .presenting_to
            .as_ref()
            .expect("draw without a swapchain");
        let made = if self.renderers {
            ""
        } else {
            " (renderers made)"
        };
        self.renderers = true;
        self.call(format!("draw {id} gaze {},{}{made}", gaze.x, gaze.y));
        Ok(self.next.pop_front().unwrap_or(Drawn::Shown {
            gpu_pass_ms: Some(vec![1.0, 2.0]),
        }))
    }

    fn locate(&self, x: f64, y: f64) -> Option<Vec2> {
        // Two eyes side by side in a 200×100 window.
        ((0.0..200.0).contains(&x) && (0.0..100.0).contains(&y)).then(|| {
            let u = (x % 100.0) / 50.0 - 1.0;
            Vec2::new(u as f32, (1.0 - y / 50.0) as f32)
        })
    }

    fn pass_names(&self) -> Vec<&'static str> {
        vec!["periphery", "fovea"]
    }
}

struct Harness {
    app: App<Fake>,
    calls: Rc<RefCell<Vec<String>>>,
}

impl Harness {
    fn new() -> Harness {
        let fake = Fake::default();
        let calls = fake.calls.clone();
        Harness {
            app: App::new(fake),
            calls,
        }
    }

    fn on(&mut self, event: Event<FakeWindow>) -> &mut Self {
        self.app.handle(event).expect("event handled");
        self
    }

    fn window(&mut self, id: u32) -> Rc<Cell<bool>> {
        let (w, alive) = FakeWindow::new(id);
        self.on(Event::WindowCreated(w, (200, 100)));
        alive
    }

    fn frames(&mut self, n: usize) -> &mut Self {
        for _ in 0..n {
            assert!(self.app.frame().expect("frame"), "the loop goes on");
        }
        self
    }

    /// The backend calls since the last look.
    fn calls(&self) -> Vec<String> {
        std::mem::take(&mut *self.calls.borrow_mut())
    }

    fn running(&mut self) -> Rc<Cell<bool>> {
        self.on(Event::Resume);
        let alive = self.window(1);
        assert_eq!(self.app.phase(), Phase::Running);
        self.frames(1);
        self.calls();
        alive
    }
}

#[test]
fn launch_either_order_then_frames() {
    let mut h = Harness::new();
    assert_eq!(h.app.phase(), Phase::Waiting);
    h.frames(2);
    assert!(h.calls().is_empty(), "nothing drawn without a window");
    h.on(Event::Resume);
    assert_eq!(h.app.phase(), Phase::Waiting);
    h.window(1);
    assert!(h.app.wants_frames());
    h.frames(2);
    assert_eq!(
        h.calls(),
        [
            "open 1 200x100",
            "draw 1 gaze 0,0 (renderers made)",
            "draw 1 gaze 0,0"
        ]
    );
    assert_eq!(h.app.presented(), 2);

    // The window before the resume: paused until resumed.
    let mut h = Harness::new();
    h.window(1);
    assert_eq!(h.app.phase(), Phase::Paused);
    assert!(!h.app.wants_frames());
    h.frames(1);
    h.on(Event::Resume).frames(1);
    assert_eq!(
        h.calls(),
        ["open 1 200x100", "draw 1 gaze 0,0 (renderers made)"]
    );
}

#[test]
fn pause_stops_frames_and_resume_restarts_them_on_the_same_swapchain() {
    let mut h = Harness::new();
    h.running();
    h.on(Event::Pause);
    assert_eq!(h.app.phase(), Phase::Paused);
    h.frames(3);
    assert!(
        h.calls().is_empty(),
        "no frame while paused, nothing remade"
    );
    h.on(Event::Resume).frames(1);
    assert_eq!(h.calls(), ["draw 1 gaze 0,0"]);
}

#[test]
fn window_destroyed_closes_the_swapchain_first_and_a_new_window_restarts() {
    let mut h = Harness::new();
    let first = h.running();
    h.on(Event::WindowDestroyed);
    assert!(!first.get(), "the window is given back");
    assert_eq!(h.app.phase(), Phase::Waiting);
    h.frames(2);
    assert_eq!(
        h.calls(),
        ["close 1"],
        "closed (while alive: checked), nothing drawn"
    );
    h.window(2);
    h.frames(1);
    assert_eq!(
        h.calls(),
        ["open 2 200x100", "draw 2 gaze 0,0"],
        "the renderers survive a window change"
    );
    // Destroyed again with no swapchain to close: nothing to do twice.
    h.on(Event::WindowDestroyed).on(Event::WindowDestroyed);
    assert_eq!(h.calls(), ["close 2"]);
}

#[test]
fn a_new_window_replaces_the_old_one_after_its_swapchain_closes() {
    let mut h = Harness::new();
    let first = h.running();
    let second = h.window(2);
    assert!(!first.get() && second.get());
    h.frames(1);
    assert_eq!(h.calls(), ["close 1", "open 2 200x100", "draw 2 gaze 0,0"]);
}

#[test]
fn window_changes_while_paused_stay_paused() {
    let mut h = Harness::new();
    h.running();
    h.on(Event::Pause).on(Event::WindowDestroyed);
    assert_eq!(h.app.phase(), Phase::Waiting);
    h.window(2);
    assert_eq!(h.app.phase(), Phase::Paused);
    h.frames(2);
    h.on(Event::Resume).frames(1);
    assert_eq!(h.calls(), ["close 1", "open 2 200x100", "draw 2 gaze 0,0"]);
}

#[test]
fn resized_reaches_the_swapchain_only_when_there_is_one() {
    let mut h = Harness::new();
    h.on(Event::WindowResized((10, 10)));
    h.running();
    h.on(Event::WindowResized((300, 150))).frames(1);
    h.on(Event::WindowDestroyed)
        .on(Event::WindowResized((5, 5)));
    assert_eq!(h.calls(), ["resize 300x150", "draw 1 gaze 0,0", "close 1"]);
}

#[test]
fn low_memory_drops_the_renderers_and_the_next_frame_remakes_them() {
    let mut h = Harness::new();
    h.running();
    h.on(Event::LowMemory);
    assert_eq!(h.app.phase(), Phase::Running, "the swapchain stays");
    h.frames(2);
    assert_eq!(
        h.calls(),
        [
            "release",
            "draw 1 gaze 0,0 (renderers made)",
            "draw 1 gaze 0,0"
        ]
    );
    // Low memory with no window at all.
    h.on(Event::WindowDestroyed).on(Event::LowMemory);
    assert_eq!(h.calls(), ["close 1", "release"]);
}

#[test]
fn destroy_releases_everything_and_ends_the_loop() {
    let mut h = Harness::new();
    let window = h.running();
    h.on(Event::Destroy);
    assert!(!window.get());
    assert_eq!(h.app.phase(), Phase::Destroyed);
    assert!(!h.app.frame().expect("frame"), "the loop ends");
    let (late, _) = FakeWindow::new(9);
    h.on(Event::WindowCreated(late, (1, 1)))
        .on(Event::Resume)
        .on(Event::LowMemory);
    assert!(!h.app.frame().expect("frame"));
    assert_eq!(h.calls(), ["close 1", "release"], "nothing after destroy");
}

#[test]
fn the_window_lost_mid_frame_then_given_back() {
    let mut h = Harness::new();
    let first = h.running();
    h.app.backend.next.push_back(Drawn::Lost);
    h.frames(1);
    assert_eq!(h.app.phase(), Phase::Lost);
    assert!(!h.app.wants_frames());
    assert!(
        first.get(),
        "the window is Android's to take back, not ours to drop"
    );
    h.frames(3);
    h.on(Event::WindowResized((50, 50)));
    assert_eq!(
        h.calls(),
        ["draw 1 gaze 0,0", "close 1"],
        "the lost swapchain is closed; nothing drawn or resized until a new window"
    );
    // Android takes the window back, then gives a new one.
    h.on(Event::WindowDestroyed);
    assert!(!first.get());
    assert_eq!(h.app.phase(), Phase::Waiting);
    h.window(2);
    h.frames(1);
    assert_eq!(h.calls(), ["open 2 200x100", "draw 2 gaze 0,0"]);
    assert_eq!(h.app.presented(), 2, "the lost frame is not counted");

    // Lost, and the next window comes without the old one's destroy.
    h.app.backend.next.push_back(Drawn::Lost);
    h.frames(1);
    h.window(3);
    h.frames(1);
    assert_eq!(
        h.calls(),
        [
            "draw 2 gaze 0,0",
            "close 2",
            "open 3 200x100",
            "draw 3 gaze 0,0"
        ]
    );
}

#[test]
fn skipped_frames_keep_running_and_are_not_counted() {
    let mut h = Harness::new();
    h.running();
    h.app.backend.next.push_back(Drawn::Skipped);
    h.frames(2);
    assert_eq!(h.app.phase(), Phase::Running);
    assert_eq!(h.app.presented(), 2, "one before, one after the skip");
}

#[test]
fn touch_moves_the_gaze_where_an_eye_is() {
    let mut h = Harness::new();
    h.running();
    h.on(Event::Touch(175.0, 25.0)).frames(1);
    assert_eq!(h.app.gaze(), Vec2::new(0.5, 0.5), "right eye, up and right");
    h.on(Event::Touch(500.0, 25.0));
    assert_eq!(h.app.gaze(), Vec2::new(0.5, 0.5), "off the eyes: unchanged");
    assert_eq!(h.calls(), ["draw 1 gaze 0.5,0.5"]);
}

#[test]
fn a_window_that_cannot_be_presented_to_is_an_error_and_nothing_draws() {
    let mut h = Harness::new();
    h.app.backend.refuse_open = true;
    h.on(Event::Resume);
    let (w, _) = FakeWindow::new(1);
    let e = h.app.handle(Event::WindowCreated(w, (1, 1))).unwrap_err();
    assert_eq!(e.to_string(), "no presentation");
    assert_eq!(h.app.phase(), Phase::Waiting);
    h.frames(1);
    assert!(h.calls().is_empty());
}
