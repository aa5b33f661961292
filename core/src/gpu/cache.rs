//! Vulkan objects shared by their description: a render pass or pipeline asked for again while
//! one with the same description is alive is that one. Entries hold weak references, so an
//! object still dies with its last user (a renderer dropped gives everything back) and the cache
//! never keeps anything alive on its own.

use std::collections::HashMap;
use std::hash::Hash;
use std::sync::{Arc, Mutex, Weak};

/// What identifies an object: every value its create info depends on, as words.
pub type Description = Vec<u64>;

/// What identifies a pipeline: the step's pipeline as the plan states it, the samples of its
/// pass, and the descriptions of its render pass and layout (compatible ones are shared).
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct PipelineKey {
    pub desc: crate::plan::PipelineDesc,
    pub samples: u32,
    pub render_pass: Description,
    pub layout: Description,
}

pub struct ObjectCache<T, K = Description> {
    entries: Mutex<HashMap<K, Weak<T>>>,
}

impl<T, K> Default for ObjectCache<T, K> {
    fn default() -> Self {
        Self {
            entries: Mutex::new(HashMap::new()),
        }
    }
}

impl<T, K: Hash + Eq> ObjectCache<T, K> {
    /// The live object with this description, or a new one from `create`.
    pub fn get_or_create<E>(
        &self,
        description: K,
        create: impl FnOnce() -> Result<T, E>,
    ) -> Result<Arc<T>, E> {
        if let Some(live) = self.lookup(&description) {
            return Ok(live);
        }
        let object = Arc::new(create()?);
        if let Ok(mut entries) = self.entries.lock() {
            entries.retain(|_, weak| weak.strong_count() > 0);
            entries.insert(description, Arc::downgrade(&object));
        }
        Ok(object)
    }

    fn lookup(&self, description: &K) -> Option<Arc<T>> {
        self.entries
            .lock()
            .ok()
            .and_then(|entries| entries.get(description).and_then(Weak::upgrade))
    }
}
