//! Benchmark, not a test (ignored by default): ray-interval updates per second of the dexel
//! simulation on the programs of `benches/simulate.rs` (a 5 000-move 3-axis ball raster and
//! the 10 000-move 5-axis program, 512 × 512 rays at pitch 0.1), from the same source
//! natively and compiled to wasm32 under Node, so the two compare like with like:
//!
//! ```text
//! cargo test --release --no-default-features --test bench_simulate -- --ignored --nocapture
//! cargo test --release --no-default-features --target wasm32-unknown-unknown --test bench_simulate -- --include-ignored --nocapture
//! ```
//! (`scripts/bench-wasm.sh` runs both.) Wall clock (Node has no thread CPU clock), the best
//! of three runs, so other processes' time slices count as little as possible.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use interpolab::fiveaxis::{Joints, Machine};
use interpolab::geom::Cutter;
use interpolab::simulate::{DexelStock, MoveKind, Program, SimMove, Simulation};
use web_time_shim::Instant;

/// `std::time::Instant` natively; `performance.now()` under Node (the shared clock of the
/// benchmarks that run both ways).
#[path = "common/web_time.rs"]
mod web_time_shim;

fn print(line: &str) {
    #[cfg(target_arch = "wasm32")]
    wasm_bindgen_test::console_log!("{line}");
    #[cfg(not(target_arch = "wasm32"))]
    println!("{line}");
}

const SIDE_MM: f64 = 51.2;

/// The zigzag raster of `benches/simulate.rs`: tips at z = 17, rows 1 mm apart, 0.5 mm moves.
fn raster_points(n_moves: usize) -> Vec<DVec3> {
    let mut pts = vec![DVec3::new(0.0, 0.0, 17.0)];
    let mut row = 0;
    while pts.len() <= n_moves {
        let y = f64::from(row) % SIDE_MM;
        for k in 1..=100 {
            let x = if row % 2 == 0 { 0.5 * f64::from(k) } else { SIDE_MM - 0.5 * f64::from(k) };
            pts.push(DVec3::new(x.clamp(0.0, SIDE_MM), y, 17.0));
        }
        row += 1;
        pts.push(DVec3::new(pts[pts.len() - 1].x, f64::from(row) % SIDE_MM, 17.0));
    }
    pts.truncate(n_moves + 1);
    pts
}

fn three_axis(n: usize) -> Program {
    let moves = raster_points(n)
        .windows(2)
        .map(|w| SimMove { kind: MoveKind::Line { from: w[0], to: w[1] }, line: 0, rapid: false })
        .collect();
    Program { moves, chord_error_mm: 0.0 }
}

/// The raster's tips with the axis swinging ±15° about X over 40 moves, joints by the table
/// A/C machine's inverse kinematics.
fn five_axis(n: usize) -> Program {
    let m = Machine { limits_rad: [None, None], ..Machine::default() };
    let mut joints: Vec<Joints> = Vec::with_capacity(n + 1);
    for (k, p) in raster_points(n).iter().enumerate() {
        let tilt = 15f64.to_radians() * (std::f64::consts::TAU * k as f64 / 40.0).sin();
        let axis = DVec3::new(0.0, -tilt.sin(), tilt.cos());
        joints.push(m.joints_from_pose(*p, axis, joints.last()).expect("inverse kinematics"));
    }
    let moves = joints
        .windows(2)
        .map(|w| SimMove { kind: MoveKind::Joints { machine: m, from: w[0], to: w[1] }, line: 0, rapid: false })
        .collect();
    Program { moves, chord_error_mm: 0.0 }
}

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
