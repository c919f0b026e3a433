//! The crowd's worker threads allocate nothing per step: a global counting allocator sees
//! every thread's allocations. This file holds one test, so nothing else runs beside it.

mod support;

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicU64, Ordering};

use crowdgaze::scenario::Scenario;
use crowdgaze::{Crowd, CrowdConfig};

struct CountingAllocator;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

// SAFETY: forwards every call to the system allocator unchanged; only counts.
unsafe impl GlobalAlloc for CountingAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: same contract as the caller's.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: same contract as the caller's.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: same contract as the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: CountingAllocator = CountingAllocator;

#[test]
fn stepping_on_worker_threads_does_not_allocate() {
    let config = CrowdConfig {
        threads: 3,
        // Storage reordered in 12 of the measured steps.
        reorder_period: 8,
        ..CrowdConfig::default()
    };
    let mut crowd = Crowd::new(config).unwrap();
    let mut scenario = Scenario::street(600, 40, 3);
    scenario.populate(&mut crowd).unwrap();
    support::mix_attention_models(&mut crowd, scenario.character_ids());
    let mut frame = 0;
    let mut advance = |crowd: &mut Crowd, scenario: &mut Scenario| {
        frame += 1;
        scenario.advance(1.0 / 30.0);
        scenario.push(crowd, f64::from(frame) / 30.0).unwrap();
        crowd.step(1.0 / 30.0).unwrap();
    };
    for _ in 0..20 {
        advance(&mut crowd, &mut scenario);
    }
    let before = ALLOCATIONS.load(Ordering::Relaxed);
    for _ in 0..100 {
        advance(&mut crowd, &mut scenario);
    }
    let allocations = ALLOCATIONS.load(Ordering::Relaxed) - before;
    assert_eq!(
        allocations, 0,
        "100 pooled steps allocated {allocations} times"
    );
    assert!((0..crowd.character_count()).any(|c| crowd.gaze_at(c).attending));
}
