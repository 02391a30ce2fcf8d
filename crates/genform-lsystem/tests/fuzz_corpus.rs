//! Replays the committed cargo-fuzz corpus (`fuzz/corpus/parse_ls`) through the
//! same steps as the fuzz target, so every input found by fuzzing is checked
//! on the stable toolchain: no panic, and every failed .ls file reports each
//! error at a `file:line:col`.

use genform_core::fixtures::{assert_located, fuzz_corpus};
use genform_core::{Rng, Scene};
use std::path::Path;

/// The committed corpus of fuzz target `target`, each input named `name`.
fn corpus(target: &str, name: &str) -> Vec<(String, genform_core::SourceFile)> {
    fuzz_corpus(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus").join(target), name)
}

#[test]
fn fuzz_corpus_never_panics_and_locates_every_error() {
    let (mut ok, mut failed) = (0, 0);
    for (input, file) in corpus("parse_ls", "fuzz.ls") {
        match genform_lsystem::compile(&file) {
            Ok((sys, _)) => {
                ok += 1;
                let mut rng = Rng::from_seed(1);
                if let Ok(s) = sys.derive_limited(3, &mut rng, 2000, |_, _| {}) {
                    let _ = sys.interpret(&s, &mut rng, 2000, &mut Scene::new());
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
