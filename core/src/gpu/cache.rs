//! Vulkan objects shared by their description: a render pass or pipeline asked for again while
//! one with the same description is alive is that one. Entries hold weak references, so an
//! object still dies with its last user (a renderer dropped gives everything back) and the cache
//! never keeps anything alive on its own.

use std::collections::HashMap;
use std::hash::{Hash, Hasher};
use std::sync::{Arc, Mutex, Weak};

/// What identifies an object: every value its create info depends on, as words.
pub type Description = Vec<u64>;

/// A stable word for a name (FNV-1a), for descriptions that include shader names.
pub fn name_word(name: &str) -> u64 {
    name.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

pub struct ObjectCache<T> {
    entries: Mutex<HashMap<Description, Weak<T>>>,
}

impl<T> Default for ObjectCache<T> {
    fn default() -> Self {
        Self {
            entries: Mutex::new(HashMap::new()),
        }
    }
}

impl<T> ObjectCache<T> {
    /// The live object with this description, or a new one from `create`.
    pub fn get_or_create<E>(
        &self,
        description: Description,
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

    fn lookup(&self, description: &Description) -> Option<Arc<T>> {
        self.entries
            .lock()
            .ok()
            .and_then(|entries| entries.get(description).and_then(Weak::upgrade))
    }
}

/// A word for any hashable value (for descriptions built from enums and flags).
pub fn hash_word(value: &impl Hash) -> u64 {
    let mut hasher = std::collections::hash_map::DefaultHasher::new();
    value.hash(&mut hasher);
    hasher.finish()
}
