//! The runs a studio has started, as the server knows them: their status,
//! the generations seen, steering, galleries and the event channel that
//! [`crate::runs`] publishes on.

use serde_json::{Value, json};
use std::collections::VecDeque;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, MutexGuard};
use tokio::sync::broadcast;

use super::api::{ApiError, Table};
use genform_app::{SteerEntry, SteerSet, Steerable};

/// Every run of this server.
#[derive(Default)]
pub struct Runs {
    pub(crate) inner: Table<RunHandle>,
}

/// Runs that may go at once: each has its own thread pool, so more would
/// only share the cores and the memory.
pub const MAX_RUNNING: usize = 4;

impl Runs {
    pub(crate) fn get(&self, id: &str) -> Result<Arc<RunHandle>, ApiError> {
        let n = id.strip_prefix('r').and_then(|n| n.parse::<u64>().ok());
        let guard = self.inner.lock().unwrap_or_else(|p| p.into_inner());
        n.and_then(|n| guard.1.get(&n).cloned()).ok_or_else(|| ApiError::not_found(format!("no run `{id}`")))
    }
}

/// One event for the event stream.
#[derive(Clone, Debug)]
pub struct Event {
    pub(crate) name: &'static str,
    pub(crate) data: String,
    /// The run's last event.
    pub(crate) last: bool,
}

/// How far a run is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Status {
    Running,
    Stopped,
    Finished,
    Failed,
}

/// A run as the server knows it.
pub struct RunHandle {
    pub(crate) id: String,
    pub(crate) scene: String,
    pub(crate) algorithm: String,
    pub(crate) seed: u64,
    pub(crate) folder: PathBuf,
    /// Where the scene's targets can be fetched (`explore::targets`).
    pub(crate) targets: Option<Value>,
    pub(crate) cancel: Arc<AtomicBool>,
    pub(crate) state: Mutex<RunState>,
    pub(crate) wake: Condvar,
    pub(crate) events: broadcast::Sender<Event>,
}

/// What changes while a run goes.
pub(crate) struct RunState {
    pub(crate) status: Status,
    pub(crate) paused: bool,
    pub(crate) error: Option<String>,
    pub(crate) generation: Option<usize>,
    pub(crate) evaluations: u64,
    pub(crate) best: Option<f64>,
    pub(crate) max_reachable: Option<f64>,
    pub(crate) stats: Vec<Value>,
    pub(crate) criteria_names: Vec<&'static str>,
    pub(crate) steering: Vec<SteerEntry>,
    pub(crate) steerable: Steerable,
    pub(crate) pending: Option<SteerSet>,
    pub(crate) galleries: VecDeque<(usize, Arc<Vec<u8>>)>,
    /// The best model so far (GLB) and the generation it is from, while
    /// the run goes.
    pub(crate) best_model: Option<(usize, Arc<Vec<u8>>)>,
}

impl RunHandle {
    pub(crate) fn lock(&self) -> MutexGuard<'_, RunState> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Whether the run is still going (paused counts).
    pub(crate) fn is_running(&self) -> bool {
        matches!(self.lock().status, Status::Running)
    }

    pub(crate) fn send(&self, name: &'static str, data: Value, last: bool) {
        // No receiver is no error: nobody is watching.
        let _ = self.events.send(Event { name, data: data.to_string(), last });
    }

    pub(crate) fn status_json(&self, s: &RunState) -> Value {
        let status = match s.status {
            Status::Running if s.paused => "paused",
            Status::Running => "running",
            Status::Stopped => "stopped",
            Status::Finished => "finished",
            Status::Failed => "failed",
        };
        json!({ "status": status, "error": s.error, "stopping": s.status == Status::Running && self.cancel.load(Ordering::SeqCst) })
    }

    pub(crate) fn snapshot(&self) -> Value {
        let s = self.lock();
        let mut v = json!({
            "id": self.id, "scene": self.scene, "algorithm": self.algorithm, "seed": self.seed,
            "folder": format!("runs/{}", self.id), "targets": self.targets,
            "generation": s.generation, "evaluations": s.evaluations, "best": s.best,
            "max_reachable": s.max_reachable, "criteria_names": s.criteria_names, "stats": s.stats,
            "steering": s.steering, "criteria": s.steerable.values(), "pending": s.pending,
            "criteria_formula": s.steerable.contribution_formula(),
            // A run that ended before its first live picture has its folder's final one.
            "gallery": s.galleries.back().map(|(g, _)| format!("/api/runs/{}/gallery/{g}.png", self.id)).or_else(|| {
                (s.status != Status::Running && self.folder.join("gallery.png").is_file())
                    .then(|| format!("/api/runs/{}/files/gallery.png", self.id))
            }),
            // Only while the run goes: then the folder's best.glb is the answer.
            "best_model": s.best_model.as_ref().filter(|_| s.status == Status::Running)
                .map(|(g, _)| format!("/api/runs/{}/best.glb?generation={g}", self.id)),
            "files": self.files(),
        });
        if let (Some(all), Value::Object(status)) = (v.as_object_mut(), self.status_json(&s)) {
            all.extend(status);
        }
        v
    }

    /// The files in the run folder now (top level, no temporary files).
    pub(crate) fn files(&self) -> Vec<String> {
        let Ok(entries) = std::fs::read_dir(&self.folder) else { return Vec::new() };
        let mut names: Vec<String> = entries
            .flatten()
            .filter(|e| e.file_type().is_ok_and(|t| t.is_file()))
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|n| !n.starts_with('.'))
            .collect();
        names.sort();
        names
    }
}
