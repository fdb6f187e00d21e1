//! Speed of seed 001's finishing paths: one CC point (matched orientation, then the side
//! step's work: both cross profiles and the scallop between them), and whole example
//! surfaces at h = 0.01 mm (iso-scallop, matched).
#![allow(missing_docs)]

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use glam::DVec2;
use interpolab::fillet::contact::{ContactFrame, CrossProfile, scallop_between};
use interpolab::fillet::orient::{Strategy, pose_at};
use interpolab::fillet::{FinishJob, FinishSetup, PartSamples, iso_scallop};
use interpolab::geom::ParametricSurface;
use interpolab::scene::finish::{FINISH_PRESETS, FinishScene};

fn job(id: &str) -> FinishJob {
    let Some(p) = FINISH_PRESETS.iter().find(|p| p.id == id) else { panic!("no preset {id}") };
    match FinishScene::from_json(p.json).and_then(|s| s.job()) {
        Ok(j) => j,
        Err(e) => panic!("{id}: {e}"),
    }
}

fn benches(c: &mut Criterion) {
    let patch = job("finish-bicubic-patch");
    let mut g = c.benchmark_group("fillet_cc_point");
    g.sample_size(20).measurement_time(Duration::from_secs(3));
    let oo = patch.options.orient;
    let uv = DVec2::new(0.4, 0.6);
    let d = patch.surface.derivatives_at(uv);
    g.bench_function("orientation_and_side_step", |b| {
        b.iter(|| {
            let Some(frame) = ContactFrame::new(&patch.surface, black_box(uv), d.du) else { return 0.0 };
            let Some((pose, _)) = pose_at(&Strategy::Matched, &patch.cutter, &frame, &oo, (0.0, 0.0)) else {
                return 0.0;
            };
            let a = CrossProfile::new(&patch.cutter, &patch.surface, frame, &pose);
            let w = 2.0 * a.reach(0.01, 1.0);
            let uv_b = uv + DVec2::new(0.0, w / 80.0);
            let Some(fb) = ContactFrame::new(&patch.surface, uv_b, d.du) else { return 0.0 };
            let bp = CrossProfile::new(&patch.cutter, &patch.surface, fb, &pose);
            scallop_between(&a, &bp, w)
        });
    });
    g.finish();
    let mut g = c.benchmark_group("fillet_whole_surface_h_0_01");
    g.sample_size(10).measurement_time(Duration::from_secs(10));
    for id in ["finish-bicubic-patch", "finish-naca-blade"] {
        let j = job(id);
        let part = PartSamples::new(&j.surface, j.options.part_grid);
        g.bench_function(id, |b| {
            b.iter(|| {
                iso_scallop(&FinishSetup { strategy: Strategy::Matched, ..j.setup(&part) }).map(|s| s.paths.len())
            });
        });
    }
    g.finish();
}

criterion_group!(fillet_benches, benches);
criterion_main!(fillet_benches);
