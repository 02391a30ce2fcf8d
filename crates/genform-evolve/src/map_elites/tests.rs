use super::*;
use crate::config::GaConfig;
use crate::fixtures::{ShipToy, ship, ship_ids};

/// [`ShipToy`] with descriptors: genome length and the number of wings.
struct Described(ShipToy);

impl Objective for Described {
    type Scratch = ();

    fn scratch(&self) {}

    fn evaluate(&self, genome: &Genome, _: &mut ()) -> f64 {
        self.0.evaluate(genome, &mut ())
    }

    fn evaluate_described(&self, genome: &Genome, _: &mut (), d: &mut [f64; 2]) -> f64 {
        let wings = genome.iter().filter(|g| g.symbol() == ship_ids::WING).count();
        *d = [genome.len() as f64, wings as f64];
        self.0.evaluate(genome, &mut ())
    }
}

fn variation() -> GaConfig {
    GaConfig { initial_length: [3, 30], max_length: 40, ..GaConfig::default() }
}

fn config() -> MapElitesConfig {
    MapElitesConfig {
        initial: 30,
        batch: 24,
        descriptors: [DescriptorAxis::new("length", 8, [0.0, 40.0]), DescriptorAxis::new("wings", 6, [0.0, 12.0])],
        ..MapElitesConfig::default()
    }
}

fn run(threads: usize, generations: usize) -> MapElites {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().unwrap();
    let mut me = MapElites::new(&ship(), &Limits::default(), &variation(), config(), 5).unwrap();
    let objective = Described(ShipToy { target: 15 });
    pool.install(|| {
        for _ in 0..=generations {
            me.step(&objective);
        }
    });
    me
}

#[test]
fn fills_cells_and_files_each_elite_under_its_descriptors() {
    let me = run(2, 0);
    let after_init = me.filled();
    assert!(after_init > 3, "30 random genomes of 3..30 genes spread over several cells, got {after_init}");
    let me = run(2, 20);
    assert!(me.filled() > after_init, "variation reaches new cells: {} → {}", after_init, me.filled());
    assert_eq!(me.capacity(), 48);
    assert_eq!(me.population().len(), me.filled());
    assert!(me.population().windows(2).all(|w| w[0].fitness >= w[1].fitness), "best first");
    assert_eq!(me.best(), me.population().first());
    let mut cells: Vec<[usize; 2]> = Vec::new();
    for e in me.elites() {
        let wings = e.individual.genome.iter().filter(|g| g.symbol() == ship_ids::WING).count();
        assert_eq!(e.descriptors, [e.individual.genome.len() as f64, wings as f64]);
        assert_eq!(e.cell, me.config().cell(e.descriptors));
        assert!(!cells.contains(&e.cell), "one elite per cell");
        cells.push(e.cell);
    }
    // Every child slot found a child within the length bounds here, so
    // each was evaluated once.
    assert_eq!(me.evaluations(), 30 + 20 * 24);
}

#[test]
fn elites_are_only_replaced_by_better_ones() {
    let pool = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let mut me = MapElites::new(&ship(), &Limits::default(), &variation(), config(), 9).unwrap();
    let objective = Described(ShipToy { target: 15 });
    let mut before: Vec<Option<f64>> = vec![None; me.capacity()];
    let rows = me.config().descriptors[1].bins;
    pool.install(|| {
        for _ in 0..15 {
            me.step(&objective);
            let mut now = vec![None; me.capacity()];
            for e in me.elites() {
                now[e.cell[0] * rows + e.cell[1]] = Some(e.individual.fitness);
            }
            for (b, n) in before.iter().zip(&now) {
                if let Some(b) = b {
                    let n = n.expect("a filled cell stays filled");
                    assert!(n >= *b, "elite fitness fell from {b} to {n}");
                }
            }
            before = now;
        }
    });
}

#[test]
fn insertion_keeps_the_incumbent_on_ties_and_drops_invalid_children() {
    let mut me = MapElites::new(&ship(), &Limits::default(), &variation(), config(), 1).unwrap();
    let genome =
        |n: usize| crate::operators::initial(&ship(), &Limits::default(), [n, n], &mut Rng::from_seed(n as u64));
    let (a, b) = (genome(5), genome(6));
    me.insert(Candidate { genome: a.clone(), fitness: 1.0, descriptors: [5.0, 0.0] });
    me.insert(Candidate { genome: b.clone(), fitness: 1.0, descriptors: [6.0, 0.0] });
    assert_eq!(me.elites().next().unwrap().individual.genome, a, "a tie keeps the incumbent");
    me.insert(Candidate { genome: b.clone(), fitness: f64::INFINITY, descriptors: [5.0, 0.0] });
    me.insert(Candidate { genome: b.clone(), fitness: f64::NAN, descriptors: [-9.0, 99.0] });
    assert_eq!(me.filled(), 1, "invalid children never enter");
    me.insert(Candidate { genome: b.clone(), fitness: 2.0, descriptors: [f64::NAN, 1e9] });
    let cells: Vec<[usize; 2]> = me.elites().map(|e| e.cell).collect();
    // Lengths 5 and 6 share bin 1 (bins 5 genes wide); NaN goes to the
    // first bin, beyond the range to the last; elites list in cell order.
    assert_eq!(cells, [[0, 5], [1, 0]]);
}

#[test]
fn same_seed_same_archive_at_any_thread_count() {
    let (a, b) = (run(1, 12), run(3, 12));
    assert_eq!(a.population(), b.population());
    let cells = |m: &MapElites| m.elites().cloned().collect::<Vec<Elite>>();
    assert_eq!(cells(&a), cells(&b));
    assert_eq!(a.evaluations(), b.evaluations());
}

#[test]
fn an_objective_without_descriptors_fills_one_cell() {
    let mut me = MapElites::new(&ship(), &Limits::default(), &variation(), config(), 2).unwrap();
    for _ in 0..4 {
        me.step(&ShipToy { target: 15 });
    }
    assert_eq!(me.filled(), 1);
    assert!(me.best().is_some());
}

#[test]
fn bins_split_the_range_evenly_and_clamp() {
    let axis = DescriptorAxis::new("x", 4, [0.0, 8.0]);
    let bins: Vec<usize> = [-1.0, 0.0, 1.99, 2.0, 7.99, 8.0, 100.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY]
        .into_iter()
        .map(|v| axis.bin(v))
        .collect();
    assert_eq!(bins, [0, 0, 0, 1, 3, 3, 3, 0, 3, 0]);
}

fn parse(text: &str) -> Result<MapElitesConfig, String> {
    toml::from_str::<MapElitesConfig>(text).map_err(|e| e.to_string())
}

#[test]
fn settings_parse_with_defaults() {
    assert_eq!(parse("").unwrap(), MapElitesConfig::default());
    let c =
        parse("batch = 50\ndescriptors = [{ name = \"height\", bins = 5, range = [0, 4] }, { name = \"primitives\" }]")
            .unwrap();
    assert_eq!((c.batch, c.initial), (50, 150));
    assert_eq!(c.descriptors[0], DescriptorAxis::new("height", 5, [0.0, 4.0]));
    assert_eq!((c.descriptors[1].bins, c.descriptors[1].range), (8, None));
    c.validate().unwrap();
    assert!(c.validate_ranges().unwrap_err().to_string().contains("descriptors.range"));
}

#[test]
fn bad_settings_are_reported_at_their_line_and_column() {
    let cases = [
        ("batch = 0", "the number of individuals must be in [1, 1000000], got 0", (1, 9)),
        ("initial = 2000000", "in [1, 1000000], got 2000000", (1, 11)),
        ("crossover = 1.5", "a probability must be in [0, 1], got 1.5", (1, 13)),
        ("\nselection = { tournament = 0 }", "selection must be \"random\"", (2, 13)),
        (
            "descriptors = [{ name = \"length\" },\n  { name = \"aspect\", bins = 0 }]",
            "bins must be in [1, 256], got 0",
            (2, 29),
        ),
        (
            "descriptors = [{ name = \"length\", range = [5, 5] }, { name = \"aspect\" }]",
            "range must be [low, high] with finite low < high, got [5.0, 5.0]",
            (1, 43),
        ),
        ("descriptors = [{ name = \"length\" }]", "expected an array of length 2", (1, 15)),
        ("descriptors = [{ nme = \"length\" }, { name = \"aspect\" }]", "unknown field `nme`", (1, 18)),
    ];
    for (text, message, (line, col)) in cases {
        let e = toml::from_str::<MapElitesConfig>(text).unwrap_err();
        assert!(e.message().contains(message), "{text}: {}", e.message());
        let at = e.span().expect("a position").start;
        let got_line = text[..at].matches('\n').count() + 1;
        let got_col = at - text[..at].rfind('\n').map_or(0, |i| i + 1) + 1;
        assert_eq!((got_line, got_col), (line, col), "{text}");
    }
}

#[test]
fn validation_checks_settings_built_in_code() {
    let bad = |c: MapElitesConfig| c.validate().unwrap_err().to_string();
    assert!(bad(MapElitesConfig { batch: 0, ..config() }).contains("batch"));
    assert!(bad(MapElitesConfig { crossover: -0.1, ..config() }).contains("crossover"));
    let mut c = config();
    c.descriptors[1].bins = 300;
    assert!(bad(c).contains("descriptors.bins must be in [1, 256], got 300"));
    let mut c = config();
    c.descriptors[0].range = Some([1.0, f64::NAN]);
    assert!(bad(c).contains("descriptors.range"));
    let e = MapElites::new(&ship(), &Limits::default(), &GaConfig { population: 1, ..variation() }, config(), 0);
    assert!(e.is_err(), "the GA settings it borrows are checked too");
}
