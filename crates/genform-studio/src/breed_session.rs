//! Breeding sessions of this server: each an application-library session
//! ([`genform_app::BreedSession`]) with its id, the path the client named
//! and the previews already rendered.

use genform_app::BreedSession;
use serde_json::{Value, json};
use std::collections::HashMap;
use std::sync::{Arc, Mutex, MutexGuard};

use super::api::{ApiError, Table};

/// Every breeding session of this server.
#[derive(Default)]
pub struct Breeds {
    pub(crate) inner: Table<Mutex<Breed>>,
}

impl Breeds {
    pub(crate) fn get(&self, id: &str) -> Result<Arc<Mutex<Breed>>, ApiError> {
        let n = id.strip_prefix('b').and_then(|n| n.parse::<u64>().ok());
        let guard = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        n.and_then(|n| guard.1.get(&n).cloned())
            .ok_or_else(|| ApiError::not_found(format!("no breeding session `{id}`")))
    }
}

pub(crate) fn lock(b: &Mutex<Breed>) -> MutexGuard<'_, Breed> {
    b.lock().unwrap_or_else(|p| p.into_inner())
}

/// One breeding session as the server keeps it.
pub(crate) struct Breed {
    pub(crate) id: String,
    /// The grammar or scene as the client names it (its root path).
    pub(crate) path: String,
    pub(crate) session: BreedSession,
    /// Rendered previews of the generation shown, by (index, extension).
    pub(crate) previews: HashMap<(usize, String), Arc<Vec<u8>>>,
}

impl Breed {
    pub(crate) fn json(&self) -> Value {
        let s = &self.session;
        let individuals: Vec<Value> = (0..s.len())
            .map(|i| {
                json!({
                    "index": i,
                    "preview": format!("/api/breed/{}/{}/{i}.png", self.id, s.round()),
                    "model": format!("/api/breed/{}/{}/{i}.glb", self.id, s.round()),
                    "fitness": s.fitness(i),
                })
            })
            .collect();
        let history: Vec<Value> =
            s.history().iter().map(|(g, f, _)| json!({ "generation": g, "favourites": f })).collect();
        let r = s.request();
        json!({
            "id": self.id, "path": self.path, "seed": r.seed, "generation": s.round(), "size": r.size,
            "mix": r.mix, "scene": s.has_scene_fitness(), "genomes": s.genomes(), "individuals": individuals,
            "history": history,
        })
    }
}
