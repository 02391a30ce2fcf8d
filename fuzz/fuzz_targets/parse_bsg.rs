//! Fuzzes the box-split front end (`.bsg`): no input may panic, every
//! failed compile has located errors, and whatever compiles also derives in
//! a small empty box under tight limits without panicking.
#![no_main]

use genform_boxsplit::{DeriveLimits, DeriveOptions};
use genform_core::Rng;
use genform_fuzz::{assert_located, source};
use glam::IVec3;
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let file = source("fuzz.bsg", data);
    match genform_boxsplit::compile(&file) {
        Ok((g, _)) => {
            let limits = DeriveLimits { applications: 2000, backtracks: 200, depth: 100 };
            let options = DeriveOptions { limits: Some(limits), trace: false };
            let _ = g.derive(None, IVec3::ZERO, IVec3::new(12, 8, 12), &mut Rng::from_seed(1), &options);
        }
        Err(diags) => assert_located(&diags),
    }
});
