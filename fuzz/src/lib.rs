//! Helpers shared by the fuzz targets: turning raw fuzzer bytes into a
//! source file and checking the front ends' diagnostics contract.

use genform_core::{Diagnostics, Severity, SourceFile};

/// The fuzzer's bytes as a source file named `name` (invalid UTF-8 is
/// replaced, so every input reaches the parser).
pub fn source(name: &str, data: &[u8]) -> SourceFile {
    SourceFile::new(name, String::from_utf8_lossy(data).into_owned())
}

/// Panics unless `diags` (a failed compile) holds at least one error and
/// every error starts inside the file, so the CLI can print `file:line:col`.
/// (An error at the end of the file may end one byte past it: the
/// renderer clamps spans.)
pub fn assert_located(diags: &Diagnostics) {
    assert!(diags.has_errors(), "a failed compile reported no error");
    let len = diags.file.text.len() as u32;
    for d in diags.items.iter().filter(|d| d.severity == Severity::Error) {
        let span = d.span.unwrap_or_else(|| panic!("error without a location: {}", d.message));
        assert!(span.start <= span.end && span.start <= len, "span {span:?} outside the file ({len} bytes)");
    }
    let _ = diags.short();
}
