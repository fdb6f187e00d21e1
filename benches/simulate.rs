//! Speed and memory of the dexel cutting simulation, and the same programs through the
//! `cutrail` crate (a mesh stock with robust booleans) for comparison.
//!
//! Programs: a 3-axis ball raster on a 51.2 × 51.2 mm block at pitch 0.1 (512 × 512 rays),
//! 0.5 mm moves, 1 mm step-over (5 000 moves); a 10 000-move 5-axis program on the same grid
//! (table A/C machine; the raster's tips with the tool axis swinging ±15° about X over 40
//! moves, joints from the inverse kinematics). Printed once before the
//! timings: ray-interval updates per second, rays visited, memory of a 1024 × 1024 stock.
#![allow(missing_docs)]

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec3;
use interpolab::geom::Cutter;
use interpolab::simulate::{DexelStock, MoveKind, Program, Simulation};
use sim_programs::{SIDE_MM, five_axis, raster_points, three_axis, tilt_rad};

/// The programs, shared with `benches/native_and_wasm/simulate.rs` (which runs them natively and in wasm).
#[path = "support/sim_programs.rs"]
mod sim_programs;
const PITCH_MM: f64 = 0.1;
const BALL_MM: f64 = 3.0;

fn stock() -> DexelStock {
    match DexelStock::block([0.0, 0.0, 0.0], [SIDE_MM, SIDE_MM, 20.0], PITCH_MM) {
        Ok(s) => s,
        Err(e) => panic!("stock: {e}"),
    }
}

fn ball() -> Cutter {
    match Cutter::ball(BALL_MM) {
        Ok(c) => c,
        Err(e) => panic!("cutter: {e}"),
    }
}

fn simulate(program: &Program) -> Simulation {
    simulate_checked(program, true)
}

/// With or without the crash checks (`simulate::crash`), to measure what they cost.
fn simulate_checked(program: &Program, checks: bool) -> Simulation {
    simulate_with(program, &ball(), checks)
}

/// `program` machined by `cutter` (a fillet end mill's 5-axis moves are sampled pose by
/// pose, each pose's corner solved ray by ray: `simulate::sweep`).
fn simulate_with(program: &Program, cutter: &Cutter, checks: bool) -> Simulation {
    let mut sim = Simulation::new(stock(), cutter);
    if !checks {
        sim = sim.without_crash_checks();
    }
    if let Err(e) = sim.run(program) {
        panic!("run: {e}");
    }
    sim
}

/// The program lowered by `dz_mm` (tips, or the joints' Z): 10 mm down, the ball's shank
/// (from 9 mm above the tip) reaches 6 mm into the 20 mm block on every move, so every move
/// checks it — the crash checks' worst case.
fn lowered(mut p: Program, dz_mm: f64) -> Program {
    for m in &mut p.moves {
        match &mut m.kind {
            MoveKind::Line { from, to } => {
                from.z -= dz_mm;
                to.z -= dz_mm;
            }
            MoveKind::Joints { from, to, .. } => {
                from.xyz_mm.z -= dz_mm;
                to.xyz_mm.z -= dz_mm;
            }
        }
    }
    p
}

/// CPU seconds of `f` on this thread (wall seconds where the CPU clock is not readable).
fn cpu_time(f: impl FnOnce()) -> f64 {
    let (t, cpu0) = (Instant::now(), thread_cpu_s());
    f();
    thread_cpu_s().zip(cpu0).map_or_else(|| t.elapsed().as_secs_f64(), |(b, a)| b - a)
}

/// A deep pocket as it is cut: the raster 5 mm down, then 10 mm down — the shank's face
/// (9 mm above the tip) below the block's top on the second pass, in stock the first pass
/// cleared: checked on every move, no crash.
fn stepped(n: usize) -> Program {
    let mut p = lowered(three_axis(n), 5.0);
    p.moves.extend(lowered(three_axis(n), 10.0).moves);
    p
}

/// What the crash checks cost, with and without them, best of three each (CPU time), and
/// the crashes they find: the deep pocket cut in steps (clean), and the programs 10 mm deeper
/// at once (the shank buried on every move: the checks' worst case).
fn report_crash_checks() {
    let cases = [
        ("3-axis 2 × 2 500 moves in two steps (clean)", stepped(2_500)),
        ("3-axis 5 000 moves 10 mm deeper (the shank buried on every move)", lowered(three_axis(5_000), 10.0)),
        ("5-axis 1 000 moves 10 mm deeper (the shank buried on every move)", lowered(five_axis(1_000), 10.0)),
    ];
    for (name, p) in cases {
        let best = |checks: bool| {
            (0..3).map(|_| cpu_time(|| drop(black_box(simulate_checked(&p, checks))))).fold(f64::INFINITY, f64::min)
        };
        let (with, without) = (best(true), best(false));
        let crashes = simulate_checked(&p, true).crashes().total();
        eprintln!(
            "crash checks, {name}: {:.3} s with, {:.3} s without (CPU): +{:.1} %, {crashes} crash reports",
            with,
            without,
            (with / without - 1.0) * 100.0
        );
    }
}

/// CPU time of this thread (s) from /proc/thread-self/schedstat (ns), `None` elsewhere: on
/// a shared machine the wall clock counts other processes' time slices too.
fn thread_cpu_s() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    text.split_whitespace().next()?.parse::<f64>().ok().map(|ns| ns * 1e-9)
}

fn report_once() {
    for (name, p) in [("3-axis 5 000 moves", three_axis(5_000)), ("5-axis 10 000 moves", five_axis(10_000))] {
        let t = Instant::now();
        let cpu0 = thread_cpu_s();
        let sim = simulate(&p);
        let s = t.elapsed().as_secs_f64();
        let cpu = thread_cpu_s().zip(cpu0).map_or(f64::NAN, |(b, a)| b - a);
        let c = sim.counters();
        eprintln!(
            "{name} on 512×512: wall {:.3} s, CPU {:.3} s, {} ray updates ({:.1} M/s wall, {:.1} M/s CPU), {} rays visited, {} samples, {:.1} µs/move (wall), removed {:.0} mm³",
            s,
            cpu,
            c.ray_updates,
            c.ray_updates as f64 / s / 1e6,
            c.ray_updates as f64 / cpu / 1e6,
            c.rays_visited,
            c.samples,
            s / p.moves.len() as f64 * 1e6,
            c.removed_mm3
        );
    }
    match DexelStock::block([0.0, 0.0, 0.0], [102.4, 102.4, 20.0], PITCH_MM) {
        Ok(big) => {
            let mut sim = Simulation::new(big, &ball());
            if let Err(e) = sim.run(&three_axis(5_000)) {
                panic!("{e}");
            }
            eprintln!(
                "1024×1024 stock after the 3-axis program: {} rays, {:.1} MiB",
                sim.stock().grid().len(),
                sim.stock().memory_bytes() as f64 / (1 << 20) as f64
            );
        }
        Err(e) => panic!("{e}"),
    }
}

/// The same raster (first `n` moves) through cutrail: a box stock, a ball end mill of the same
/// diameter, one linear segment per move; returns seconds per segment.
fn cutrail_per_segment(n: usize, tilted: bool) -> f64 {
    use cutrail::{Engine, EngineOptions, ManifoldKernel, MotionSegment, Pose, StockShape, Tool};
    let stock = StockShape::Box { min: [0.0, 0.0, 0.0], max: [SIDE_MM, SIDE_MM, 20.0] };
    let mut engine = match Engine::new(ManifoldKernel, &[stock], EngineOptions::default()) {
        Ok(e) => e,
        Err(e) => panic!("cutrail engine: {e}"),
    };
    let tool = Tool::ball_end_mill(2.0 * BALL_MM, 3.0 * BALL_MM);
    let pts = raster_points(n);
    let pose = |k: usize, p: DVec3| {
        if tilted {
            Pose::tilted_about_y([p.x, p.y, p.z], tilt_rad(k).to_degrees())
        } else {
            Pose::vertical([p.x, p.y, p.z])
        }
    };
    let t = Instant::now();
    for (k, w) in pts.windows(2).enumerate() {
        let seg = MotionSegment::linear(pose(k, w[0]), pose(k + 1, w[1]));
        if let Err(e) = engine.cut(&tool, &seg) {
            panic!("cutrail cut {k}: {e}");
        }
    }
    t.elapsed().as_secs_f64() / n as f64
}

fn benches(c: &mut Criterion) {
    report_once();
    report_crash_checks();
    let n_peer = 500;
    let ours3 = {
        let p = three_axis(n_peer);
        let t = Instant::now();
        black_box(simulate(&p));
        t.elapsed().as_secs_f64() / n_peer as f64
    };
    let ours5 = {
        let p = five_axis(n_peer);
        let t = Instant::now();
        black_box(simulate(&p));
        t.elapsed().as_secs_f64() / n_peer as f64
    };
    let peer3 = cutrail_per_segment(n_peer, false);
    let peer5 = cutrail_per_segment(n_peer, true);
    eprintln!(
        "first {n_peer} moves, per move: dexel 3-axis {:.1} µs vs cutrail {:.1} µs ({:.0}×); dexel 5-axis {:.1} µs vs cutrail {:.1} µs ({:.0}×)",
        ours3 * 1e6,
        peer3 * 1e6,
        peer3 / ours3,
        ours5 * 1e6,
        peer5 * 1e6,
        peer5 / ours5
    );

    let mut g = c.benchmark_group("simulate_512x512");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    let p3 = three_axis(5_000);
    g.bench_function("three_axis_5000_moves", |b| b.iter(|| black_box(simulate(&p3))));
    // The whole 10 000-move 5-axis program is timed once by `report_once` (tens of seconds);
    // criterion repeats its first 1 000 moves.
    let p5 = five_axis(1_000);
    g.bench_function("five_axis_1000_moves", |b| b.iter(|| black_box(simulate(&p5))));
    // The same moves with a fillet end mill (R 3, r 1 mm): poses one pitch apart.
    let fillet = match Cutter::fillet(BALL_MM, 1.0) {
        Ok(c) => c,
        Err(e) => panic!("cutter: {e}"),
    };
    g.bench_function("five_axis_1000_moves_fillet", |b| b.iter(|| black_box(simulate_with(&p5, &fillet, true))));
    // The crash checks' worst case: the shank in the stock on every move, with and without.
    let deep3 = lowered(three_axis(5_000), 10.0);
    g.bench_function("three_axis_5000_deep_checked", |b| b.iter(|| black_box(simulate_checked(&deep3, true))));
    g.bench_function("three_axis_5000_deep_unchecked", |b| b.iter(|| black_box(simulate_checked(&deep3, false))));
    g.finish();
}

criterion_group!(simulate_benches, benches);
criterion_main!(simulate_benches);
