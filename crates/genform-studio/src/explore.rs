//! Exploring grammars: the list of grammars and scenes under the roots,
//! their text, and sampling through the formalism table — the same
//! `LoadedGrammar::sample` and `Sample::write` as `genform sample`.

use axum::extract::{Path as UrlPath, Query, State};
use axum::http::{HeaderValue, header};
use axum::response::{IntoResponse, Response};
use genform_app::{SAMPLE_OPTIONS, SampleRequest};
use genform_core::Scene;
use genform_export::Format;
use serde::Deserialize;
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::api::{ApiError, JsonBody, blocking, bytes_response};
use super::assets::content_type;
use super::files::walk;
use super::sample_store::{KEEP_SAMPLES, SampleEntry};
use super::state::{App, Shared};

/// The `sample` options the studio passes on: those of the application's
/// table it offers (the others name files outside its roots).
pub fn studio_options() -> Vec<&'static str> {
    SAMPLE_OPTIONS.iter().filter(|o| o.studio).map(|o| o.name).collect()
}

/// `GET /api/grammars`.
pub async fn grammars(State(app): State<Shared>) -> Result<Response, ApiError> {
    let list = blocking(move || Ok(list(&app))).await?;
    Ok(axum::Json(list).into_response())
}

/// Every grammar and scene under the roots `examples` and `scene`, and
/// the grammars saved from the editor (`runs/grammars/`).
pub(crate) fn list(app: &App) -> Vec<Value> {
    let mut seen: Vec<PathBuf> = Vec::new();
    let mut out = Vec::new();
    let saved = app.out.join(SAVED);
    // The given file's own folder first, so its files carry `scene/` paths.
    for name in ["scene", "examples", "runs"] {
        let Some(root) = app.roots.get(name) else { continue };
        let dir = if name == "runs" { saved.canonicalize().unwrap_or(saved.clone()) } else { root.dir.clone() };
        if !dir.is_dir() {
            continue;
        }
        for file in walk(&dir, 6, 5000) {
            if seen.contains(&file) {
                continue;
            }
            let Some(shown) = app.roots.display(&file) else { continue };
            if let Some(mut item) = describe(&file, &shown) {
                item["default"] = json!(app.default.as_deref() == Some(file.as_path()));
                out.push(item);
                seen.push(file);
            }
        }
    }
    out
}

/// The list entry of `file`, or `None` when it is neither a grammar nor a scene.
fn describe(file: &Path, shown: &str) -> Option<Value> {
    let stem = file.file_name()?.to_string_lossy().split('.').next().unwrap_or_default().to_string();
    if genform_app::ends_with_any(file, &[".toml"]) {
        let summary = genform_app::Scene::summary(file)?;
        let title = summary.description.filter(|d| !d.is_empty()).unwrap_or(stem);
        let mut item = json!({ "path": shown, "kind": "scene", "title": title });
        item["formalism"] = json!(if summary.codons { "codon scene" } else { "scene" });
        item["algorithms"] = json!(summary.algorithms);
        match summary.scene {
            Ok(scene) => {
                item["criteria"] = json!(genform_app::Steerable::of_scene(&scene).values());
                if let Some(targets) = targets_of(&scene, shown) {
                    item["targets"] = targets;
                }
            }
            Err(e) => item["error"] = json!(format!("{e:#}")),
        }
        return Some(item);
    }
    let f = genform_app::formalism_of(file).ok()?;
    let options: Vec<&str> = studio_options().into_iter().filter(|o| f.reads(o)).collect();
    Some(json!({ "path": shown, "kind": "grammar", "formalism": f.name(), "title": stem, "options": options }))
}

/// `{"glb": url | null, "images": [url]}`: where the scene's targets can be
/// fetched (`shown` is its root path); `None` for scenes without targets.
pub fn targets(file: &Path, shown: &str) -> Option<Value> {
    targets_of(&genform_app::Scene::load(file, &[]).ok()?, shown)
}

/// [`targets`] of a loaded scene.
fn targets_of(scene: &genform_app::Scene, shown: &str) -> Option<Value> {
    let pictures = scene.target_pictures();
    if !scene.has_target_model() && pictures.is_empty() {
        return None;
    }
    let q = query_path(shown);
    let volume = scene.has_target_model().then(|| format!("/api/target.glb?path={q}"));
    let images: Vec<String> = (0..pictures.len())
        .filter(|i| !genform_app::ends_with_any(&pictures[*i], &[".pfm"]))
        .map(|i| format!("/api/target.png?path={q}&index={i}"))
        .collect();
    Some(json!({ "glb": volume, "images": images }))
}

/// A root path as a query value (`/` kept; the few characters that would
/// break a query escaped).
fn query_path(path: &str) -> String {
    path.replace('%', "%25").replace('&', "%26").replace('#', "%23").replace('+', "%2B").replace(' ', "%20")
}

/// Query of `GET /api/target.glb` and `/api/target.png`.
#[derive(Deserialize)]
pub struct TargetQuery {
    path: String,
    #[serde(default)]
    index: usize,
}

/// `GET /api/target.glb?path=SCENE`: the scene's volume targets (meshes, or
/// fixed genomes expressed) as one GLB, for showing with the model.
pub async fn target_glb(State(app): State<Shared>, Query(q): Query<TargetQuery>) -> Result<Response, ApiError> {
    let file = app.roots.resolve(&q.path)?;
    let bytes = blocking(move || {
        let scene = genform_app::Scene::load(&file, &[]).map_err(|e| ApiError::from_anyhow(&e, |n| app.shown(n)))?;
        if !scene.has_target_model() {
            return Err(ApiError::not_found(format!("`{}` has no [volume] target", q.path)));
        }
        scene.target_glb().map_err(|e| ApiError::bad_request(format!("{e:#}")))
    })
    .await?;
    Ok(bytes_response("model/gltf-binary", bytes))
}

/// `GET /api/target.png?path=SCENE&index=I`: the scene's I-th image target picture.
pub async fn target_png(State(app): State<Shared>, Query(q): Query<TargetQuery>) -> Result<Response, ApiError> {
    let file = app.roots.resolve(&q.path)?;
    let bytes = blocking(move || {
        let scene = genform_app::Scene::load(&file, &[]).map_err(|e| ApiError::from_anyhow(&e, |n| app.shown(n)))?;
        let picture = scene
            .target_pictures()
            .into_iter()
            .nth(q.index)
            .filter(|p| genform_app::ends_with_any(p, &[".png"]))
            .ok_or_else(|| ApiError::not_found(format!("`{}` has no PNG image target #{}", q.path, q.index)))?;
        std::fs::read(&picture).map_err(|e| ApiError::not_found(format!("{}: {e}", picture.display())))
    })
    .await?;
    Ok(bytes_response("image/png", bytes))
}

/// The folder (under `--out`) of grammars saved from the editor.
const SAVED: &str = "grammars";
/// The folder (under `--out`) of the editor's drafts, sampled as the user types.
const DRAFTS: &str = "drafts";

/// Body of `POST /api/grammars/save`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SaveBody {
    /// A file name with a grammar extension, e.g. `my_tower.sg`.
    name: String,
    /// The grammar text.
    text: String,
    /// A draft (the editor's live copy) rather than a saved grammar.
    #[serde(default)]
    draft: bool,
}

/// `POST /api/grammars/save {name, text, draft?}`: writes the text to
/// `--out/grammars/NAME` (or `--out/drafts/NAME`), the studio's own folder
/// and nowhere else, and answers its root path for `/api/sample`.
pub async fn save(State(app): State<Shared>, JsonBody(body): JsonBody<SaveBody>) -> Result<Response, ApiError> {
    let name = checked_name(&body.name)?;
    let answer = blocking(move || {
        let dir = app.out.join(if body.draft { DRAFTS } else { SAVED });
        let file = dir.join(&name);
        genform_app::write_atomic(&file, body.text.as_bytes()).map_err(|e| ApiError::from_anyhow(&e, |n| n.into()))?;
        let shown = app.roots.display(&file.canonicalize().unwrap_or(file)).unwrap_or_default();
        Ok(json!({ "path": shown }))
    })
    .await?;
    Ok(axum::Json(answer).into_response())
}

/// `name` if it is a plain file name (letters, digits, `_`, `-`, `.`; no
/// folder, not hidden) with the extension of a grammar formalism.
fn checked_name(name: &str) -> Result<String, ApiError> {
    let plain = !name.is_empty()
        && name.len() <= 100
        && !name.starts_with('.')
        && name.chars().all(|c| c.is_ascii_alphanumeric() || "_-.".contains(c));
    if !plain {
        return Err(ApiError::bad_request(format!(
            "`{name}`: a grammar's name is a plain file name (letters, digits, _ - .; at most 100 characters)"
        )));
    }
    genform_app::formalism_of(Path::new(name)).map_err(|e| ApiError::bad_request(e.to_string()))?;
    Ok(name.to_string())
}

/// Query of `GET /api/grammars/source`.
#[derive(Deserialize)]
pub struct SourceQuery {
    path: String,
}

/// `GET /api/grammars/source?path=P`: the text of a grammar or scene.
pub async fn source(State(app): State<Shared>, Query(q): Query<SourceQuery>) -> Result<Response, ApiError> {
    let file = app.roots.resolve(&q.path)?;
    let text = blocking(move || {
        let meta = std::fs::metadata(&file).map_err(|e| ApiError::not_found(e.to_string()))?;
        if !meta.is_file() || meta.len() > super::api::BODY_LIMIT as u64 {
            return Err(ApiError::bad_request(format!("`{}` is not a text file of at most 1 MiB", q.path)));
        }
        let text = std::fs::read_to_string(&file).map_err(|e| ApiError::bad_request(e.to_string()))?;
        Ok(json!({ "path": q.path, "text": text }))
    })
    .await?;
    Ok(axum::Json(text).into_response())
}

/// Body of `POST /api/sample`.
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SampleBody {
    path: String,
    #[serde(default)]
    seed: u64,
    #[serde(default)]
    options: serde_json::Map<String, Value>,
    #[serde(default)]
    format: Option<String>,
}

/// `POST /api/sample`.
pub async fn sample(State(app): State<Shared>, JsonBody(body): JsonBody<SampleBody>) -> Result<Response, ApiError> {
    let file = app.roots.resolve(&body.path)?;
    let answer = blocking(move || {
        let f = genform_app::formalism_of(&file).map_err(|e| ApiError::bad_request(e.to_string()))?;
        let request = request(&app, body.seed, &body.options)?;
        f.check(&request).map_err(|e| ApiError::bad_request(e.to_string()))?;
        let shown = |name: &str| app.shown(name);
        let loaded = f.load(&file).map_err(|e| ApiError::from_anyhow(&e, shown))?;
        let sampled = loaded.sample(&request).map_err(|e| ApiError::from_anyhow(&e, shown))?;
        let formats = formats(sampled.scene(), f.output_extensions());
        let preview = if is_flat(sampled.scene()) { "svg" } else { "glb" };
        let format = body.format.unwrap_or_else(|| preview.to_string());
        if !formats.contains(&format) {
            return Err(ApiError::bad_request(format!("format `{format}`: use one of {}", formats.join(", "))));
        }
        let summary = sampled.summary();
        let stem = file.file_name().map(|n| n.to_string_lossy().split('.').next().unwrap_or("model").to_string());
        let (id, _) = app.samples.insert(|id| SampleEntry {
            sample: sampled,
            formats: formats.clone(),
            export: request.export(),
            dir: app.out.join(".samples").join(format!("s{id}")),
            stem: stem.unwrap_or_default(),
            seed: body.seed,
            writing: Mutex::new(()),
        });
        Ok(json!({
            "id": format!("s{id}"), "summary": summary, "formats": formats, "preview": preview,
            "model": format!("/api/models/s{id}.{format}"),
        }))
    })
    .await?;
    Ok(axum::Json(answer).into_response())
}

/// The `SampleRequest` of a studio request: each option checked by the
/// application's table as every door's are (files resolved within the
/// roots), and noted as given so the formalism table refuses options its
/// formalism does not read with the command line's message.
fn request(app: &App, seed: u64, options: &serde_json::Map<String, Value>) -> Result<SampleRequest, ApiError> {
    let mut r = SampleRequest::new(seed);
    let offered = studio_options();
    for (raw, value) in options {
        let name = raw.trim_start_matches("--").replace('_', "-");
        if !offered.contains(&name.as_str()) {
            return Err(ApiError::bad_request(format!(
                "unknown option `{raw}`; the studio's sample options are {}",
                offered.join(", ")
            )));
        }
        let resolve = |p: &str| app.roots.resolve(p).map_err(|e| anyhow::anyhow!("{}", e.message));
        r.set(&name, value, &resolve).map_err(|e| ApiError::bad_request(format!("{e:#}")))?;
    }
    Ok(r)
}

/// The formats a sample can be written in: the Scene formats (block
/// formats only for block models) and what the formalism writes itself
/// (except region files, which need a world to copy).
fn formats(scene: &Scene, own: &[&str]) -> Vec<String> {
    let mut out: Vec<String> = Format::extensions()
        .iter()
        .filter(|e| !scene.blocks.is_empty() || !matches!(**e, "schem" | "litematic" | "vox"))
        .map(|e| e.to_string())
        .collect();
    // An OBJ's materials come as a second file: offered beside it.
    if let Some(i) = out.iter().position(|e| e == "obj") {
        out.insert(i + 1, "mtl".to_string());
    }
    out.extend(own.iter().map(|e| e.trim_start_matches('.').to_string()).filter(|e| e != "mca" && e != "yml"));
    out
}

/// `obj` with its `mtllib` line naming `library` (the line is among the
/// first few; the rest of the file is left as it is).
fn renamed_mtllib(obj: &[u8], library: &str) -> Vec<u8> {
    let Some(start) = obj.windows(7).take(4096).position(|w| w == b"mtllib ") else { return obj.to_vec() };
    let end = obj[start..].iter().position(|&b| b == b'\n').map_or(obj.len(), |i| start + i);
    [&obj[..start], format!("mtllib {library}").as_bytes(), &obj[end..]].concat()
}

/// Whether a model is a flat drawing (shown as SVG): 2D shapes, or only
/// lines and polygons in the plane z = 0.
fn is_flat(scene: &Scene) -> bool {
    let solid = !scene.instances.is_empty() || !scene.surfaces.is_empty() || !scene.blocks.is_empty();
    if solid {
        return false;
    }
    if !scene.shapes2d.is_empty() {
        return true;
    }
    let mut points = scene.polylines.points().iter().chain(scene.polygons.iter().flat_map(|p| &p.points));
    let mut any = false;
    points.all(|p| {
        any = true;
        p.z == 0.0
    }) && any
}

/// Query of `GET /api/models/…`.
#[derive(Deserialize)]
pub struct ModelQuery {
    #[serde(default)]
    download: Option<String>,
}

/// `GET /api/models/<id>.<ext>`: the sample written as `genform sample --out x.<ext>` writes it.
pub async fn model(
    State(app): State<Shared>,
    UrlPath(file): UrlPath<String>,
    Query(q): Query<ModelQuery>,
) -> Result<Response, ApiError> {
    let (id, ext) = file.split_once('.').ok_or_else(|| ApiError::not_found(format!("no model `{file}`")))?;
    let entry =
        id.strip_prefix('s').and_then(|n| n.parse::<u64>().ok()).and_then(|n| app.samples.get(n)).ok_or_else(|| {
            ApiError::not_found(format!("no sample `{id}` (samples are kept for the last {KEEP_SAMPLES})"))
        })?;
    if !entry.formats.iter().any(|f| f == ext) {
        return Err(ApiError::not_found(format!(
            "sample `{id}` has no format `{ext}`; it has {}",
            entry.formats.join(", ")
        )));
    }
    let ext = ext.to_string();
    let out = ext.clone();
    let bytes = blocking(move || {
        // The `.mtl` is the OBJ writer's second file.
        let written_as = if out == "mtl" { "obj" } else { out.as_str() };
        let path = entry.dir.join(format!("model.{written_as}"));
        let _one = entry.writing.lock().unwrap_or_else(|p| p.into_inner());
        if !path.is_file() {
            genform_app::create_dir(&entry.dir).map_err(|e| ApiError::from_anyhow(&e, |n| n.into()))?;
            let written =
                entry.sample.write(&path, &entry.export).map_err(|e| ApiError::from_anyhow(&e, |n| n.into()))?;
            if !written.contains(&path) {
                return Err(ApiError::internal(format!("the {out} writer did not write one file")));
            }
        }
        let served = entry.dir.join(format!("model.{out}"));
        let mut bytes = std::fs::read(&served).map_err(|e| ApiError::internal(e.to_string()))?;
        let name = format!("{}-{}", entry.stem, entry.seed);
        if out == "obj" {
            // Downloaded, the pair is named after the sample: the OBJ's
            // `mtllib` must name the `.mtl` as it is downloaded.
            bytes = renamed_mtllib(&bytes, &format!("{name}.mtl"));
        }
        Ok((bytes, format!("{name}.{out}")))
    })
    .await?;
    let mut r = bytes_response(content_type(&format!("m.{ext}")), bytes.0);
    if q.download.is_some()
        && let Ok(v) = HeaderValue::from_str(&format!("attachment; filename=\"{}\"", bytes.1))
    {
        r.headers_mut().insert(header::CONTENT_DISPOSITION, v);
    }
    Ok(r)
}
