//! Benchmarks that run from one source natively and compiled to wasm32 under Node, so the
//! two numbers compare like with like (criterion has no wasm32 runner; the criterion
//! benchmarks are the other files of `benches/`). A test target that `cargo test` does not
//! build (`test = false` in Cargo.toml): every function is `#[ignore]`d and prints what it
//! measures; nothing is asserted. `scripts/bench-wasm.sh` runs them both ways:
//!
//! ```text
//! cargo test --release --no-default-features --test native_and_wasm -- --ignored --nocapture
//! cargo test --release --no-default-features --target wasm32-unknown-unknown --test native_and_wasm -- --include-ignored --nocapture
//! ```

// `std::time::Instant` natively; `performance.now()` under Node (no std clock on wasm32).
#[path = "../support/web_time.rs"]
mod web_time_shim;

// The feed planner's program and machines, shared with the criterion benchmark `benches/plan.rs`.
#[path = "../support/plan_programs.rs"]
mod plan_programs;

// The simulation benchmarks' programs, shared with the criterion benchmark `benches/simulate.rs`.
#[path = "../support/sim_programs.rs"]
mod sim_programs;

// Seed 001: a whole example surface's iso-scallop paths.
mod fillet;
// A million-line program through the interpreter.
mod interp;
// Planning a 100 000-block G01 program (path, blends, feed, block times).
mod plan;
// A 10 000-period crease recompute (what a slider move costs).
mod recompute;
// Ray-interval updates per second of the cutting simulation, and its job as the worker runs it.
mod simulate;
