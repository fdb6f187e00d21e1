//! Benchmark, not a test (ignored by default): planning the 100 000-block G01 program of
//! `benches/plan.rs` (the same program and machines) — natively and compiled to wasm32 under
//! Node from the same source, so the two numbers compare like with like:
//!
//! ```text
//! cargo test --release --no-default-features --test native_and_wasm plan:: -- --ignored --nocapture
//! cargo test --release --no-default-features --target wasm32-unknown-unknown --test native_and_wasm plan:: -- --include-ignored --nocapture
//! ```
//! (`scripts/bench-wasm.sh` runs both.) Reports the median of five runs per machine.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::plan_programs::{machines, wavy_spiral};
use crate::web_time_shim::{Instant, print};
use interpolab::plan::time_program;

const BLOCKS: usize = 100_000;

#[test]
#[ignore = "benchmark; run with --ignored --nocapture"]
fn plan_100k_blocks() {
    let platform = if cfg!(target_arch = "wasm32") { "wasm32 (Node)" } else { "native" };
    let program = wavy_spiral(BLOCKS);
    for (name, m) in machines() {
        let mut ms = Vec::new();
        let mut total = 0.0;
        for _ in 0..5 {
            let t = Instant::now();
            let timing = time_program(program.iter().cloned(), &m).expect("plans");
            total = std::hint::black_box(timing.total_s());
            drop(timing);
            ms.push(t.elapsed().as_secs_f64() * 1000.0);
        }
        ms.sort_by(f64::total_cmp);
        print(&format!(
            "{platform}: plan {BLOCKS} G01 blocks, {name}: {:.0} ms (median of 5; min {:.0}), program {total:.3} s",
            ms[2], ms[0]
        ));
    }
}
