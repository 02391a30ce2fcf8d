//! Replays the committed cargo-fuzz corpora (`fuzz/corpus/parse_gr8`,
//! `fuzz/corpus/parse_env`) through the same steps as the fuzz targets, on the
//! stable toolchain: no panic, every failed file reports each error at a
//! `file:line:col`, and whatever compiles grows two steps under small limits.

use genform_core::fixtures::{assert_located, fuzz_corpus};
use genform_core::{Rng, SourceFile};
use genform_hemls::{Environment, GrowthLimits, Settings};
use std::path::Path;

const LIMITS: GrowthLimits = GrowthLimits { max_vertices: 2000, max_edges: 4000, max_faces: 2000 };
const KOCH: &str = "Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 - Edge0 + + Edge0 - Edge0\nAngle 60\n";

/// The committed corpus of fuzz target `target`, each input named `name`.
fn corpus(target: &str, name: &str) -> Vec<(String, SourceFile)> {
    fuzz_corpus(&Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fuzz/corpus").join(target), name)
}

#[test]
fn gr8_corpus_never_panics_and_locates_every_error() {
    let (mut ok, mut failed) = (0, 0);
    for (input, file) in corpus("parse_gr8", "fuzz.gr8") {
        match genform_hemls::compile(&file) {
            Ok((h, _)) => {
                ok += 1;
                let settings = Settings { steps: 2, limits: LIMITS, ..Settings::default() };
                let _ = genform_hemls::grow(&h, &settings, &Environment::new(), &mut Rng::from_seed(1));
            }
            Err(diags) => {
                failed += 1;
                assert_located(&input, &diags);
            }
        }
    }
    assert!(ok > 0 && failed > 0, "compiled {ok}, failed {failed}");
}

#[test]
fn env_corpus_never_panics_and_locates_every_error() {
    let koch = genform_hemls::parse_str("koch.gr8", KOCH).unwrap();
    let (mut ok, mut failed) = (0, 0);
    for (input, file) in corpus("parse_env", "fuzz.toml") {
        match genform_hemls::parse_env(&file) {
            Ok(spec) => {
                ok += 1;
                let Ok((mut settings, env)) = spec.resolve(&mut |_| Err("no meshes here".into())) else { continue };
                settings.steps = settings.steps.min(2);
                settings.limits = LIMITS;
                let _ = genform_hemls::grow(&koch, &settings, &env, &mut Rng::from_seed(1));
            }
            Err(diags) => {
                failed += 1;
                assert_located(&input, &diags);
            }
        }
    }
    assert!(ok > 0 && failed > 0, "parsed {ok}, failed {failed}");
}

#[test]
fn toml_nested_past_the_parser_limit_is_a_located_error() {
    // The fuzzer's find: a recursion-limit error of the TOML parser can come
    // without a position of its own; it must still be located (else at 1:1).
    for text in [format!("a = {}{}\n", "[".repeat(400), "]".repeat(400)), format!("a = {}\n", "{ b = ".repeat(300))] {
        let d = genform_hemls::parse_env(&SourceFile::new("deep.toml", text)).unwrap_err();
        assert!(d.short().starts_with("deep.toml:1:"), "{}", d.short());
        assert_located("deep.toml", &d);
    }
}
