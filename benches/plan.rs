//! Speed of the feed planner on a 100 000-block program: a G01 polyline of 0.5 mm chords
//! along a wavy spiral in XY with Z rising (every chord a corner to blend), as canonical
//! motions in memory — the planning alone (path, blends, passes, profile), then the
//! per-period interpolation on the plan.
#![allow(missing_docs)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec3;
use interpolab::gcode::interp::{Canon, Feed, FeedMode, Loc, Origin, Pose};
use interpolab::plan::{Dynamics, Period, time_program};

/// `n` G01 blocks of about 0.5 mm along r = 40 + 5 sin(7θ) in XY, z rising 0.02 mm a turn.
#[must_use]
pub fn wavy_spiral(n: usize) -> Vec<Canon> {
    let feed = Feed { mode: FeedMode::PerMinute, rate: 3000.0, spindle_rpm: 10_000.0 };
    let mut out = Vec::with_capacity(n + 1);
    out.push(Canon::Traverse { loc: Loc::main(1), end: Pose::at(DVec3::new(40.0, 0.0, 0.0)), origin: Origin::Programmed });
    let mut th: f64 = 0.0;
    for k in 0..n {
        th += 0.5 / 40.0;
        let r = 40.0 + 5.0 * (7.0 * th).sin();
        let p = DVec3::new(r * th.cos(), r * th.sin(), 0.02 * th / std::f64::consts::TAU);
        out.push(Canon::Line { loc: Loc::main(k as u32 + 2), end: Pose::at(p), feed, origin: Origin::Programmed });
    }
    out
}

fn benches(c: &mut Criterion) {
    let program = wavy_spiral(100_000);
    let mut g = c.benchmark_group("plan_100k_blocks");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    for (name, m) in [
        ("vmc_jerk_limited", Dynamics::preset("vmc")),
        ("vmc_jerk_free", Dynamics::preset("vmc").map(Dynamics::without_jerk)),
        ("hobby_router_window_50", Dynamics::preset("hobby-router").map(|mut d| {
            d.window_blocks = Some(50);
            d
        })),
    ] {
        let Some(m) = m else { continue };
        g.bench_function(name, |b| {
            b.iter(|| {
                let t = time_program(black_box(program.iter().cloned()), &m);
                black_box(t.map(|t| t.total_s()).unwrap_or(0.0))
            });
        });
    }
    g.finish();
    let Some(m) = Dynamics::preset("vmc") else { return };
    let Ok(t) = time_program(program.iter().cloned(), &m) else { return };
    let mut g = c.benchmark_group("periods");
    g.sample_size(10).measurement_time(Duration::from_secs(4));
    g.bench_function("all_periods_100k_blocks", |b| {
        b.iter(|| {
            let mut s = t.sampler();
            let mut p = Period::default();
            let mut sum = 0.0;
            while s.next_period(&mut p) {
                sum += p.q[0];
            }
            black_box(sum)
        });
    });
    g.finish();
}

criterion_group!(plan_benches, benches);
criterion_main!(plan_benches);
