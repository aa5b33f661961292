//! Frames in flight as an engine keeps them, for callers that have no frame loop of their own
//! (`foveate view`, `foveate xr`, the Android demo): one command buffer and fence per frame slot
//! of a [`Renderer`], each frame recorded with [`Renderer::record`] and submitted without
//! waiting. A slot's fence is waited on only when the slot comes round again, and the figures
//! of the frame it held are read then.

use ash::vk;

use super::Renderer;
use crate::foveation_layer::{FrameInput, FrameRecord, FrameStats};
use crate::gpu::{CommandPool, Fence, Gpu, GpuError, VkResultExt};

struct Slot {
    cmd: vk::CommandBuffer,
    _pool: CommandPool,
    fence: Fence,
    /// The frame submitted from this slot whose figures were not read yet.
    pending: Option<FrameRecord>,
    /// Whether its fence was waited on already (and reset: not to be waited on again).
    waited: bool,
}

/// One command buffer and fence per frame slot of a renderer, taken in turn.
///
/// Per frame: [`FramesInFlight::begin`] (waits for the frame that held the slot and returns
/// its figures), [`Renderer::record`] into [`BegunFrame::cmd`] and whatever the caller records
/// after it (a copy to a swapchain image), then [`FramesInFlight::submit`] with the caller's
/// semaphores. [`FramesInFlight::render`] does all three for a frame that waits on nothing.
///
/// ```no_run
/// # fn main() -> Result<(), foveate::gpu::GpuError> {
/// use foveate::gpu::{Gpu, GpuOptions};
/// use foveate::render::{FrameInput, FramesInFlight, Renderer};
/// let gpu = Gpu::new(&GpuOptions::default())?;
/// let scene = foveate::scene::default_scene();
/// let plan = foveate::plan(&scene, &foveate::plan::RenderConfig::default(), gpu.caps())?;
/// let mut renderer = Renderer::new(&gpu, &plan, &scene)?;
/// let mut frames = FramesInFlight::new(&renderer)?;
/// for _ in 0..100 {
///     // The figures of the frame that held this slot before (none while the slots fill).
///     if let Some(stats) = frames.render(&mut renderer, &FrameInput::new(scene.head))? {
///         println!("{:.2} ms", stats.gpu_pass_ms.iter().sum::<f64>());
///     }
/// }
/// frames.wait_all()?;
/// # Ok(())
/// # }
/// ```
pub struct FramesInFlight {
    gpu: Gpu,
    slots: Vec<Slot>,
    /// The slot submitted from last.
    last: Option<usize>,
}

/// A frame slot's command buffer, begun by [`FramesInFlight::begin`]: record the frame into
/// it, then hand it to [`FramesInFlight::submit`].
#[derive(Debug)]
#[must_use = "a begun frame is submitted with FramesInFlight::submit"]
pub struct BegunFrame {
    /// The frame slot (the renderer's next).
    pub slot: usize,
    /// The slot's command buffer, recording.
    pub cmd: vk::CommandBuffer,
}

impl FramesInFlight {
    /// One command buffer and fence per frame slot of `renderer`, on its device.
    pub fn new(renderer: &Renderer) -> Result<Self, GpuError> {
        let gpu = renderer.gpu().clone();
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
        Ok(FramesInFlight {
            gpu,
            slots,
            last: None,
        })
    }

    /// How many frames may be in flight.
    pub fn len(&self) -> usize {
        self.slots.len()
    }

    /// Always false: a renderer has at least one frame slot.
    pub fn is_empty(&self) -> bool {
        self.slots.is_empty()
    }

    /// Waits for the frame that last held `renderer`'s next slot, reads its figures (`None`
    /// while the first frames fill the slots) and begins the slot's command buffer.
    pub fn begin(
        &mut self,
        renderer: &mut Renderer,
    ) -> Result<(BegunFrame, Option<FrameStats>), GpuError> {
        let index = renderer.next_slot();
        let count = self.slots.len();
        let slot = self.slots.get_mut(index).ok_or_else(|| {
            GpuError::FramesInFlight(format!(
                "frame slot {index}: these were made for a renderer with {count} slots"
            ))
        })?;
        let finished = match slot.pending.take() {
            Some(record) => {
                if !std::mem::take(&mut slot.waited) {
                    self.gpu.wait(&slot.fence)?;
                }
                renderer.frame_stats(record)?
            }
            None => None,
        };
        let device = self.gpu.device();
        // SAFETY: the slot's last submission was waited on above, so its buffer is idle; one
        // left recording by a refused frame is reset too.
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
        let cmd = slot.cmd;
        Ok((BegunFrame { slot: index, cmd }, finished))
    }

    /// Ends `frame`'s command buffer and submits it, waiting for `waits` and signalling
    /// `signals` (a swapchain's acquire and present semaphores; none for a headless frame).
    /// `record` is what [`Renderer::record`] returned for it.
    ///
    /// # Safety
    /// Everything recorded into `frame.cmd` stays alive until the slot's next
    /// [`FramesInFlight::begin`] or [`FramesInFlight::wait_all`]; the semaphores are as
    /// [`Gpu::submit_with_semaphores`] asks.
    pub unsafe fn submit(
        &mut self,
        frame: BegunFrame,
        record: FrameRecord,
        waits: &[(vk::Semaphore, vk::PipelineStageFlags)],
        signals: &[vk::Semaphore],
    ) -> Result<(), GpuError> {
        if record.slot != frame.slot {
            return Err(GpuError::FramesInFlight(format!(
                "the frame recorded into slot {} was submitted from slot {}",
                record.slot, frame.slot
            )));
        }
        let slot = &mut self.slots[frame.slot];
        let device = self.gpu.device();
        unsafe { device.end_command_buffer(slot.cmd) }.vk("vkEndCommandBuffer")?;
        // SAFETY: ended above and idle since `begin`; the caller keeps what it uses alive.
        unsafe {
            self.gpu
                .submit_with_semaphores(slot.cmd, waits, signals, &slot.fence)?
        };
        slot.pending = Some(record);
        self.last = Some(frame.slot);
        Ok(())
    }

    /// Records and submits the frame `input` describes, waiting on nothing; returns the
    /// figures of the frame that last held its slot (`None` while the first frames fill the
    /// slots).
    pub fn render(
        &mut self,
        renderer: &mut Renderer,
        input: &FrameInput,
    ) -> Result<Option<FrameStats>, GpuError> {
        let (frame, finished) = self.begin(renderer)?;
        // SAFETY: recording into this device's buffer for the slot `begin` waited for.
        let record = unsafe { renderer.record(frame.cmd, input)? };
        // SAFETY: the renderer's objects live until it drops, and a renderer drops only after
        // its frames (the caller's `wait_all`, or this struct's drop before the renderer's).
        unsafe { self.submit(frame, record, &[], &[])? };
        Ok(finished)
    }

    /// Waits for the frame submitted last from `slot` (to read its image back); its figures
    /// stay to be read when the slot comes round.
    pub fn wait_slot(&mut self, slot: usize) -> Result<(), GpuError> {
        let Some(slot) = self.slots.get_mut(slot) else {
            return Ok(());
        };
        if slot.pending.is_some() && !slot.waited {
            self.gpu.wait(&slot.fence)?;
            slot.waited = true;
        }
        Ok(())
    }

    /// Waits for the frame submitted last (to read its image back).
    pub fn wait_last(&mut self) -> Result<(), GpuError> {
        self.last.map_or(Ok(()), |k| self.wait_slot(k))
    }

    /// Waits for every frame in flight: before a renderer, or what a frame used, goes.
    pub fn wait_all(&mut self) -> Result<(), GpuError> {
        (0..self.slots.len()).try_for_each(|k| self.wait_slot(k))
    }
}

impl Drop for FramesInFlight {
    /// Waits for the frames still running: their command buffers go with their pools.
    fn drop(&mut self) {
        if let Err(e) = self.wait_all() {
            log::warn!("frames in flight: waiting for them on drop failed: {e}");
        }
    }
}
