//! Data-driven diagnostics fixtures: every `tests/fixtures/errors/*.bsg`
//! file carries its expected diagnostics as `# Error: L:C text` comments
//! (`genform_core::fixtures`); one compile must report exactly those.

use genform_core::SourceFile;
use std::path::Path;

fn check(path: &Path) -> Result<(), String> {
    let src = std::fs::read_to_string(path).map_err(|e| e.to_string())?;
    let name = path.file_name().unwrap().to_string_lossy().into_owned();
    let file = SourceFile::new(name, src);
    let diags = match genform_boxsplit::compile(&file) {
        Ok((_, warnings)) => warnings,
        Err(errors) => errors,
    };
    genform_core::fixtures::check(&file, &diags, "#")
}

#[test]
fn error_fixtures_report_exactly_their_annotations() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/errors");
    let mut files: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    files.retain(|p| p.extension().is_some_and(|e| e == "bsg"));
    files.sort();
    assert!(files.len() >= 5, "fixtures missing in {}", dir.display());
    let failures: Vec<String> = files.iter().filter_map(|p| check(p).err()).collect();
    assert!(failures.is_empty(), "\n{}", failures.join("\n\n"));
}
