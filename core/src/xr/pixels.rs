//! Proof of what the runtime received: the submitted swapchain image, read back, against
//! `foveate render`'s path (a renderer with an image of its own) given the same eyes, head and
//! gaze; and a control that moves the head 5 cm, which must change the image (a check that
//! cannot fail proves nothing).

use std::fmt;

use glam::{Mat4, Vec3};

use crate::gpu::{Gpu, GpuError};
use crate::plan::RenderConfig;
use crate::render::{Renderer, StereoImage};
use crate::scene::Scene;
use crate::view::HiddenArea;

/// The comparison of one submitted frame.
#[derive(Clone, Debug)]
pub struct PixelCheck {
    /// Pixels compared (both eyes).
    pub pixels: usize,
    /// Pixels where the submitted image differs from the reference.
    pub differing: usize,
    /// Pixels where the reference with the head moved 5 cm differs from the reference.
    pub control_differing: usize,
    /// The submitted image.
    pub submitted: StereoImage,
}

impl PixelCheck {
    /// The submitted image is the reference, and the control shows the comparison can fail.
    pub fn passed(&self) -> bool {
        self.differing == 0 && self.control_differing > 0
    }
}

impl fmt::Display for PixelCheck {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "pixel check: the submitted image {} `foveate render`'s of the same views ({} of {} pixels differ; control, the head 5 cm to the right: {} differ)",
            if self.differing == 0 { "equals" } else { "DIFFERS FROM" },
            self.differing,
            self.pixels,
            self.control_differing
        )
    }
}

fn differing(a: &StereoImage, b: &StereoImage) -> usize {
    a.eyes()
        .iter()
        .zip(b.eyes())
        .map(|(x, y)| {
            x.data
                .chunks_exact(4)
                .zip(y.data.chunks_exact(4))
                .filter(|(p, q)| p != q)
                .count()
        })
        .sum()
}

/// Reads back `renderer`'s last frame (in the runtime's image) and renders the same frame —
/// `config` without the external output, the renderer's eyes, gaze and `hidden_area`,
/// `world_from_head` — into an image of its own, then the control.
pub fn check_pixels(
    gpu: &Gpu,
    scene: &Scene,
    config: &RenderConfig,
    renderer: &mut Renderer,
    hidden_area: Option<&[HiddenArea; 2]>,
    world_from_head: Mat4,
) -> Result<PixelCheck, GpuError> {
    let submitted = renderer.readback()?;
    let own = RenderConfig {
        external_output: false,
        ..config.clone()
    };
    let plan = crate::plan(scene, &own, gpu.caps())?;
    let render = |head: Mat4| -> Result<StereoImage, GpuError> {
        let mut own = Renderer::new(gpu, &plan, scene)?;
        own.set_eyes(renderer.plan().eyes)?;
        own.set_gaze(renderer.gaze())?;
        if let Some(areas) = hidden_area {
            own.set_hidden_area(areas.clone())?;
        }
        own.render_frame(head)?;
        own.readback()
    };
    let expected = render(world_from_head)?;
    let moved = render(world_from_head * Mat4::from_translation(Vec3::X * 0.05))?;
    let pixels = submitted
        .eyes()
        .iter()
        .map(|e| (e.width * e.height) as usize)
        .sum();
    Ok(PixelCheck {
        pixels,
        differing: differing(&submitted, &expected),
        control_differing: differing(&moved, &expected),
        submitted,
    })
}
