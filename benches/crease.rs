//! Nanoseconds per interpolation period for every example scene: the seed-000 stepper and the
//! exact (Newton) stepper on the same path. Each iteration runs `PERIODS` periods from the
//! start (the setup — placing the start on the crease — is not timed).
//!
//! `cargo bench --bench crease` ; `scripts/bench-table.py` turns the results into the README
//! table.

use std::hint::black_box;

use criterion::{BatchSize, Criterion, Throughput, criterion_group, criterion_main};
use interpolab::crease::{CreaseJob, InterpOptions, Interpolator, Method, Step};
use interpolab::scene::{PRESETS, Scene};

const PERIODS: u64 = 500;

fn periods(c: &mut Criterion) {
    for (name, text) in PRESETS.iter().map(|p| (p.id, p.json)) {
        let scene = Scene::from_json(text).expect("example parses");
        let job = CreaseJob::from_scene(&scene).expect("example builds");
        let mut group = c.benchmark_group(name);
        group.throughput(Throughput::Elements(PERIODS));
        for (label, method) in [("seed000", Method::Seed000), ("exact", Method::Exact)] {
            let fresh = Interpolator::new(job.clone(), InterpOptions { method, ..InterpOptions::default() })
                .expect("example starts");
            group.bench_function(label, |b| {
                b.iter_batched(
                    || fresh.clone(),
                    |mut it| {
                        for _ in 0..PERIODS {
                            match it.step() {
                                Ok(Step::Row(r)) => {
                                    black_box(r);
                                }
                                other => panic!("{name}: {other:?} within {PERIODS} periods"),
                            }
                        }
                        it
                    },
                    BatchSize::SmallInput,
                );
            });
        }
        group.finish();
    }
}

criterion_group! {
    name = benches;
    config = Criterion::default().sample_size(30).measurement_time(std::time::Duration::from_secs(2));
    targets = periods
}
criterion_main!(benches);
