//! Fuzzes the graph-grammar front end (`.gg.yaml`): no input may panic,
//! every failed compile has located errors, and whatever compiles also runs
//! 20 steps with a small element limit without panicking.
#![no_main]

use genform_core::Rng;
use genform_fuzz::{assert_located, source};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let file = source("fuzz.gg.yaml", data);
    match genform_graph::compile(&file) {
        Ok((g, _)) => {
            let _ = g.derive(&mut Rng::from_seed(1), Some(20), 500);
        }
        Err(diags) => assert_located(&diags),
    }
});
