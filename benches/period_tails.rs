//! The worst period, not just the typical one: every period of a million is timed on its own
//! (`std::time::Instant` around one [`Interpolator::step`]) and the median, p99, p99.9 and
//! maximum are printed per example scene and method. Criterion reports means and their
//! confidence, which hide the tail a real-time controller must budget for.
//!
//! `cargo bench --no-default-features --bench period_tails` (the number of periods can be set
//! with `INTERPOLAB_TAIL_PERIODS`, default 1 000 000). An example stops after 800–3 500
//! periods; it is then restarted from a clone made before the start (the restart is not
//! timed). The times include one clock read (its cost is printed as "clock").

use std::hint::black_box;
use std::time::Instant;

use interpolab::crease::{CreaseJob, InterpOptions, Interpolator, Method, Step};
use interpolab::scene::{PRESETS, Scene};

/// Sorted nanoseconds → (median, p99, p99.9, max).
fn tails(ns: &mut [u32]) -> [u32; 4] {
    ns.sort_unstable();
    let at = |q: f64| ns[((ns.len() - 1) as f64 * q).round() as usize];
    [at(0.5), at(0.99), at(0.999), ns[ns.len() - 1]]
}

fn main() {
    let periods: usize =
        std::env::var("INTERPOLAB_TAIL_PERIODS").ok().and_then(|s| s.parse().ok()).unwrap_or(1_000_000).max(1);
    // Touched up front so that no page fault lands inside a timed period.
    let mut ns = vec![0u32; periods];

    let mut clock = ns.clone();
    for slot in &mut clock {
        let t0 = Instant::now();
        *slot = t0.elapsed().as_nanos().min(u128::from(u32::MAX)) as u32;
    }
    let [m, p99, p999, max] = tails(&mut clock);
    println!("{periods} periods per row; times in ns per period (one clock read included)");
    println!("{:<22} {:<8} {:>7} {:>7} {:>7} {:>9}", "scene", "method", "median", "p99", "p99.9", "max");
    println!("{:<22} {:<8} {m:>7} {p99:>7} {p999:>7} {max:>9}", "(clock alone)", "");

    for preset in PRESETS {
        let scene = Scene::from_json(preset.json).expect("example parses");
        let job = CreaseJob::from_scene(&scene).expect("example builds");
        for (label, method) in [("seed000", Method::Seed000), ("exact", Method::Exact)] {
            let fresh = Interpolator::new(job.clone(), InterpOptions { method, ..InterpOptions::default() })
                .expect("example starts");
            let mut it = fresh.clone();
            let mut n = 0;
            while n < periods {
                let t0 = Instant::now();
                let step = it.step();
                let dt = t0.elapsed();
                match step {
                    Ok(Step::Row(r)) => {
                        black_box(r);
                        ns[n] = dt.as_nanos().min(u128::from(u32::MAX)) as u32;
                        n += 1;
                    }
                    Ok(Step::Stopped(_)) => it = fresh.clone(),
                    Err(e) => panic!("{}: {e}", preset.id),
                }
            }
            let [m, p99, p999, max] = tails(&mut ns);
            println!("{:<22} {label:<8} {m:>7} {p99:>7} {p999:>7} {max:>9}", preset.id);
        }
    }
}
