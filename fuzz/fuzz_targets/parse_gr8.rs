//! Fuzzes the HEMLS front end (`.gr8`): no input may panic, every failed
//! compile has located errors, and whatever compiles also grows 2 steps
//! with small element limits without panicking.
#![no_main]

use genform_core::Rng;
use genform_fuzz::{assert_located, source};
use genform_hemls::{Environment, GrowthLimits, Settings};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let file = source("fuzz.gr8", data);
    match genform_hemls::compile(&file) {
        Ok((h, _)) => {
            let limits = GrowthLimits { max_vertices: 2000, max_edges: 4000, max_faces: 2000 };
            let settings = Settings { steps: 2, limits, ..Settings::default() };
            let _ = genform_hemls::grow(&h, &settings, &Environment::new(), &mut Rng::from_seed(1));
        }
        Err(diags) => assert_located(&diags),
    }
});
