//! The demo's backend on Vulkan: the default scene, lit and foveated, rendered by the core
//! renderer and presented through `gpu::Swapchain` (the same code as `foveate view`) on the
//! window Android gives: `VK_KHR_android_surface` there, any window `ash-window` knows on a
//! host (the tests use X11).

use std::marker::PhantomData;

use foveate::foveation::FoveationConfig;
use foveate::gpu::{Acquired, Gpu, Presented, Swapchain};
use foveate::plan::OutputStage;
use foveate::plan::{FramePlan, RenderConfig};
use foveate::render::{FrameInput, FramesInFlight, Renderer};
use foveate::scene::{default_scene, Scene, Shading};
use glam::Vec2;
use raw_window_handle::{HasWindowHandle, RawDisplayHandle};

use crate::app::{Backend, DemoError, Drawn};

/// The frame the demo shows: the library's default foveation (a 0.35 fovea, the periphery at 0.6
/// accumulated over frames) with its default blend band, MSAA 4, the HMD mask,
/// through the lens output stage (what a phone in a headset shows), 1024² per eye.
pub fn demo_config() -> RenderConfig {
    RenderConfig {
        foveation: Some(FoveationConfig {
            ..FoveationConfig::default()
        }),
        hmd_mask: true,
        output: OutputStage::Lens,
        ..RenderConfig::default()
    }
}

/// The default scene, lit.
pub fn demo_scene() -> Scene {
    default_scene().with_shading(Shading::Lit)
}

/// The renderer and its frames in flight (declared first: dropped, so waited for, before
/// the renderer their commands use).
struct Rendering {
    frames: FramesInFlight,
    renderer: Renderer,
}

/// Renders on `gpu` and presents to windows of type `W` of `display`.
pub struct VulkanBackend<'g, W> {
    gpu: &'g Gpu,
    display: RawDisplayHandle,
    scene: Scene,
    plan: FramePlan,
    rendering: Option<Rendering>,
    swapchain: Option<Swapchain>,
    window: PhantomData<W>,
}

impl<'g, W> VulkanBackend<'g, W> {
    /// A backend for `config`, planned now (a refused configuration fails here rather than at
    /// the first frame); the renderers are made from that plan when a frame needs them. `gpu` must have been opened for `display`.
    pub fn new(
        gpu: &'g Gpu,
        display: RawDisplayHandle,
        scene: Scene,
        config: RenderConfig,
    ) -> Result<Self, DemoError> {
        let plan = foveate::plan(&scene, &config, gpu.caps())?;
        log::info!("{plan}");
        Ok(VulkanBackend {
            gpu,
            display,
            scene,
            plan,
            rendering: None,
            swapchain: None,
            window: PhantomData,
        })
    }

    /// Whether the renderers exist (they are dropped on low memory).
    pub fn has_renderer(&self) -> bool {
        self.rendering.is_some()
    }

    /// The swapchain's size, while there is one.
    pub fn extent(&self) -> Option<(u32, u32)> {
        self.swapchain
            .as_ref()
            .map(|s| (s.extent.width, s.extent.height))
    }

    fn rendering(&mut self) -> Result<&mut Rendering, DemoError> {
        if self.rendering.is_none() {
            let renderer = Renderer::new(self.gpu, &self.plan, &self.scene)?;
            let frames = FramesInFlight::new(&renderer)?;
            self.rendering = Some(Rendering { frames, renderer });
        }
        Ok(self.rendering.as_mut().expect("made above"))
    }
}

impl<W: HasWindowHandle> Backend for VulkanBackend<'_, W> {
    type Window = W;

    unsafe fn open(&mut self, window: &W, size: (u32, u32)) -> Result<(), DemoError> {
        let handle = window
            .window_handle()
            .map_err(|e| format!("the window has no handle: {e}"))?
            .as_raw();
        // SAFETY: the caller keeps the window alive until `close`.
        let swapchain = unsafe { Swapchain::new(self.gpu, self.display, handle, size) }?;
        self.swapchain = Some(swapchain);
        Ok(())
    }

    fn close(&mut self) {
        self.swapchain = None;
    }

    fn resize(&mut self, size: (u32, u32)) {
        if let Some(s) = &mut self.swapchain {
            s.resize(size);
        }
    }

    fn release_memory(&mut self) {
        self.rendering = None;
    }

    fn draw(&mut self, gaze: Vec2) -> Result<Drawn, DemoError> {
        let gpu = self.gpu;
        let input = FrameInput::new(self.scene.head).with_gaze([gaze; 2]);
        self.swapchain.as_ref().ok_or("draw without a window")?;
        self.rendering()?;
        let Rendering { frames, renderer } = self.rendering.as_mut().expect("made above");
        let swapchain = self.swapchain.as_mut().expect("checked above");
        // Waits for the frame that held this slot before: the one before it may still run.
        let (begun, finished) = frames.begin(renderer)?;
        // SAFETY: `begin` waited for the frame that acquired with this slot before.
        let acquired = unsafe { swapchain.acquire(gpu, begun.slot)? };
        // SAFETY: the slot's buffer, begun by `begin`, whose previous frame finished.
        let record = unsafe { renderer.record(begun.cmd, &input)? };
        let image = match acquired {
            Acquired::Image(image) => image,
            Acquired::Skipped | Acquired::Lost => {
                // SAFETY: the renderer outlives its frames (`Rendering` drops `frames` first).
                unsafe { frames.submit(begun, record, &[], &[])? };
                return Ok(match acquired {
                    Acquired::Lost => Drawn::Lost,
                    _ => Drawn::Skipped,
                });
            }
        };
        let sources = renderer.present_sources()?;
        // SAFETY: recorded after the frame into its buffer; the outputs live with the renderer.
        unsafe { swapchain.record_copy(gpu, begun.cmd, &image, &sources, false)? };
        // SAFETY: as above; the image's semaphores are waited for and signalled once each.
        unsafe { frames.submit(begun, record, &image.waits(), &image.signals())? };
        Ok(match swapchain.present(gpu, image)? {
            Presented::Shown => Drawn::Shown {
                gpu_pass_ms: finished.map(|s| s.gpu_pass_ms),
            },
            Presented::Lost => Drawn::Lost,
        })
    }

    fn locate(&self, x: f64, y: f64) -> Option<Vec2> {
        let (_, gaze) = self.swapchain.as_ref()?.locate(x, y)?;
        Some(Vec2::from(gaze))
    }

    fn pass_names(&self) -> Vec<&'static str> {
        self.plan.passes.iter().map(|p| p.name).collect()
    }
}
