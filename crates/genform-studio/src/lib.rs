//! The studio behind `genform serve`: a local web server for one page
//! (embedded, [`assets`]) and a JSON API over the application library
//! (`genform-app`), the same code the command line's verbs use.
//!
//! - [`explore`]: the grammar list and sampling (the formalism table).
//! - [`runs`]: `evolve` runs on their own threads through the shared run
//!   loop (`genform_app::evolve`), watched over Server-Sent Events,
//!   paused, stopped and steered.
//! - [`breed`]: interactive evolution, the GA driven by ask/tell with the
//!   user's favourites as the fitness.
//! - [`files`]: the roots the server may touch and the path checks.
//!
//! Threads: a tokio runtime serves HTTP; library work (compiling, sampling,
//! rendering) runs on its blocking pool; each run has a thread of its own
//! with its own rayon pool. See ARCHITECTURE.md ("genform serve").

pub mod api;
pub mod assets;
pub mod breed;
pub mod breed_session;
pub mod explore;
pub mod files;
pub mod guard;
pub mod run_handle;
pub mod runs;
pub mod sample_store;
pub mod state;

use anyhow::{Context, Result};
use axum::Router;
use axum::extract::{DefaultBodyLimit, Path as UrlPath};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use std::path::PathBuf;
use std::sync::Arc;

pub use api::BODY_LIMIT;
use api::{ApiError, bytes_response};
use files::Roots;
use state::{App, Shared};

/// What the studio serves and where.
#[derive(Clone, Debug, Default)]
pub struct ServeOptions {
    /// A scene config (.toml) or grammar to open first; its folder is
    /// served too (as `scene/…`).
    pub file: Option<PathBuf>,
    /// Port to listen on; 0 picks a free one.
    pub port: u16,
    /// Address to listen on (`None`: 127.0.0.1, this machine only).
    pub host: Option<String>,
    /// Folder for run folders, breeding saves and sampled models.
    pub out: PathBuf,
    /// Folder of example grammars and scenes (`None`: ./examples if it exists).
    pub examples: Option<PathBuf>,
}

/// Serves the studio until the process is stopped; `listening` gets the
/// page's address once the port is bound, and the warnings a user should
/// see at start (no grammars found, and where they come from).
pub fn serve(a: ServeOptions, listening: impl FnOnce(&str, &[String]) + Send) -> Result<()> {
    let app = Arc::new(app(&a)?);
    let mut warnings = Vec::new();
    if explore::list(&app).is_empty() {
        warnings.push(format!(
            "warning: no grammars or scenes found: the studio lists those under --examples (default ./examples, \
             which {} has not), the folder of a file given on the command line, and the editor's saves; start it \
             with `genform serve --examples PATH/TO/examples`, or write one in Explore → Grammar source → Edit",
            std::env::current_dir().map(|d| d.display().to_string()).unwrap_or_else(|_| "this folder".into())
        ));
    }
    // Whatever a request names — a `set` value, a grammar's mesh, an
    // environment — is read only below the roots, and written only below
    // `--out`, through links never.
    let read: Vec<PathBuf> = app.roots.list().iter().map(|r| r.dir.clone()).collect();
    genform_app::confine(&read, &app.out, "examples/, scene/ and runs/")?;
    let host = a.host.clone().unwrap_or_else(|| "127.0.0.1".to_string());
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .context("cannot start the server's threads")?;
    runtime.block_on(async move {
        let listener = tokio::net::TcpListener::bind((host.as_str(), a.port))
            .await
            .with_context(|| format!("cannot listen on {host}:{}", a.port))?;
        let addr = listener.local_addr()?;
        let shown = if addr.is_ipv6() { format!("[{}]", addr.ip()) } else { addr.ip().to_string() };
        listening(&format!("http://{shown}:{}/", addr.port()), &warnings);
        axum::serve(listener, router(app)).await.context("the server stopped")
    })
}

/// The shared state of `a`: the roots, created `--out`, the given file.
fn app(a: &ServeOptions) -> Result<App> {
    let mut roots = Roots::default();
    let default = match &a.file {
        Some(f) => {
            let f = f.canonicalize().with_context(|| format!("cannot open {}", f.display()))?;
            let dir = f.parent().map(PathBuf::from).unwrap_or_default();
            roots.add("scene", &dir).with_context(|| format!("cannot open folder {}", dir.display()))?;
            Some(f)
        }
        None => None,
    };
    let examples = match &a.examples {
        Some(e) if !e.is_dir() => anyhow::bail!("--examples {}: not a folder", e.display()),
        Some(e) => Some(e.clone()),
        None => Some(PathBuf::from("examples")).filter(|e| e.is_dir()),
    };
    if let Some(e) = examples {
        roots.add("examples", &e).with_context(|| format!("cannot open folder {}", e.display()))?;
    }
    roots.add("runs", &a.out).with_context(|| format!("cannot create output folder {}", a.out.display()))?;
    let out = roots.get("runs").map(|r| r.dir.clone()).context("the output folder")?;
    // Samples are a cache numbered from 1 by each server: an earlier
    // server's `.samples/sN` must never answer for this one's `sN`.
    let samples = out.join(".samples");
    if samples.exists() {
        std::fs::remove_dir_all(&samples).with_context(|| format!("cannot clear {}", samples.display()))?;
    }
    Ok(App {
        roots,
        out,
        default,
        samples: sample_store::Samples::default(),
        runs: run_handle::Runs::default(),
        breeds: breed_session::Breeds::default(),
        allowed: state::Allowed { host: a.host.as_ref().map(|h| h.to_ascii_lowercase()) },
    })
}

/// Every route.
pub fn router(app: Shared) -> Router {
    Router::new()
        .route("/", get(index))
        .route("/studio/{*path}", get(asset))
        .route("/api/grammars", get(explore::grammars))
        .route("/api/grammars/source", get(explore::source))
        .route("/api/grammars/save", post(explore::save))
        .route("/api/sample", post(explore::sample))
        .route("/api/models/{file}", get(explore::model))
        .route("/api/target.glb", get(explore::target_glb))
        .route("/api/target.png", get(explore::target_png))
        .route("/api/status", get(state::status))
        .route("/api/runs", post(runs::start).get(runs::list))
        .route("/api/runs/{id}", get(runs::snapshot))
        .route("/api/runs/{id}/events", get(runs::events))
        .route("/api/runs/{id}/pause", post(runs::pause))
        .route("/api/runs/{id}/resume", post(runs::resume))
        .route("/api/runs/{id}/stop", post(runs::stop))
        .route("/api/runs/{id}/steer", post(runs::steer))
        .route("/api/runs/{id}/files/{*name}", get(runs::file))
        .route("/api/runs/{id}/gallery/{file}", get(runs::gallery))
        .route("/api/runs/{id}/best.glb", get(runs::best_model))
        .route("/api/breed", post(breed::start))
        .route("/api/breed/{id}", get(breed::state))
        .route("/api/breed/{id}/pick", post(breed::pick))
        .route("/api/breed/{id}/save", post(breed::save))
        .route("/api/breed/{id}/{generation}/{file}", get(breed::model))
        .fallback(not_found)
        .layer(DefaultBodyLimit::max(BODY_LIMIT))
        .layer(axum::middleware::from_fn_with_state(app.clone(), guard::guard))
        .with_state(app)
}

async fn index() -> Response {
    match assets::get("index.html") {
        Some(bytes) => bytes_response(assets::content_type("index.html"), bytes.to_vec()),
        None => bytes_response("text/html; charset=utf-8", assets::PLACEHOLDER.as_bytes().to_vec()),
    }
}

async fn asset(UrlPath(path): UrlPath<String>) -> Response {
    match assets::get(&path) {
        Some(bytes) => bytes_response(assets::content_type(&path), bytes.to_vec()),
        None => ApiError::not_found(format!("no studio file `{path}`")).into_response(),
    }
}

async fn not_found(uri: axum::http::Uri) -> ApiError {
    ApiError::new(StatusCode::NOT_FOUND, format!("no such endpoint: {}", uri.path()))
}
