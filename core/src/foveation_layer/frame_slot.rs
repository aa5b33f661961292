//! Frame slots: what one frame in flight writes from the CPU or reads back — the views' uniform
//! block, the culled instance ids, the counting frame's counters, the scene's descriptor set
//! over them, the query pools — one set per slot, so frame N+1 records into its slot while
//! frame N still runs on the GPU. Images the GPU alone writes and reads are shared by every
//! slot: one queue orders them, and the plan's barriers synchronize them.

use ash::vk;

use super::descriptors::DescriptorSet;
use super::pipelines::{scene_bindings, LitBindings};
use super::setup::{effect_buffer, query_pool};
use super::stats::{FrameStats, PassStatistics};
use super::views::ViewsBlock;
use crate::gpu::{
    Buffer, CommandPool, Event, Fence, Gpu, GpuError, MemoryLocation, QueryPool, VkResultExt,
};
use crate::plan::FramePlan;

/// One frame slot's resources, and what its last frame recorded.
pub(crate) struct FrameSlot {
    /// The scene's descriptor set over this slot's buffers (used through the bound steps).
    pub bindings: DescriptorSet,
    pub views_block: Buffer,
    pub counter: Option<Buffer>,
    pub instance_ids: Option<Buffer>,
    /// The instances as they stand this frame, when they move (else the scene's buffer).
    pub instances: Option<Buffer>,
    pub queries: Option<QueryPool>,
    /// Pipeline-statistics queries, one per pass (counting frames on devices that have them).
    pub statistics: Option<QueryPool>,
    /// The command buffer `Renderer::render_frame` records the slot's frames into,
    /// and the fence it waits on (a caller of `record` brings its own).
    pub cmd: vk::CommandBuffer,
    pub pool: CommandPool,
    pub fence: Fence,
    /// Set by the GPU when the slot's last frame has run to its end (the last command the
    /// layer records into it): the layer's own word on whether the slot is free again, in
    /// whoever's command buffer the frame was recorded.
    pub finished: Event,
    /// The last frame recorded in this slot, until another is.
    pub recorded: Option<SlotFrame>,
}

/// What recording a frame measured on the CPU; the GPU's figures come from the slot's queries.
#[derive(Clone, Debug, Default)]
pub(crate) struct SlotFrame {
    /// The frame's number (frames recorded before it).
    pub frame: u64,
    pub cpu_record_ms: f64,
    pub cpu_cull_ms: f64,
    pub draw_calls: u64,
    pub triangles: u64,
    pub pass_triangles: Vec<u64>,
    pub instances_drawn: Vec<u64>,
}

/// The scene's resources a slot's descriptor set binds beside the slot's own buffers, handed in
/// by whoever draws the scene steps: foveate's scene renderer's instances and a lit scene's
/// materials; none when an engine draws the scene.
#[derive(Clone, Copy, Default)]
pub(crate) struct SharedBindings<'a> {
    pub instances: Option<&'a Buffer>,
    pub lit: Option<LitBindings<'a>>,
}

impl FrameSlot {
    /// A slot's buffers and query pools, as the plan asks for them (none that an effect off
    /// would need), and the scene's bindings over them with this slot's `masks` buffer.
    pub fn new(
        gpu: &Gpu,
        plan: &FramePlan,
        shared: &SharedBindings,
        masks: Option<&Buffer>,
    ) -> Result<Self, GpuError> {
        let views_block = Buffer::new(
            gpu,
            "views",
            std::mem::size_of::<ViewsBlock>() as u64,
            vk::BufferUsageFlags::UNIFORM_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let counter = effect_buffer(
            gpu,
            plan.fragment_counter(),
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
        )?;
        let instance_ids = effect_buffer(
            gpu,
            plan.instance_ids(),
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let instances = effect_buffer(
            gpu,
            plan.moving_instances(),
            vk::BufferUsageFlags::STORAGE_BUFFER,
            MemoryLocation::CpuToGpu,
        )?;
        let bindings = scene_bindings(
            gpu,
            &views_block,
            instances.as_ref().or(shared.instances),
            counter.as_ref(),
            masks,
            instance_ids.as_ref(),
            shared.lit,
        )?;
        let pool = gpu.command_pool(vk::CommandPoolCreateFlags::TRANSIENT)?;
        let queries = query_pool(gpu, vk::QueryType::TIMESTAMP, plan.timestamp_pool_slots())?;
        let statistics = query_pool(
            gpu,
            vk::QueryType::PIPELINE_STATISTICS,
            plan.statistics_pool_slots(),
        )?;
        reset_queries(
            gpu,
            [
                (queries.as_ref(), plan.timestamp_pool_slots()),
                (statistics.as_ref(), plan.statistics_pool_slots()),
            ],
        )?;
        Ok(FrameSlot {
            bindings,
            cmd: gpu.allocate_command_buffer(&pool)?,
            pool,
            fence: gpu.fence()?,
            finished: gpu.event()?,
            views_block,
            counter,
            instance_ids,
            instances,
            queries,
            statistics,
            recorded: None,
        })
    }

    /// `Ok` when the slot may take a frame: none recorded yet, or its last one has run to its
    /// end on the GPU; else an error naming that frame.
    pub fn check_free(&self, gpu: &Gpu, slot: usize) -> Result<(), GpuError> {
        let Some(last) = &self.recorded else {
            return Ok(());
        };
        // SAFETY: the event is this slot's, alive.
        let status = unsafe { gpu.device().get_event_status(self.finished.raw) };
        // An engine's own fence wait may have met a lost device first: this marks it here.
        let done = gpu.noting_loss(status.vk("vkGetEventStatus"))?;
        if done {
            return Ok(());
        }
        Err(GpuError::SlotInFlight {
            frame: last.frame,
            slot,
        })
    }

    /// Unsets the slot's event for the frame about to be recorded (its last frame has finished:
    /// [`FrameSlot::check_free`]).
    pub fn unset_finished(&self, gpu: &Gpu) -> Result<(), GpuError> {
        // SAFETY: no pending work sets or waits on the event: the slot was checked free.
        unsafe { gpu.device().reset_event(self.finished.raw) }.vk("vkResetEvent")
    }

    /// Records, at the end of the frame recorded into `cmd`, the GPU's word that it has run:
    /// the event set once everything before it in `cmd` has completed.
    pub fn record_finished(&self, gpu: &Gpu, cmd: vk::CommandBuffer) {
        // Set once every command before it has completed every stage.
        let stage = vk::PipelineStageFlags::BOTTOM_OF_PIPE;
        // SAFETY: `cmd` is recording, outside a render pass (the frame's passes are closed).
        unsafe { gpu.device().cmd_set_event(cmd, self.finished.raw, stage) }
    }

    /// The slot's last frame's figures: `None` while its queries are not yet available (the
    /// frame has not finished), unless `wait` says to wait for them. Counters are read as they
    /// are, so a counting frame is read only after its fence.
    pub fn stats(
        &mut self,
        gpu: &Gpu,
        plan: &FramePlan,
        wait: bool,
    ) -> Result<Option<FrameStats>, GpuError> {
        let flags = if wait {
            vk::QueryResultFlags::TYPE_64 | vk::QueryResultFlags::WAIT
        } else {
            vk::QueryResultFlags::TYPE_64
        };
        let Some((gpu_ms, gpu_pass_ms)) = self.read_gpu_times(gpu, plan, flags)? else {
            return Ok(None);
        };
        let Some(pass_statistics) = self.read_pass_statistics(gpu, plan, flags)? else {
            return Ok(None);
        };
        let (steps, history) = match self.counter.as_mut() {
            Some(counter) => super::counting::read_counts(plan, counter),
            None => (Vec::new(), None),
        };
        let frame = self.recorded.clone().unwrap_or_default();
        let mut stats = FrameStats {
            cpu_record_ms: frame.cpu_record_ms,
            cpu_submit_ms: 0.0,
            frame_ms: frame.cpu_record_ms + frame.cpu_cull_ms,
            gpu_ms,
            gpu_pass_ms,
            pass_names: plan.passes.iter().map(|p| p.name).collect(),
            fragments: Vec::new(),
            far_fragments: None,
            steps,
            history,
            cpu_cull_ms: frame.cpu_cull_ms,
            instances_drawn: frame.instances_drawn,
            draw_calls: frame.draw_calls,
            triangles: frame.triangles,
            pass_triangles: frame.pass_triangles,
            pass_statistics,
        };
        if self.counter.is_some() {
            stats.split_scene_fragments(plan.views, plan.mffr.is_some());
        }
        Ok(Some(stats))
    }

    /// Frame and per-pass GPU times from the timestamps; `None` when not yet available.
    #[allow(clippy::type_complexity)]
    fn read_gpu_times(
        &self,
        gpu: &Gpu,
        plan: &FramePlan,
        flags: vk::QueryResultFlags,
    ) -> Result<Option<(Option<f64>, Vec<f64>)>, GpuError> {
        let Some(q) = &self.queries else {
            return Ok(Some((None, Vec::new())));
        };
        let mut ticks = vec![0u64; plan.timestamp_queries as usize];
        // SAFETY: the pool is this slot's, sized by the plan.
        let read = unsafe {
            gpu.device()
                .get_query_pool_results(q.raw, 0, &mut ticks, flags)
        };
        if !queries_read(gpu, read)? {
            return Ok(None);
        }
        let ms = |a: u64, b: u64| b.wrapping_sub(a) as f64 * gpu.timestamp_period_ns / 1e6;
        let passes = ticks.windows(2).map(|w| ms(w[0], w[1])).collect();
        Ok(Some((Some(ms(ticks[0], ticks[ticks.len() - 1])), passes)))
    }

    /// Each pass's pipeline statistics (empty without statistics queries); `None` when not yet
    /// available.
    fn read_pass_statistics(
        &self,
        gpu: &Gpu,
        plan: &FramePlan,
        flags: vk::QueryResultFlags,
    ) -> Result<Option<Vec<PassStatistics>>, GpuError> {
        let Some(q) = &self.statistics else {
            return Ok(Some(Vec::new()));
        };
        // One [u64; 4] per query: ash derives the query count and stride from the element.
        let mut values = vec![[0u64; 4]; plan.statistics_queries as usize];
        // SAFETY: the pool is this slot's, sized by the plan.
        let read = unsafe {
            gpu.device()
                .get_query_pool_results(q.raw, 0, &mut values, flags)
        };
        if !queries_read(gpu, read)? {
            return Ok(None);
        }
        Ok(Some(
            values
                .iter()
                .map(|v| PassStatistics {
                    assembled: v[0],
                    clipped_in: v[1],
                    rasterised: v[2],
                    fragment_invocations: v[3],
                })
                .collect(),
        ))
    }
}

/// Whether a read of a frame's queries found them (`false`: not yet ready); a wait that gave up
/// on queries its finished frame never wrote is an error saying so.
fn queries_read(gpu: &Gpu, read: Result<(), vk::Result>) -> Result<bool, GpuError> {
    match read {
        Err(vk::Result::NOT_READY) => Ok(false),
        Err(result @ vk::Result::TIMEOUT) => Err(GpuError::QueriesNeverWritten {
            call: "vkGetQueryPoolResults",
            result,
        }),
        other => gpu
            .noting_loss(other.vk("vkGetQueryPoolResults"))
            .map(|()| true),
    }
}

/// Resets new query pools once, on the device: a frame's figures asked for before it ran then
/// find its queries unavailable (not ready) rather than never initialised, which Vulkan forbids
/// reading.
fn reset_queries(gpu: &Gpu, pools: [(Option<&QueryPool>, u32); 2]) -> Result<(), GpuError> {
    let pools: Vec<(&QueryPool, u32)> = pools
        .into_iter()
        .filter_map(|(pool, slots)| pool.map(|p| (p, slots)))
        .collect();
    if pools.is_empty() {
        return Ok(());
    }
    let device = gpu.device();
    gpu.one_shot(|cmd| {
        for (pool, slots) in &pools {
            // SAFETY: the pools are new and idle; every query of each is reset.
            unsafe { device.cmd_reset_query_pool(cmd, pool.raw, 0, *slots) };
        }
    })
}
