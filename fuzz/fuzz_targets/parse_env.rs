//! Fuzzes the HEMLS environment files (`.toml`): no input may panic, every
//! failed parse has located errors, and whatever parses (meshes refused)
//! also grows the Koch grammar 2 steps in it with small limits.
#![no_main]

use genform_core::Rng;
use genform_fuzz::{assert_located, source};
use genform_hemls::GrowthLimits;
use libfuzzer_sys::fuzz_target;

const KOCH: &str = "Edge0 + Edge0 + Edge0\nEdge0 -> Edge0 - Edge0 + + Edge0 - Edge0\nAngle 60\n";

fuzz_target!(|data: &[u8]| {
    let file = source("fuzz.toml", data);
    match genform_hemls::parse_env(&file) {
        Ok(spec) => {
            let Ok((mut settings, env)) = spec.resolve(&mut |_| Err("no meshes while fuzzing".into())) else { return };
            settings.steps = settings.steps.min(2);
            settings.limits = GrowthLimits { max_vertices: 2000, max_edges: 4000, max_faces: 2000 };
            let h = genform_hemls::parse_str("koch.gr8", KOCH).expect("the Koch grammar compiles");
            let _ = genform_hemls::grow(&h, &settings, &env, &mut Rng::from_seed(1));
        }
        Err(diags) => assert_located(&diags),
    }
});
