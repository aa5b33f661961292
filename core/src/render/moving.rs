//! Instances that move between frames ([`crate::plan::RenderConfig::moving_instances`]): the
//! scene as it stands now, written into each frame slot's instance buffer every frame, and
//! whether culling must place the instances again before the next frame.

use glam::Mat4;

use crate::scene::{Instance, Scene};
use crate::vocab::ConfigError;

pub(super) struct MovingInstances {
    /// The scene as it stands now: its instances where they were last moved to. (A copy of
    /// the scene the renderer was made with: culling places clusters and levels from its
    /// meshes.)
    scene: Scene,
    /// Each instance's batch and place in it, in the order of the flattened instance buffer.
    places: Vec<(usize, usize)>,
    /// Whether an instance moved since culling last placed them.
    moved: bool,
}

impl MovingInstances {
    pub fn new(scene: &Scene) -> Self {
        let places = scene
            .batches
            .iter()
            .enumerate()
            .filter(|(_, b)| !b.instances.is_empty())
            .flat_map(|(k, b)| (0..b.instances.len()).map(move |i| (k, i)))
            .collect();
        MovingInstances {
            scene: scene.clone(),
            places,
            moved: false,
        }
    }

    /// Puts instance `index` (in the order of the scene's draws: batch by batch) at `model`.
    pub fn move_instance(&mut self, index: usize, model: Mat4) -> Result<(), ConfigError> {
        let Some(&(batch, i)) = self.places.get(index) else {
            return Err(ConfigError::new(
                "instance",
                index,
                format!(
                    "below the scene's {} instances (instances are numbered batch by batch)",
                    self.places.len()
                ),
            ));
        };
        if !model.is_finite() {
            return Err(ConfigError::new(
                "model",
                format!("{:?}", model.to_cols_array()),
                "a finite matrix",
            ));
        }
        self.scene.batches[batch].instances[i].model = model;
        self.moved = true;
        Ok(())
    }

    /// Every instance as it stands, in buffer order.
    pub fn instances(&self) -> Vec<Instance> {
        self.scene.flat_instances()
    }

    /// The scene as it stands, when an instance moved since the last call.
    pub fn moved_scene(&mut self) -> Option<&Scene> {
        std::mem::take(&mut self.moved).then_some(&self.scene)
    }
}
