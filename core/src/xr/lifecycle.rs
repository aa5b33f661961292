//! An OpenXR session's life as the runtime drives it, as a state machine over the runtime's
//! events, deciding what exists and when frames run. It holds no OpenXR handle, so it is tested
//! on every host against a recording backend (as the Android demo's `App` is).
//!
//! Rules (OpenXR 1.1 §10.3): `Ready` begins the session, and the swapchains and renderers are
//! made then; frames run (wait, begin, end) from then on through `Synchronized`, `Visible` and
//! `Focused` (the runtime moves on to `Synchronized` only once frames come), rendered only
//! while the runtime says so; `Stopping` drops the renderers and swapchains, then ends the
//! session; `LossPending` and instance loss drop everything and end the run with an error;
//! `Exiting` ends it cleanly. Asking to stop (after the frames wanted) requests the exit and
//! keeps running frames until the runtime says `Stopping`.

/// The runtime's session states (`XrSessionState`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SessionState {
    /// Created, not yet ready.
    Idle,
    /// Ready to begin.
    Ready,
    /// Running, frames not shown.
    Synchronized,
    /// Frames shown, no input focus.
    Visible,
    /// Frames shown, with input focus.
    Focused,
    /// The session must end.
    Stopping,
    /// The session is being lost.
    LossPending,
    /// The application should exit.
    Exiting,
}

impl SessionState {
    /// Whether the runtime expects the frame loop (wait, begin, end) in this state, once the
    /// session is begun.
    pub fn runs_frames(self) -> bool {
        matches!(
            self,
            SessionState::Ready
                | SessionState::Synchronized
                | SessionState::Visible
                | SessionState::Focused
        )
    }
}

/// What the runtime tells the application, as the lifecycle needs it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RuntimeEvent {
    /// `XrEventDataSessionStateChanged`.
    State(SessionState),
    /// `XrEventDataInstanceLossPending`: the runtime is going away.
    InstanceLossPending,
}

/// What one frame of the loop did.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FrameOutcome {
    /// Rendered and submitted (a projection layer).
    Submitted,
    /// Submitted with no layer: the runtime said not to render this frame.
    Skipped,
}

/// What the lifecycle does through: the OpenXR session in `foveate xr`, a recording in tests.
pub trait SessionBackend {
    /// What its calls fail with.
    type Error;
    /// `xrBeginSession`, then the swapchains and renderers.
    fn begin(&mut self) -> Result<(), Self::Error>;
    /// Drops the renderers and swapchains, then `xrEndSession`.
    fn end(&mut self) -> Result<(), Self::Error>;
    /// One frame: wait, begin, render when the runtime says so, end.
    fn frame(&mut self) -> Result<FrameOutcome, Self::Error>;
    /// `xrRequestExitSession`.
    fn request_exit(&mut self) -> Result<(), Self::Error>;
    /// Drops everything of the session (after loss: nothing can be ended).
    fn abandon(&mut self);
}

/// Why a run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ended {
    /// The runtime said `Exiting` (after our request, or its own).
    Exited,
    /// The session was lost (`LossPending`): the headset went away.
    SessionLost,
    /// The runtime is going away (`XrEventDataInstanceLossPending`).
    InstanceLost,
}

/// The session's lifecycle over a backend.
pub struct Lifecycle<B: SessionBackend> {
    backend: B,
    state: SessionState,
    /// The session is begun (between `Ready` and `Stopping`).
    running: bool,
    exit_requested: bool,
    ended: Option<Ended>,
    submitted: u64,
    skipped: u64,
}

impl<B: SessionBackend> Lifecycle<B> {
    /// A lifecycle in `Idle`, driving `backend`.
    pub fn new(backend: B) -> Self {
        Lifecycle {
            backend,
            state: SessionState::Idle,
            running: false,
            exit_requested: false,
            ended: None,
            submitted: 0,
            skipped: 0,
        }
    }

    /// The session's state as last told.
    pub fn state(&self) -> SessionState {
        self.state
    }

    /// The backend.
    pub fn backend(&self) -> &B {
        &self.backend
    }

    /// The backend, to change.
    pub fn backend_mut(&mut self) -> &mut B {
        &mut self.backend
    }

    /// Frames rendered and submitted, and frames submitted without rendering.
    pub fn frames(&self) -> (u64, u64) {
        (self.submitted, self.skipped)
    }

    /// Why the run ended, once it has.
    pub fn ended(&self) -> Option<Ended> {
        self.ended
    }

    /// Moves the session on for one runtime event: begins, ends, or drops everything as the state calls for.
    pub fn handle(&mut self, event: RuntimeEvent) -> Result<(), B::Error> {
        if self.ended.is_some() {
            return Ok(());
        }
        match event {
            RuntimeEvent::InstanceLossPending => self.abandon(Ended::InstanceLost),
            RuntimeEvent::State(state) => {
                if state != self.state {
                    log::info!("OpenXR session: {:?} -> {state:?}", self.state);
                }
                self.state = state;
                match state {
                    SessionState::Ready if !self.running => {
                        self.backend.begin()?;
                        self.running = true;
                    }
                    SessionState::Stopping if self.running => {
                        self.running = false;
                        self.backend.end()?;
                    }
                    SessionState::LossPending => self.abandon(Ended::SessionLost),
                    SessionState::Exiting => {
                        if self.running {
                            self.running = false;
                            self.backend.end()?;
                        }
                        self.ended = Some(Ended::Exited);
                    }
                    _ => {}
                }
            }
        }
        Ok(())
    }

    fn abandon(&mut self, why: Ended) {
        self.running = false;
        self.backend.abandon();
        self.ended = Some(why);
    }

    /// Asks the runtime to end the session (once); frames go on until it says `Stopping`.
    pub fn stop(&mut self) -> Result<(), B::Error> {
        if self.running && !self.exit_requested {
            self.exit_requested = true;
            self.backend.request_exit()?;
        }
        Ok(())
    }

    /// Whether a frame is due: the session is begun and the runtime runs frames.
    pub fn wants_frame(&self) -> bool {
        self.ended.is_none() && self.running && self.state.runs_frames()
    }

    /// One frame when one is due; false when none was.
    pub fn frame(&mut self) -> Result<bool, B::Error> {
        if !self.wants_frame() {
            return Ok(false);
        }
        match self.backend.frame()? {
            FrameOutcome::Submitted => self.submitted += 1,
            FrameOutcome::Skipped => self.skipped += 1,
        }
        Ok(true)
    }
}

#[cfg(test)]
#[path = "lifecycle_tests.rs"]
mod tests;
