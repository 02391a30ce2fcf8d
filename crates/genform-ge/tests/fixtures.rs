//! Data-driven diagnostics fixtures: every `tests/fixtures/errors/*.bnf`
//! file carries its expected diagnostics as `# Error: L:C text` comments
//! (`genform_core::fixtures`); one compile must report exactly those.

use genform_core::fixtures::check_dir;
use std::path::Path;

#[test]
fn error_fixtures_report_exactly_their_annotations() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/errors");
    let checked = check_dir(&dir, ".bnf", "#", |file| match genform_ge::compile(file) {
        Ok((_, warnings)) => warnings,
        Err(errors) => errors,
    });
    match checked {
        Ok(n) => assert!(n >= 4, "fixtures missing in {}", dir.display()),
        Err(e) => panic!("\n{e}"),
    }
}
