//! What every handler shares: the roots, the output folder and the tables
//! of samples, runs and breeding sessions; and the server's status
//! (`GET /api/status`: the memory budget and what runs hold of it).

use axum::extract::State;
use axum::response::{IntoResponse, Response};
use std::path::PathBuf;
use std::sync::Arc;

use super::breed_session::Breeds;
use super::files::Roots;
use super::run_handle::Runs;
use super::sample_store::Samples;

/// What every handler shares.
pub struct App {
    /// The folders the server may touch.
    pub roots: Roots,
    /// `--out`, canonical.
    pub out: PathBuf,
    /// The file given on the command line, canonical.
    pub default: Option<PathBuf>,
    /// Sampled models.
    pub samples: Samples,
    /// Evolution runs.
    pub runs: Runs,
    /// Breeding sessions.
    pub breeds: Breeds,
    /// The `Host` names requests may carry (see [`crate::guard`]).
    pub allowed: Allowed,
}

impl App {
    /// A file name as a client may see it: its root path, else its name alone.
    pub fn shown(&self, name: &str) -> String {
        let path = std::path::Path::new(name);
        path.canonicalize()
            .ok()
            .and_then(|p| self.roots.display(&p))
            .unwrap_or_else(|| path.file_name().map_or_else(String::new, |n| n.to_string_lossy().into_owned()))
    }
}

/// The state handlers get.
pub type Shared = Arc<App>;

/// The `Host` names this server answers to besides IP literals and
/// `localhost`: the `--host` value, if it is a name.
#[derive(Clone, Debug, Default)]
pub struct Allowed {
    /// `--host`, lower-case, when given.
    pub host: Option<String>,
}

/// `GET /api/status`: the process's memory budget (bytes, and where it
/// came from) and the bytes runs and breeding sessions hold of it now,
/// with the runs going.
pub async fn status(State(app): State<Shared>) -> Response {
    let memory = genform_app::usage();
    let running =
        app.runs.inner.lock().unwrap_or_else(|p| p.into_inner()).1.values().filter(|h| h.is_running()).count();
    axum::Json(serde_json::json!({
        "memory": {
            "budget": memory.budget.bytes,
            "in_use": memory.in_use,
            "origin": memory.budget.origin,
            "holders": memory.holders,
        },
        "runs_going": running,
    }))
    .into_response()
}
