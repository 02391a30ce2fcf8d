//! Replays the committed cargo-fuzz corpus (`fuzz/corpus/parse_bsg`) through the
//! same steps as the fuzz target, so every input found by fuzzing is checked
//! on the stable toolchain: no panic, and every failed .bsg file reports each
//! error at a `file:line:col`.

use genform_boxsplit::{DeriveLimits, DeriveOptions};
use genform_core::Rng;
use genform_core::{Diagnostics, Severity, SourceFile};
use glam::IVec3;
use std::path::Path;

/// Every file of the corpus, as the fuzz target sees it (lossy UTF-8).
fn corpus() -> Vec<(String, SourceFile)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus/parse_bsg");
    let mut files = Vec::new();
    for entry in std::fs::read_dir(&dir).expect("corpus folder") {
        let path = entry.unwrap().path();
        let bytes = std::fs::read(&path).unwrap();
        let text = String::from_utf8_lossy(&bytes).into_owned();
        files.push((path.display().to_string(), SourceFile::new("fuzz.bsg", text)));
    }
    assert!(files.len() >= 10, "corpus has only {} inputs", files.len());
    files
}

/// At least one error, each starting inside the file.
fn assert_located(input: &str, diags: &Diagnostics) {
    assert!(diags.has_errors(), "{input}: a failed compile reported no error");
    let len = diags.file.text.len() as u32;
    for d in diags.items.iter().filter(|d| d.severity == Severity::Error) {
        let span = d.span.unwrap_or_else(|| panic!("{input}: error without a location: {}", d.message));
        assert!(span.start <= span.end && span.start <= len, "{input}: span {span:?} outside the file");
    }
    assert!(diags.short().lines().all(|l| l.starts_with("fuzz.bsg:") || l.starts_with("  hint:")));
}

#[test]
fn fuzz_corpus_never_panics_and_locates_every_error() {
    let (mut ok, mut failed) = (0, 0);
    for (input, file) in corpus() {
        match genform_boxsplit::compile(&file) {
            Ok((g, _)) => {
                ok += 1;
                let limits = DeriveLimits { applications: 2000, backtracks: 200, depth: 100 };
                let options = DeriveOptions { limits: Some(limits), trace: false };
                let _ = g.derive(None, IVec3::ZERO, IVec3::new(12, 8, 12), &mut Rng::from_seed(1), &options);
            }
            Err(diags) => {
                failed += 1;
                assert_located(&input, &diags);
            }
        }
    }
    // The corpus holds both kinds, so both paths stay covered.
    assert!(ok > 0 && failed > 0, "compiled {ok}, failed {failed}");
}
