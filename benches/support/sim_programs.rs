//! The simulation benchmarks' programs, shared by `benches/simulate.rs` (criterion, native)
//! and `benches/native_and_wasm/simulate.rs` (the same source natively and as wasm32 under Node), so both
//! time the same moves. They live in the core (`interpolab::simulate::bench`), where the
//! command line (`--benchmark`) and the app's worker build the same ones; this file only
//! gives the benchmarks their old names.
#![allow(dead_code, unused_imports)]

use interpolab::simulate::Program;
pub use interpolab::simulate::bench::{SIDE_MM, axis, machine, raster_points, tilt_rad};

/// `n` straight 3-axis moves along the raster.
pub fn three_axis(n: usize) -> Program {
    interpolab::simulate::bench::three_axis(n).expect("a benchmark of at most a million moves")
}

/// `n` 5-axis moves (see `interpolab::simulate::bench::five_axis`).
pub fn five_axis(n: usize) -> Program {
    interpolab::simulate::bench::five_axis(n).expect("joints for every block of the benchmark")
}
