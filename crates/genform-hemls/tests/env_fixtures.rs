//! Data-driven diagnostics fixtures for environment files: every
//! `tests/env_fixtures/*.toml` carries its expected errors as
//! `# Error: L:C text` comments (`genform_core::fixtures`); parsing must
//! report exactly those.

use genform_core::fixtures::check_dir;
use std::path::Path;

#[test]
fn env_fixtures_report_exactly_their_annotations() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/env_fixtures");
    let checked = check_dir(&dir, ".toml", "#", |file| match genform_hemls::parse_env(file) {
        Ok(_) => genform_core::Diagnostics::new(file.clone()),
        Err(errors) => errors,
    });
    match checked {
        Ok(n) => assert!(n >= 6, "fixtures missing in {}", dir.display()),
        Err(e) => panic!("\n{e}"),
    }
}
