//! The demo's life as Android drives it: a state machine over what the activity is told
//! (resumed, paused, a window given, resized or taken away, low memory, destroyed, a touch),
//! deciding what exists and whether a frame is drawn. It compiles and is tested on every host;
//! the Android layer only translates `android-activity`'s events into [`Event`]s.
//!
//! Rules: a swapchain exists exactly while a window does (made when it arrives, dropped before
//! the window goes back to Android); frames are drawn only while resumed with a swapchain; a
//! window lost under a frame drops the swapchain and the demo waits for the next window; low
//! memory drops the renderers, made again for the next frame; after `Destroy` nothing is drawn.

use std::error::Error;
use std::time::Instant;

use foveate::metrics::PerSecond;
use glam::Vec2;

pub type DemoError = Box<dyn Error + Send + Sync>;

/// What Android tells the activity, as the demo needs it.
#[derive(Debug)]
pub enum Event<W> {
    /// In the foreground (onResume): draw.
    Resume,
    /// Out of the foreground (onPause): stop drawing, keep what is made.
    Pause,
    /// A window to draw into, `size` pixels.
    WindowCreated(W, (u32, u32)),
    /// The window is now `size` pixels.
    WindowResized((u32, u32)),
    /// The window goes back to Android when this event's handling returns.
    WindowDestroyed,
    /// The system is short of memory: free what can be made again.
    LowMemory,
    /// The activity ends.
    Destroy,
    /// A finger at window pixel (x, y): the gaze.
    Touch(f64, f64),
}

/// Where the demo stands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// No window (before the first, or between one taken away and the next).
    Waiting,
    /// A window, but not in the foreground.
    Paused,
    /// Drawing a frame per iteration.
    Running,
    /// The window vanished under a frame: its swapchain is dropped until a new window comes.
    Lost,
    /// Destroyed: nothing more is drawn.
    Destroyed,
}

/// What a frame did.
#[derive(Clone, Debug, PartialEq)]
pub enum Drawn {
    /// Presented; each pass's GPU time of the frame that finished meanwhile (with frames in
    /// flight an earlier one; `None` while the first frames fill the slots).
    Shown { gpu_pass_ms: Option<Vec<f64>> },
    /// Nothing presented this time (a zero-sized window, a remade swapchain).
    Skipped,
    /// The window is gone (the surface was lost).
    Lost,
}

/// What renders and presents: the Vulkan one on a device, a recording fake in tests.
pub trait Backend {
    type Window;
    /// Makes a swapchain for `window`, `size` pixels.
    ///
    /// # Safety
    /// `window` must stay valid until [`Backend::close`] (the `App` guarantees it).
    unsafe fn open(&mut self, window: &Self::Window, size: (u32, u32)) -> Result<(), DemoError>;
    /// Drops the swapchain (and its surface).
    fn close(&mut self);
    fn resize(&mut self, size: (u32, u32));
    /// Drops what can be made again (the renderers and their images).
    fn release_memory(&mut self);
    /// Renders a frame looking at `gaze` (-1..1, y up) and presents it.
    fn draw(&mut self, gaze: Vec2) -> Result<Drawn, DemoError>;
    /// The gaze at window pixel (x, y), where the last present put an eye.
    fn locate(&self, x: f64, y: f64) -> Option<Vec2>;
    /// The frame's passes, in plan order (for the once-a-second log line).
    fn pass_names(&self) -> Vec<&'static str>;
}

/// The demo: a backend driven by Android's lifecycle.
pub struct App<B: Backend> {
    // Declared before `window`: the backend's swapchain drops before the window it presents to.
    backend: B,
    window: Option<B::Window>,
    /// The backend has a swapchain for `window`.
    surface: bool,
    lost: bool,
    resumed: bool,
    destroyed: bool,
    gaze: Vec2,
    second: PerSecond,
    presented: u64,
}

impl<B: Backend> App<B> {
    pub fn new(backend: B) -> Self {
        App {
            backend,
            window: None,
            surface: false,
            lost: false,
            resumed: false,
            destroyed: false,
            gaze: Vec2::ZERO,
            second: PerSecond::default(),
            presented: 0,
        }
    }

    pub fn phase(&self) -> Phase {
        match (self.destroyed, self.lost, self.surface, self.resumed) {
            (true, ..) => Phase::Destroyed,
            (_, true, ..) => Phase::Lost,
            (_, _, false, _) => Phase::Waiting,
            (_, _, true, false) => Phase::Paused,
            (_, _, true, true) => Phase::Running,
        }
    }

    pub fn backend(&self) -> &B {
        &self.backend
    }

    pub fn gaze(&self) -> Vec2 {
        self.gaze
    }

    /// Frames presented so far.
    pub fn presented(&self) -> u64 {
        self.presented
    }

    pub fn handle(&mut self, event: Event<B::Window>) -> Result<(), DemoError> {
        if self.destroyed {
            return Ok(());
        }
        match event {
            Event::Resume => {
                self.resumed = true;
                // Time spent paused is no frame's.
                self.second = PerSecond::default();
            }
            Event::Pause => self.resumed = false,
            Event::WindowCreated(window, size) => {
                self.drop_window();
                let window = self.window.insert(window);
                // SAFETY: the window stays in `self.window` until `drop_window` closes the
                // swapchain first.
                unsafe { self.backend.open(window, size) }?;
                self.surface = true;
            }
            Event::WindowResized(size) => {
                if self.surface {
                    self.backend.resize(size);
                }
            }
            Event::WindowDestroyed => self.drop_window(),
            Event::LowMemory => {
                log::info!("low memory: dropping the renderers until the next frame");
                self.backend.release_memory();
            }
            Event::Destroy => {
                self.drop_window();
                self.backend.release_memory();
                self.destroyed = true;
            }
            Event::Touch(x, y) => {
                if let Some(gaze) = self.backend.locate(x, y) {
                    self.gaze = gaze;
                }
            }
        }
        Ok(())
    }

    /// One turn of the loop: a frame when running, and once a second a log line of the
    /// frames' median times. False once destroyed.
    pub fn frame(&mut self) -> Result<bool, DemoError> {
        if self.phase() != Phase::Running {
            return Ok(!self.destroyed);
        }
        let started = Instant::now();
        match self.backend.draw(self.gaze)? {
            Drawn::Shown { gpu_pass_ms } => {
                self.presented += 1;
                if let Some(gpu_pass_ms) = gpu_pass_ms {
                    self.second
                        .push(started.elapsed().as_secs_f64() * 1e3, gpu_pass_ms);
                }
            }
            Drawn::Skipped => {}
            Drawn::Lost => {
                log::warn!("the window was lost under a frame; waiting for the next one");
                self.backend.close();
                self.surface = false;
                self.lost = true;
            }
        }
        if self.second.due() {
            if let Some(second) = self.second.take() {
                log::info!("{}", second.describe(&self.backend.pass_names()));
            }
        }
        Ok(true)
    }

    /// Whether the loop should poll without waiting (a frame is due) or wait for an event.
    pub fn wants_frames(&self) -> bool {
        self.phase() == Phase::Running
    }

    /// Closes the swapchain, then lets the window go.
    fn drop_window(&mut self) {
        if self.surface {
            self.backend.close();
            self.surface = false;
        }
        self.lost = false;
        self.window = None;
    }
}

#[cfg(test)]
#[path = "app_tests.rs"]
mod tests;
