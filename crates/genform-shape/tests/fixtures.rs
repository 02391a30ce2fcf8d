//! Data-driven diagnostics fixtures: every `tests/fixtures/errors/*.sg`
//! file carries its expected diagnostics as `// Error: L:C text` comments
//! (`genform_core::fixtures`); one compile must report exactly those.

use genform_core::fixtures::check_dir;
use std::path::Path;

#[test]
fn error_fixtures_report_exactly_their_annotations() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/errors");
    let checked = check_dir(&dir, ".sg", "//", |file| match genform_shape::compile(file, &genform_shape::NoAssets) {
        Ok((_, warnings)) => warnings,
        Err(errors) => errors,
    });
    match checked {
        Ok(n) => assert!(n >= 8, "fixtures missing in {}", dir.display()),
        Err(e) => panic!("\n{e}"),
    }
}

/// Every `tests/fixtures/ok/*.sg` file compiles without any diagnostic and
/// its samples express without error.
#[test]
fn ok_fixtures_compile_cleanly_and_express() {
    use genform_core::{Generator, Rng, Scene, SourceFile};
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/ok");
    let mut files: Vec<_> = std::fs::read_dir(&dir).unwrap().map(|e| e.unwrap().path()).collect();
    files.sort();
    assert!(!files.is_empty(), "fixtures missing in {}", dir.display());
    for path in files {
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        let file = SourceFile::new(name.clone(), std::fs::read_to_string(&path).unwrap());
        let (g, warnings) = genform_shape::compile(&file, &genform_shape::NoAssets)
            .unwrap_or_else(|e| panic!("{name}:\n{}", e.short()));
        assert!(warnings.items.is_empty(), "{name}: {}", warnings.short());
        let limits = g.limits();
        for seed in 0..50 {
            let s = g.sample(&mut Rng::from_seed(seed), &limits).unwrap_or_else(|e| panic!("{name} {seed}: {e}"));
            let mut scene = Scene::new();
            g.express(&s.genome, &limits, &mut scene).unwrap_or_else(|e| panic!("{name} {seed}: {e}"));
            assert!(!scene.is_empty(), "{name} {seed}");
        }
    }
}
