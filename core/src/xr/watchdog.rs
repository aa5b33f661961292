//! A watchdog over calls that can block for as long as a runtime pleases: `xrWaitFrame` and
//! `xrWaitSwapchainImage` wait on the compositor, and a compositor that stops answering (a
//! crashed or stopped process) leaves them waiting for ever. OpenXR has no way to cancel them,
//! so the watchdog does what can be done: when a watched call outlasts its limit, it hands the
//! stall to its `on_stall` (on its own thread), which writes what the run has and ends it.

use std::sync::{Arc, Condvar, Mutex};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

/// A watched call that outlasted the limit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Stall {
    /// What was called (as given to [`Watchdog::watch`]).
    pub call: &'static str,
    /// How long it had been waiting.
    pub waited: Duration,
}

#[derive(Default)]
struct Watch {
    /// The call in progress and when it began.
    armed: Option<(&'static str, Instant)>,
    stop: bool,
}

/// Watches calls one at a time; dropping it ends its thread.
pub struct Watchdog {
    shared: Arc<(Mutex<Watch>, Condvar)>,
    thread: Option<JoinHandle<()>>,
}

impl Watchdog {
    /// A watchdog that calls `on_stall` once, from its own thread, when a watched call has run
    /// for `limit`; the watched call itself cannot be interrupted, so `on_stall` usually reports
    /// and exits the process.
    pub fn new(limit: Duration, on_stall: impl FnOnce(Stall) + Send + 'static) -> Watchdog {
        let shared = Arc::new((Mutex::new(Watch::default()), Condvar::new()));
        let theirs = shared.clone();
        let thread = std::thread::Builder::new()
            .name("foveate-watchdog".into())
            .spawn(move || {
                if let Some(stall) = wait_for_stall(&theirs, limit) {
                    on_stall(stall);
                }
            })
            .expect("spawning the watchdog thread");
        Watchdog {
            shared,
            thread: Some(thread),
        }
    }

    /// Runs `f`, named `call`, under the watch.
    pub fn watch<T>(&self, call: &'static str, f: impl FnOnce() -> T) -> T {
        self.set(|w| w.armed = Some((call, Instant::now())));
        let result = f();
        self.set(|w| w.armed = None);
        result
    }

    fn set(&self, change: impl FnOnce(&mut Watch)) {
        let (lock, wake) = &*self.shared;
        change(&mut lock.lock().unwrap_or_else(|e| e.into_inner()));
        wake.notify_one();
    }
}

/// The watchdog thread: sleeps while nothing is armed, and until the armed call's deadline.
fn wait_for_stall(shared: &(Mutex<Watch>, Condvar), limit: Duration) -> Option<Stall> {
    let (lock, wake) = shared;
    let mut watch = lock.lock().unwrap_or_else(|e| e.into_inner());
    loop {
        if watch.stop {
            return None;
        }
        watch = match watch.armed {
            None => wake.wait(watch).unwrap_or_else(|e| e.into_inner()),
            Some((call, since)) => {
                let waited = since.elapsed();
                if waited >= limit {
                    return Some(Stall { call, waited });
                }
                wake.wait_timeout(watch, limit - waited)
                    .unwrap_or_else(|e| e.into_inner())
                    .0
            }
        };
    }
}

impl Drop for Watchdog {
    fn drop(&mut self) {
        self.set(|w| w.stop = true);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}
