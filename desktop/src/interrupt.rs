//! Ctrl-C and SIGTERM end a long run cleanly instead of killing it: the first one sets a flag
//! the long loops read (a sweep stops after the row in hand and writes the rows finished so far;
//! `foveate xr` asks the runtime to end the session and prints its summary), and the run exits
//! non-zero saying so. A second signal ends the process at once, for a loop that no longer looks.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, OnceLock};

use signal_hook::consts::{SIGINT, SIGTERM};

static REQUESTED: OnceLock<Arc<AtomicBool>> = OnceLock::new();

/// Installs the handlers, for the commands whose loops read the flag (the others keep the
/// default: a signal ends them, and the files they write are whole or absent). A failure is
/// said, not fatal: signals then end the run as before.
pub fn install() {
    if let Err(e) = try_install() {
        log::warn!("Ctrl-C will end this run abruptly: its handler could not be installed ({e})");
    }
}

fn try_install() -> std::io::Result<()> {
    let flag = REQUESTED.get_or_init(|| Arc::new(AtomicBool::new(false)));
    for signal in [SIGINT, SIGTERM] {
        // Registered first, so it sees the flag as the previous signal left it: a second
        // signal exits at once (128 + the signal, as a shell reports a killed process).
        signal_hook::flag::register_conditional_shutdown(signal, 128 + signal, flag.clone())?;
        signal_hook::flag::register(signal, flag.clone())?;
    }
    Ok(())
}

/// Whether Ctrl-C or SIGTERM asked the run to end.
pub fn requested() -> bool {
    REQUESTED
        .get()
        .is_some_and(|flag| flag.load(Ordering::Relaxed))
}

/// The error a run ends with once it has stopped for a signal and written what it had.
pub fn stopped(done: &str) -> anyhow::Error {
    anyhow::anyhow!("interrupted (Ctrl-C or SIGTERM): {done}")
}

/// The error a run ends with once it has written what it had: `failed`, the failure that
/// stopped it, with `done` said first, or else the signal's ([`stopped`]).
pub fn stopped_by(failed: Option<anyhow::Error>, done: &str) -> anyhow::Error {
    match failed {
        Some(e) => e.context(done.to_string()),
        None => stopped(done),
    }
}
