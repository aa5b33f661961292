//! Instances that move, come and go between frames ([`RenderConfig::moving_instances`](crate::plan::RenderConfig::moving_instances),
//! [`RenderConfig::spare_instances`](crate::plan::RenderConfig::spare_instances)): the scene as it stands now, written into a frame slot's
//! instance buffer when the slot's copy is older than the last change; which instances are in
//! the scene (absent ones are neither culled nor drawn); and whether culling must place the
//! instances again before the next frame.

use glam::Mat4;

use crate::foveation_layer::frame_input::finite_matrix;
use crate::gpu::Buffer;
use crate::scene::{Draw, Instance, Scene};
use crate::vocab::ConfigError;

pub(super) struct MovingInstances {
    /// The scene as it stands now, its spare instances included: its instances where they
    /// were last put. (A copy of the scene the renderer was made with: culling places
    /// clusters and levels from its meshes.)
    scene: Scene,
    /// Each instance's batch and place in it, in the order of the flattened instance buffer.
    places: Vec<(usize, usize)>,
    /// The instances as they stand, in buffer order: what every slot's buffer must hold.
    flat: Vec<Instance>,
    /// Whether each instance is in the scene (false: removed, or a spare not added yet).
    present: Vec<bool>,
    /// The scene's own instances (numbered below this; the spares above).
    own: usize,
    /// Changes made so far (a move, an addition, a removal).
    changes: u64,
    /// The changes culling and the draws last followed.
    followed: u64,
    /// Whether an instance was taken out since the last frame asked (`take_removed`).
    removed: bool,
    /// Each frame slot's buffer: the changes it holds the instances after (`None`: unwritten).
    written: Vec<Option<u64>>,
}

/// The scene after a change: what culling and the draws follow.
pub(super) struct Changed<'a> {
    pub scene: &'a Scene,
    pub present: &'a [bool],
    /// The draws of the present instances: each batch's runs of them.
    pub draws: Vec<Draw>,
}

impl MovingInstances {
    /// `scene` with its spare instances ([`Scene::with_spare_instances`]), of which the first
    /// `own` are the scene's own, present from the start.
    pub fn new(scene: &Scene, own: usize, slots: usize) -> Self {
        let places: Vec<_> = scene
            .batches
            .iter()
            .enumerate()
            .filter(|(_, b)| !b.instances.is_empty())
            .flat_map(|(k, b)| (0..b.instances.len()).map(move |i| (k, i)))
            .collect();
        let present = (0..places.len()).map(|i| i < own).collect();
        MovingInstances {
            scene: scene.clone(),
            flat: scene.flat_instances(),
            places,
            present,
            own,
            // With spares, the first frame already draws fewer instances than the buffer holds.
            changes: u64::from(own < scene.instance_count()),
            followed: 0,
            removed: false,
            written: vec![None; slots],
        }
    }

    fn instance(&self, index: usize) -> Result<(usize, usize), ConfigError> {
        let &place = self.places.get(index).ok_or_else(|| {
            ConfigError::new(
                "instance",
                index,
                format!(
                    "below the {} instances planned (instances are numbered batch by batch, the \
                     spare ones after the scene's)",
                    self.places.len()
                ),
            )
        })?;
        if !self.present[index] {
            return Err(ConfigError::new(
                "instance",
                index,
                "an instance in the scene (it was removed, or is a spare not added)",
            ));
        }
        Ok(place)
    }

    /// Puts `instance` in place `index`, marked as one that moves (its pixels' history is
    /// clipped: `Instance::moves`).
    fn put(&mut self, index: usize, mut instance: Instance) {
        instance.moves = 1;
        let (batch, i) = self.places[index];
        self.scene.batches[batch].instances[i] = instance;
        self.flat[index] = instance;
        self.changes += 1;
    }

    /// Puts instance `index` at `model`.
    pub fn move_instance(&mut self, index: usize, model: Mat4) -> Result<(), ConfigError> {
        self.instance(index)?;
        finite(model)?;
        let mut instance = self.flat[index];
        instance.model = model;
        self.put(index, instance);
        Ok(())
    }

    /// Adds `instance` of mesh `mesh` in an absent place of that mesh's; returns its number.
    pub fn add_instance(&mut self, mesh: usize, instance: Instance) -> Result<usize, ConfigError> {
        let meshes = self.scene.meshes.len();
        if mesh >= meshes {
            let limit = format!("below the scene's {meshes} meshes");
            return Err(ConfigError::new("mesh", mesh, limit));
        }
        finite(instance.model)?;
        let materials = self.scene.materials.len();
        if materials > 0 && instance.material as usize >= materials {
            let limit = format!("below the scene's {materials} materials");
            return Err(ConfigError::new("material", instance.material, limit));
        }
        let of_mesh = |&i: &usize| self.scene.batches[self.places[i].0].mesh == mesh;
        // A spare first, then a place an instance was removed from.
        let free = (self.own..self.places.len())
            .chain(0..self.own)
            .filter(of_mesh)
            .find(|&i| !self.present[i]);
        let Some(index) = free else {
            let places = (0..self.places.len()).filter(of_mesh).count();
            return Err(ConfigError::new(
                "spare_instances",
                self.places.len() - self.own,
                format!(
                    "room for another instance of mesh {mesh}: its {places} places are all in \
                     use (remove one, or plan more spare instances)"
                ),
            ));
        };
        self.present[index] = true;
        self.put(index, instance);
        Ok(index)
    }

    /// Takes instance `index` out of the scene.
    pub fn remove_instance(&mut self, index: usize) -> Result<(), ConfigError> {
        self.instance(index)?;
        self.present[index] = false;
        self.changes += 1;
        self.removed = true;
        Ok(())
    }

    /// Whether an instance was taken out since the last call: the frame after it cannot mark
    /// where it lay (it draws nothing there), so the accumulation clips everywhere once.
    pub fn take_removed(&mut self) -> bool {
        std::mem::take(&mut self.removed)
    }

    /// Brings frame slot `slot`'s `buffer` up to the instances as they stand, when it is older.
    pub fn write_slot(&mut self, slot: usize, buffer: &mut Buffer) {
        if self.written[slot] != Some(self.changes) {
            buffer.write(&self.flat);
            self.written[slot] = Some(self.changes);
        }
    }

    /// The scene as it stands, when it changed since the last call.
    pub fn changed(&mut self) -> Option<Changed<'_>> {
        if std::mem::replace(&mut self.followed, self.changes) == self.changes {
            return None;
        }
        let mut draws = Vec::new();
        for draw in self.scene.draws() {
            let mut run: Option<Draw> = None;
            for i in draw.first_instance..draw.first_instance + draw.instance_count {
                match (&mut run, self.present[i as usize]) {
                    (Some(r), true) => r.instance_count += 1,
                    (None, true) => {
                        run = Some(Draw {
                            first_instance: i,
                            instance_count: 1,
                            ..draw
                        })
                    }
                    (r, false) => draws.extend(r.take()),
                }
            }
            draws.extend(run);
        }
        Some(Changed {
            scene: &self.scene,
            present: &self.present,
            draws,
        })
    }
}

fn finite(model: Mat4) -> Result<(), ConfigError> {
    finite_matrix("model", model, "a finite matrix")
}
