//! The demo's backend on Vulkan: the default scene, lit and foveated, rendered by the core
//! renderer and presented through `gpu::Swapchain` (the same code as `foveate view`) on the
//! window Android gives: `VK_KHR_android_surface` there, any window `ash-window` knows on a
//! host (the tests use X11).

use std::marker::PhantomData;

use foveate::foveation::FoveationConfig;
use foveate::gpu::{Gpu, Presented, Swapchain};
use foveate::plan::OutputStage;
use foveate::render::Renderer;
use foveate::scene::{default_scene, Scene, Shading};
use foveate::{FramePlan, RenderConfig};
use glam::Vec2;
use raw_window_handle::{HasWindowHandle, RawDisplayHandle};

use crate::app::{Backend, DemoError, Drawn};

/// The frame the demo shows: foveation 0.35 with its default blend band, MSAA 4, the HMD mask,
/// through the lens output stage (what a phone in a headset shows), 1024² per eye.
pub fn demo_config() -> RenderConfig {
    RenderConfig {
        foveation: Some(FoveationConfig {
            blend_band_px: -1.0,
            ..FoveationConfig::default()
        }),
        views: 4,
        hmd_mask: true,
        output: OutputStage::Lens,
        ..RenderConfig::default()
    }
}

/// The default scene, lit.
pub fn demo_scene() -> Scene {
    default_scene().with_shading(Shading::Lit)
}

/// Renders on `gpu` and presents to windows of type `W` of `display`.
pub struct VulkanBackend<'g, W> {
    gpu: &'g Gpu,
    display: RawDisplayHandle,
    scene: Scene,
    plan: FramePlan,
    renderer: Option<Renderer>,
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
            renderer: None,
            swapchain: None,
            window: PhantomData,
        })
    }

    /// Whether the renderers exist (they are dropped on low memory).
    pub fn has_renderer(&self) -> bool {
        self.renderer.is_some()
    }

    /// The swapchain's size, while there is one.
    pub fn extent(&self) -> Option<(u32, u32)> {
        self.swapchain
            .as_ref()
            .map(|s| (s.extent.width, s.extent.height))
    }

    fn renderer(&mut self) -> Result<&mut Renderer, DemoError> {
        if self.renderer.is_none() {
            self.renderer = Some(Renderer::new(self.gpu, &self.plan, &self.scene)?);
        }
        Ok(self.renderer.as_mut().expect("made above"))
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
        self.renderer = None;
    }

    fn draw(&mut self, gaze: Vec2) -> Result<Drawn, DemoError> {
        let gpu = self.gpu;
        let head = self.scene.head;
        let renderer = self.renderer()?;
        renderer.set_gaze([gaze; 2])?;
        let stats = renderer.render_frame(head)?;
        let sources = renderer.present_sources()?;
        let swapchain = self.swapchain.as_mut().ok_or("draw without a window")?;
        Ok(match swapchain.present(gpu, &sources, false)? {
            Presented::Shown(_) => Drawn::Shown {
                gpu_pass_ms: stats.gpu_pass_ms,
            },
            Presented::Skipped => Drawn::Skipped,
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
