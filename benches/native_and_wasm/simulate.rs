//! Benchmark, not a test (ignored by default): ray-interval updates per second of the dexel
//! simulation on the programs of `benches/simulate.rs` (a 5 000-move 3-axis ball raster and
//! the 10 000-move 5-axis program, 512 × 512 rays at pitch 0.1), from the same source
//! natively and compiled to wasm32 under Node, so the two compare like with like:
//!
//! ```text
//! cargo test --release --no-default-features --test native_and_wasm simulate:: -- --ignored --nocapture
//! cargo test --release --no-default-features --target wasm32-unknown-unknown --test native_and_wasm simulate:: -- --include-ignored --nocapture
//! ```
//! (`scripts/bench-wasm.sh` runs both.) Wall clock (Node has no thread CPU clock), the best
//! of three runs, so other processes' time slices count as little as possible.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::sim_programs::{SIDE_MM, five_axis, three_axis};
use crate::web_time_shim::{Instant, print};
use interpolab::geom::Cutter;
use interpolab::simulate::{DexelStock, Simulation};

#[test]
#[ignore = "benchmark; run with --ignored --nocapture"]
fn ray_updates_per_second() {
    let platform = if cfg!(target_arch = "wasm32") { "wasm32 (Node)" } else { "native" };
    for (name, program) in [("3-axis 5 000 moves", three_axis(5_000)), ("5-axis 10 000 moves", five_axis(10_000))] {
        let mut best = f64::INFINITY;
        let mut updates = 0;
        for _ in 0..3 {
            let stock = DexelStock::block([0.0, 0.0, 0.0], [SIDE_MM, SIDE_MM, 20.0], 0.1).expect("stock");
            let mut sim = Simulation::new(stock, &Cutter::ball(3.0).expect("cutter"));
            let t = Instant::now();
            sim.run(&program).expect("runs");
            best = best.min(t.elapsed().as_secs_f64());
            updates = sim.counters().ray_updates;
        }
        print(&format!(
            "{platform}: {name} on 512×512: {:.3} s, {updates} ray updates, {:.1} M updates/s",
            best,
            updates as f64 / best / 1e6
        ));
    }
}

/// The simulation tab's whole job as its Web Worker runs it (`jobs::run_encoded` on the
/// benchmark request of `e2e/sim-bench.mjs`: the program built, machined with its keyframes
/// and kept stocks, measured, the output written as text), the first run in a fresh process
/// (as a fresh worker runs it: the wasm's code not yet optimised by the engine) and a second
/// one, then a replay to move 8 100 from the kept stocks.
#[test]
#[ignore = "benchmark; run with --ignored --nocapture"]
fn the_simulation_job_as_the_worker_runs_it() {
    use interpolab::jobs::simulate_run::SimulateRun;
    use interpolab::jobs::simulate_run::request::{ProgramSource, Request};
    use interpolab::jobs::{JobKind, NoProgress, run_encoded};
    use interpolab::simulate::bench::BenchKind;
    let platform = if cfg!(target_arch = "wasm32") { "wasm32 (Node)" } else { "native" };
    let req = Request { keyframes: 40, ..Request::benchmark(BenchKind::FiveAxis, 10_000, 0.1).expect("cutter") };
    let text = SimulateRun::encode_request(&req);
    for run in ["first", "second"] {
        let t = Instant::now();
        let out = run_encoded(SimulateRun::NAME, &text, &mut NoProgress).expect("runs");
        print(&format!(
            "{platform}: the simulation job, {run} run: {:.3} s ({} bytes of output)",
            t.elapsed().as_secs_f64(),
            out.len()
        ));
    }
    let program = BenchKind::FiveAxis.program(10_000).expect("program");
    let replay =
        Request { source: ProgramSource::Moves(program), target: Some(8_100), keyframes: 8, resume: true, ..req };
    let t = Instant::now();
    let replay_text = SimulateRun::encode_request(&replay);
    let encoded = t.elapsed().as_secs_f64();
    run_encoded(SimulateRun::NAME, &replay_text, &mut NoProgress).expect("runs");
    print(&format!(
        "{platform}: a replay to move 8 100 from the kept stocks: {:.3} s (its request written in {:.3} s, {} bytes)",
        t.elapsed().as_secs_f64(),
        encoded,
        replay_text.len()
    ));
}
