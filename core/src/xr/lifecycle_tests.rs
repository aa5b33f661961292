use super::*;
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

fn to(life: &mut Lifecycle<Recording>, states: &[SessionState]) {
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
