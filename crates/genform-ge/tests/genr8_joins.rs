//! Joining in rule sets drawn at random from Genr8's EA grammar
//! (`examples/ge/genr8.bnf`): the default join test must let branches give
//! random phenotypes internal structure (issue 24: with genform's former
//! cone test, 8 of 60 reached 4 faces in 4 steps).

use genform_core::{Rng, SourceFile};
use genform_ge::{MapOptions, Mapper};
use genform_hemls::{Environment, JoinTest, Settings};

/// Faces after 4 steps, branches drawn and joins made for each valid
/// phenotype of `n` genomes (lengths 50–200, codons 0–999) from `seed`.
fn grow_random(seed: u64, n: usize, join: JoinTest) -> Vec<(usize, u64, u64)> {
    let path = format!("{}/../../examples/ge/genr8.bnf", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    let (bnf, _) = genform_ge::compile(&SourceFile::new("genr8.bnf", text)).unwrap();
    let mut mapper = Mapper::new(&bnf, MapOptions::genr8()).unwrap();
    let mut rng = Rng::from_seed(seed);
    let settings = Settings { steps: 4, join, ..Settings::default() };
    let mut out = Vec::new();
    for _ in 0..n {
        let len = 50 + rng.below(151) as usize;
        let genome: Vec<u32> = (0..len).map(|_| rng.below(1000) as u32).collect();
        mapper.map(&genome);
        let Some(text) = mapper.phenotype() else { continue };
        let h = genform_hemls::parse_str("random.gr8", text).unwrap_or_else(|e| panic!("{text}\n{}", e.short()));
        let g = genform_hemls::grow(&h, &settings, &Environment::default(), &mut Rng::from_seed(0));
        if let Ok(g) = g {
            out.push((g.map.face_count(), g.branches, g.joins));
        }
    }
    out
}

#[test]
fn most_random_phenotypes_join_into_four_faces_or_more_with_the_default_test() {
    let share = |join| {
        let r = grow_random(1, 60, join);
        assert!(r.len() >= 50, "valid phenotypes: {}", r.len());
        r.iter().filter(|x| x.0 >= 4).count() as f64 / r.len() as f64
    };
    let default = share(JoinTest::default());
    // Measured 35 of 60 (58 %); the goal of issue 24 is 40 %.
    assert!(default >= 0.40, "share with >= 4 faces: {default}");
    // The cone reading joins less: 19 of 60.
    assert!(share(JoinTest::Cone) < default);
}

/// The table of docs/hemls.md: `cargo test --release -p genform-ge --test
/// genr8_joins -- --ignored --nocapture`.
#[test]
#[ignore]
fn measure() {
    for seed in [1u64, 2, 3, 24] {
        for join in JoinTest::ALL {
            let r = grow_random(seed, 60, join);
            let four = r.iter().filter(|x| x.0 >= 4).count();
            let one = r.iter().filter(|x| x.0 <= 1).count();
            let br: u64 = r.iter().map(|x| x.1).sum();
            let jn: u64 = r.iter().map(|x| x.2).sum();
            let mut faces: Vec<usize> = r.iter().map(|x| x.0).collect();
            faces.sort();
            println!(
                "seed {seed} {:7} valid {} >=4 faces {} ({:.0}%) single {} branches joined {:.1}% median faces {}",
                join.name(),
                r.len(),
                four,
                100.0 * four as f64 / r.len() as f64,
                one,
                200.0 * jn as f64 / br.max(1) as f64,
                faces[faces.len() / 2]
            );
        }
    }
}

/// Evolved systems under every reading: `GENFORM_GR8="a.gr8 b.gr8" cargo
/// test --release -p genform-ge --test genr8_joins -- --ignored --nocapture`
/// (docs/hemls.md measures the bests of `genform evolve` runs).
#[test]
#[ignore]
fn measure_files() {
    let Ok(paths) = std::env::var("GENFORM_GR8") else { return };
    for join in JoinTest::ALL {
        let settings = Settings { steps: 4, join, ..Settings::default() };
        let (mut faces, mut branches, mut joins, mut four, mut n) = (Vec::new(), 0, 0, 0, 0);
        for p in paths.split_whitespace() {
            let text = std::fs::read_to_string(p).unwrap();
            let h = genform_hemls::parse_str(p, &text).unwrap_or_else(|e| panic!("{}", e.short()));
            let g = genform_hemls::grow(&h, &settings, &Environment::default(), &mut Rng::from_seed(0)).unwrap();
            faces.push(g.map.face_count());
            four += usize::from(g.map.face_count() >= 4);
            n += 1;
            (branches, joins) = (branches + g.branches, joins + g.joins);
        }
        println!(
            "{:7} files {n} >=4 faces {four} branches joined {:.1}% faces {faces:?}",
            join.name(),
            200.0 * joins as f64 / branches.max(1) as f64
        );
    }
}
