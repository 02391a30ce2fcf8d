//! ARCHITECTURE.md's rule for the application library, the door crates
//! (CLI, studio, Python) and the formalism crates: their files import one
//! another without a circle, so each file can be read knowing only the
//! files below it. A file "imports" another when it names
//! an item of that file's module by a `crate::`, `super::` or child-module
//! path (in `use` or inline); test modules are left out.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use syn::visit::Visit;

/// A module by its path from the crate root (`[]` is the root).
type Module = Vec<String>;

/// Every file module under `src` (bin targets aside), by module path.
fn modules(src: &Path) -> BTreeMap<Module, PathBuf> {
    let mut found = BTreeMap::new();
    let mut todo = vec![src.to_path_buf()];
    while let Some(dir) = todo.pop() {
        for entry in std::fs::read_dir(&dir).expect("source folder").flatten() {
            let path = entry.path();
            if path.is_dir() {
                if path.file_name() != Some("bin".as_ref()) {
                    todo.push(path);
                }
                continue;
            }
            if path.extension() != Some("rs".as_ref()) {
                continue;
            }
            let rel = path.strip_prefix(src).expect("under src").with_extension("");
            let mut parts: Module = rel.iter().map(|p| p.to_string_lossy().into_owned()).collect();
            if parts == ["lib"] || parts == ["main"] || parts.last().is_some_and(|p| p == "mod") {
                parts.pop();
            }
            found.insert(parts, path);
        }
    }
    found
}

/// The `crate::`/`super::`/child paths a file names, as segment lists.
#[derive(Default)]
struct Paths(Vec<Vec<String>>);

impl Paths {
    fn use_tree(&mut self, prefix: &mut Vec<String>, tree: &syn::UseTree) {
        match tree {
            syn::UseTree::Path(p) => {
                prefix.push(p.ident.to_string());
                self.use_tree(prefix, &p.tree);
                prefix.pop();
            }
            syn::UseTree::Name(n) if n.ident == "self" => self.0.push(prefix.clone()),
            syn::UseTree::Name(n) => self.0.push([prefix.as_slice(), &[n.ident.to_string()]].concat()),
            syn::UseTree::Rename(r) => self.0.push([prefix.as_slice(), &[r.ident.to_string()]].concat()),
            syn::UseTree::Glob(_) => self.0.push(prefix.clone()),
            syn::UseTree::Group(g) => g.items.iter().for_each(|t| self.use_tree(prefix, t)),
        }
    }
}

fn is_test_only(attrs: &[syn::Attribute]) -> bool {
    attrs
        .iter()
        .any(|a| a.path().is_ident("cfg") && a.meta.require_list().is_ok_and(|l| l.tokens.to_string() == "test"))
}

impl<'ast> Visit<'ast> for Paths {
    fn visit_item(&mut self, item: &'ast syn::Item) {
        if let syn::Item::Mod(m) = item
            && is_test_only(&m.attrs)
        {
            return;
        }
        syn::visit::visit_item(self, item);
    }
    fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
        self.use_tree(&mut Vec::new(), &u.tree);
    }
    fn visit_visibility(&mut self, _: &'ast syn::Visibility) {
        // `pub(crate)` names a scope, not an item.
    }
    fn visit_path(&mut self, p: &'ast syn::Path) {
        self.0.push(p.segments.iter().map(|s| s.ident.to_string()).collect());
        syn::visit::visit_path(self, p);
    }
}

/// The module file a path names from module `from`, if it is this crate's.
fn target(from: &Module, path: &[String], all: &BTreeMap<Module, PathBuf>) -> Option<Module> {
    let (mut base, mut rest) = (from.clone(), path);
    match rest.first().map(String::as_str) {
        Some("crate") => (base, rest) = (Vec::new(), &rest[1..]),
        Some("super" | "self") => {
            while let Some(head) = rest.first().filter(|h| *h == "super" || *h == "self") {
                if head == "super" {
                    base.pop();
                }
                rest = &rest[1..];
            }
        }
        Some(child) if all.contains_key(&[from.as_slice(), &[child.to_string()]].concat()) => {}
        _ => return None,
    }
    for seg in rest {
        base.push(seg.clone());
        if !all.contains_key(&base) {
            base.pop();
            break;
        }
    }
    Some(base)
}

/// Who imports whom among the files of the crate at `dir`.
fn imports(dir: &Path) -> BTreeMap<Module, BTreeSet<Module>> {
    let all = modules(&dir.join("src"));
    let mut graph = BTreeMap::new();
    for (module, file) in &all {
        let text = std::fs::read_to_string(file).expect("readable");
        let ast = syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let mut paths = Paths::default();
        paths.visit_file(&ast);
        let to: BTreeSet<Module> =
            paths.0.iter().filter_map(|p| target(module, p, &all)).filter(|t| t != module).collect();
        graph.insert(module.clone(), to);
    }
    graph
}

/// A circle of imports, if there is one.
fn circle(graph: &BTreeMap<Module, BTreeSet<Module>>) -> Option<Vec<Module>> {
    fn walk(
        at: &Module,
        graph: &BTreeMap<Module, BTreeSet<Module>>,
        done: &mut BTreeSet<Module>,
        stack: &mut Vec<Module>,
    ) -> Option<Vec<Module>> {
        if let Some(i) = stack.iter().position(|m| m == at) {
            return Some(stack[i..].to_vec());
        }
        if !done.insert(at.clone()) {
            return None;
        }
        stack.push(at.clone());
        for next in graph.get(at).into_iter().flatten() {
            if let Some(c) = walk(next, graph, done, stack) {
                return Some(c);
            }
        }
        stack.pop();
        None
    }
    let mut done = BTreeSet::new();
    graph.keys().find_map(|m| walk(m, graph, &mut done, &mut Vec::new()))
}

/// Every group of files that import one another (strongly connected
/// components of more than one file), each sorted.
fn circles(graph: &BTreeMap<Module, BTreeSet<Module>>) -> Vec<Vec<Module>> {
    // Files that reach each other both ways share a group.
    let reach = |from: &Module| {
        let mut seen = BTreeSet::new();
        let mut todo = vec![from.clone()];
        while let Some(m) = todo.pop() {
            for next in graph.get(&m).into_iter().flatten() {
                if seen.insert(next.clone()) {
                    todo.push(next.clone());
                }
            }
        }
        seen
    };
    let reached: BTreeMap<&Module, BTreeSet<Module>> = graph.keys().map(|m| (m, reach(m))).collect();
    let mut groups: Vec<Vec<Module>> = Vec::new();
    for m in graph.keys() {
        if groups.iter().any(|g| g.contains(m)) || !reached[m].contains(m) {
            continue;
        }
        let group: Vec<Module> = reached[m].iter().filter(|o| reached[*o].contains(m)).cloned().collect();
        groups.push(group);
    }
    groups
}

fn shown(m: &Module) -> String {
    if m.is_empty() { "lib.rs/main.rs".to_string() } else { m.join("/") + ".rs" }
}

/// The crates whose files must import one another without a circle: the
/// application library, the doors, the formalism crates and the engine
/// crates under them.
const CHECKED: [&str; 14] = [
    "genform-app",
    "genform-cli",
    "genform-studio",
    "genform-py",
    "genform-shape",
    "genform-lsystem",
    "genform-boxsplit",
    "genform-graph",
    "genform-hemls",
    "genform-ge",
    "genform-core",
    "genform-score",
    "genform-evolve",
    "genform-export",
];

#[test]
fn no_import_circle_in_any_crate() {
    assert_no_circle(&CHECKED);
}

/// Panics with every group of files that import one another in `crates`.
fn assert_no_circle(crates: &[&str]) {
    let mut found = Vec::new();
    for krate in crates {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(krate);
        let graph = imports(&dir);
        assert!(graph.len() >= 4, "{krate}: found its source files");
        for group in circles(&graph) {
            let example =
                circle(&graph).map(|c| c.iter().map(shown).collect::<Vec<_>>().join(" → ")).unwrap_or_default();
            found.push(format!("{krate}: {} (e.g. {example})", group.iter().map(shown).collect::<Vec<_>>().join(", ")));
        }
    }
    assert!(found.is_empty(), "files import one another in a circle:\n{}", found.join("\n"));
}

#[test]
fn the_check_sees_a_circle() {
    // The application's objectives import the scene they open; were the
    // scene to name an objective, that would be a circle.
    let graph = imports(Path::new(env!("CARGO_MANIFEST_DIR")));
    let (objective, scene) = (vec!["objective".to_string()], vec!["scene".to_string()]);
    assert!(graph[&objective].contains(&scene), "objective.rs imports scene/mod.rs");
    assert!(circle(&graph).is_none() && circles(&graph).is_empty());
    let mut with_circle = graph.clone();
    with_circle.get_mut(&scene).expect("scene/mod.rs").insert(objective.clone());
    assert!(circle(&with_circle).is_some());
    assert_eq!(circles(&with_circle), [vec![objective, scene]]);
    // Through the studio's state, as before.
    let studio = imports(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../genform-studio"));
    let state = vec!["state".to_string()];
    assert!(studio[&vec!["runs".to_string()]].contains(&state), "runs.rs imports state.rs");
}
