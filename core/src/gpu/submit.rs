use ash::vk;

use super::{CommandPool, Event, Fence, Gpu, GpuError, ShaderModule, VkResultExt};
use crate::shaders::ShaderBinary;

impl Gpu {
    /// A shader module of `shader`'s SPIR-V.
    pub(crate) fn shader_module(&self, shader: &ShaderBinary) -> Result<ShaderModule, GpuError> {
        let words = shader.words();
        let info = vk::ShaderModuleCreateInfo::default().code(&words);
        // SAFETY: valid SPIR-V (compiled and validated at build time); owned by the result.
        let raw = unsafe { self.device().create_shader_module(&info, None) }
            .vk("vkCreateShaderModule")?;
        Ok(ShaderModule::from_raw(&self.dev, raw))
    }

    /// Records commands with `record`, submits them and waits for completion. For set-up and
    /// readback, not for frames.
    pub fn one_shot(&self, record: impl FnOnce(vk::CommandBuffer)) -> Result<(), GpuError> {
        let pool = self.command_pool(vk::CommandPoolCreateFlags::TRANSIENT)?;
        let cmd = self.allocate_command_buffer(&pool)?;
        let fence = self.fence()?;
        let device = self.device();
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: fresh command buffer from a pool owned here; waited on before the pool drops.
        unsafe { device.begin_command_buffer(cmd, &begin) }.vk("vkBeginCommandBuffer")?;
        record(cmd);
        unsafe { device.end_command_buffer(cmd) }.vk("vkEndCommandBuffer")?;
        // SAFETY: `cmd` was recorded and ended above; its pool and `fence` outlive the wait.
        unsafe { self.submit(cmd, &fence)? };
        self.wait(&fence)
    }

    #[doc(hidden)]
    pub fn command_pool(&self, flags: vk::CommandPoolCreateFlags) -> Result<CommandPool, GpuError> {
        let info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(self.queue_family)
            .flags(flags);
        let raw =
            unsafe { self.device().create_command_pool(&info, None) }.vk("vkCreateCommandPool")?;
        Ok(CommandPool::from_raw(&self.dev, raw))
    }

    #[doc(hidden)]
    pub fn allocate_command_buffer(
        &self,
        pool: &CommandPool,
    ) -> Result<vk::CommandBuffer, GpuError> {
        let info = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool.raw)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let buffers = unsafe { self.device().allocate_command_buffers(&info) }
            .vk("vkAllocateCommandBuffers")?;
        Ok(buffers[0])
    }

    #[doc(hidden)]
    pub fn fence(&self) -> Result<Fence, GpuError> {
        let raw = unsafe {
            self.device()
                .create_fence(&vk::FenceCreateInfo::default(), None)
        }
        .vk("vkCreateFence")?;
        Ok(Fence::from_raw(&self.dev, raw))
    }

    /// An event, unset: the GPU sets it from a command buffer, the host reads it.
    pub(crate) fn event(&self) -> Result<Event, GpuError> {
        // SAFETY: a plain event, owned by the result.
        let raw = unsafe {
            self.device()
                .create_event(&vk::EventCreateInfo::default(), None)
        }
        .vk("vkCreateEvent")?;
        Ok(Event::from_raw(&self.dev, raw))
    }

    /// Submits one command buffer to the graphics queue, signalling `fence` (unsignalled).
    /// Other threads' submissions wait meanwhile (the queue is locked).
    ///
    /// # Safety
    /// `cmd` is a command buffer of this device in the executable state (recorded and ended),
    /// not pending elsewhere, and it and everything it uses stay alive until `fence` signals.
    pub unsafe fn submit(&self, cmd: vk::CommandBuffer, fence: &Fence) -> Result<(), GpuError> {
        // SAFETY: as the caller promised; no semaphores.
        unsafe { self.submit_with_semaphores(cmd, &[], &[], fence) }
    }

    /// Submits one command buffer that waits for `waits` (each semaphore at its stage) and
    /// signals `signals` and `fence` when done: a frame whose image comes from a swapchain
    /// and goes back to it. Other threads' submissions wait meanwhile (the queue is locked).
    ///
    /// # Safety
    /// As [`Gpu::submit`]; the semaphores are this device's, each wait one that a signal
    /// already submitted (or an acquire) will signal, each signal unsignalled with no
    /// operation pending.
    pub unsafe fn submit_with_semaphores(
        &self,
        cmd: vk::CommandBuffer,
        waits: &[(vk::Semaphore, vk::PipelineStageFlags)],
        signals: &[vk::Semaphore],
        fence: &Fence,
    ) -> Result<(), GpuError> {
        let cmds = [cmd];
        let (wait_semaphores, stages): (Vec<_>, Vec<_>) = waits.iter().copied().unzip();
        let mut info = vk::SubmitInfo::default().command_buffers(&cmds);
        // Empty lists stay null pointers (best practices flags a pointer with a zero count).
        if !waits.is_empty() {
            info = info
                .wait_semaphores(&wait_semaphores)
                .wait_dst_stage_mask(&stages);
        }
        if !signals.is_empty() {
            info = info.signal_semaphores(signals);
        }
        let submit = [info];
        self.before_submit()?;
        let submitted = self
            .with_queue(|queue| unsafe { self.device().queue_submit(queue, &submit, fence.raw) });
        self.noting_loss(submitted.vk("vkQueueSubmit"))
    }

    /// Waits for `fence` and resets it for the next submission.
    pub fn wait(&self, fence: &Fence) -> Result<(), GpuError> {
        self.check_alive()?;
        let fences = [fence.raw];
        let waited = unsafe { self.device().wait_for_fences(&fences, true, u64::MAX) };
        self.noting_loss(waited.vk("vkWaitForFences"))?;
        unsafe { self.device().reset_fences(&fences).vk("vkResetFences") }
    }
}

/// One side of an image layout transition: the stage, its accesses, and the layout.
pub(crate) type ImageState = (vk::PipelineStageFlags, vk::AccessFlags, vk::ImageLayout);

/// Records a transition of `range` of `image` from `src` to `dst` into `cmd`.
///
/// # Safety
/// `cmd` is recording, and `image` outlives its execution.
pub(crate) unsafe fn transition_image(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    image: vk::Image,
    range: vk::ImageSubresourceRange,
    src: ImageState,
    dst: ImageState,
) {
    let barrier = vk::ImageMemoryBarrier::default()
        .old_layout(src.2)
        .new_layout(dst.2)
        .src_access_mask(src.1)
        .dst_access_mask(dst.1)
        .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
        .image(image)
        .subresource_range(range);
    unsafe {
        device.cmd_pipeline_barrier(
            cmd,
            src.0,
            dst.0,
            vk::DependencyFlags::empty(),
            &[],
            &[],
            &[barrier],
        )
    };
}

/// The (stage, access) pairs the judge's and the readback's barriers name.
pub(crate) mod access {
    use ash::vk::{AccessFlags as A, PipelineStageFlags as S};

    /// A transfer's writes (copies, fills).
    pub const TRANSFER_WRITE: (S, A) = (S::TRANSFER, A::TRANSFER_WRITE);
    /// A transfer's reads (the source of a copy).
    pub const TRANSFER_READ: (S, A) = (S::TRANSFER, A::TRANSFER_READ);
    /// A compute shader's writes.
    pub const COMPUTE_WRITE: (S, A) = (S::COMPUTE_SHADER, A::SHADER_WRITE);
    /// A compute shader's reads.
    pub const COMPUTE_READ: (S, A) = (S::COMPUTE_SHADER, A::SHADER_READ);
    /// A compute shader's reads and writes.
    pub const COMPUTE_READ_WRITE: (S, A) = (
        S::COMPUTE_SHADER,
        A::from_raw(A::SHADER_READ.as_raw() | A::SHADER_WRITE.as_raw()),
    );
    /// The host's reads of mapped memory, after a fence.
    pub const HOST_READ: (S, A) = (S::HOST, A::HOST_READ);
}

/// A global memory barrier: what `src` did, available to and visible for `dst`.
///
/// # Safety
/// `cmd` is a command buffer of `device` in the recording state.
pub(crate) unsafe fn memory_barrier(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    src: (vk::PipelineStageFlags, vk::AccessFlags),
    dst: (vk::PipelineStageFlags, vk::AccessFlags),
) {
    let barrier = [vk::MemoryBarrier::default()
        .src_access_mask(src.1)
        .dst_access_mask(dst.1)];
    device.cmd_pipeline_barrier(
        cmd,
        src.0,
        dst.0,
        vk::DependencyFlags::empty(),
        &barrier,
        &[],
        &[],
    );
}
