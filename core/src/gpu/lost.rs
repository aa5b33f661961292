//! A lost device (`VK_ERROR_DEVICE_LOST`): the first call that finds it lost marks the device,
//! and every later call through foveate on it is [`GpuError::DeviceLost`] naming that call,
//! instead of a Vulkan call on a dead device whose result nobody checks. Tests lose the device
//! through the seam [`Gpu::simulate_device_lost`], since no driver here loses one on demand.

use ash::vk;

use super::{Gpu, GpuError};

impl Gpu {
    /// The call that found the device lost, if one has.
    pub fn device_lost(&self) -> Option<&'static str> {
        *self.dev.lost.lock().unwrap_or_else(|e| e.into_inner())
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
        lost.get_or_insert(call);
    }

    /// The seam for tests: marks the device lost as if `call` had returned
    /// `VK_ERROR_DEVICE_LOST` (the device itself goes on working, unused by foveate).
    #[doc(hidden)]
    pub fn simulate_device_lost(&self, call: &'static str) {
        self.mark_lost(call);
    }
}
