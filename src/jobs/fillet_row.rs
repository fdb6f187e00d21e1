//! One row of the fillet tab's comparison table as a background job: a finishing scene (its
//! strategy written into it) machined with iso-scallop or iso-parametric paths by
//! [`iso_scallop`] / [`iso_parametric`] (from the scene's `finish.start`), and the
//! numbers of the paths ([`Stats`]). A row is one whole core run, 1–1.5 s natively and more
//! in a browser: far more than a frame.
//!
//! The request carries the scene as its `interpolab-scene/1` text ([`FinishScene::to_json`],
//! exact: every number reads back bit for bit), the output the row's numbers by their bits.

use serde_json::json;

use super::{DecodeError, JobError, JobKind, Progress, Reader, nums, parse};
use crate::fillet::{Layout, PartSamples, Stats, iso_parametric, iso_scallop};
use crate::scene::finish::FinishScene;

/// One row: the scene (strategy included) and the layout of its paths.
#[derive(Clone, Debug, PartialEq)]
pub struct Request {
    /// The finishing scene, with the row's strategy and lead.
    pub scene: FinishScene,
    /// Iso-scallop or iso-parametric paths.
    pub layout: Layout,
}

/// The job kind.
#[derive(Clone, Copy, Debug)]
pub struct FilletRow;

fn layout_name(l: Layout) -> &'static str {
    l.name()
}

fn layout_of(name: &str) -> Result<Layout, DecodeError> {
    [Layout::IsoScallop, Layout::IsoParametric].into_iter().find(|l| l.name() == name).ok_or_else(|| {
        format!("fillet-row request.layout: \"{name}\" is neither iso-scallop nor iso-parametric").into()
    })
}

impl JobKind for FilletRow {
    const NAME: &'static str = "fillet-row";
    type Request = Request;
    type Output = Result<Stats, JobError>;
    type Partial = ();

    fn run(request: &Request, progress: &mut dyn Progress) -> Self::Output {
        let job = request.scene.job().map_err(JobError::failed)?;
        let part = PartSamples::new(&job.surface, job.options.part_grid);
        if progress.cancelled() {
            return Err(JobError::Cancelled);
        }
        progress.progress(0.1);
        let paths = match request.layout {
            Layout::IsoScallop => iso_scallop(&job.setup(&part)),
            Layout::IsoParametric => iso_parametric(&job.setup(&part)),
        };
        paths.map(|p| p.stats(job.options.feed_mm_per_min)).map_err(JobError::failed)
    }

    fn encode_request(r: &Request) -> String {
        json!({ "scene": r.scene.to_json(), "layout": layout_name(r.layout) }).to_string()
    }

    fn decode_request(text: &str) -> Result<Request, DecodeError> {
        let v = parse(text, "fillet-row request")?;
        let r = Reader::new(&v, "fillet-row request")?;
        let scene = FinishScene::from_json(r.str("scene")?).map_err(|e| format!("fillet-row request.scene: {e}"))?;
        Ok(Request { scene, layout: layout_of(r.str("layout")?)? })
    }

    fn encode_output(out: &Self::Output) -> String {
        match out {
            Err(e) => e.encode(),
            Ok(s) => json!({
                "passes": s.passes,
                "nodes": s.nodes,
                "length_mm": super::num(s.length_mm),
                "strip_mm": nums(s.strip_mm),
                "scallop_mm": nums(s.scallop_mm),
                "time_min": super::num(s.time_min),
                "adjusted": s.adjusted,
            })
            .to_string(),
        }
    }

    fn decode_output(text: &str) -> Result<Self::Output, DecodeError> {
        let v = parse(text, "fillet-row output")?;
        if let Some(e) = JobError::decode(&v, "fillet-row output")? {
            return Ok(Err(e));
        }
        let r = Reader::new(&v, "fillet-row output")?;
        let three = |key: &str| -> Result<[f64; 3], DecodeError> {
            r.f64s(key)?.try_into().map_err(|_| format!("fillet-row output.{key}: not three numbers").into())
        };
        let two = |key: &str| -> Result<[f64; 2], DecodeError> {
            r.f64s(key)?.try_into().map_err(|_| format!("fillet-row output.{key}: not two numbers").into())
        };
        Ok(Ok(Stats {
            passes: r.usize("passes")?,
            nodes: r.usize("nodes")?,
            length_mm: r.f64("length_mm")?,
            strip_mm: three("strip_mm")?,
            scallop_mm: two("scallop_mm")?,
            time_min: r.f64("time_min")?,
            adjusted: r.usize("adjusted")?,
        }))
    }

    fn decode_partial(_text: &str) -> Result<(), DecodeError> {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fillet::{PathStart, Strategy};
    use crate::jobs::NoProgress;
    use crate::scene::finish::FINISH_PRESETS;
    use crate::scene::finish::StartSpec;

    /// A deterministic stream of awkward doubles: random bit patterns of finite numbers in
    /// a given range, so their shortest decimal texts have 15–17 digits (where a parser
    /// that is not correctly rounded lands one unit in the last place off).
    fn awkward(seed: &mut u64, lo: f64, hi: f64) -> f64 {
        *seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        let u = (*seed >> 11) as f64 / (1u64 << 53) as f64;
        let x = lo + (hi - lo) * u;
        // Perturb the last bits so the text needs all its digits.
        f64::from_bits(x.to_bits() ^ (*seed & 0x7))
    }

    /// A finishing scene written by `to_json` reads back as the same scene, every number
    /// bit for bit — the presets, and presets with every optional key set to awkward values.
    #[test]
    fn finish_scene_text_round_trips_bit_for_bit() {
        let mut seed = 0x1234_5678_9abc_def0;
        for p in FINISH_PRESETS {
            let scene = FinishScene::from_json(p.json).unwrap();
            assert_eq!(FinishScene::from_json(&scene.to_json()).unwrap(), scene, "{}", p.id);
            for _ in 0..50 {
                let mut s = scene.clone();
                let r = awkward(&mut seed, 2.0, 8.0);
                s.finish.cutter.radius = r;
                s.finish.cutter.corner_radius = awkward(&mut seed, 0.0, r);
                s.finish.cutter.flute_length = Some(awkward(&mut seed, 3.0 * r, 4.0 * r));
                s.finish.cutter.shank_radius = Some(awkward(&mut seed, r, 1.2 * r));
                s.finish.cutter.gauge_length = Some(awkward(&mut seed, 6.0 * r, 7.0 * r));
                s.finish.cutter.holder_radius = Some(awkward(&mut seed, 2.5 * r, 3.0 * r));
                s.finish.cutter.holder_length = Some(awkward(&mut seed, 6.0 * r, 7.0 * r));
                s.finish.scallop = awkward(&mut seed, 1e-3, 0.1);
                s.finish.tolerance = awkward(&mut seed, 1e-3, 0.1);
                "fixed-lead".clone_into(&mut s.finish.strategy);
                s.finish.lead = Some(awkward(&mut seed, -30.0, 30.0));
                s.finish.max_step = Some(awkward(&mut seed, 0.1, 3.0));
                s.finish.margin = Some(awkward(&mut seed, 0.0, 0.01));
                s.finish.max_inclination = Some(awkward(&mut seed, 1.0, 80.0));
                s.finish.feed = Some(awkward(&mut seed, 100.0, 5000.0));
                let text = s.to_json();
                let back = FinishScene::from_json(&text).unwrap();
                assert_eq!(back, s, "{text}");
                let bits = |x: &FinishScene| {
                    let f = &x.finish;
                    let c = &f.cutter;
                    [c.radius, c.corner_radius, f.scallop, f.tolerance, f.lead.unwrap_or(0.0), f.feed.unwrap_or(0.0)]
                        .map(f64::to_bits)
                };
                assert_eq!(bits(&back), bits(&s));
            }
        }
    }

    /// The request and the output cross unchanged, and the job is the core's own row.
    #[test]
    fn the_row_crosses_unchanged_and_is_the_core_run() {
        let mut scene = FinishScene::from_json(FINISH_PRESETS[0].json).unwrap();
        "ball".clone_into(&mut scene.finish.strategy);
        // A coarse scallop keeps the test quick; the start curve must cross to the worker.
        scene.finish.scallop = 0.05;
        scene.finish.start = Some(StartSpec::Curve(vec![[0.2, 0.4], [0.8, 0.6]]));
        for layout in [Layout::IsoScallop, Layout::IsoParametric] {
            let req = Request { scene: scene.clone(), layout };
            let back = FilletRow::decode_request(&FilletRow::encode_request(&req)).unwrap();
            assert_eq!(back, req);
            let out = FilletRow::run(&back, &mut NoProgress);
            let stats = out.clone().unwrap();
            let got = FilletRow::decode_output(&FilletRow::encode_output(&out)).unwrap().unwrap();
            assert_eq!(got, stats);
            assert_eq!(got.time_min.to_bits(), stats.time_min.to_bits());
            let job = scene.job().unwrap();
            assert_eq!(job.strategy, Strategy::Ball);
            assert!(matches!(job.start, PathStart::Curve(_)));
            let part = PartSamples::new(&job.surface, job.options.part_grid);
            let direct = match layout {
                Layout::IsoScallop => iso_scallop(&job.setup(&part)),
                Layout::IsoParametric => iso_parametric(&job.setup(&part)),
            }
            .unwrap()
            .stats(job.options.feed_mm_per_min);
            assert_eq!(stats, direct);
            assert!(stats.passes > 1 && stats.strip_mm[0] > 0.0);
        }
        let failed = JobError::Failed("no paths".to_owned());
        let err = FilletRow::decode_output(&FilletRow::encode_output(&Err(failed.clone()))).unwrap();
        assert_eq!(err.unwrap_err(), failed);
        let bad =
            FilletRow::decode_request("{\"scene\": \"{}\", \"layout\": \"iso-scallop\"}").unwrap_err().to_string();
        assert!(bad.starts_with("fillet-row request.scene"), "{bad}");
        let bad = FilletRow::decode_request(&json!({"scene": scene.to_json(), "layout": "zigzag"}).to_string())
            .unwrap_err()
            .to_string();
        assert!(bad.contains("zigzag"), "{bad}");
    }
}
