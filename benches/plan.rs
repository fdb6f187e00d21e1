//! Speed of the feed planner on a 100 000-block program: a G01 polyline of 0.5 mm chords
//! along a wavy spiral in XY with Z rising (every chord a corner to blend), as canonical
//! motions in memory — the planning alone (path, blends, passes, profile), then the
//! per-period interpolation on the plan.
#![allow(missing_docs)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use interpolab::gcode::{ProgramKind, ProgramOptions, write_program};
use interpolab::nurbs_path::{Parabola, RealtimeOptions, Update, interpolate_realtime};
use interpolab::plan::{Dynamics, Period, canon_of_toolpath, time_program};
use plan_programs::wavy_spiral;

/// The program and machines, shared with `benches/native_and_wasm/plan.rs` (natively and in wasm).
#[path = "support/plan_programs.rs"]
mod plan_programs;

fn benches(c: &mut Criterion) {
    let program = wavy_spiral(100_000);
    let mut g = c.benchmark_group("plan_100k_blocks");
    g.sample_size(10).measurement_time(Duration::from_secs(8));
    for (name, m) in plan_programs::machines() {
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
