//! Breeding by eye (interactive evolution) over HTTP: the application
//! library's breeding sessions ([`genform_app::BreedSession`]: an optimizer
//! driven by ask/tell with the user's favourites as the fitness), numbered,
//! their previews rendered and cached, their picks saved under `--out`.
//!
//! Same path, seed, size, mix and picks → the same individuals.

use axum::extract::{Path as UrlPath, State};
use axum::response::{IntoResponse, Response};
use genform_app::{BreedRequest, BreedSession};
use genform_export::{ExportOptions, Format};
use serde::Deserialize;
use serde_json::json;
use std::collections::HashMap;
use std::sync::{Arc, Mutex};

use super::api::{ApiError, JsonBody, blocking, bytes_response, claim_id};
use super::breed_session::{Breed, lock};
use super::state::Shared;

/// Preview pictures' size in pixels.
const PREVIEW: (u32, u32) = (320, 240);
/// Breeding sessions kept; older ones are forgotten.
const KEEP: usize = 32;

fn twelve() -> usize {
    12
}

/// Body of `POST /api/breed`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartBody {
    path: String,
    #[serde(default)]
    seed: u64,
    #[serde(default = "twelve")]
    size: usize,
    #[serde(default)]
    mix: f64,
}

/// `POST /api/breed`: a new session showing its first generation.
pub async fn start(State(app): State<Shared>, JsonBody(body): JsonBody<StartBody>) -> Result<Response, ApiError> {
    let file = app.roots.resolve(&body.path)?;
    let answer = blocking(move || {
        let request = BreedRequest { path: file.clone(), seed: body.seed, size: body.size, mix: body.mix };
        let session = BreedSession::start(request).map_err(|e| ApiError::from_anyhow(&e, |n| app.shown(n)))?;
        let id = {
            let mut guard = app.breeds.inner.lock().unwrap_or_else(|p| p.into_inner());
            // Like runs: skip numbers whose saved folder an earlier server left.
            format!("b{}", claim_id(&mut guard.0, |n| app.out.join(format!("breed-b{n}")).exists()))
        };
        let path = app.roots.display(&file).unwrap_or_default();
        let breed = Breed { id, path, session, previews: HashMap::new() };
        let answer = breed.json();
        let mut guard = app.breeds.inner.lock().unwrap_or_else(|p| p.into_inner());
        let n: u64 = breed.id[1..].parse().unwrap_or_default();
        guard.1.insert(n, Arc::new(Mutex::new(breed)));
        while guard.1.len() > KEEP {
            guard.1.pop_first();
        }
        Ok(answer)
    })
    .await?;
    Ok(axum::Json(answer).into_response())
}

/// `GET /api/breed/<id>`.
pub async fn state(State(app): State<Shared>, UrlPath(id): UrlPath<String>) -> Result<Response, ApiError> {
    let b = app.breeds.get(&id)?;
    let v = lock(&b).json();
    Ok(axum::Json(v).into_response())
}

/// Body of `POST /api/breed/<id>/pick`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PickBody {
    favourites: Vec<usize>,
}

/// `POST /api/breed/<id>/pick`: the next generation, bred from the favourites.
pub async fn pick(
    State(app): State<Shared>,
    UrlPath(id): UrlPath<String>,
    JsonBody(body): JsonBody<PickBody>,
) -> Result<Response, ApiError> {
    let b = app.breeds.get(&id)?;
    let answer = blocking(move || {
        let mut breed = lock(&b);
        breed.session.pick(&body.favourites).map_err(|e| ApiError::bad_request(format!("{e:#}")))?;
        breed.previews.clear();
        Ok(breed.json())
    })
    .await?;
    Ok(axum::Json(answer).into_response())
}

/// `POST /api/breed/<id>/save`: the favourites and the individuals shown
/// as genome files (for `genform derive`) under `--out/breed-<id>/`.
pub async fn save(State(app): State<Shared>, UrlPath(id): UrlPath<String>) -> Result<Response, ApiError> {
    let b = app.breeds.get(&id)?;
    let answer = blocking(move || {
        let breed = lock(&b);
        let dir = app.out.join(format!("breed-{}", breed.id));
        let files = breed.session.save(&dir, &breed.path).map_err(|e| ApiError::internal(format!("{e:#}")))?;
        Ok(json!({ "folder": format!("runs/breed-{}", breed.id), "files": files }))
    })
    .await?;
    Ok(axum::Json(answer).into_response())
}

/// `GET /api/breed/<id>/<generation>/<index>.png|glb`: an individual shown.
pub async fn model(
    State(app): State<Shared>,
    UrlPath((id, generation, file)): UrlPath<(String, String, String)>,
) -> Result<Response, ApiError> {
    let b = app.breeds.get(&id)?;
    let missing = || {
        ApiError::not_found(format!(
            "no individual `{generation}/{file}` in `{id}` (only the generation shown is kept)"
        ))
    };
    let (index, ext) = file.split_once('.').ok_or_else(missing)?;
    let (index, ext) = (index.parse::<usize>().map_err(|_| missing())?, ext.to_string());
    if ext != "png" && ext != "glb" {
        return Err(missing());
    }
    let (job, key) = {
        let breed = lock(&b);
        if generation.parse::<usize>().ok() != Some(breed.session.round()) || index >= breed.session.len() {
            return Err(missing());
        }
        let key = (index, ext.clone());
        if let Some(bytes) = breed.previews.get(&key) {
            let kind = if ext == "png" { "image/png" } else { "model/gltf-binary" };
            return Ok(bytes_response(kind, bytes.to_vec()));
        }
        (breed.session.job(index), key)
    };
    let png = ext == "png";
    let bytes = blocking(move || {
        if png {
            Ok(job.preview_png(PREVIEW.0, PREVIEW.1))
        } else {
            let (scene, _) =
                job.scene().map_err(|e| ApiError::not_found(format!("this individual has no model: {e}")))?;
            genform_export::export(&scene, Format::Glb, &ExportOptions::default())
                .map_err(|e| ApiError::internal(format!("cannot export: {e}")))
        }
    })
    .await?;
    let bytes = Arc::new(bytes);
    let mut breed = lock(&b);
    if generation.parse::<usize>().ok() == Some(breed.session.round()) {
        breed.previews.insert(key, bytes.clone());
    }
    drop(breed);
    Ok(bytes_response(if png { "image/png" } else { "model/gltf-binary" }, bytes.to_vec()))
}
