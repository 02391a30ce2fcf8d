//! Fuzzes the L-system front end (`.ls`): no input may panic, every failed
//! compile has located errors, and whatever compiles also derives 3 steps
//! and draws within small limits without panicking.
#![no_main]

use genform_core::{Rng, Scene};
use genform_fuzz::{assert_located, source};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let file = source("fuzz.ls", data);
    match genform_lsystem::compile(&file) {
        Ok((sys, _)) => {
            let mut rng = Rng::from_seed(1);
            if let Ok(s) = sys.derive_limited(3, &mut rng, 2000, |_, _| {}) {
                let _ = sys.interpret(&s, &mut rng, 2000, &mut Scene::new());
            }
        }
        Err(diags) => assert_located(&diags),
    }
});
