//! Data-driven diagnostics fixtures, shared by every language's tests.
//!
//! A fixture is a grammar file that carries its expected diagnostics as
//! comments in its own comment syntax, e.g. for `.sg` files
//!
//! ```text
//! box2; // Error: 3:5 unknown operation
//! ```
//!
//! meaning "an error at line 3, column 5 whose message contains `unknown
//! operation`" (`Warning:` for warnings). [`check`] compares one compile's
//! diagnostics with the annotations: every annotation must be matched and
//! nothing may be reported unannotated.

use crate::diag::{Diagnostics, Severity, SourceFile};

#[derive(Debug)]
struct Expected {
    severity: Severity,
    line: usize,
    col: usize,
    text: String,
    /// Line of the annotation (for messages).
    at: usize,
}

fn annotations(src: &str, comment: &str) -> Result<Vec<Expected>, String> {
    let mut out = Vec::new();
    for (i, line) in src.lines().enumerate() {
        for (tag, severity) in [("Error:", Severity::Error), ("Warning:", Severity::Warning)] {
            let marker = format!("{comment} {tag}");
            let Some(pos) = line.find(&marker) else { continue };
            let rest = line[pos + marker.len()..].trim();
            let (loc, text) = rest.split_once(' ').unwrap_or((rest, ""));
            let parsed = loc.split_once(':').and_then(|(l, c)| Some((l.parse().ok()?, c.parse().ok()?)));
            let Some((line_no, col)) = parsed else {
                return Err(format!("line {}: bad annotation `{rest}` (expected `L:C text`)", i + 1));
            };
            out.push(Expected { severity, line: line_no, col, text: text.trim().to_string(), at: i + 1 });
        }
    }
    Ok(out)
}

/// Checks `diags` (from compiling `file`) against the annotations in the
/// file's text, written after `comment` (`"//"`, `"#"`). `Err` lists every
/// mismatch and what was reported.
pub fn check(file: &SourceFile, diags: &Diagnostics, comment: &str) -> Result<(), String> {
    let name = &file.name;
    let mut expected = annotations(&file.text, comment)?;
    if expected.is_empty() {
        return Err(format!("{name}: no annotations; reported:\n{}", diags.short()));
    }
    let mut problems = Vec::new();
    for d in &diags.items {
        let (line, col) = d.span.map_or((0, 0), |s| file.line_col(s.start));
        let hit = expected
            .iter()
            .position(|e| e.severity == d.severity && e.line == line && e.col == col && d.message.contains(&e.text));
        match hit {
            Some(i) => {
                expected.remove(i);
            }
            None => problems.push(format!("unexpected {}:{}:{}: {}: {}", name, line, col, d.severity, d.message)),
        }
    }
    for e in expected {
        problems.push(format!(
            "missing {name}:{}:{}: {}: …{}… (annotated on line {})",
            e.line, e.col, e.severity, e.text, e.at
        ));
    }
    if problems.is_empty() { Ok(()) } else { Err(format!("{}\nreported:\n{}", problems.join("\n"), diags.short())) }
}

/// Checks every file in `dir` whose name ends with `suffix` (sorted by
/// name): `compile` returns its diagnostics (warnings on success, errors on
/// failure), which must match the file's annotations after `comment`.
/// Returns the number of files checked, or every mismatch of every file.
///
/// Test support: this reads the folder it is given (the fixtures of the
/// calling crate's tests).
pub fn check_dir(
    dir: &std::path::Path,
    suffix: &str,
    comment: &str,
    compile: impl Fn(&SourceFile) -> Diagnostics,
) -> Result<usize, String> {
    let entries = std::fs::read_dir(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut files: Vec<_> = entries.filter_map(|e| e.ok().map(|e| e.path())).collect();
    files.retain(|p| p.file_name().is_some_and(|n| n.to_string_lossy().ends_with(suffix)));
    files.sort();
    let mut failures = Vec::new();
    for path in &files {
        let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_default();
        let file = SourceFile::new(name, text);
        if let Err(e) = check(&file, &compile(&file), comment) {
            failures.push(e);
        }
    }
    if failures.is_empty() { Ok(files.len()) } else { Err(failures.join("\n\n")) }
}

/// Every file of a cargo-fuzz corpus folder as its fuzz target sees it
/// (lossy UTF-8), each named `name` (so diagnostics print `name:L:C`) and
/// paired with its path. Panics when the folder holds fewer than 10 inputs:
/// a corpus that shrank that far no longer covers its front end.
pub fn fuzz_corpus(dir: &std::path::Path, name: &str) -> Vec<(String, SourceFile)> {
    let mut files = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap_or_else(|e| panic!("corpus folder {}: {e}", dir.display())) {
        let path = entry.unwrap().path();
        let text = String::from_utf8_lossy(&std::fs::read(&path).unwrap()).into_owned();
        files.push((path.display().to_string(), SourceFile::new(name, text)));
    }
    files.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(files.len() >= 10, "{} has only {} inputs", dir.display(), files.len());
    files
}

/// Asserts that a failed compile of `input` reported at least one error and
/// that every error has a location inside the file (what the fuzz targets
/// check).
pub fn assert_located(input: &str, diags: &Diagnostics) {
    assert!(diags.has_errors(), "{input}: a failed compile reported no error");
    let len = diags.file.text.len() as u32;
    for d in diags.items.iter().filter(|d| d.severity == Severity::Error) {
        let span = d.span.unwrap_or_else(|| panic!("{input}: error without a location: {}", d.message));
        assert!(span.start <= span.end && span.end <= len, "{input}: span {span:?} outside the file ({len} bytes)");
    }
    let name = &diags.file.name;
    assert!(diags.short().lines().all(|l| l.starts_with(&format!("{name}:")) || l.starts_with("  ")), "{input}");
}
