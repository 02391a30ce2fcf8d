//! Data-driven fixtures: every `tests/fixtures/errors/*.ls` file carries
//! its expected diagnostics as `# Error: L:C text` comments
//! (`genform_core::fixtures`), and one compile must report exactly those;
//! every `tests/fixtures/good/*.ls` file compiles cleanly and derives the
//! string (and global state) its `# Expect:` lines give.

use genform_core::fixtures::check_dir;
use genform_core::{Rng, SourceFile};
use std::path::Path;

/// The text after `# key:` on the file's lines, in order.
fn expectations<'t>(text: &'t str, key: &str) -> Vec<&'t str> {
    let prefix = format!("# {key}:");
    text.lines().filter_map(|l| l.trim().strip_prefix(prefix.as_str()).map(str::trim)).collect()
}

#[test]
fn good_fixtures_derive_their_expected_strings() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/good");
    let mut files: Vec<_> = std::fs::read_dir(&dir).unwrap().filter_map(|e| e.ok().map(|e| e.path())).collect();
    files.retain(|p| p.extension().is_some_and(|e| e == "ls"));
    files.sort();
    assert!(files.len() >= 3, "fixtures missing in {}", dir.display());
    for path in files {
        let name = path.file_name().unwrap().to_string_lossy().into_owned();
        let text = std::fs::read_to_string(&path).unwrap();
        let (system, warnings) = match genform_lsystem::compile(&SourceFile::new(name.clone(), text.clone())) {
            Ok(r) => r,
            Err(e) => panic!("{name}:\n{}", e.short()),
        };
        assert!(warnings.items.is_empty(), "{name}: {}", warnings.short());
        let m = system.derive(system.settings.derivation, &mut Rng::from_seed(0)).unwrap();
        let want = expectations(&text, "Expect");
        assert_eq!(want.len(), 1, "{name}: one `# Expect:` line");
        assert_eq!(m.display(&system.alphabet, true), want[0], "{name}");
        if let Some(state) = expectations(&text, "Expect-state").first() {
            let state: Vec<f64> = state.split(',').map(|v| v.trim().parse().unwrap()).collect();
            assert_eq!(m.state, state, "{name}: iteration, then the globals");
        }
    }
}

#[test]
fn error_fixtures_report_exactly_their_annotations() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/errors");
    let checked = check_dir(&dir, ".ls", "#", |file| match genform_lsystem::compile(file) {
        Ok((_, warnings)) => warnings,
        Err(errors) => errors,
    });
    match checked {
        Ok(n) => assert!(n >= 4, "fixtures missing in {}", dir.display()),
        Err(e) => panic!("\n{e}"),
    }
}
