//! Fuzzes the shape-grammar front end: no input may panic, and whatever
//! compiles must also sample and express within limits without panicking.
#![no_main]

use genform_core::{Generator, Limits, Rng, Scene, SourceFile};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else { return };
    let file = SourceFile::new("fuzz.sg", text);
    if let Ok((g, _)) = genform_shape::compile(&file, &genform_shape::NoAssets) {
        let limits = Limits { max_genes: 500, max_depth: 50, max_primitives: 2000 };
        if let Ok(s) = g.sample(&mut Rng::from_seed(1), &limits) {
            let mut scene = Scene::new();
            let _ = g.express(&s.genome, &limits, &mut scene);
        }
    }
});
