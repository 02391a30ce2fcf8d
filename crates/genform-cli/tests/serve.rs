//! End-to-end tests of `genform serve`: the real binary on a free port,
//! driven over HTTP (ureq, and raw sockets where a client would clean up
//! the path).

mod common;

use common::server::Server;
use common::{fitness_columns, json, ok, root, s, small_scene, small_ship};
use serde_json::{Value, json};
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::time::Duration;

/// A small spaceship scene (tiny population and grid) in `dir`.
fn ship(dir: &Path) -> PathBuf {
    small_ship(dir, &[])
}

/// Reads Server-Sent Events from `url` on a thread until the stream ends
/// or `max` events came; each as (event name, data JSON).
fn listen(url: String, max: usize) -> std::thread::JoinHandle<Vec<(String, Value)>> {
    std::thread::spawn(move || {
        let agent: ureq::Agent =
            ureq::Agent::config_builder().timeout_global(Some(Duration::from_secs(120))).build().into();
        let r = agent.get(&url).call().unwrap();
        assert!(r.headers().get("content-type").unwrap().to_str().unwrap().starts_with("text/event-stream"));
        let mut lines = BufReader::new(r.into_body().into_reader()).lines();
        let mut events = Vec::new();
        let mut name = String::new();
        while let Some(Ok(line)) = lines.next() {
            if let Some(n) = line.strip_prefix("event: ") {
                name = n.to_string();
            } else if let Some(d) = line.strip_prefix("data: ") {
                events.push((name.clone(), serde_json::from_str(d).unwrap()));
                if events.len() >= max {
                    break;
                }
            }
        }
        events
    })
}

#[test]
fn the_page_and_the_grammars_are_served() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let server = Server::start(tmp.path(), &[s(&scene)]);
    let page = server.get("/").ok();
    assert!(page.content_type.starts_with("text/html"), "{}", page.content_type);
    let list = server.get("/api/grammars").ok().json();
    let find = |p: &str| list.as_array().unwrap().iter().find(|g| g["path"] == p).cloned();
    let ship = find("examples/shape/spaceship.sg").expect("spaceship.sg listed");
    assert_eq!((ship["kind"].as_str(), ship["formalism"].as_str()), (Some("grammar"), Some("shape grammar")));
    let ls = find("examples/lsystem/koch_snowflake.ls").expect("an L-system listed");
    assert!(ls["options"].as_array().unwrap().contains(&json!("steps")), "{ls}");
    let given = find("scene/spaceship_volume.toml").expect("the given scene listed under scene/");
    assert_eq!(given["default"], true);
    assert_eq!(given["criteria"]["weights"]["good"], 2.0);
    let target = server.get(given["targets"]["glb"].as_str().expect("a volume target")).ok();
    assert_eq!(&target.body[..4], b"glTF");
    let sketch = find("examples/scenes/tree_sketch.toml").unwrap();
    let png = server.get(sketch["targets"]["images"][0].as_str().expect("an image target")).ok();
    assert_eq!(&png.body[..4], b"\x89PNG");
    assert!(sketch["targets"]["glb"].is_null());
    let genr8 = find("examples/scenes/genr8_canopy.toml").unwrap();
    assert!(genr8["targets"].is_null(), "surface scenes have no target model");
    assert_eq!(
        (genr8["formalism"].as_str(), genr8["criteria"]["targets"]["size"].as_f64()),
        (Some("codon scene"), Some(10.0))
    );
    let text = server.get("/api/grammars/source?path=examples/shape/spaceship.sg").ok().json();
    assert!(text["text"].as_str().unwrap().len() > 10);
    assert_eq!(server.get("/studio/no-such-file.js").status, 404);
    assert!(!server.stderr().contains("warning: listening"), "no warning on the default host");
}

#[test]
fn sampling_goes_through_the_formalism_table() {
    let tmp = tempfile::tempdir().unwrap();
    let server = Server::start(tmp.path(), &[]);
    // A shape grammar: the GLB is byte for byte what `genform sample` writes.
    let a = server.post("/api/sample", &json!({"path": "examples/shape/spaceship.sg", "seed": 3})).ok().json();
    assert_eq!(a["preview"], "glb");
    assert!(a["formats"].as_array().unwrap().iter().any(|f| f == "stl"), "{a}");
    let glb = server.get(a["model"].as_str().unwrap()).ok();
    assert_eq!(&glb.body[..4], b"glTF");
    assert_eq!(glb.content_type, "model/gltf-binary");
    ok(tmp.path(), &["sample", s(&root().join("examples/shape/spaceship.sg")), "--seed", "3", "--out", "cli.glb"]);
    assert_eq!(glb.body, std::fs::read(tmp.path().join("cli.glb")).unwrap(), "the CLI's bytes");
    let id = a["id"].as_str().unwrap();
    let obj = server.get(&format!("/api/models/{id}.obj?download=1")).ok();
    let obj = String::from_utf8_lossy(&obj.body).into_owned();
    assert!(obj.contains("\nv "), "an OBJ");
    // Its materials are a second download, named as the OBJ names them.
    assert!(a["formats"].as_array().unwrap().iter().any(|f| f == "mtl"), "{a}");
    assert!(obj.contains("\nmtllib spaceship-3.mtl\n"), "{}", &obj[..200.min(obj.len())]);
    let mtl = String::from_utf8_lossy(&server.get(&format!("/api/models/{id}.mtl?download=1")).ok().body).into_owned();
    assert!(mtl.contains("newmtl ") && mtl.contains("Kd "), "{mtl}");
    for used in obj.lines().filter_map(|l| l.strip_prefix("usemtl ")) {
        assert!(mtl.contains(&format!("newmtl {used}\n")), "`usemtl {used}` is in the library");
    }
    assert_eq!(server.get(&format!("/api/models/{id}.mca")).status, 404);
    // An L-system with a parameter; a 3D one previews as GLB.
    let l = server
        .post("/api/sample", &json!({"path": "examples/lsystem/bush_3d.ls", "options": {"steps": 2}}))
        .ok()
        .json();
    assert_eq!(&server.get(l["model"].as_str().unwrap()).ok().body[..4], b"glTF");
    // A graph grammar is a drawing: SVG.
    let g = server.post("/api/sample", &json!({"path": "examples/graph/tree.gg.yaml", "seed": 1})).ok().json();
    assert_eq!(g["preview"], "svg");
    let svg = server.get(g["model"].as_str().unwrap()).ok();
    assert!(svg.content_type.starts_with("image/svg+xml") && String::from_utf8_lossy(&svg.body).contains("<svg"));
    // Options are checked as on the command line.
    let e = server.post("/api/sample", &json!({"path": "examples/shape/spaceship.sg", "options": {"steps": 2}}));
    assert_eq!(e.status, 400);
    assert!(e.json()["error"].as_str().unwrap().starts_with("--steps applies to L-systems"));
    let e = server.post("/api/sample", &json!({"path": "examples/lsystem/bush_3d.ls", "options": {"steps": -1}}));
    assert_eq!(e.status, 400);
    // Compile errors come with their diagnostics.
    std::fs::create_dir_all(tmp.path().join("g")).unwrap();
    std::fs::write(tmp.path().join("g/broken.sg"), "Start {\n  boxx;\n}\n").unwrap();
    let server = Server::start(tmp.path(), &[s(&tmp.path().join("g/broken.sg"))]);
    let e = server.post("/api/sample", &json!({"path": "scene/broken.sg"}));
    assert_eq!(e.status, 400);
    let d = &e.json()["diagnostics"][0];
    assert_eq!((d["file"].as_str(), d["line"].as_u64()), (Some("scene/broken.sg"), Some(2)), "{d}");
}

#[test]
fn a_run_is_watched_paused_steered_stopped_and_replayed() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let server = Server::start(tmp.path(), &[s(&scene)]);
    let r = server.post("/api/runs", &json!({"scene": "scene/spaceship_volume.toml", "seed": 5, "budget": "10m"}));
    assert_eq!(r.status, 201, "{}", String::from_utf8_lossy(&r.body));
    let id = r.json()["id"].as_str().unwrap().to_string();
    let events = format!("{}/api/runs/{id}/events", server.url);
    let (one, two) = (listen(events.clone(), 100_000), listen(events.clone(), 100_000));
    // A client that leaves after two events neither stops nor blocks the run.
    let gone = listen(events, 2);
    server.wait_run(&id, "reached generation 2", |s| s["generation"].as_u64() >= Some(2));
    assert_eq!(gone.join().unwrap().len(), 2);
    // Pause: the generation stands still.
    assert_eq!(server.post(&format!("/api/runs/{id}/pause"), &json!({})).ok().json()["status"], "paused");
    // The generation under way ends, then the run waits.
    std::thread::sleep(Duration::from_millis(500));
    let held = server.get(&format!("/api/runs/{id}")).json()["generation"].clone();
    std::thread::sleep(Duration::from_millis(400));
    let snap = server.get(&format!("/api/runs/{id}")).json();
    assert_eq!((snap["status"].as_str(), &snap["generation"]), (Some("paused"), &held));
    // Steer while paused: it takes effect at the next generation.
    let bad = server.post(&format!("/api/runs/{id}/steer"), &json!({"weights": {"godo": 3}}));
    assert_eq!(bad.status, 400);
    assert!(bad.json()["error"].as_str().unwrap().contains("did you mean `good`"));
    let q = server.post(&format!("/api/runs/{id}/steer"), &json!({"weights": {"good": 3.5}})).ok().json();
    let at = held.as_u64().unwrap() + 1;
    assert_eq!(q["generation"].as_u64(), Some(at));
    server.post(&format!("/api/runs/{id}/resume"), &json!({})).ok();
    let snap = server.wait_run(&id, "applied the steering", |s| s["generation"].as_u64() >= Some(at + 2));
    assert_eq!(snap["steering"], json!([{"generation": at, "set": {"weights": {"good": 3.5}}}]));
    assert_eq!(snap["criteria"]["weights"]["good"], 3.5);
    assert_eq!(snap["max_reachable"], 3.5, "what is reachable follows the weights");
    let target = server.get(snap["targets"]["glb"].as_str().expect("the scene's target")).ok();
    assert_eq!(&target.body[..4], b"glTF");
    // While the run goes, its best so far is offered as a model.
    let live = server.get(snap["best_model"].as_str().expect("a live best model")).ok();
    assert_eq!(&live.body[..4], b"glTF");
    server.post(&format!("/api/runs/{id}/stop"), &json!({})).ok();
    let snap = server.wait_run(&id, "stopped", |s| s["status"] == "stopped");
    assert!(snap["best_model"].is_null(), "an ended run's answer is its folder's best.glb");
    assert_eq!(server.post(&format!("/api/runs/{id}/resume"), &json!({})).status, 409);
    // Both clients saw the same generations, the steering and the end.
    for events in [one.join().unwrap(), two.join().unwrap()] {
        let seen: Vec<u64> =
            events.iter().filter(|(n, _)| n == "generation").map(|(_, d)| d["generation"].as_u64().unwrap()).collect();
        assert!(seen.windows(2).all(|w| w[1] == w[0] + 1), "every generation once, in order: {seen:?}");
        assert_eq!(seen.last().copied(), snap["generation"].as_u64());
        let steered: Vec<&Value> = events.iter().filter(|(n, _)| n == "steering").map(|(_, d)| d).collect();
        assert_eq!(steered.len(), 1);
        assert_eq!(steered[0]["generation"].as_u64(), Some(at));
        assert!(events.iter().any(|(n, _)| n == "gallery"));
        assert_eq!(events.last().unwrap().1["status"], "stopped");
    }
    // The run folder is a CLI run's, interrupted where it was stopped.
    let folder = tmp.path().join("out").join(&id);
    let run = json(&folder.join("run.json"));
    assert_eq!(run["stopped_by"], "interrupted");
    assert_eq!(run["steering"], json!([{"generation": at, "set": {"weights": {"good": 3.5}}}]));
    let files = snap["files"].as_array().unwrap();
    for f in ["best.glb", "best-genome.json", "stats.csv", "gallery.png", "run.json"] {
        assert!(files.contains(&json!(f)), "{f} missing from {files:?}");
    }
    let glb = server.get(&format!("/api/runs/{id}/files/best.glb")).ok();
    assert_eq!(&glb.body[..4], b"glTF");
    let gallery = server.get(snap["gallery"].as_str().unwrap()).ok();
    assert_eq!(&gallery.body[..4], b"\x89PNG");
    // Replaying the log gives the same run; without it, another.
    let generations = run["generations"].to_string();
    let replay = |out: &str, steering: Option<&Path>| {
        let mut args = vec!["evolve", s(&scene), "--seed", "5", "--generations", &generations, "--out", out, "-q"];
        if let Some(p) = steering {
            args.extend(["--steering", s(p)]);
        }
        ok(tmp.path(), &args);
        let csv = std::fs::read_to_string(tmp.path().join(out).join("stats.csv")).unwrap();
        (std::fs::read(tmp.path().join(out).join("best-genome.json")).unwrap(), fitness_columns(&csv))
    };
    let served = (
        std::fs::read(folder.join("best-genome.json")).unwrap(),
        fitness_columns(&std::fs::read_to_string(folder.join("stats.csv")).unwrap()),
    );
    assert!(served == replay("replay", Some(&folder.join("run.json"))), "replaying run.json gives the same run");
    std::fs::write(tmp.path().join("log.json"), run["steering"].to_string()).unwrap();
    assert!(served == replay("replay2", Some(&tmp.path().join("log.json"))), "a bare list works too");
    assert!(served.1 != replay("plain", None).1, "steering changed the run");
}

/// Time spent paused does not count against a run's budget: a run paused
/// past its budget still goes on after resuming, and its folder reports
/// the running time only.
#[test]
fn grammars_written_in_the_page_are_checked_sampled_and_saved_in_the_studio_folder_only() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let server = Server::start(tmp.path(), &[s(&scene)]);
    let broken = "grammar \"cube\";\naxiom A;\nA { boxx; }\n";
    let draft =
        server.post("/api/grammars/save", &json!({"name": "cube.sg", "text": broken, "draft": true})).ok().json();
    assert_eq!(draft["path"], "runs/drafts/cube.sg");
    let e = server.post("/api/sample", &json!({"path": "runs/drafts/cube.sg"}));
    assert_eq!(e.status, 400);
    let d = &e.json()["diagnostics"][0];
    assert_eq!(
        (d["file"].as_str(), d["line"].as_u64(), d["col"].as_u64()),
        (Some("runs/drafts/cube.sg"), Some(3), Some(5)),
        "{d}"
    );
    let fixed = broken.replace("boxx", "box");
    let saved = server.post("/api/grammars/save", &json!({"name": "cube.sg", "text": fixed})).ok().json();
    assert_eq!(saved["path"], "runs/grammars/cube.sg");
    assert_eq!(std::fs::read_to_string(tmp.path().join("out/grammars/cube.sg")).unwrap(), fixed);
    let sample = server.post("/api/sample", &json!({"path": "runs/grammars/cube.sg"})).ok().json();
    assert!(sample["summary"].as_str().unwrap().contains("12 triangles"), "{sample}");
    let list = server.get("/api/grammars").ok().json();
    assert!(list.as_array().unwrap().iter().any(|e| e["path"] == "runs/grammars/cube.sg"), "{list}");
    for name in ["../cube.sg", "a/b.sg", ".hidden.sg", "notes.txt", ""] {
        let r = server.post("/api/grammars/save", &json!({"name": name, "text": fixed}));
        assert_eq!(r.status, 400, "{name}");
    }
    assert!(!tmp.path().join("cube.sg").exists() && !tmp.path().join("out/a").exists());
}

#[test]
fn a_run_takes_a_settings_patch_as_the_cli_does() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let server = Server::start(tmp.path(), &[s(&scene)]);
    let body =
        json!({"scene": "scene/spaceship_volume.toml", "generations": 1, "set": ["ga.population=10", "ga.elitism=1"]});
    let id = server.post("/api/runs", &body).ok().json()["id"].as_str().unwrap().to_string();
    server.wait_run(&id, "finished", |s| s["status"] == "finished");
    let run = server.get(&format!("/api/runs/{id}/files/run.json")).ok().json();
    assert_eq!(run["config"]["ga"]["population"], 10, "{run}");
    let bad = json!({"scene": "scene/spaceship_volume.toml", "generations": 1, "set": ["ga.populaton=10"]});
    let e = server.post("/api/runs", &bad);
    assert_eq!(e.status, 400);
    assert!(e.json()["error"].as_str().unwrap().contains("did you mean `population`"), "{}", e.json());
}

#[test]
fn a_paused_run_keeps_its_budget() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let server = Server::start(tmp.path(), &[s(&scene)]);
    let r = server.post("/api/runs", &json!({"scene": "scene/spaceship_volume.toml", "seed": 2, "budget": "3s"}));
    assert_eq!(r.status, 201, "{}", String::from_utf8_lossy(&r.body));
    let id = r.json()["id"].as_str().unwrap().to_string();
    server.wait_run(&id, "reached generation 1", |s| s["generation"].as_u64() >= Some(1));
    server.post(&format!("/api/runs/{id}/pause"), &json!({})).ok();
    server.wait_run(&id, "paused", |s| s["status"] == "paused");
    std::thread::sleep(Duration::from_millis(300));
    let held = server.get(&format!("/api/runs/{id}")).json()["generation"].as_u64().unwrap();
    // Paused longer than the whole budget.
    std::thread::sleep(Duration::from_millis(3200));
    server.post(&format!("/api/runs/{id}/resume"), &json!({})).ok();
    let snap = server.wait_run(&id, "finished", |s| s["status"] == "finished");
    let end = snap["generation"].as_u64().unwrap();
    assert!(end > held + 1, "the run went on after resuming: paused at generation {held}, ended at {end}");
    let run = json(&tmp.path().join("out").join(&id).join("run.json"));
    assert_eq!(run["stopped_by"], "budget");
    let seconds = run["seconds"].as_f64().unwrap();
    assert!((2.9..4.5).contains(&seconds), "{seconds} s of running time, the pause left out");
}

#[test]
fn breeding_by_eye_picks_favourites_for_two_generations() {
    let tmp = tempfile::tempdir().unwrap();
    let server = Server::start(tmp.path(), &[]);
    let start = json!({"path": "examples/shape/spaceship.sg", "seed": 2, "size": 9});
    let b = server.post("/api/breed", &start).ok().json();
    let id = b["id"].as_str().unwrap().to_string();
    let shown = b["individuals"].as_array().unwrap();
    assert!((2..=9).contains(&shown.len()) && b["generation"] == 0, "{b}");
    let png = server.get(shown[0]["preview"].as_str().unwrap()).ok();
    assert_eq!((&png.body[..4], png.content_type.as_str()), (&b"\x89PNG"[..], "image/png"));
    assert_eq!(&server.get(shown[1]["model"].as_str().unwrap()).ok().body[..4], b"glTF");
    let pick = format!("/api/breed/{id}/pick");
    assert_eq!(server.post(&pick, &json!({"favourites": [99]})).status, 400);
    let g1 = server.post(&pick, &json!({"favourites": [0, 2]})).ok().json();
    assert_eq!(g1["generation"], 1);
    assert_eq!(server.get(shown[0]["preview"].as_str().unwrap()).status, 404, "old generations are gone");
    let g2 = server.post(&pick, &json!({"favourites": [1]})).ok().json();
    assert_eq!(g2["generation"], 2);
    assert_eq!(server.get(&format!("/api/breed/{id}")).ok().json()["history"].as_array().unwrap().len(), 2);
    let model = |state: &Value| server.get(state["individuals"][0]["model"].as_str().unwrap()).ok().body;
    // The same seed and picks breed the same models.
    let again = server.post("/api/breed", &start).ok().json();
    let id2 = again["id"].as_str().unwrap();
    server.post(&format!("/api/breed/{id2}/pick"), &json!({"favourites": [0, 2]})).ok();
    let again = server.post(&format!("/api/breed/{id2}/pick"), &json!({"favourites": [1]})).ok().json();
    assert_eq!(model(&g2), model(&again));
    let saved = server.post(&format!("/api/breed/{id}/save"), &json!({})).ok().json();
    let dir = tmp.path().join("out").join(format!("breed-{id}"));
    assert!(dir.join("favourites.json").is_file() && dir.join("gen-0/fav-0.json").is_file(), "{saved}");
    let genome = dir.join("gen-1/fav-1.json");
    ok(tmp.path(), &["derive", s(&root().join("examples/shape/spaceship.sg")), "--genome", s(&genome), "-o", "f.obj"]);
    // Sizes, mixes and grammars without a generator are refused.
    assert_eq!(server.post("/api/breed", &json!({"path": "examples/shape/spaceship.sg", "size": 5})).status, 400);
    let mix = server.post("/api/breed", &json!({"path": "examples/shape/spaceship.sg", "mix": 0.5}));
    assert_eq!(mix.status, 400);
    assert_eq!(server.post("/api/breed", &json!({"path": "examples/graph/tree.gg.yaml"})).status, 400);
}

#[test]
fn breeding_mixes_in_a_scene_fitness() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let server = Server::start(tmp.path(), &[s(&scene)]);
    let b = server
        .post("/api/breed", &json!({"path": "scene/spaceship_volume.toml", "seed": 1, "size": 9, "mix": 0.5}))
        .ok()
        .json();
    assert!(b["individuals"][0]["fitness"].is_number(), "{b}");
    let id = b["id"].as_str().unwrap();
    assert_eq!(server.post(&format!("/api/breed/{id}/pick"), &json!({"favourites": []})).ok().json()["generation"], 1);
}

#[test]
fn nothing_outside_the_roots_is_read_or_served() {
    let tmp = tempfile::tempdir().unwrap();
    std::fs::create_dir_all(tmp.path().join("scene")).unwrap();
    let scene = ship(&tmp.path().join("scene"));
    let outside = tmp.path().join("outside");
    std::fs::create_dir_all(&outside).unwrap();
    std::fs::write(outside.join("secret.sg"), "Start {\n  box;\n}\n").unwrap();
    #[cfg(unix)]
    std::os::unix::fs::symlink(outside.join("secret.sg"), tmp.path().join("scene/leak.sg")).unwrap();
    let server = Server::start(tmp.path(), &[s(&scene)]);
    for path in ["scene/../outside/secret.sg", "/etc/passwd", "examples/../Cargo.toml", "scene/./leak.sg", "out/x"] {
        let a = server.post("/api/sample", &json!({"path": path}));
        assert!(a.status == 403 || a.status == 400, "{path}: {}", a.status);
        assert!(a.json()["error"].is_string());
    }
    #[cfg(unix)]
    {
        let a = server.post("/api/sample", &json!({"path": "scene/leak.sg"}));
        assert_eq!(a.status, 403, "a symbolic link out of the root");
        let list = server.get("/api/grammars").ok().json();
        assert!(!list.to_string().contains("leak.sg"), "links out of a root are not listed");
    }
    for target in [
        "/api/grammars/source?path=examples/..%2f..%2fCargo.toml",
        "/api/grammars/source?path=%2e%2e/Cargo.toml",
        "/api/grammars/source?path=%2Fetc%2Fpasswd",
        "/api/grammars/source?path=scene%2F..%2Foutside%2Fsecret.sg",
    ] {
        assert_eq!(server.raw_status(target), 403, "{target}");
    }
    // A run's files: encoded and plain `..`, absolute paths, links out.
    let id =
        server.post("/api/runs", &json!({"scene": "scene/spaceship_volume.toml", "generations": 1})).ok().json()["id"]
            .as_str()
            .unwrap()
            .to_string();
    server.wait_run(&id, "finished", |s| s["status"] == "finished");
    #[cfg(unix)]
    std::os::unix::fs::symlink(outside.join("secret.sg"), tmp.path().join("out").join(&id).join("link.sg")).unwrap();
    assert_eq!(server.raw_status(&format!("/api/runs/{id}/files/run.json")), 200);
    for name in [
        "%2e%2e/%2e%2e/outside/secret.sg",
        "..%2f..%2foutside%2fsecret.sg",
        "../../outside/secret.sg",
        "%2Fetc%2Fpasswd",
    ] {
        assert_eq!(server.raw_status(&format!("/api/runs/{id}/files/{name}")), 403, "{name}");
    }
    #[cfg(unix)]
    assert_eq!(server.raw_status(&format!("/api/runs/{id}/files/link.sg")), 403);
    assert_eq!(server.raw_status("/studio/..%2f..%2fCargo.toml"), 404, "assets are only the embedded files");
    assert_eq!(server.raw_status("/studio/../../Cargo.toml"), 404);
}

/// What a page on another site could make a browser send is refused: a
/// simple cross-site POST (`text/plain`, foreign `Origin`), a rebound
/// `Host`; the server's own page and plain clients are served; error
/// answers show no absolute server path; at most four runs go at once.
#[test]
fn requests_a_foreign_page_could_send_are_refused() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(&tmp.path().join("scene"));
    let server = Server::start(tmp.path(), &[s(&scene)]);
    let addr = server.url.trim_start_matches("http://").to_string();
    let start = r#"{"scene": "scene/spaceship_volume.toml", "generations": 1}"#;
    let json = "Content-Type: application/json";
    let evil_origin = "Origin: http://evil.example";
    let (status, text) = server.raw("POST", "/api/runs", &["Content-Type: text/plain", evil_origin], start);
    assert_eq!(status, 403, "{text}");
    let (status, text) = server.raw("POST", "/api/runs", &["Content-Type: text/plain"], start);
    assert_eq!(status, 415, "{text}");
    let (status, text) = server.raw("POST", "/api/runs", &[json, evil_origin], start);
    assert_eq!(status, 403, "{text}");
    let (status, text) = server.raw("POST", "/api/runs", &[json, "Sec-Fetch-Site: cross-site"], start);
    assert_eq!(status, 403, "{text}");
    for host in ["Host: evil.example", "Host: evil.example:80", "Host: localhost.evil.example"] {
        let (status, text) = server.raw("POST", "/api/runs", &[host, json], start);
        assert_eq!(status, 421, "{host}: {text}");
        let (status, text) = server.raw("GET", "/api/grammars", &[host], "");
        assert_eq!(status, 421, "{host}: {text}");
    }
    assert!(!server.get("/api/runs").ok().json().to_string().contains("\"r1\""), "no refused request started a run");
    // The page's own requests and clients without Origin go through.
    let own = format!("Origin: http://{addr}");
    let (status, text) = server.raw("POST", "/api/runs", &[json, &own, "Sec-Fetch-Site: same-origin"], start);
    assert_eq!(status, 201, "{text}");
    let (status, _) =
        server.raw("GET", "/api/grammars", &[&format!("Host: localhost:{}", addr.rsplit(':').next().unwrap())], "");
    assert_eq!(status, 200);
    assert!(!text.contains("Access-Control-Allow-Origin"), "no CORS: {text}");
    // Error answers name roots, not the server's folders.
    let (status, text) = server.raw("POST", "/api/sample", &[json], r#"{"path": "scene/missing.sg"}"#);
    assert!(status >= 400, "{text}");
    let folder = tmp.path().canonicalize().unwrap();
    assert!(!text.contains(s(&folder)), "absolute path in {text}");
    // At most four runs at once.
    let long = json!({"scene": "scene/spaceship_volume.toml", "generations": 100000000});
    let ids: Vec<String> =
        (0..4).map(|_| server.post("/api/runs", &long).json()["id"].as_str().unwrap_or_default().to_string()).collect();
    let fifth = server.post("/api/runs", &long);
    assert_eq!(fifth.status, 429, "{}", String::from_utf8_lossy(&fifth.body));
    for id in ids.iter().filter(|id| !id.is_empty()) {
        server.post(&format!("/api/runs/{id}/stop"), &json!({})).ok();
        server.wait_run(id, "stopped", |s| s["status"] != "running");
    }
    server.post("/api/runs", &json!({"scene": "scene/spaceship_volume.toml", "generations": 1})).ok();
}

#[test]
fn bad_requests_get_json_errors() {
    let tmp = tempfile::tempdir().unwrap();
    let server = Server::start(tmp.path(), &["--host", "127.0.0.1"]);
    // A body over 1 MiB is refused from its declared length, before it is read.
    let (status, text) = server.raw_post_head("/api/sample", 2 << 20);
    assert_eq!(status, 413, "{text}");
    assert!(text.contains("larger than"), "{text}");
    let a = server.post_raw("/api/sample", &format!("{{\"path\": \"{}\"}}", "x".repeat(1000)));
    assert_eq!(a.status, 400, "a body under the limit is read");
    let a = server.post_raw("/api/sample", "{not json");
    assert_eq!(a.status, 400);
    assert!(a.json()["error"].as_str().unwrap().starts_with("bad JSON"));
    assert_eq!(server.post("/api/sample", &json!({"path": 3})).status, 400);
    assert_eq!(
        server.post("/api/runs", &json!({"scene": "examples/scenes/tree_volume.toml", "algorithm": "ants"})).status,
        400
    );
    assert_eq!(server.post("/api/runs", &json!({"scene": "examples/shape/spaceship.sg"})).status, 400);
    for path in ["/api/runs/r999", "/api/runs/zz/events", "/api/breed/b999", "/api/models/s999.glb", "/api/nothing"] {
        let a = server.get(path);
        assert_eq!(a.status, 404, "{path}");
        assert!(a.json()["error"].is_string(), "{path}");
    }
    assert_eq!(server.post("/api/runs/r999/stop", &json!({})).status, 404);
    assert!(server.stderr().contains("warning: listening on 127.0.0.1"), "--host warns");
}

#[test]
fn genr8_criteria_are_watched_per_criterion_and_their_targets_steered() {
    let tmp = tempfile::tempdir().unwrap();
    let edits = [("population = 100", "population = 14")];
    let scene = small_scene(tmp.path(), "genr8_canopy.toml", &edits);
    let server = Server::start(tmp.path(), &[s(&scene)]);
    let r = server.post("/api/runs", &json!({"scene": "scene/genr8_canopy.toml", "seed": 4, "budget": "10m"}));
    let id = r.ok().json()["id"].as_str().unwrap().to_string();
    server.wait_run(&id, "made generation 1", |s| s["generation"].as_u64() >= Some(1));
    server.post(&format!("/api/runs/{id}/pause"), &json!({})).ok();
    std::thread::sleep(Duration::from_millis(500));
    let change = json!({"weights": {"symmetry": 2.0}, "targets": {"size": 4.0}});
    let at = server.post(&format!("/api/runs/{id}/steer"), &change).ok().json()["generation"].as_u64().unwrap();
    server.post(&format!("/api/runs/{id}/resume"), &json!({})).ok();
    let snap = server.wait_run(&id, "steered", |s| s["generation"].as_u64() > Some(at));
    assert_eq!(snap["criteria"]["targets"]["size"], 4.0);
    let names = snap["criteria_names"].as_array().unwrap();
    assert!(names.contains(&json!("size")) && names.contains(&json!("symmetry")), "{names:?}");
    assert!(snap["stats"][0]["criteria"]["size"].is_number(), "{}", snap["stats"][0]);
    assert_eq!(snap["criteria_formula"], "w/(1+e)", "the bounded form's contribution");
    server.post(&format!("/api/runs/{id}/stop"), &json!({})).ok();
    server.wait_run(&id, "stopped", |s| s["status"] == "stopped");
    let folder = tmp.path().join("out").join(&id);
    let run = json(&folder.join("run.json"));
    assert_eq!(run["steering"], json!([{"generation": at, "set": change}]));
    let generations = run["generations"].to_string();
    let log = folder.join("run.json");
    let args = [
        "evolve",
        s(&scene),
        "--seed",
        "4",
        "--generations",
        &generations,
        "--out",
        "replay",
        "-q",
        "--steering",
        s(&log),
    ];
    ok(tmp.path(), &args);
    let codons = |dir: &Path| json(&dir.join("best-codons.json"))["codons"].clone();
    assert_eq!(codons(&folder), codons(&tmp.path().join("replay")));
    let csv = |dir: &Path| fitness_columns(&std::fs::read_to_string(dir.join("stats.csv")).unwrap());
    assert_eq!(csv(&folder), csv(&tmp.path().join("replay")));
}

#[test]
fn steering_logs_with_mistakes_are_refused_before_the_run() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = ship(tmp.path());
    let log = tmp.path().join("log.json");
    std::fs::write(&log, r#"[{"generation": 3, "set": {"weights": {"goood": 1}}}]"#).unwrap();
    let err = common::fails(tmp.path(), &["evolve", s(&scene), "--steering", s(&log), "--out", "run", "-q"]);
    assert!(err.contains("steering of generation 3") && err.contains("did you mean `good`"), "{err}");
    assert!(!tmp.path().join("run/stats.csv").exists(), "nothing ran");
    std::fs::write(&log, r#"{"steering": [{"generation": 1, "set": {"targets": {"size": 3}}}]}"#).unwrap();
    let err = common::fails(tmp.path(), &["evolve", s(&scene), "--steering", s(&log), "--out", "run", "-q"]);
    assert!(err.contains("no target `size`"), "{err}");
}

#[test]
fn genr8_surfaces_breed_by_eye_with_ge() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = small_scene(tmp.path(), "genr8_canopy.toml", &[]);
    let server = Server::start(tmp.path(), &[s(&scene)]);
    let start = json!({"path": "scene/genr8_canopy.toml", "seed": 3, "size": 9, "mix": 0.25});
    let b = server.post("/api/breed", &start).ok().json();
    assert_eq!((b["genomes"].as_str(), b["scene"].as_bool()), (Some("codon"), Some(true)), "{b}");
    let id = b["id"].as_str().unwrap().to_string();
    let png = server.get(b["individuals"][0]["preview"].as_str().unwrap()).ok();
    assert_eq!(&png.body[..4], b"\x89PNG");
    let g1 = server.post(&format!("/api/breed/{id}/pick"), &json!({"favourites": [0, 1]})).ok().json();
    let g2 = server.post(&format!("/api/breed/{id}/pick"), &json!({"favourites": [2]})).ok().json();
    assert_eq!((g1["generation"].as_u64(), g2["generation"].as_u64()), (Some(1), Some(2)));
    server.post(&format!("/api/breed/{id}/save"), &json!({})).ok();
    let fav = tmp.path().join("out").join(format!("breed-{id}")).join("gen-0/fav-0.json");
    let text = ok(tmp.path(), &["score", s(&scene), "--genome", s(&fav)]).stdout();
    assert!(text.starts_with("fitness "), "a saved codon genome scores: {text}");
}

#[test]
fn a_restarted_server_never_answers_with_an_earlier_servers_files() {
    let tmp = tempfile::tempdir().unwrap();
    let first = Server::start(tmp.path(), &[]);
    let a = first.post("/api/sample", &json!({"path": "examples/shape/spaceship.sg", "seed": 3})).ok().json();
    let old = first.get(a["model"].as_str().unwrap()).ok().body;
    let b = first.post("/api/breed", &json!({"path": "examples/shape/spaceship.sg", "seed": 1, "size": 9})).ok().json();
    first.post(&format!("/api/breed/{}/save", b["id"].as_str().unwrap()), &json!({})).ok();
    drop(first);
    // Same --out: the new server's first sample and breeding session get
    // fresh files, not the earlier server's under the same number.
    let second = Server::start(tmp.path(), &[]);
    let c = second.post("/api/sample", &json!({"path": "examples/shape/spaceship.sg", "seed": 4})).ok().json();
    assert_eq!(c["id"], a["id"], "numbering starts again");
    let new = second.get(c["model"].as_str().unwrap()).ok().body;
    ok(tmp.path(), &["sample", s(&root().join("examples/shape/spaceship.sg")), "--seed", "4", "--out", "cli4.glb"]);
    assert_eq!(new, std::fs::read(tmp.path().join("cli4.glb")).unwrap(), "seed 4's model, not seed 3's");
    assert_ne!(new, old);
    let d =
        second.post("/api/breed", &json!({"path": "examples/shape/spaceship.sg", "seed": 1, "size": 9})).ok().json();
    assert_ne!(d["id"], b["id"], "a saved session's folder is not reused");
}
