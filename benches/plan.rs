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
use interpolab::gcode::{ProgramKind, ProgramOptions, write_program};
use interpolab::nurbs_path::{Parabola, RealtimeOptions, Update, interpolate_realtime};
use interpolab::plan::{Dynamics, Period, canon_of_toolpath, time_program};

/// `n` G01 blocks of about 0.5 mm along r = 40 + 5 sin(7θ) in XY, z rising 0.02 mm a turn.
#[must_use]
pub fn wavy_spiral(n: usize) -> Vec<Canon> {
    let feed = Feed { mode: FeedMode::PerMinute, rate: 3000.0, spindle_rpm: 10_000.0 };
    let mut out = Vec::with_capacity(n + 1);
    out.push(Canon::Traverse {
        loc: Loc::main(1),
        end: Pose::at(DVec3::new(40.0, 0.0, 0.0)),
        origin: Origin::Programmed,
    });
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
        (
            "hobby_router_window_50",
            Dynamics::preset("hobby-router").map(|mut d| {
                d.window_blocks = Some(50);
                d
            }),
        ),
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
    // Per period on a NURBS curve: the planned interpolator against today's real-time NURBS
    // interpolation (seed 004, corrected update) of the same curve at the same period.
    let design = Parabola::paper_like();
    if let Ok(p) = write_program(ProgramKind::Nurbs, &design, 0.01, &ProgramOptions::default().with_feed(1500.0)) {
        let canon = canon_of_toolpath(&p.parsed.toolpath);
        if let (Ok(t), Some(curve)) = (time_program(canon, &m), p.read_back_curves().next()) {
            let mut g = c.benchmark_group("per_period_nurbs_parabola");
            g.sample_size(10).measurement_time(Duration::from_secs(4));
            g.bench_function("planned_sampler_all_periods", |b| {
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
            let ro =
                RealtimeOptions::default().with_feed(1500.0, 1.0).with_update(Update::Corrected).with_samples(false);
            g.bench_function("realtime_nurbs_corrected_all_periods", |b| {
                b.iter(|| black_box(interpolate_realtime(curve, &ro).map(|r| r.stats.periods).unwrap_or(0)));
            });
            g.finish();
            eprintln!(
                "periods: planned {} (whole program, rapids included), real-time at F {} periods",
                t.sampler().periods(),
                interpolate_realtime(curve, &ro).map(|r| r.stats.periods).unwrap_or(0)
            );
        }
    }
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
