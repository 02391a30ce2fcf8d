//! The studio under hostile requests, end to end (the CLI's cases are in
//! `hostile.rs`):
//!
//! - one memory budget per process: `genform serve --max-memory SIZE` with
//!   a budget one run of a scene fits in but three do not. Three runs
//!   started at once: what fits is admitted, the others are refused with a
//!   message that says why (memory), the server stays up, its status shows
//!   the budget and the bytes held, and the bytes come back when the run
//!   ends;
//! - nothing outside the roots: `set` values, grammars written in the
//!   editor and what they reference are refused (403) outside `examples/`,
//!   `scene/` and `runs/`, with one message whether or not the file exists,
//!   and no answer names a server path;
//! - no writing through planted links below `--out`.

mod common;

use common::server::Server;
use common::{s, small_ship};
use serde_json::{Value, json};
use std::path::Path;
use std::time::{Duration, Instant};

/// The studio as these tests drive it: answers as (status, JSON).
struct Studio(Server);

impl Studio {
    fn start(dir: &Path, args: &[&str]) -> Studio {
        Studio(Server::start(dir, args))
    }

    fn get(&self, path: &str) -> (u16, Value) {
        let a = self.0.get(path);
        (a.status, a.json())
    }

    fn post(&self, path: &str, body: &Value) -> (u16, Value) {
        let a = self.0.post(path, body);
        (a.status, a.json())
    }

    /// Polls `GET path` until `done` holds for its answer (at most 30 s).
    fn wait(&self, path: &str, what: &str, done: impl Fn(&Value) -> bool) -> Value {
        let start = Instant::now();
        loop {
            let (status, v) = self.get(path);
            if status == 200 && done(&v) {
                return v;
            }
            assert!(start.elapsed() < Duration::from_secs(30), "{path} never {what}: {v:#}");
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

#[test]
fn concurrent_runs_share_one_memory_budget_and_the_server_stays_up() {
    let tmp = tempfile::tempdir().unwrap();
    // The small spaceship scene with a population whose genomes dominate
    // the estimate: 2 × 2000 genomes of up to 30 genes (2 KiB each) ≈ 7.8
    // MiB, with the default MAP-Elites archive (20 × 20 cells of up to 100
    // genes) ≈ 2.5 MiB, the 25×25×50 grid, 8 MH chains and 40 SMC particles
    // ≈ 11.3 MiB in all.
    let scene = small_ship(tmp.path(), &[("population = 24", "population = 2000")]);
    let one_run = u64::try_from(genform_app::Scene::load(&scene, &[]).unwrap().estimated_bytes()).unwrap();
    assert!((10 << 20..13 << 20).contains(&one_run), "estimate of one run: {one_run}");
    // One run fits, two do not (let alone three).
    let budget = one_run * 3 / 2;
    let server = Studio::start(tmp.path(), &["--max-memory", &budget.to_string(), s(&scene)]);
    let (status, idle) = server.get("/api/status");
    assert_eq!(status, 200);
    assert_eq!(idle["memory"]["budget"], budget);
    assert_eq!(idle["memory"]["in_use"], 0);
    assert!(idle["memory"]["origin"].as_str().unwrap().starts_with("--max-memory "), "{idle}");

    // Three runs started at once, each long enough to be going while the others ask.
    let body = json!({"scene": "scene/spaceship_volume.toml", "generations": 100000, "threads": 1});
    let start = std::sync::Barrier::new(3);
    let answers: Vec<(u16, Value)> = std::thread::scope(|scope| {
        let asks: Vec<_> = (0..3)
            .map(|_| {
                scope.spawn(|| {
                    start.wait();
                    server.post("/api/runs", &body)
                })
            })
            .collect();
        asks.into_iter().map(|a| a.join().unwrap()).collect()
    });
    let admitted: Vec<&Value> = answers.iter().filter(|(s, _)| *s == 201).map(|(_, v)| v).collect();
    let refused: Vec<&(u16, Value)> = answers.iter().filter(|(s, _)| *s != 201).collect();
    assert_eq!((admitted.len(), refused.len()), (1, 2), "one run fits: {answers:#?}");
    for (status, v) in &refused {
        assert_eq!(*status, 503, "{v}");
        let e = v["error"].as_str().unwrap();
        assert!(
            e.starts_with("this run needs about 11.")
                && e.contains(" MiB of the memory budget of ")
                && e.contains("(--max-memory ")
                && e.contains("is held by 1 other run; wait for one to finish or lower [ga] population"),
            "{e}"
        );
    }

    // The server is up; its status shows what the admitted run holds.
    let (status, held) = server.get("/api/status");
    assert_eq!(status, 200);
    assert_eq!(
        held["memory"],
        json!({"budget": budget, "in_use": one_run, "origin": idle["memory"]["origin"], "holders": 1})
    );
    assert_eq!(held["runs_going"], 1);
    assert_eq!(server.get("/api/runs").1.as_array().unwrap().len(), 1, "refused runs are never listed");

    // Once the run ends its bytes come back, and the next run is admitted.
    let id = admitted[0]["id"].as_str().unwrap().to_string();
    assert_eq!(server.post(&format!("/api/runs/{id}/stop"), &json!({})).0, 200);
    server.wait(&format!("/api/runs/{id}"), "stopped", |v| v["status"] == "stopped");
    let free = server.wait("/api/status", "gave the memory back", |v| v["memory"]["in_use"] == 0);
    assert_eq!(free["memory"]["holders"], 0);
    let (status, next) = server.post("/api/runs", &body);
    assert_eq!(status, 201, "{next}");
    let next = next["id"].as_str().unwrap().to_string();
    assert_eq!(server.post(&format!("/api/runs/{next}/stop"), &json!({})).0, 200);
    server.wait(&format!("/api/runs/{next}"), "stopped", |v| v["status"] == "stopped");
}

#[test]
fn a_breeding_session_past_the_budget_held_is_refused_too() {
    let tmp = tempfile::tempdir().unwrap();
    let scene = small_ship(tmp.path(), &[("population = 24", "population = 2000")]);
    let one_run = u64::try_from(genform_app::Scene::load(&scene, &[]).unwrap().estimated_bytes()).unwrap();
    // The run leaves less room than a breeding session mixing in the
    // scene's fitness (its 25×25×50 grid) needs.
    let budget = one_run + 100_000;
    let server = Studio::start(tmp.path(), &["--max-memory", &budget.to_string(), s(&scene)]);
    let body = json!({"scene": "scene/spaceship_volume.toml", "generations": 100000, "threads": 1});
    let (status, run) = server.post("/api/runs", &body);
    assert_eq!(status, 201, "{run}");
    let (status, e) = server.post("/api/breed", &json!({"path": "scene/spaceship_volume.toml", "mix": 0.5}));
    assert_eq!(status, 503, "{e}");
    let e = e["error"].as_str().unwrap();
    assert!(e.starts_with("this breeding session needs about") && e.contains("held by 1 other run"), "{e}");
    // Without the scene's fitness it needs only its dozen genomes.
    let (status, b) = server.post("/api/breed", &json!({"path": "scene/spaceship_volume.toml"}));
    assert_eq!(status, 200, "{b}");
    let id = run["id"].as_str().unwrap().to_string();
    assert_eq!(server.post(&format!("/api/runs/{id}/stop"), &json!({})).0, 200);
    server.wait(&format!("/api/runs/{id}"), "stopped", |v| v["status"] == "stopped");
    // The breeding session still holds its few bytes.
    let status = server.wait("/api/status", "gave the run's memory back", |v| v["memory"]["holders"] == 1);
    assert!(status["memory"]["in_use"].as_u64().unwrap() < 100_000, "{status}");
}

/// A tree `dir/outside` the studio must never read, with a grammar, a mesh
/// and a secret line in each.
fn outside(dir: &Path) -> std::path::PathBuf {
    let out = dir.join("outside");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("secret.sg"), "SECRET-LINE\nStart { box; }\n").unwrap();
    std::fs::write(out.join("secret.obj"), "# SECRET-LINE\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    out.canonicalize().unwrap()
}

#[test]
fn nothing_outside_the_roots_is_read_whatever_names_it() {
    let tmp = tempfile::tempdir().unwrap();
    let secret = outside(tmp.path());
    let scene = small_ship(&tmp.path().join("scene"), &[]);
    let server = Studio::start(tmp.path(), &[s(&scene)]);
    let no_server_path = |v: &Value| {
        let text = v.to_string();
        assert!(!text.contains("SECRET-LINE"), "an outside file's content leaked: {text}");
        assert!(!text.contains(s(&tmp.path().canonicalize().unwrap())), "a server path leaked: {text}");
    };
    // A `set` value naming a grammar outside: refused before the run.
    let grammar = format!("grammar=\"{}\"", secret.join("secret.sg").display());
    let body = json!({"scene": "scene/spaceship_volume.toml", "generations": 1, "set": [grammar]});
    let (status, e) = server.post("/api/runs", &body);
    assert_eq!(status, 403, "{e}");
    assert!(e["error"].as_str().unwrap().contains("is outside the folders this studio may read"), "{e}");
    assert!(server.get("/api/runs").1.as_array().unwrap().is_empty(), "no run was started");
    // The same through `..` from the scene's folder.
    let up =
        json!({"scene": "scene/spaceship_volume.toml", "generations": 1, "set": ["grammar=\"../outside/secret.sg\""]});
    let (status, e) = server.post("/api/runs", &up);
    assert_eq!(status, 403, "{e}");
    // A grammar written in the editor whose mesh lies outside.
    let mut messages = Vec::new();
    let mesh = |path: &str| format!("mesh m = \"{path}\";\nStart {{ mesh(m); }}\n");
    for (name, path) in [
        ("a.sg", secret.join("secret.obj").display().to_string()),
        ("b.sg", "/etc/shadow".to_string()),
        ("c.sg", "/no/such/file.obj".to_string()),
    ] {
        let (status, saved) = server.post("/api/grammars/save", &json!({"name": name, "text": mesh(&path)}));
        assert_eq!(status, 200, "{saved}");
        let (status, e) = server.post("/api/sample", &json!({"path": saved["path"]}));
        assert_eq!(status, 403, "{name}: {e}");
        no_server_path(&e);
        // One message whether the file exists, is unreadable or is missing:
        // past the path as given, the same words.
        let message = e["error"].as_str().unwrap().to_string();
        let words = message.splitn(3, '`').nth(2).unwrap_or_default().to_string();
        assert!(words.starts_with(" is outside the folders this studio may read"), "{message}");
        messages.push(words);
    }
    assert!(messages.windows(2).all(|w| w[0] == w[1]), "{messages:#?}");
}

#[cfg(unix)]
#[test]
fn planted_links_below_out_are_never_followed() {
    let tmp = tempfile::tempdir().unwrap();
    let secret = outside(tmp.path());
    let scene = small_ship(&tmp.path().join("scene"), &[]);
    std::fs::create_dir_all(tmp.path().join("out")).unwrap();
    std::os::unix::fs::symlink(&secret, tmp.path().join("out/grammars")).unwrap();
    std::os::unix::fs::symlink(&secret, tmp.path().join("out/drafts")).unwrap();
    std::os::unix::fs::symlink(tmp.path().join("nowhere"), tmp.path().join("out/r1")).unwrap();
    let before: Vec<_> = std::fs::read_dir(&secret).unwrap().flatten().map(|e| e.file_name()).collect();
    let server = Studio::start(tmp.path(), &[s(&scene)]);
    for draft in [false, true] {
        let body = json!({"name": "x.sg", "text": "Start { box; }\n", "draft": draft});
        let (status, e) = server.post("/api/grammars/save", &body);
        assert_eq!(status, 403, "{e}");
        assert!(e["error"].as_str().unwrap().contains("is a symbolic link in the studio's folder"), "{e}");
    }
    let after: Vec<_> = std::fs::read_dir(&secret).unwrap().flatten().map(|e| e.file_name()).collect();
    assert_eq!(before, after, "nothing was written outside --out");
    // A dangling link where the first run's folder goes: the run fails,
    // and its snapshot names no server path.
    let body = json!({"scene": "scene/spaceship_volume.toml", "generations": 1});
    let (status, run) = server.post("/api/runs", &body);
    assert_eq!(status, 201, "{run}");
    let id = run["id"].as_str().unwrap().to_string();
    let done = server.wait(&format!("/api/runs/{id}"), "ended", |v| v["status"] != "running");
    let text = done.to_string();
    assert!(!text.contains(s(&tmp.path().canonicalize().unwrap())), "a server path leaked: {text}");
    assert!(!tmp.path().join("nowhere").exists(), "the link was not followed");
}
