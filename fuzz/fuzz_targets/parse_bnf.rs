//! Fuzzes the GE grammar front end (`.bnf`): no input may panic, every
//! failed compile has located errors, and whatever compiles also maps a few
//! random genomes, as standard GE and with Genr8's extensions.
#![no_main]

use genform_core::Rng;
use genform_fuzz::{assert_located, source};
use genform_ge::{Mapper, MapOptions};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let file = source("fuzz.bnf", data);
    match genform_ge::compile(&file) {
        Ok((bnf, _)) => {
            let mut rng = Rng::from_seed(1);
            for options in [MapOptions::standard(2, Some(30)), MapOptions::genr8()] {
                let Ok(mut mapper) = Mapper::new(&bnf, options) else { continue };
                for _ in 0..3 {
                    let genome: Vec<u32> = (0..40).map(|_| rng.next_u64() as u32).collect();
                    let _ = mapper.map(&genome);
                }
            }
        }
        Err(diags) => assert_located(&diags),
    }
});
