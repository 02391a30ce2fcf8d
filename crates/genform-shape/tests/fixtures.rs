//! Data-driven language fixtures: every `tests/fixtures/errors/*.sg` file
//! carries its expected diagnostics as comments,
//!
//! ```text
//! box2; // Error: 3:5 unknown operation
//! ```
//!
//! meaning "an error at line 3, column 5 whose message contains `unknown
//! operation`" (`// Warning:` for warnings). One compile must report exactly
//! the annotated set: every annotation matched, nothing unannotated.

use genform_core::{Severity, SourceFile};
use std::path::Path;

#[derive(Debug)]
struct Expected {
    severity: Severity,
    line: usize,
    col: usize,
    text: String,
    /// Line of the annotation (for messages).
    at: usize,
}

fn annotations(src: &str) -> Vec<Expected> {
    let mut out = Vec::new();
    for (i, line) in src.lines().enumerate() {
        for (tag, severity) in [("// Error:", Severity::Error), ("// Warning:", Severity::Warning)] {
            let Some(pos) = line.find(tag) else { continue };
            let rest = line[pos + tag.len()..].trim();
            let (loc, text) = rest.split_once(' ').unwrap_or((rest, ""));
            let (l, c) = loc.split_once(':').unwrap_or_else(|| panic!("line {}: bad annotation `{rest}`", i + 1));
            out.push(Expected {
                severity,
                line: l.parse().expect("line number"),
                col: c.parse().expect("column"),
                text: text.trim().to_string(),
                at: i + 1,
            });
        }
    }
    out
}

fn check(path: &Path) -> Result<(), String> {
    let src = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let file = SourceFile::new(name.clone(), src.clone());
    let diags = match genform_shape::compile(&file, &genform_shape::NoAssets) {
        Ok((_, warnings)) => warnings,
        Err(errors) => errors,
    };
    let mut expected = annotations(&src);
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

#[test]
fn error_fixtures_report_exactly_their_annotations() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/errors");
    let mut files: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    files.retain(|p| p.extension().is_some_and(|e| e == "sg"));
    files.sort();
    assert!(files.len() >= 8, "fixtures missing in {}", dir.display());
    let failures: Vec<String> = files.iter().filter_map(|p| check(p).err()).collect();
    assert!(failures.is_empty(), "\n{}", failures.join("\n\n"));
}
