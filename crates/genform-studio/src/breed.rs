//! Breeding by eye (interactive evolution): an optimizer driven by
//! ask/tell (`genform_evolve::ask_tell`) with the user's favourites as the
//! fitness: a favourite scores 1, the others 0, optionally mixed with the
//! scene's fitness (rescaled to 0..1 over the individuals shown) as
//! `(1 − mix)·favourite + mix·scene`. Tree grammars and tree scenes breed
//! with the GA, codon scenes (Genr8 surfaces, GE L-systems, codon-driven
//! box-split and graph grammars) with GE; both keep no elites (elitism 0),
//! so every generation shown is new children of the favourites, and the GA
//! never restarts.
//!
//! Same path, seed, size, mix and picks → the same individuals.

use axum::extract::{Path as UrlPath, State};
use axum::response::{IntoResponse, Response};
use genform_app::codon_objective::CodonObjective;
use genform_app::grammar;
use genform_app::output::write_atomic;
use genform_app::scene_file::SceneFile;
use genform_core::{Generator, Scene};
use genform_evolve::ask_tell::AskTell;
use genform_evolve::{AnyCodonOptimizer, AnyOptimizer, CodonAlgorithm, Codons, Horizon, Settings};
use genform_export::{ExportOptions, Format, RenderOptions};
use serde::Deserialize;
use serde_json::json;
use std::collections::HashMap;
use std::path::Path;
use std::sync::{Arc, Mutex};

use super::api::{ApiError, JsonBody, blocking, bytes_response, claim_id};
use super::breed_session::{Breed, Pool, lock};
use super::state::{App, Shared};

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
    if !(9..=16).contains(&body.size) {
        return Err(ApiError::bad_request(format!("size must be 9..=16, not {}", body.size)));
    }
    if !(0.0..=1.0).contains(&body.mix) {
        return Err(ApiError::bad_request(format!("mix must be in 0..=1, not {}", body.mix)));
    }
    let file = app.roots.resolve(&body.path)?;
    let answer = blocking(move || {
        let breed = open(&app, &file, body)?;
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

/// A session on the grammar or scene at `file`.
fn open(app: &App, file: &Path, body: StartBody) -> Result<Breed, ApiError> {
    let shown = |n: &str| app.shown(n);
    let err = |e: anyhow::Error| ApiError::from_anyhow(&e, shown);
    let is_scene = genform_app::formalism::ends_with_any(file, &[".toml"]);
    let scene = if is_scene { Some(SceneFile::load(file, &[]).map_err(err)?) } else { None };
    let pool = if let Some(SceneFile::Codon(scene)) = scene {
        let objective = Arc::new(CodonObjective::new(&scene).map_err(err)?);
        let mut ge = scene.config.ge.clone();
        ge.population = body.size;
        ge.elitism = 0;
        let opt = AnyCodonOptimizer::new(CodonAlgorithm::Ge, &ge, body.seed)
            .map_err(|e| ApiError::bad_request(format!("[ge]: {e}")))?;
        let reads = Arc::clone(&objective);
        let ask = AskTell::new(opt).map_err(ApiError::internal)?.with_expressed(move |c: &Codons| {
            use genform_evolve::Objective;
            reads.expressed(c, &mut reads.scratch())
        });
        let keys = Arc::clone(&objective);
        let ask = ask.with_phenotype_key(move |c: &Codons| {
            use genform_evolve::Objective;
            keys.phenotype_key(c, &mut keys.scratch())
        });
        Pool::Codon { objective, ask: Box::new(ask), batch: Vec::new() }
    } else {
        let (loaded, limits, mut settings, scorers) = if let Some(SceneFile::Tree(scene)) = scene {
            let config = scene.config;
            let loaded = grammar::load(&config.grammar).map_err(err)?;
            let limits = config.limits.overrides().apply(loaded.limits);
            // The targets are built (voxelized) only when they are mixed in.
            let scorers =
                if body.mix > 0.0 { Some(Box::new(genform_app::targets::build(&config).map_err(err)?)) } else { None };
            (loaded, limits, config.settings(), scorers)
        } else {
            if body.mix > 0.0 {
                return Err(ApiError::bad_request("mix > 0 mixes in a scene's fitness: breed a scene (.toml)"));
            }
            let loaded = grammar::load(file).map_err(err)?;
            let limits = loaded.limits;
            (loaded, limits, Settings::default(), None)
        };
        settings.ga.population = body.size;
        settings.ga.elitism = Some(0);
        settings.ga.restart_after = 0;
        let generator: Arc<dyn Generator> = Arc::from(loaded.generator);
        let opt = AnyOptimizer::new(
            genform_evolve::Algorithm::Ga,
            generator.graph(),
            &limits,
            &settings,
            body.seed,
            Horizon::default(),
        )
        .map_err(|e| ApiError::bad_request(format!("[ga]: {e}")))?;
        let ask = Box::new(AskTell::new(opt).map_err(ApiError::internal)?);
        Pool::Tree { generator, limits, scorers, ask, batch: Vec::new() }
    };
    let id = {
        let mut guard = app.breeds.inner.lock().unwrap_or_else(|p| p.into_inner());
        // Like runs: skip numbers whose saved folder an earlier server left.
        format!("b{}", claim_id(&mut guard.0, |n| app.out.join(format!("breed-b{n}")).exists()))
    };
    let mut breed = Breed {
        id,
        path: app.roots.display(file).unwrap_or_default(),
        seed: body.seed,
        size: body.size,
        mix: body.mix,
        pool,
        round: 0,
        fitness: Vec::new(),
        history: Vec::new(),
        previews: HashMap::new(),
    };
    breed.next_batch()?;
    Ok(breed)
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
        let mut favourites = body.favourites;
        favourites.sort_unstable();
        favourites.dedup();
        if let Some(bad) = favourites.iter().find(|i| **i >= breed.pool.len()) {
            return Err(ApiError::bad_request(format!(
                "favourite {bad} is not shown: the indices are 0..{}",
                breed.pool.len()
            )));
        }
        let scores = breed.scores(&favourites);
        breed.pool.tell(&scores)?;
        let genomes = favourites.iter().map(|i| breed.pool.genome_file(*i)).collect();
        let round = breed.round;
        breed.history.push((round, favourites, genomes));
        breed.round += 1;
        breed.next_batch()?;
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
        let mut files = Vec::new();
        let mut write = |rel: String, text: &str| -> Result<(), ApiError> {
            write_atomic(&dir.join(&rel), text.as_bytes()).map_err(|e| ApiError::internal(format!("{e:#}")))?;
            files.push(rel);
            Ok(())
        };
        for (g, favs, genomes) in &breed.history {
            for (i, genome) in favs.iter().zip(genomes) {
                write(format!("gen-{g}/fav-{i}.json"), genome)?;
            }
        }
        for i in 0..breed.pool.len() {
            write(format!("gen-{}/ind-{i}.json", breed.round), &breed.pool.genome_file(i))?;
        }
        let summary = json!({
            "path": breed.path, "seed": breed.seed, "size": breed.size, "mix": breed.mix, "generation": breed.round,
            "history": breed.history.iter().map(|(g, f, _)| json!({ "generation": g, "favourites": f })).collect::<Vec<_>>(),
        });
        write("favourites.json".into(), &serde_json::to_string_pretty(&summary).unwrap_or_default())?;
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
        if generation.parse::<usize>().ok() != Some(breed.round) || index >= breed.pool.len() {
            return Err(missing());
        }
        let key = (index, ext.clone());
        if let Some(bytes) = breed.previews.get(&key) {
            let kind = if ext == "png" { "image/png" } else { "model/gltf-binary" };
            return Ok(bytes_response(kind, bytes.to_vec()));
        }
        (breed.pool.job(index), key)
    };
    let png = ext == "png";
    let bytes = blocking(move || {
        // An individual that builds no model (an invalid codon string) previews as an empty picture.
        let built = job.scene();
        if png {
            let scene = match &built {
                Ok((scene, true)) => genform_app::codon_report::z_up(scene),
                Ok((scene, false)) => scene.clone(),
                Err(_) => Scene::new(),
            };
            let options = RenderOptions { width: PREVIEW.0, height: PREVIEW.1, ..RenderOptions::default() };
            Ok(genform_export::render_png(&scene, &options))
        } else {
            let (scene, _) = built.map_err(|e| ApiError::not_found(format!("this individual has no model: {e}")))?;
            genform_export::export(&scene, Format::Glb, &ExportOptions::default())
                .map_err(|e| ApiError::internal(format!("cannot export: {e}")))
        }
    })
    .await?;
    let bytes = Arc::new(bytes);
    let mut breed = lock(&b);
    if generation.parse::<usize>().ok() == Some(breed.round) {
        breed.previews.insert(key, bytes.clone());
    }
    drop(breed);
    Ok(bytes_response(if png { "image/png" } else { "model/gltf-binary" }, bytes.to_vec()))
}
