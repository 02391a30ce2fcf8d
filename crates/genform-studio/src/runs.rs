//! Evolution runs: each on a thread of its own through the shared run loop
//! (`genform_app::evolve`, as `genform evolve` runs, writing the same
//! run folder under `--out/<id>/`), watched by a
//! [`Watcher`] that records every generation, publishes it on a broadcast
//! channel (Server-Sent Events), holds the run while it is paused and
//! hands over queued steering between generations.
//!
//! A client that disconnects only drops its receiver: sending never
//! blocks and never fails the run. Late joiners read the snapshot.

use axum::extract::{Path as UrlPath, State};
use axum::http::StatusCode;
use axum::response::sse::{Event as SseEvent, KeepAlive, Sse};
use axum::response::{IntoResponse, Response};
use futures_util::Stream;
use serde::Deserialize;
use serde_json::{Value, json};
use std::collections::VecDeque;
use std::convert::Infallible;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex};
use std::time::Duration;
use tokio::sync::broadcast;

use super::api::{ApiError, JsonBody, blocking, bytes_response, claim_id};
use super::assets::content_type;
use super::explore;
use super::files::resolve_in;
use super::run_handle::{Event, MAX_RUNNING, RunHandle, RunState, Status};
use super::state::Shared;
use genform_app::{Admitted, Control, EvolveRequest, Start, SteerEntry, SteerSet, Steerable, Tick, Watch};

/// A gallery picture is made every this many generations (and at the end,
/// as the run folder's `gallery.png`).
pub const GALLERY_EVERY: usize = 5;
/// Live gallery pictures kept per run.
const KEEP_GALLERIES: usize = 6;
/// Events a slow client may fall behind by before it skips some.
const CHANNEL: usize = 1024;

/// The run loop's [`Watch`]: records, publishes, pauses, steers.
struct Watcher(Arc<RunHandle>);

impl Watch for Watcher {
    fn started(&mut self, start: &Start) {
        let mut s = self.0.lock();
        s.max_reachable = Some(start.max_reachable);
        s.steerable = start.steerable.clone();
    }

    fn generation(&mut self, tick: &Tick) -> Option<SteerSet> {
        let h = &self.0;
        let st = tick.stats;
        let criteria: serde_json::Map<String, Value> =
            tick.criteria.iter().map(|(n, v)| (n.to_string(), json!(v))).collect();
        let row = json!({
            "generation": st.generation, "evaluations": st.evaluations, "total_evaluations": st.total_evaluations,
            "best": st.max, "mean": st.avg, "min": st.min, "best_so_far": tick.best, "invalid": st.invalid,
            "seconds": tick.seconds, "criteria": criteria,
        });
        let mut s = h.lock();
        for (n, _) in &tick.criteria {
            if !s.criteria_names.contains(n) {
                s.criteria_names.push(n);
            }
        }
        s.generation = Some(st.generation);
        s.evaluations = st.total_evaluations;
        s.best = tick.best;
        s.stats.push(row.clone());
        h.send("generation", row, false);
        while s.paused && !h.cancel.load(Ordering::SeqCst) {
            s = h.wake.wait_timeout(s, Duration::from_millis(250)).unwrap_or_else(|p| p.into_inner()).0;
        }
        s.pending.take()
    }

    fn wants_gallery(&mut self, generation: usize) -> bool {
        generation.is_multiple_of(GALLERY_EVERY)
    }

    fn gallery(&mut self, generation: usize, png: Vec<u8>) {
        let h = &self.0;
        let mut s = h.lock();
        s.galleries.push_back((generation, Arc::new(png)));
        while s.galleries.len() > KEEP_GALLERIES {
            s.galleries.pop_front();
        }
        h.send(
            "gallery",
            json!({ "generation": generation, "url": format!("/api/runs/{}/gallery/{generation}.png", h.id) }),
            false,
        );
    }

    fn best_model(&mut self, generation: usize, glb: Vec<u8>) {
        self.0.lock().best_model = Some((generation, Arc::new(glb)));
    }

    fn steered(&mut self, entry: &SteerEntry, now: &Steerable, max_reachable: f64) {
        let h = &self.0;
        let mut s = h.lock();
        s.steering.push(entry.clone());
        s.steerable = now.clone();
        s.max_reachable = Some(max_reachable);
        h.send(
            "steering",
            json!({
                "generation": entry.generation, "set": entry.set, "criteria": now.values(),
                "max_reachable": max_reachable,
            }),
            false,
        );
    }
}

/// Body of `POST /api/runs`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartBody {
    scene: String,
    #[serde(default)]
    algorithm: Option<String>,
    #[serde(default)]
    seed: u64,
    #[serde(default)]
    generations: Option<usize>,
    #[serde(default)]
    budget: Option<String>,
    #[serde(default)]
    evaluations: Option<u64>,
    #[serde(default)]
    threads: Option<usize>,
    /// A settings patch, `KEY=VALUE` each, as `genform evolve --set`.
    #[serde(default)]
    set: Vec<String>,
}

/// `POST /api/runs`: starts a run; 201 with its id.
pub async fn start(State(app): State<Shared>, JsonBody(body): JsonBody<StartBody>) -> Result<Response, ApiError> {
    let file = app.roots.resolve(&body.scene)?;
    if !genform_app::ends_with_any(&file, &[".toml"]) {
        return Err(ApiError::bad_request(format!("`{}` is not a scene (.toml)", body.scene)));
    }
    if let Some(name) = &body.algorithm {
        genform_app::check_algorithm(name).map_err(|e| ApiError::bad_request(format!("{e}")))?;
    }
    if let Some(b) = &body.budget {
        genform_app::parse_duration(b).map_err(|e| ApiError::bad_request(format!("budget: {e:#}")))?;
    }
    if body.threads.is_some_and(|t| t == 0 || t > 256) {
        return Err(ApiError::bad_request("threads must be 1..=256"));
    }
    let request = EvolveRequest {
        scene: file.clone(),
        seed: body.seed,
        generations: body.generations,
        budget: body.budget,
        evaluations: body.evaluations,
        threads: body.threads,
        out: None,
        algorithm: body.algorithm.clone(),
        set: body.set,
        ..EvolveRequest::default()
    };
    let shown_app = app.clone();
    let scene = body.scene.clone();
    let (mut admitted, steerable, targets) = blocking(move || {
        // The run as it will go, admitted to the memory budget: a bad
        // patch, an algorithm that cannot evolve the scene or a run that
        // does not fit beside the others is refused here, never started.
        let admitted = genform_app::admit(&request).map_err(|e| ApiError::from_anyhow(&e, |n| shown_app.shown(n)))?;
        let steerable = Steerable::of_scene(admitted.scene());
        Ok((admitted, steerable, explore::targets(&file, &scene)))
    })
    .await?;
    let algorithm = admitted.algorithm();
    let (tx, _) = broadcast::channel(CHANNEL);
    let handle = {
        let mut guard = app.runs.inner.lock().unwrap_or_else(|p| p.into_inner());
        let running = guard.1.values().filter(|h| h.is_running()).count();
        if running >= MAX_RUNNING {
            return Err(ApiError::new(
                StatusCode::TOO_MANY_REQUESTS,
                format!("{running} runs are going already (at most {MAX_RUNNING}); stop one or wait for it to end"),
            ));
        }
        let n = claim_id(&mut guard.0, |n| app.out.join(format!("r{n}")).exists());
        let id = format!("r{n}");
        let handle = Arc::new(RunHandle {
            folder: app.out.join(&id),
            id,
            scene: body.scene.clone(),
            algorithm: algorithm.to_string(),
            seed: body.seed,
            targets,
            cancel: Arc::new(AtomicBool::new(false)),
            state: Mutex::new(RunState {
                status: Status::Running,
                paused: false,
                error: None,
                generation: None,
                evaluations: 0,
                best: None,
                max_reachable: None,
                stats: Vec::new(),
                criteria_names: Vec::new(),
                steering: Vec::new(),
                steerable,
                pending: None,
                galleries: VecDeque::new(),
                best_model: None,
            }),
            wake: Condvar::new(),
            events: tx,
        });
        guard.1.insert(n, handle.clone());
        handle
    };
    admitted.set_out(Some(handle.folder.clone()));
    let h = handle.clone();
    std::thread::Builder::new()
        .name(format!("genform-run-{}", handle.id))
        .spawn({
            let app = app.clone();
            move || run_thread(h, admitted, &app)
        })
        .map_err(|e| ApiError::internal(format!("cannot start a thread: {e}")))?;
    let answer = json!({ "id": handle.id, "folder": format!("runs/{}", handle.id) });
    Ok((StatusCode::CREATED, axum::Json(answer)).into_response())
}

/// The run's thread: the shared run loop, then the final status. The
/// run's memory reservation is given back when the loop returns.
fn run_thread(h: Arc<RunHandle>, run: Admitted, app: &crate::state::App) {
    let mut watcher = Watcher(h.clone());
    let control = Control { cancel: h.cancel.clone(), schedule: Vec::new(), watch: Some(&mut watcher) };
    let result = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| run.run(control)));
    let (status, error) = match result {
        Ok(Ok(_)) if h.cancel.load(Ordering::SeqCst) => (Status::Stopped, None),
        Ok(Ok(_)) => (Status::Finished, None),
        // Snapshots are answers too: no server path in them.
        Ok(Err(e)) => (Status::Failed, Some(crate::guard::scrub(app, &format!("{e:#}")))),
        Err(_) => (Status::Failed, Some("internal error: the run panicked".to_string())),
    };
    let mut s = h.lock();
    s.status = status;
    s.paused = false;
    s.error = error;
    let v = h.status_json(&s);
    drop(s);
    h.send("status", v, true);
}

/// `GET /api/runs`.
pub async fn list(State(app): State<Shared>) -> Response {
    let runs: Vec<Arc<RunHandle>> =
        app.runs.inner.lock().unwrap_or_else(|p| p.into_inner()).1.values().cloned().collect();
    let list: Vec<Value> = runs
        .iter()
        .map(|h| {
            let s = h.lock();
            let mut v = json!({ "id": h.id, "scene": h.scene, "generation": s.generation });
            v["status"] = h.status_json(&s)["status"].clone();
            v
        })
        .collect();
    axum::Json(list).into_response()
}

/// `GET /api/runs/<id>`.
pub async fn snapshot(State(app): State<Shared>, UrlPath(id): UrlPath<String>) -> Result<Response, ApiError> {
    let h = app.runs.get(&id)?;
    Ok(axum::Json(h.snapshot()).into_response())
}

/// `GET /api/runs/<id>/events`: the run's events as Server-Sent Events,
/// beginning with its current status; the stream ends after the final status.
pub async fn events(
    State(app): State<Shared>,
    UrlPath(id): UrlPath<String>,
) -> Result<Sse<impl Stream<Item = Result<SseEvent, Infallible>>>, ApiError> {
    let h = app.runs.get(&id)?;
    // Subscribe before reading the status, so nothing falls between.
    let rx = h.events.subscribe();
    let (first, done) = {
        let s = h.lock();
        (Event { name: "status", data: h.status_json(&s).to_string(), last: false }, s.status != Status::Running)
    };
    let stream = futures_util::stream::unfold((rx, Some(first), done), |(mut rx, first, done)| async move {
        if let Some(ev) = first {
            return Some((Ok(sse(&ev)), (rx, None, done)));
        }
        if done {
            return None;
        }
        loop {
            match rx.recv().await {
                Ok(ev) => return Some((Ok(sse(&ev)), (rx, None, ev.last))),
                Err(broadcast::error::RecvError::Lagged(_)) => continue,
                Err(broadcast::error::RecvError::Closed) => return None,
            }
        }
    });
    Ok(Sse::new(stream).keep_alive(KeepAlive::new().interval(Duration::from_secs(15))))
}

fn sse(ev: &Event) -> SseEvent {
    SseEvent::default().event(ev.name).data(&ev.data)
}

/// `POST /api/runs/<id>/pause`.
pub async fn pause(State(app): State<Shared>, UrlPath(id): UrlPath<String>) -> Result<Response, ApiError> {
    control(&app, &id, |s, _| s.paused = true)
}

/// `POST /api/runs/<id>/resume`.
pub async fn resume(State(app): State<Shared>, UrlPath(id): UrlPath<String>) -> Result<Response, ApiError> {
    control(&app, &id, |s, _| s.paused = false)
}

/// `POST /api/runs/<id>/stop`: ends the run after the current generation;
/// it writes its folder as a CLI run interrupted there.
pub async fn stop(State(app): State<Shared>, UrlPath(id): UrlPath<String>) -> Result<Response, ApiError> {
    control(&app, &id, |_, h| h.cancel.store(true, Ordering::SeqCst))
}

/// Changes a running run's state with `f`, wakes it, tells the watchers.
fn control(app: &Shared, id: &str, f: impl FnOnce(&mut RunState, &RunHandle)) -> Result<Response, ApiError> {
    let h = app.runs.get(id)?;
    let mut s = h.lock();
    if s.status != Status::Running {
        return Err(ApiError::conflict(format!("run `{id}` has ended ({})", h.status_json(&s)["status"])));
    }
    f(&mut s, &h);
    h.wake.notify_all();
    let v = h.status_json(&s);
    drop(s);
    h.send("status", v.clone(), false);
    Ok(axum::Json(v).into_response())
}

/// `POST /api/runs/<id>/steer`: queues a change for the next generation.
pub async fn steer(
    State(app): State<Shared>,
    UrlPath(id): UrlPath<String>,
    JsonBody(set): JsonBody<SteerSet>,
) -> Result<Response, ApiError> {
    let h = app.runs.get(&id)?;
    let mut s = h.lock();
    if s.status != Status::Running || h.cancel.load(Ordering::SeqCst) {
        return Err(ApiError::conflict(format!("run `{id}` has ended or is stopping; steering needs a running run")));
    }
    if set.is_empty() {
        return Err(ApiError::bad_request("nothing to change: give `weights` or `targets`"));
    }
    let mut pending = s.pending.clone().unwrap_or_default();
    pending.merge(set.clone());
    s.steerable.check(&pending).map_err(|e| ApiError::bad_request(format!("{e:#}")))?;
    s.pending = Some(pending);
    // The change is taken after the generation under way (or, paused, at once).
    let generation = match s.generation {
        None => 1,
        Some(g) if s.paused => g + 1,
        Some(g) => g + 2,
    };
    Ok(axum::Json(json!({ "queued": set, "generation": generation })).into_response())
}

/// `GET /api/runs/<id>/files/<name>`: a file of the run folder.
pub async fn file(
    State(app): State<Shared>,
    UrlPath((id, name)): UrlPath<(String, String)>,
) -> Result<Response, ApiError> {
    let h = app.runs.get(&id)?;
    let folder =
        h.folder.canonicalize().map_err(|_| ApiError::not_found(format!("run `{id}` has written nothing yet")))?;
    let path = resolve_in(&folder, &name)?;
    let kind = content_type(&name);
    let bytes = blocking(move || {
        if !path.is_file() {
            return Err(ApiError::not_found(format!("`{name}` is not a file")));
        }
        std::fs::read(&path).map_err(|e| ApiError::not_found(e.to_string()))
    })
    .await?;
    Ok(bytes_response(kind, bytes))
}

/// `GET /api/runs/<id>/gallery/<generation>.png`: a live gallery picture.
pub async fn gallery(
    State(app): State<Shared>,
    UrlPath((id, file)): UrlPath<(String, String)>,
) -> Result<Response, ApiError> {
    let h = app.runs.get(&id)?;
    let g = file.strip_suffix(".png").and_then(|g| g.parse::<usize>().ok());
    let s = h.lock();
    let png = s.galleries.iter().find(|(n, _)| Some(*n) == g).map(|(_, p)| p.clone()).ok_or_else(|| {
        ApiError::not_found(format!(
            "no gallery `{file}` (the last {KEEP_GALLERIES} are kept; the run folder has gallery.png)"
        ))
    })?;
    Ok(bytes_response("image/png", png.to_vec()))
}

/// `GET /api/runs/<id>/best.glb`: the best model so far of a running run
/// (made with each gallery picture when the best changed; the folder's
/// `best.glb` once the run ended).
pub async fn best_model(State(app): State<Shared>, UrlPath(id): UrlPath<String>) -> Result<Response, ApiError> {
    let h = app.runs.get(&id)?;
    let glb = h.lock().best_model.as_ref().map(|(_, glb)| glb.clone()).ok_or_else(|| {
        ApiError::not_found("no live best model yet (one comes with the gallery when the best changes)".to_string())
    })?;
    Ok(bytes_response("model/gltf-binary", glb.to_vec()))
}
