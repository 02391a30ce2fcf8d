//! Replays the committed cargo-fuzz corpus (`fuzz/corpus/parse_sg`) through
//! the same steps as the fuzz target, so every regression input found by
//! fuzzing is checked on the stable toolchain in CI.

use genform_core::{Generator, Limits, Rng, Scene, SourceFile};
use std::path::Path;

#[test]
fn fuzz_corpus_never_panics() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus/parse_sg");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).expect("corpus folder") {
        let bytes = std::fs::read(entry.unwrap().path()).unwrap();
        let Ok(text) = std::str::from_utf8(&bytes) else { continue };
        n += 1;
        let file = SourceFile::new("fuzz.sg", text);
        if let Ok((g, _)) = genform_shape::compile(&file, &genform_shape::NoAssets) {
            let limits = Limits { max_genes: 500, max_depth: 50, max_primitives: 2000 };
            if let Ok(s) = g.sample(&mut Rng::from_seed(1), &limits) {
                assert!(s.genome.validate(g.graph()).is_ok());
                let _ = g.express(&s.genome, &limits, &mut Scene::new());
            }
        }
    }
    assert!(n >= 10, "corpus has only {n} inputs");
}
