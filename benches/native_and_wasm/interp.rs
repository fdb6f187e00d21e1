//! Benchmark, not a test (ignored by default): reading a 1 000 000-line program through the
//! interpreter into canonical calls, and into the path the simulation takes — natively and
//! compiled to wasm32 under Node from the same source (what the browser's worker pays):
//!
//! ```text
//! cargo test --release --no-default-features --test native_and_wasm interp:: -- --ignored --nocapture
//! cargo test --release --no-default-features --target wasm32-unknown-unknown --test native_and_wasm interp:: -- --include-ignored --nocapture
//! ```
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use std::fmt::Write as _;

use crate::web_time_shim::{Instant, print};
use interpolab::gcode::interp::{Interpreter, Options};
use interpolab::gcode::{Dialect, read_program};

const LINES: usize = 1_000_000;

/// A zig-zag raster of G1 lines with 3-decimal numbers, as a CAM post writes them.
fn raster() -> String {
    let mut s = String::with_capacity(LINES * 30);
    s.push_str("G21 G90 G17\nG0 X0 Y0 Z5\nG1 Z-1 F800\n");
    for i in 0..LINES {
        let x = (i % 200) as f64 * 0.5;
        let y = (i / 200) as f64 * 0.25;
        let _ = writeln!(s, "G1 X{x:.3} Y{y:.3} Z{:.3}", -1.0 - 0.001 * (i % 7) as f64);
    }
    s.push_str("M30\n");
    s
}

#[test]
#[ignore = "benchmark; run with --ignored --nocapture"]
fn read_a_million_lines() {
    let platform = if cfg!(target_arch = "wasm32") { "wasm32 (Node)" } else { "native" };
    let text = raster();
    let mut canon = Vec::new();
    let mut path = Vec::new();
    for _ in 0..3 {
        let t = Instant::now();
        let n = Interpreter::from_text(&text, Options::default()).count();
        canon.push(t.elapsed().as_secs_f64());
        assert!(n > LINES, "{n} calls");
        let t = Instant::now();
        let p = read_program(&text, Dialect::LinuxCnc, &Options::default()).expect("reads");
        path.push(t.elapsed().as_secs_f64());
        assert!(p.toolpath.blocks.len() >= LINES);
    }
    canon.sort_by(f64::total_cmp);
    path.sort_by(f64::total_cmp);
    print(&format!(
        "{platform}: {LINES} G1 lines: canonical calls {:.2} s (median of 3), into the path {:.2} s",
        canon[1], path[1]
    ));
}
