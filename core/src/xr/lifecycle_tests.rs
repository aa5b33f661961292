use super::*;
use crate::xr::{Stall, Watchdog};
use SessionState::*;

/// Records what the lifecycle asked for; what exists follows from it.
#[derive(Default)]
struct Recording {
    calls: Vec<&'static str>,
    /// Swapchains and renderers exist.
    targets: bool,
    /// The runtime says to render.
    visible: bool,
    fail_begin: bool,
}

impl SessionBackend for Recording {
    type Error = &'static str;
    fn begin(&mut self) -> Result<(), &'static str> {
        self.calls.push("begin");
        if self.fail_begin {
            return Err("no swapchain format we can render to");
        }
        self.targets = true;
        Ok(())
    }
    fn end(&mut self) -> Result<(), &'static str> {
        self.calls.push("end");
        self.targets = false;
        Ok(())
    }
    fn frame(&mut self) -> Result<FrameOutcome, &'static str> {
        assert!(self.targets, "a frame without swapchains");
        self.calls.push("frame");
        Ok(if self.visible {
            FrameOutcome::Submitted
        } else {
            FrameOutcome::Skipped
        })
    }
    fn request_exit(&mut self) -> Result<(), &'static str> {
        self.calls.push("request_exit");
        Ok(())
    }
    fn abandon(&mut self) {
        self.calls.push("abandon");
        self.targets = false;
    }
}

fn to<B: SessionBackend<Error = &'static str>>(life: &mut Lifecycle<B>, states: &[SessionState]) {
    for &s in states {
        life.handle(RuntimeEvent::State(s)).unwrap();
    }
}

#[test]
fn a_whole_session_begins_at_ready_renders_when_visible_and_ends_at_stopping() {
    let mut life = Lifecycle::new(Recording::default());
    assert!(!life.frame().unwrap(), "no frame before the session begins");
    to(&mut life, &[Ready]);
    assert!(life.backend().targets, "swapchains made at Ready");
    assert!(
        life.frame().unwrap(),
        "frames run from Ready: the runtime synchronises on them"
    );
    life.backend_mut().visible = true;
    to(&mut life, &[Visible, Focused]);
    life.frame().unwrap();
    life.frame().unwrap();
    assert_eq!(life.frames(), (2, 1));
    to(&mut life, &[Synchronized]);
    life.stop().unwrap();
    life.stop().unwrap();
    assert!(
        life.frame().unwrap(),
        "frames go on until the runtime stops the session"
    );
    to(&mut life, &[Visible, Synchronized, Stopping]);
    assert!(!life.backend().targets, "swapchains dropped at Stopping");
    assert!(!life.frame().unwrap());
    to(&mut life, &[Idle, Exiting]);
    assert_eq!(life.ended(), Some(Ended::Exited));
    let calls = &life.backend().calls;
    assert_eq!(
        calls,
        &[
            "begin",
            "frame",
            "frame",
            "frame",
            "request_exit",
            "frame",
            "end"
        ]
    );
}

#[test]
fn a_lost_session_drops_everything_and_says_so() {
    let mut life = Lifecycle::new(Recording::default());
    to(&mut life, &[Ready, Synchronized, Visible, LossPending]);
    assert_eq!(life.ended(), Some(Ended::SessionLost));
    assert!(!life.backend().targets);
    assert!(!life.frame().unwrap(), "no frame after the loss");
    // What the runtime says after the loss changes nothing.
    to(&mut life, &[Ready, Focused]);
    assert_eq!(life.backend().calls, ["begin", "abandon"]);
}

#[test]
fn instance_loss_ends_the_run_from_any_state() {
    for state in [Idle, Ready, Focused] {
        let mut life = Lifecycle::new(Recording::default());
        to(&mut life, &[state]);
        life.handle(RuntimeEvent::InstanceLossPending).unwrap();
        assert_eq!(life.ended(), Some(Ended::InstanceLost), "from {state:?}");
        assert!(!life.backend().targets && !life.wants_frame());
    }
}

#[test]
fn exiting_while_running_ends_the_session_first() {
    let mut life = Lifecycle::new(Recording::default());
    to(&mut life, &[Ready, Synchronized, Exiting]);
    assert_eq!(life.backend().calls, ["begin", "end"]);
    assert_eq!(life.ended(), Some(Ended::Exited));
}

#[test]
fn a_failed_begin_is_an_error_and_runs_no_frame() {
    let mut life = Lifecycle::new(Recording {
        fail_begin: true,
        ..Recording::default()
    });
    let err = life.handle(RuntimeEvent::State(Ready)).unwrap_err();
    assert!(err.contains("swapchain format"));
    to(&mut life, &[Synchronized]);
    assert!(!life.wants_frame() && !life.frame().unwrap());
    assert!(life.stop().is_ok(), "nothing to stop");
    assert_eq!(life.backend().calls, ["begin"]);
}

/// A runtime that stops answering: each frame blocks until the test lets it go (as
/// `xrWaitFrame` does while the compositor is stopped).
struct Stalled {
    release: std::sync::mpsc::Receiver<()>,
}

impl SessionBackend for Stalled {
    type Error = &'static str;
    fn begin(&mut self) -> Result<(), &'static str> {
        Ok(())
    }
    fn end(&mut self) -> Result<(), &'static str> {
        Ok(())
    }
    fn frame(&mut self) -> Result<FrameOutcome, &'static str> {
        self.release.recv().map_err(|_| "released")?;
        Ok(FrameOutcome::Submitted)
    }
    fn request_exit(&mut self) -> Result<(), &'static str> {
        Ok(())
    }
    fn abandon(&mut self) {}
}

/// The frame loop under the watchdog as `foveate xr` runs it, against a runtime that answers
/// `answered` frames and then stops: what the watchdog reports, if anything, within `wait`.
fn watched_run(
    answered: usize,
    limit: std::time::Duration,
    wait: std::time::Duration,
) -> Option<Stall> {
    let (stalled, reported) = std::sync::mpsc::channel();
    let (release, released) = std::sync::mpsc::channel();
    for _ in 0..answered {
        release.send(()).unwrap();
    }
    let runner = std::thread::spawn(move || {
        let watchdog = Watchdog::new(limit, move |stall| stalled.send(stall).unwrap());
        let mut life = Lifecycle::new(Stalled { release: released });
        to(&mut life, &[Ready, Synchronized, Visible, Focused]);
        while watchdog.watch("frame", || life.frame()).is_ok() {}
    });
    let report = reported.recv_timeout(wait).ok();
    drop(release);
    runner.join().unwrap();
    report
}

/// A stalled runtime is reported within the limit (plus the scheduler's slack), naming the
/// call; frames that keep coming are never reported (the negative control: the same loop with
/// a runtime that answers within the limit).
#[test]
fn a_runtime_that_stops_answering_is_reported_within_the_limit() {
    use std::time::Duration;
    let limit = Duration::from_millis(300);
    let start = std::time::Instant::now();
    let stall = watched_run(3, limit, limit + Duration::from_secs(1)).expect("the stall reported");
    assert_eq!(stall.call, "frame");
    assert!(stall.waited >= limit, "{stall:?}");
    assert!(
        start.elapsed() < limit + Duration::from_secs(1),
        "{:?}",
        start.elapsed()
    );

    // Two seconds of frames, each well within the limit: never reported.
    let (reported, received) = std::sync::mpsc::channel();
    {
        let watchdog = Watchdog::new(limit, move |s| reported.send(s).unwrap());
        for _ in 0..10 {
            watchdog.watch("frame", || std::thread::sleep(limit / 5));
        }
    }
    assert!(received.try_recv().is_err(), "no stall while frames came");
}
