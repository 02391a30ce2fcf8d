//! Data-driven diagnostics fixtures: every `tests/fixtures/errors/*.gr8`
//! file carries its expected diagnostics as `// Error: L:C text` (or
//! `// Warning:`) comments (`genform_core::fixtures`); one compile must
//! report exactly those.

use genform_core::fixtures::check_dir;
use std::path::Path;

#[test]
fn error_fixtures_report_exactly_their_annotations() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/errors");
    let checked = check_dir(&dir, ".gr8", "//", |file| match genform_hemls::compile(file) {
        Ok((_, warnings)) => warnings,
        Err(errors) => errors,
    });
    match checked {
        Ok(n) => assert!(n >= 18, "fixtures missing in {}: {n}", dir.display()),
        Err(e) => panic!("\n{e}"),
    }
}
