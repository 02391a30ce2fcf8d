//! The README's and docs/ge.md's commands as a newcomer runs them: every
//! `genform map` example maps successfully, and every README command writes
//! into `out/` (which .gitignore covers) under a name of its own.

mod common;

use common::{genform, root};

/// The `genform …` command lines of the fenced code blocks in `file`
/// (backslash continuations joined, trailing `# comments` dropped).
fn commands(file: &str) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(root().join(file)).unwrap();
    let (mut out, mut fenced, mut pending) = (Vec::new(), false, String::new());
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
            continue;
        }
        if !fenced {
            continue;
        }
        let code = line.split(" #").next().unwrap().trim_end();
        pending.push_str(code.strip_suffix('\\').unwrap_or(code));
        if code.ends_with('\\') {
            continue;
        }
        let words: Vec<String> = pending.split_whitespace().map(String::from).collect();
        pending.clear();
        if words.first().map(String::as_str) == Some("genform") {
            out.push(words);
        }
    }
    out
}

#[test]
fn every_map_example_in_the_docs_maps_successfully() {
    let mut seen = 0;
    for file in ["README.md", "docs/ge.md"] {
        for words in commands(file).into_iter().filter(|w| w[1] == "map") {
            let args: Vec<&str> = words[1..].iter().map(String::as_str).collect();
            let run = genform(&root(), &args).ok();
            let out = run.stdout();
            assert!(out.contains("\nvalid: ") || out.contains("\"valid\":true"), "{file}: {words:?}\n{out}");
            seen += 1;
        }
    }
    assert!(seen >= 4, "{seen} map examples");
}

#[test]
fn readme_commands_write_into_out_under_distinct_names() {
    let gitignore = std::fs::read_to_string(root().join(".gitignore")).unwrap();
    assert!(gitignore.lines().any(|l| l.trim() == "/out/"), ".gitignore covers out/");
    let mut written: Vec<String> = Vec::new();
    let all = commands("README.md");
    assert!(all.len() > 20, "{} commands", all.len());
    for words in &all {
        let verb = words[1].as_str();
        let mut has_out = false;
        for pair in words.windows(2) {
            if ["--out", "-o", "--string-out", "--genome-out"].contains(&pair[0].as_str()) {
                assert!(pair[1].starts_with("out/"), "{words:?} writes outside out/");
                assert!(!written.contains(&pair[1]), "{} is written twice", pair[1]);
                written.push(pair[1].clone());
                has_out = true;
            }
        }
        let writes = ["sample", "derive", "evolve", "compare", "sweep", "serve"].contains(&verb);
        let only_text = words.iter().any(|w| w == "--string-out");
        assert!(!writes || has_out || only_text, "{words:?} would write into a default folder");
    }
}
