//! Interned names (labels, attribute names): text ↔ small integer ids.

use std::collections::HashMap;
use std::sync::Arc;

/// A name table. Id 0 is always the empty name ("no label").
#[derive(Clone, Debug)]
pub(crate) struct Interner {
    names: Vec<Arc<str>>,
    ids: HashMap<Arc<str>, u32>,
}

impl Default for Interner {
    fn default() -> Self {
        let empty: Arc<str> = Arc::from("");
        Interner { names: vec![empty.clone()], ids: HashMap::from([(empty, 0)]) }
    }
}

impl Interner {
    /// The id of `name`, adding it when new.
    pub(crate) fn intern(&mut self, name: &str) -> u32 {
        if let Some(&id) = self.ids.get(name) {
            return id;
        }
        let id = self.names.len() as u32;
        let name: Arc<str> = Arc::from(name);
        self.names.push(name.clone());
        self.ids.insert(name, id);
        id
    }

    /// The id of `name`, if known.
    pub(crate) fn get(&self, name: &str) -> Option<u32> {
        self.ids.get(name).copied()
    }

    /// The name of `id` (`""` for unknown ids).
    pub(crate) fn name(&self, id: u32) -> &str {
        self.names.get(id as usize).map_or("", |s| s)
    }

    /// Every name, in id order (the empty name first).
    pub(crate) fn all(&self) -> impl Iterator<Item = &str> {
        self.names.iter().map(|s| &**s)
    }
}
