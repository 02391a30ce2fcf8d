//! Replays the committed cargo-fuzz corpus (`fuzz/corpus/parse_bnf`) through the
//! same steps as the fuzz target, so every input found by fuzzing is checked
//! on the stable toolchain: no panic, and every failed .bnf file reports each
//! error at a `file:line:col`.

use genform_core::Rng;
use genform_core::{Diagnostics, Severity, SourceFile};
use genform_ge::{MapOptions, Mapper};
use std::path::Path;

/// Every file of the corpus, as the fuzz target sees it (lossy UTF-8).
fn corpus() -> Vec<(String, SourceFile)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus/parse_bnf");
    let mut files = Vec::new();
    for entry in std::fs::read_dir(&dir).expect("corpus folder") {
        let path = entry.unwrap().path();
        let bytes = std::fs::read(&path).unwrap();
        let text = String::from_utf8_lossy(&bytes).into_owned();
        files.push((path.display().to_string(), SourceFile::new("fuzz.bnf", text)));
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
    assert!(diags.short().lines().all(|l| l.starts_with("fuzz.bnf:") || l.starts_with("  hint:")));
}

#[test]
fn fuzz_corpus_never_panics_and_locates_every_error() {
    let (mut ok, mut failed) = (0, 0);
    for (input, file) in corpus() {
        match genform_ge::compile(&file) {
            Ok((bnf, _)) => {
                ok += 1;
                let mut rng = Rng::from_seed(1);
                for options in [MapOptions::standard(2, Some(30)), MapOptions::genr8()] {
                    let Ok(mut mapper) = Mapper::new(&bnf, options) else { continue };
                    for _ in 0..3 {
                        let genome: Vec<u32> = (0..40).map(|_| rng.next_u64() as u32).collect();
                        let _ = mapper.map(&genome);
                    }
                }
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
