//! Speed of seed 004's layer on a few-hundred-mm path (the torus crease, 350 mm): fitting,
//! each program writer (including its read-back check), the whole comparison, real-time
//! interpolation and reading a program. What an app panel pays per tolerance-slider move.
#![allow(missing_docs)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use interpolab::crease::{CreaseCurve, CreaseJob};
use interpolab::gcode::{
    CompareOptions, DeviationOptions, ProgramKind, ProgramOptions, compare, crease_design, deviation, parse_program,
    write_program,
};
use interpolab::nurbs_path::{
    ApproxOptions, Parabola, RealtimeOptions, Update, approximate_curve, interpolate_realtime,
};
use interpolab::scene::Scene;

fn torus() -> CreaseCurve {
    let scene = match Scene::from_json(include_str!("../examples/torus-plane.json")) {
        Ok(s) => s,
        Err(e) => panic!("example scene: {e}"),
    };
    let job = match CreaseJob::from_scene(&scene) {
        Ok(j) => j,
        Err(e) => panic!("example job: {e}"),
    };
    match crease_design(&job) {
        Ok(c) => c,
        Err(e) => panic!("crease: {e}"),
    }
}

fn benches(c: &mut Criterion) {
    let design = torus();
    let tol = 0.01;
    let mut g = c.benchmark_group("nurbs_gcode_torus_350mm");
    g.sample_size(10).measurement_time(Duration::from_secs(4));
    g.bench_function("approximate_curve", |b| {
        b.iter(|| approximate_curve(black_box(&design), tol, &ApproxOptions::default().with_knot_quantum(Some(0.001))))
    });
    for kind in ProgramKind::ALL {
        g.bench_function(format!("write_program_{}", kind.as_str()), |b| {
            b.iter(|| write_program(kind, black_box(&design), tol, &ProgramOptions::default()))
        });
    }
    g.bench_function("compare", |b| b.iter(|| compare(black_box(&design), tol, &CompareOptions::default())));
    let fit = match approximate_curve(&design, tol, &ApproxOptions::default()) {
        Ok(f) => f.curve,
        Err(e) => panic!("fit: {e}"),
    };
    for update in Update::ALL {
        g.bench_function(format!("realtime_{}", update.as_str()), |b| {
            b.iter(|| {
                interpolate_realtime(
                    black_box(&fit),
                    &RealtimeOptions::default().with_update(update).with_samples(false),
                )
            })
        });
    }
    let program = match write_program(ProgramKind::Lines, &design, tol, &ProgramOptions::default()) {
        Ok(p) => p,
        Err(e) => panic!("program: {e}"),
    };
    g.bench_function("parse_g01_program", |b| b.iter(|| parse_program(black_box(&program.text))));
    g.bench_function("deviation_g01_program", |b| {
        b.iter(|| deviation(black_box(&program.parsed.toolpath), &design, &DeviationOptions::default()))
    });
    g.finish();
    let para = Parabola::paper_like();
    c.bench_function("compare_parabola", |b| b.iter(|| compare(black_box(&para), tol, &CompareOptions::default())));
}

criterion_group!(nurbs, benches);
criterion_main!(nurbs);
