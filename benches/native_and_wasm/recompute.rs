//! Benchmark, not a test (ignored by default): the time to recompute a 10 000-period crease
//! path, the app's work when a slider moves. The same source runs natively and compiled to
//! wasm32 under Node, so the two numbers compare like with like:
//!
//! ```text
//! cargo test --release --no-default-features --test native_and_wasm recompute:: -- --ignored --nocapture
//! cargo test --release --no-default-features --target wasm32-unknown-unknown --test native_and_wasm recompute:: -- --include-ignored --nocapture
//! ```
//! (`scripts/bench-wasm.sh` runs both.) Reports the median of several runs.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::web_time_shim::{Instant, print};
use interpolab::crease::{CreaseJob, InterpOptions, Interpolator, Step, diagnose};
use interpolab::scene::Scene;

const PERIODS: u64 = 10_000;

/// Runs `PERIODS` periods of a closed crease (turning as often as needed); with `measure`
/// also the per-period error measurement the app does.
fn recompute(job: &CreaseJob, measure: bool) -> f64 {
    let t = Instant::now();
    let mut it =
        Interpolator::new(job.clone(), InterpOptions { turns: u32::MAX, ..InterpOptions::default() }).expect("starts");
    let mut n = 0;
    while n < PERIODS {
        match it.step().expect("continues") {
            Step::Row(r) => {
                if measure {
                    std::hint::black_box(diagnose(job, &r));
                }
                n += 1;
            }
            Step::Stopped(reason) => panic!("stopped early: {reason}"),
        }
    }
    t.elapsed().as_secs_f64() * 1000.0
}

#[test]
#[ignore = "benchmark; run with --ignored --nocapture"]
fn recompute_10k_periods() {
    let platform = if cfg!(target_arch = "wasm32") { "wasm32 (Node)" } else { "native" };
    for (name, json) in [
        ("torus-plane", include_str!("../../examples/torus-plane.json")),
        ("crossing-cylinders", include_str!("../../examples/crossing-cylinders.json")),
    ] {
        let mut scene = Scene::from_json(json).expect("example");
        scene.path.max_steps = PERIODS + 1;
        let job = CreaseJob::from_scene(&scene).expect("builds");
        for measure in [false, true] {
            // Warm up (the wasm engine optimises hot code after a while), then take the median.
            for _ in 0..3 {
                recompute(&job, measure);
            }
            let mut ms: Vec<f64> = (0..9).map(|_| recompute(&job, measure)).collect();
            ms.sort_by(f64::total_cmp);
            print(&format!(
                "{platform}: {name}, {PERIODS} periods{}: median {:.2} ms ({:.3} µs/period), min {:.2} ms",
                if measure { " with error measurement" } else { "" },
                ms[4],
                ms[4] * 1000.0 / PERIODS as f64,
                ms[0]
            ));
        }
    }
}
