//! The mapper's fast path allocates nothing once warmed up: mapping the
//! same population a second time, standard and Genr8 (with repair), makes
//! no heap allocation. Counted with a global allocator, so this test file
//! holds only this test; only the test's own thread is counted, because the
//! test harness's main thread may allocate while the test runs (CI saw 4).

use genform_core::{Rng, SourceFile};
use genform_ge::{MapOptions, Mapper};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

struct Counting;

thread_local! {
    // Const-initialised so that reading it never allocates.
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    // `try_with`: during thread teardown the slot may be gone already.
    let _ = ALLOCATIONS.try_with(|n| n.set(n.get() + 1));
}

fn allocations() -> usize {
    ALLOCATIONS.with(Cell::get)
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn load(name: &str) -> genform_ge::Bnf {
    let path = format!("{}/../../examples/ge/{name}.bnf", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).expect("grammar");
    genform_ge::compile(&SourceFile::new(name, text)).map(|(b, _)| b).expect("compiles")
}

#[test]
fn mapping_allocates_nothing_after_warm_up() {
    let mut rng = Rng::from_seed(9);
    let population: Vec<Vec<u32>> =
        (0..300).map(|_| (0..50 + rng.below(150)).map(|_| rng.below(1000) as u32).collect()).collect();
    for (name, options) in [("arith", MapOptions::standard(4, None)), ("genr8", MapOptions::genr8())] {
        let bnf = load(name);
        let mut mapper = Mapper::new(&bnf, options).expect("options");
        let mut valid = 0;
        for g in &population {
            valid += usize::from(mapper.map(g).valid());
        }
        assert!(valid > 200, "{name}: {valid} valid");
        let before = allocations();
        let mut codons = 0;
        for g in &population {
            codons += mapper.map(g).used_codons;
        }
        let allocated = allocations() - before;
        assert_eq!(allocated, 0, "{name}: {allocated} allocations while mapping {codons} codons");
    }
}
