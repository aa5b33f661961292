//! The session's frames in flight, driven as an engine drives foveate: one command buffer and
//! fence per frame slot of the renderer, each frame recorded with `Renderer::record` and
//! submitted without waiting; a slot's fence is waited on only when the slot comes round
//! again, and the figures of the frame it held are read then.

use ash::vk;

use crate::gpu::{CommandPool, Fence, Gpu, GpuError, VkResultExt};
use crate::render::{FrameInput, FrameRecord, FrameStats, Renderer};

struct Slot {
    cmd: vk::CommandBuffer,
    _pool: CommandPool,
    fence: Fence,
    /// The frame submitted from this slot whose figures were not read yet.
    pending: Option<FrameRecord>,
    /// Whether its fence was waited on already (and reset: not to be waited on again).
    waited: bool,
}

pub(super) struct FramesInFlight {
    slots: Vec<Slot>,
    next: usize,
}

impl FramesInFlight {
    /// One slot per frame slot of `renderer`, for a renderer that has recorded nothing yet.
    pub fn new(gpu: &Gpu, renderer: &Renderer) -> Result<Self, GpuError> {
        let slots = (0..renderer.frame_slots())
            .map(|_| {
                let pool = gpu.command_pool(vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER)?;
                Ok(Slot {
                    cmd: gpu.allocate_command_buffer(&pool)?,
                    _pool: pool,
                    fence: gpu.fence()?,
                    pending: None,
                    waited: false,
                })
            })
            .collect::<Result<_, GpuError>>()?;
        Ok(FramesInFlight { slots, next: 0 })
    }

    /// How many frames may be in flight.
    pub fn len(&self) -> usize {
        self.slots.len()
    }

    /// Records and submits the frame `input` describes; returns the figures of the frame that
    /// last held its slot, which it waited for (`None` while the first frames fill the slots).
    pub fn render(
        &mut self,
        gpu: &Gpu,
        renderer: &mut Renderer,
        input: &FrameInput,
    ) -> Result<Option<FrameStats>, GpuError> {
        let slot = &mut self.slots[self.next];
        let finished = match slot.pending.take() {
            Some(record) => {
                if !std::mem::take(&mut slot.waited) {
                    gpu.wait(&slot.fence)?;
                }
                renderer.frame_stats(record)?
            }
            None => None,
        };
        let device = gpu.device();
        // SAFETY: the slot's last submission was waited on above, so its buffer is idle; one
        // left recording by a refused input is reset too.
        unsafe {
            device
                .reset_command_buffer(slot.cmd, vk::CommandBufferResetFlags::empty())
                .vk("vkResetCommandBuffer")?;
            let begin = vk::CommandBufferBeginInfo::default()
                .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
            device
                .begin_command_buffer(slot.cmd, &begin)
                .vk("vkBeginCommandBuffer")?;
        }
        // SAFETY: recording into this device's buffer; the renderer's slot is the one whose
        // fence was waited on (both take their slots in turn, as many of them).
        let record = unsafe { renderer.record(slot.cmd, input)? };
        unsafe { device.end_command_buffer(slot.cmd) }.vk("vkEndCommandBuffer")?;
        // SAFETY: ended above; the renderer outlives it (the session waits for the device
        // before dropping a renderer).
        unsafe { gpu.submit(slot.cmd, &slot.fence)? };
        slot.pending = Some(record);
        self.next = (self.next + 1) % self.slots.len();
        Ok(finished)
    }

    /// Waits for the frame submitted last (to read its image back before the runtime takes
    /// it); its figures stay to be read when its slot comes round.
    pub fn wait_last(&mut self, gpu: &Gpu) -> Result<(), GpuError> {
        let last = (self.next + self.slots.len() - 1) % self.slots.len();
        let slot = &mut self.slots[last];
        if slot.pending.is_some() && !slot.waited {
            gpu.wait(&slot.fence)?;
            slot.waited = true;
        }
        Ok(())
    }
}
