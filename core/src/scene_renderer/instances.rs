//! The renderer's side of instances that move, come and go between frames (the state is
//! `moving.rs`'s): the public calls, and culling and the draws following a change before a
//! frame records.

use glam::Mat4;

use super::culling::FrameCulling;
use super::moving::MovingInstances;
use super::renderer::Renderer;
use crate::scene::Instance;
use crate::vocab::ConfigError;

/// What instances that move or come and go need from the renderer.
fn moving_of(renderer: &mut Renderer) -> Result<&mut MovingInstances, ConfigError> {
    renderer.moving.as_mut().ok_or_else(|| {
        ConfigError::new(
            "moving_instances",
            false,
            "a plan whose instances move (RenderConfig::moving_instances on)",
        )
    })
}

impl Renderer {
    /// Puts instance `index` (numbered as the scene's draws take them: batch by batch, then
    /// the spare ones) at `model` from the next frame on: it is drawn there, culled there,
    /// and its levels of detail chosen there. The plan must have
    /// [`RenderConfig::moving_instances`](crate::plan::RenderConfig::moving_instances); a bad index, an absent instance or a matrix that is
    /// not finite is an error and moves nothing.
    pub fn move_instance(&mut self, index: usize, model: Mat4) -> Result<(), ConfigError> {
        moving_of(self)?.move_instance(index, model)
    }

    /// Adds `instance` (model, colour, material) of the scene's mesh `mesh` from the next frame
    /// on, in room the plan made ([`RenderConfig::spare_instances`](crate::plan::RenderConfig::spare_instances)) or that a removal freed;
    /// returns the number it has (for [`Renderer::move_instance`] and
    /// [`Renderer::remove_instance`]). No room left, a bad mesh or material or a matrix that
    /// is not finite is an error and adds nothing.
    pub fn add_instance(&mut self, mesh: usize, instance: Instance) -> Result<usize, ConfigError> {
        moving_of(self)?.add_instance(mesh, instance)
    }

    /// Takes instance `index` out of the scene from the next frame on: neither culled nor
    /// drawn; its place is free for [`Renderer::add_instance`].
    pub fn remove_instance(&mut self, index: usize) -> Result<(), ConfigError> {
        moving_of(self)?.remove_instance(index)
    }

    /// Before a frame records into `slot`: culling and the draws follow a change, and the
    /// slot's instance buffer is brought up to date. Returns the time it took, in ms.
    pub(super) fn follow_instances(&mut self, slot: usize) -> f64 {
        let Some(moving) = &mut self.moving else {
            return 0.0;
        };
        let start = std::time::Instant::now();
        if let Some(changed) = moving.changed() {
            if self.culling.is_some() {
                let culling = FrameCulling::new(changed.scene, &self.scene, &self.layer.plan);
                self.culling = Some(culling.with_present(changed.present));
            }
            self.present_draws = Some(changed.draws);
        }
        if let Some(buffer) = &mut self.layer.slots[slot].instances {
            moving.write_slot(slot, buffer);
        }
        start.elapsed().as_secs_f64() * 1e3
    }
}
