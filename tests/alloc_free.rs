//! A real controller's rule: no heap allocation in the per-period stepper. A counting global
//! allocator (over the system one) counts every allocation, reallocation and free made by
//! this thread while [`Interpolator::step`] runs, for both methods on every example scene,
//! from the first period after start to the stop (or `PERIODS` periods).
//!
//! This is the only file of the package with `unsafe` code: a `GlobalAlloc` impl must be
//! `unsafe`. The package lint is `deny(unsafe_code)` so that this file can allow it; the
//! library and the binary forbid it at their crate roots (`#![forbid(unsafe_code)]`).
#![allow(unsafe_code)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

use interpolab::crease::{CreaseJob, InterpOptions, Interpolator, Method, Step};
use interpolab::scene::{PRESETS, Scene};

/// Periods run per scene and method (each example stops well before, or runs this far).
const PERIODS: u64 = 5_000;

thread_local! {
    /// Heap operations (alloc, realloc, dealloc) of this thread while counting is on.
    static OPS: Cell<u64> = const { Cell::new(0) };
    static COUNTING: Cell<bool> = const { Cell::new(false) };
}

struct Counting;

fn note() {
    // `try_with`: the allocator also runs while thread-locals are torn down.
    let _ = COUNTING.try_with(|on| {
        if on.get() {
            let _ = OPS.try_with(|n| n.set(n.get() + 1));
        }
    });
}

// SAFETY: every call is forwarded unchanged to `System`, which upholds the contract; the
// counting touches only const-initialised thread-locals without destructors (no allocation).
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note();
        // SAFETY: same layout, same contract as the caller's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note();
        // SAFETY: as above.
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note();
        // SAFETY: `ptr` was allocated by `System` (through this wrapper) with `layout`.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        note();
        // SAFETY: `ptr` was allocated by `System` (through this wrapper) with `layout`.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOC: Counting = Counting;

/// Heap operations made by this thread while `f` runs, and its result.
fn heap_ops<T>(f: impl FnOnce() -> T) -> (u64, T) {
    OPS.with(|n| n.set(0));
    COUNTING.with(|c| c.set(true));
    let out = f();
    COUNTING.with(|c| c.set(false));
    (OPS.with(Cell::get), out)
}

#[test]
fn the_counter_sees_an_allocation_and_a_free() {
    let (ops, v) = heap_ops(|| std::hint::black_box(Vec::<u64>::with_capacity(3)));
    assert_eq!(ops, 1, "one allocation");
    let (ops, ()) = heap_ops(|| drop(v));
    assert_eq!(ops, 1, "one free");
    let (ops, s) = heap_ops(|| std::hint::black_box(format!("{}", 1.5f64)));
    assert!(ops >= 1, "formatting into a String allocates");
    assert_eq!(s, "1.5");
}

#[test]
fn no_heap_allocation_per_period_in_either_stepper() {
    for preset in PRESETS {
        let scene = Scene::from_json(preset.json).expect("example parses");
        let job = CreaseJob::from_scene(&scene).expect("example builds");
        for method in [Method::Seed000, Method::Exact] {
            let mut it = Interpolator::new(job.clone(), InterpOptions { method, ..InterpOptions::default() })
                .expect("example starts");
            let mut rows = 0u64;
            let mut total_ops = 0u64;
            let mut stopped = false;
            for _ in 0..PERIODS {
                let (ops, step) = heap_ops(|| it.step());
                total_ops += ops;
                assert_eq!(ops, 0, "{} {method:?}: period {} made {ops} heap operations", preset.id, rows + 1);
                match step {
                    Ok(Step::Row(_)) => rows += 1,
                    Ok(Step::Stopped(_)) => {
                        stopped = true;
                        break;
                    }
                    Err(e) => panic!("{} {method:?}: the example fails at period {}: {e}", preset.id, rows + 1),
                }
            }
            assert!(rows > 100, "{} {method:?}: only {rows} periods ran", preset.id);
            println!("{} {method:?}: {rows} periods, stopped: {stopped}, no heap operation", preset.id);
            assert_eq!(total_ops, 0);
            // The stop is final and free as well.
            if stopped {
                let (ops, step) = heap_ops(|| it.step());
                assert!(matches!(step, Ok(Step::Stopped(_))));
                assert_eq!(ops, 0, "{} {method:?}: the repeated stop allocates", preset.id);
            }
        }
    }
}

/// The planned interpolator (`plan::Sampler`) allocates nothing per period either: on the
/// parabola's G01 (lines and blends), G02/G03 and G06.2 programs, jerk-limited and not.
#[test]
fn no_heap_allocation_per_period_in_the_planned_interpolator() {
    use interpolab::gcode::{ProgramKind, ProgramOptions, write_program};
    use interpolab::nurbs_path::Parabola;
    use interpolab::plan::{Dynamics, Period, canon_of_toolpath, time_program};
    for kind in ProgramKind::ALL {
        let p = write_program(kind, &Parabola::paper_like(), 0.01, &ProgramOptions::default().with_feed(1500.0))
            .expect("program");
        for m in [Dynamics::preset("vmc").expect("preset"), Dynamics::preset("vmc").expect("preset").without_jerk()] {
            let t = time_program(canon_of_toolpath(&p.parsed.toolpath), &m).expect("plans");
            let mut s = t.sampler();
            let mut per = Period::default();
            let (ops, periods) = heap_ops(|| {
                let mut n = 0u64;
                while s.next_period(&mut per) {
                    n += 1;
                }
                n
            });
            assert!(periods > 1000);
            assert_eq!(ops, 0, "{kind:?}: {ops} heap operations over {periods} periods");
        }
    }
}
