//! Benchmark, not a test (ignored by default): seed 001's finishing paths, a whole example
//! surface at h = 0.01 mm (iso-scallop, matched), natively and compiled to wasm32 under
//! Node from the same source, so the two numbers compare like with like:
//!
//! ```text
//! cargo test --release --no-default-features --test native_and_wasm fillet:: -- --ignored --nocapture
//! cargo test --release --no-default-features --target wasm32-unknown-unknown --test native_and_wasm fillet:: -- --include-ignored --nocapture
//! ```
//! (`scripts/bench-wasm.sh` runs both.) Reports the median of several runs; the criterion
//! benchmark `benches/fillet.rs` measures the same work natively.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::web_time_shim::{Instant, print};
use interpolab::fillet::{FinishSetup, PartSamples, Strategy, iso_scallop};
use interpolab::scene::finish::{FINISH_PRESETS, FinishScene};

#[test]
#[ignore = "benchmark: run with --ignored --nocapture (scripts/bench-wasm.sh)"]
fn whole_surface_paths_native_and_wasm() {
    let platform = if cfg!(target_arch = "wasm32") { "wasm32" } else { "native" };
    for id in ["finish-bicubic-patch", "finish-naca-blade"] {
        let preset = FINISH_PRESETS.iter().find(|p| p.id == id).expect("preset");
        let job = FinishScene::from_json(preset.json).and_then(|s| s.job()).expect("builds");
        let part = PartSamples::new(&job.surface, job.options.part_grid);
        let run = || {
            let t = Instant::now();
            let set = iso_scallop(&FinishSetup { strategy: Strategy::Matched, ..job.setup(&part) }).expect("paths");
            (t.elapsed().as_secs_f64() * 1000.0, set.stats(job.options.feed_mm_per_min).nodes)
        };
        // Warm up once (the wasm engine optimises hot code after a while), then the median of 5.
        let (_, nodes) = run();
        let mut ms: Vec<f64> = (0..5).map(|_| run().0).collect();
        ms.sort_by(f64::total_cmp);
        print(&format!(
            "{platform}: {id}, iso-scallop matched, h {} mm: median {:.1} ms ({:.1} µs per CC point, {nodes} points), min {:.1} ms",
            job.options.scallop_mm,
            ms[2],
            ms[2] * 1000.0 / nodes as f64,
            ms[0]
        ));
    }
}
