//! A lost device (`VK_ERROR_DEVICE_LOST`): the first call that finds it lost (a submission or
//! wait of foveate's, or a layer's check of its slot or read of its queries) marks the device,
//! and every later call through foveate on it is [`GpuError::DeviceLost`] naming that call,
//! instead of a Vulkan call on a dead device whose result nobody checks. Tests lose the device
//! through the seam [`Gpu::simulate_device_lost`], since no driver here loses one on demand, and
//! a program's own fault tests through the environment: with
//! `FOVEATE_LOSE_DEVICE_AFTER_SUBMITS=N` a device foveate opens is lost at its N-th submission.

use ash::vk;

use super::{Gpu, GpuError};

/// The environment variable that loses a device at its N-th submission (fault tests).
const LOSE_AFTER: &str = "FOVEATE_LOSE_DEVICE_AFTER_SUBMITS";

/// Whether a device is lost, and where a fault test loses it.
#[derive(Debug, Default)]
pub(crate) struct Loss {
    /// The call that found the device lost.
    found: Option<&'static str>,
    /// The submission a fault test loses the device at (`None`: never).
    lose_at: Option<u64>,
    /// Submissions so far (counted only for a fault test).
    submits: u64,
}

impl Loss {
    /// No loss yet; the simulated one from the environment, if it asks for one.
    pub(crate) fn from_env() -> Self {
        let lose_at = std::env::var(LOSE_AFTER).ok().and_then(|v| {
            let n = v.parse::<u64>().ok().filter(|&n| n > 0);
            if n.is_none() {
                log::warn!("{LOSE_AFTER}={v} ignored: a whole number of submissions, 1 or more");
            }
            n
        });
        Loss {
            lose_at,
            ..Loss::default()
        }
    }
}

impl Gpu {
    /// The call that found the device lost, if one has.
    pub fn device_lost(&self) -> Option<&'static str> {
        self.dev
            .lost
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .found
    }

    /// `Ok` while the device is not known lost; else [`GpuError::DeviceLost`].
    pub fn check_alive(&self) -> Result<(), GpuError> {
        match self.device_lost() {
            None => Ok(()),
            Some(call) => Err(GpuError::DeviceLost { call }),
        }
    }

    /// `result`, the device marked lost when it says so (and the error then names the loss).
    pub(crate) fn noting_loss<T>(&self, result: Result<T, GpuError>) -> Result<T, GpuError> {
        match result {
            Err(GpuError::Vk {
                call,
                result: vk::Result::ERROR_DEVICE_LOST,
            }) => {
                self.mark_lost(call);
                Err(GpuError::DeviceLost { call })
            }
            other => other,
        }
    }

    fn mark_lost(&self, call: &'static str) {
        let mut lost = self.dev.lost.lock().unwrap_or_else(|e| e.into_inner());
        lost.found.get_or_insert(call);
    }

    /// `Ok` when a submission may go ahead: the device is not lost, and a fault test's
    /// countdown ([`Loss::from_env`]) has not run out at this one (then it is lost here).
    pub(crate) fn before_submit(&self) -> Result<(), GpuError> {
        self.check_alive()?;
        let mut lost = self.dev.lost.lock().unwrap_or_else(|e| e.into_inner());
        let Some(lose_at) = lost.lose_at else {
            return Ok(());
        };
        lost.submits += 1;
        // A test reads the count (RUST_LOG=foveate::gpu=debug) to place the loss.
        log::debug!(
            "{LOSE_AFTER}: submission {} (lost at {lose_at})",
            lost.submits
        );
        if lost.submits < lose_at {
            return Ok(());
        }
        let call = "vkQueueSubmit";
        lost.found.get_or_insert(call);
        log::warn!("{LOSE_AFTER}: the device is lost at this submission (a fault test)");
        Err(GpuError::DeviceLost { call })
    }

    /// The seam for tests: marks the device lost as if `call` had returned
    /// `VK_ERROR_DEVICE_LOST` (the device itself goes on working, unused by foveate).
    #[doc(hidden)]
    pub fn simulate_device_lost(&self, call: &'static str) {
        self.mark_lost(call);
    }
}
