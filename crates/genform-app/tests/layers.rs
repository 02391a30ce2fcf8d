//! The house rules of ARCHITECTURE.md that the dependency graph shows: the
//! application library and the Python binding link no argument parser,
//! web server, async runtime or terminal widget (those belong to the CLI
//! and studio doors), and no library crate depends on a door.

use std::collections::{BTreeMap, BTreeSet};

/// Every package of the workspace's dependency graph with the names of
/// what it links (normal and build dependencies; dev-dependencies, which
/// only tests and benches link, left out), from `cargo metadata`.
fn graph() -> BTreeMap<String, Vec<String>> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let out = std::process::Command::new(cargo)
        .args(["metadata", "--format-version", "1", "--offline", "--manifest-path"])
        .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/../../Cargo.toml"))
        .output()
        .expect("cargo metadata runs");
    assert!(out.status.success(), "cargo metadata: {}", String::from_utf8_lossy(&out.stderr));
    let meta: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    let name_of: BTreeMap<&str, &str> = meta["packages"]
        .as_array()
        .expect("packages")
        .iter()
        .map(|p| (p["id"].as_str().expect("id"), p["name"].as_str().expect("name")))
        .collect();
    let mut graph = BTreeMap::new();
    for node in meta["resolve"]["nodes"].as_array().expect("resolve.nodes") {
        let deps =
            node["deps"].as_array().expect("deps").iter().filter(|d| {
                d["dep_kinds"].as_array().is_some_and(|k| k.iter().any(|k| k["kind"].as_str() != Some("dev")))
            });
        let names = deps.map(|d| name_of[d["pkg"].as_str().expect("pkg")].to_string()).collect();
        graph.insert(name_of[node["id"].as_str().expect("id")].to_string(), names);
    }
    graph
}

/// Every `.rs` file under `dir`.
fn rust_files(dir: &std::path::Path, out: &mut Vec<std::path::PathBuf>) {
    for entry in std::fs::read_dir(dir).expect("a source folder").flatten() {
        let path = entry.path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// Everything `root` links, itself included.
fn closure(graph: &BTreeMap<String, Vec<String>>, root: &str) -> BTreeSet<String> {
    let mut seen = BTreeSet::new();
    let mut todo = vec![root.to_string()];
    while let Some(p) = todo.pop() {
        if seen.insert(p.clone()) {
            todo.extend(graph.get(&p).into_iter().flatten().cloned());
        }
    }
    seen
}

#[test]
fn the_application_library_and_python_link_no_door_machinery() {
    let graph = graph();
    for root in ["genform-app", "genform-py"] {
        let all = closure(&graph, root);
        assert!(all.len() > 20, "{root} is in the lock file with its dependencies");
        for door in ["clap", "axum", "tokio", "indicatif", "ctrlc", "genform-cli", "genform-studio"] {
            assert!(!all.contains(door), "{root} links {door}");
        }
    }
}

#[test]
fn libraries_depend_on_no_door() {
    let graph = graph();
    let doors = ["genform-cli", "genform-studio", "genform-py"];
    for lib in graph.keys().filter(|n| n.starts_with("genform-") && !doors.contains(&n.as_str())) {
        let all = closure(&graph, lib);
        for door in doors {
            assert!(!all.contains(door), "{lib} depends on the door {door}");
        }
    }
    assert!(closure(&graph, "genform-studio").contains("genform-app"), "the studio runs on the application library");
    assert!(closure(&graph, "genform-cli").contains("clap"), "the graph sees the doors' own dependencies");
}

/// The application library prints nothing: notes go to the door's sink or
/// the run's watcher (comments and test modules aside).
#[test]
fn the_application_library_does_not_print() {
    let mut files = Vec::new();
    rust_files(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("src"), &mut files);
    assert!(files.len() > 20, "the app's sources are found");
    for file in files {
        let text = std::fs::read_to_string(&file).unwrap();
        // Test modules come last in a file.
        let code = text.split("#[cfg(test)]").next().unwrap_or_default();
        for (n, line) in code.lines().enumerate() {
            let line = line.trim_start();
            if line.starts_with("//") {
                continue;
            }
            for mac in ["println!(", "eprintln!(", "print!(", "eprint!(", "std::io::stdout()", "std::io::stderr()."] {
                assert!(!line.contains(mac), "{}:{}: {line}", file.display(), n + 1);
            }
        }
    }
}

/// The doors fill requests and hold handles: they construct no optimizer,
/// scorer or scene and read no scene TOML themselves (the application
/// does, behind its facade). Their sources name none of the constructors
/// (comments aside) and their manifests link no TOML reader.
#[test]
fn the_doors_construct_no_optimizer_scorer_or_scene() {
    const BUILDERS: [&str; 13] = [
        "AnyOptimizer::new",
        "AnyCodonOptimizer::new",
        "AskTell::new",
        "Ga::new",
        "Ge::new",
        "Mh::new",
        "Smc::new",
        "VolumeScorer::new",
        "ImageScorer::new",
        "SurfaceScorer::new",
        "Targets::new",
        "toml::",
        "toml_edit::",
    ];
    let graph = graph();
    for door in ["genform-cli", "genform-studio", "genform-py"] {
        let deps = &graph[door];
        assert!(!deps.iter().any(|d| d == "toml" || d == "toml_edit"), "{door} links a TOML reader: {deps:?}");
        let mut files = Vec::new();
        rust_files(&std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(door).join("src"), &mut files);
        assert!(files.len() >= 4, "{door}: its sources are found");
        for file in files {
            let text = std::fs::read_to_string(&file).unwrap();
            for (n, line) in text.lines().enumerate() {
                let code = line.split("//").next().unwrap_or_default();
                for b in BUILDERS {
                    assert!(!code.contains(b), "{}:{}: a door calls {b}: {line}", file.display(), n + 1);
                }
            }
        }
    }
}

/// The CLI links the studio behind its default feature `studio`: built
/// without it, no web server or async runtime is linked.
#[test]
fn the_cli_without_its_default_features_links_no_http_stack() {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_string());
    let out = std::process::Command::new(cargo)
        .args(["tree", "-p", "genform-cli", "--no-default-features", "-e", "normal", "--prefix", "none", "--offline"])
        .arg("--manifest-path")
        .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/../../Cargo.toml"))
        .output()
        .expect("cargo tree runs");
    assert!(out.status.success(), "cargo tree: {}", String::from_utf8_lossy(&out.stderr));
    let tree = String::from_utf8_lossy(&out.stdout);
    assert!(tree.lines().count() > 20, "the tree is listed:\n{tree}");
    for name in ["axum ", "tokio ", "hyper ", "genform-studio "] {
        assert!(!tree.lines().any(|l| l.starts_with(name)), "genform-cli --no-default-features links {name}");
    }
    assert!(tree.lines().any(|l| l.starts_with("clap ")), "the CLI's own dependencies are listed");
}
