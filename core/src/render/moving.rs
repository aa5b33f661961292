//! Instances that move between frames ([`crate::plan::RenderConfig::moving_instances`]): the
//! scene as it stands now, written into a frame slot's instance buffer when the slot's copy is
//! older than the last move, and whether culling must place the instances again before the
//! next frame.

use glam::Mat4;

use crate::gpu::Buffer;
use crate::scene::{Instance, Scene};
use crate::vocab::ConfigError;

pub(super) struct MovingInstances {
    /// The scene as it stands now: its instances where they were last moved to. (A copy of
    /// the scene the renderer was made with: culling places clusters and levels from its
    /// meshes.)
    scene: Scene,
    /// Each instance's batch and place in it, in the order of the flattened instance buffer.
    places: Vec<(usize, usize)>,
    /// The instances as they stand, in buffer order: what every slot's buffer must hold.
    flat: Vec<Instance>,
    /// Moves made so far.
    moves: u64,
    /// The moves culling last placed the instances after.
    culled: u64,
    /// Each frame slot's buffer: the moves it holds the instances after (`None`: unwritten).
    written: Vec<Option<u64>>,
}

impl MovingInstances {
    pub fn new(scene: &Scene, slots: usize) -> Self {
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
            flat: scene.flat_instances(),
            moves: 0,
            culled: 0,
            written: vec![None; slots],
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
        self.flat[index].model = model;
        self.moves += 1;
        Ok(())
    }

    /// Brings frame slot `slot`'s `buffer` up to the instances as they stand, when it is older.
    pub fn write_slot(&mut self, slot: usize, buffer: &mut Buffer) {
        if self.written[slot] != Some(self.moves) {
            buffer.write(&self.flat);
            self.written[slot] = Some(self.moves);
        }
    }

    /// The scene as it stands, when an instance moved since the last call.
    pub fn moved_scene(&mut self) -> Option<&Scene> {
        let moved = std::mem::replace(&mut self.culled, self.moves) != self.moves;
        moved.then_some(&self.scene)
    }
}
