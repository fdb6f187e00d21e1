//! Paths end where they should (issue 11): the last row of a run is the exact end — the
//! crease point of `path.end`, the first point of a closed crease, or the crease point where
//! a contact parameter reaches its domain's bound — after a final shorter period whose time
//! is its chord at the programmed feed; and no step, however long, jumps over an end.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use glam::DVec3;
use interpolab::crease::{
    CreaseJob, InterpOptions, Location, Method, Row, StopReason, crease_deviation, locate_crease_point, run_to_end,
};
use interpolab::geom::ParametricSurface;
use interpolab::scene::PRESETS;

fn run(job: &CreaseJob, opts: InterpOptions) -> (Vec<Row>, StopReason) {
    let r = run_to_end(job.clone(), opts);
    match r.outcome {
        Ok(reason) => (r.rows, reason),
        Err(e) => panic!("run failed: {e}"),
    }
}

fn preset(id: &str) -> CreaseJob {
    let p = PRESETS.iter().find(|p| p.id == id).expect("preset");
    support::job(p.json)
}

/// A job with another feed per period f (mm), F changed with it at the same Ts.
fn with_feed(mut job: CreaseJob, f: f64) -> CreaseJob {
    job.feed_per_period_mm = f;
    job.feed_mm_per_s = f / job.period_s;
    job
}

/// The exact end of a run by an independent computation, and how the last row must match.
fn assert_exact_end(name: &str, job: &CreaseJob, rows: &[Row], reason: StopReason) {
    let last = rows[rows.len() - 1];
    match reason {
        StopReason::Closed { .. } => {
            assert_eq!(last.p, rows[0].p, "{name}: a closed crease closes on its first point");
        }
        StopReason::ReachedEnd => {
            let end = locate_crease_point(job, job.end.expect("end"), Location::End).expect("end on the crease");
            assert!((last.p - end.p).length() <= 1e-9, "{name}: {} from the end", (last.p - end.p).length());
        }
        StopReason::LeftDomain { surface, param, .. } => {
            let d = job.surfaces[surface].domain();
            let range = if param == 'u' { d.u } else { d.v };
            let x = if param == 'u' { last.uv[surface].x } else { last.uv[surface].y };
            let gap = (x - range.min).abs().min((x - range.max).abs());
            assert!(gap <= 1e-12 * range.width().max(1.0), "{name}: {param} = {x} is not on its bound");
            // And the point is on the exact crease (not only its parameter on the edge).
            let (dev, _) = crease_deviation(job, last.p, last.uv).expect("exact crease");
            assert!(dev <= 1e-9, "{name}: {dev} mm off the crease");
        }
        StopReason::MaxSteps => {}
    }
    // The last period is the final shorter one: its time is its chord at the feed.
    let prev = rows[rows.len() - 2];
    if reason != StopReason::MaxSteps {
        let chord = (last.p - prev.p).length();
        let f = job.feed_per_period_mm;
        assert!(chord <= f * (1.0 + 1e-6), "{name}: final chord {chord} longer than f = {f}");
        let dt = last.t_s - prev.t_s;
        assert!((dt - job.period_s * chord / f).abs() <= 1e-9 * job.period_s, "{name}: final period {dt} s");
        assert!(last.t_s <= last.k as f64 * job.period_s + 1e-12, "{name}: t_s of the final row");
        assert_eq!(last.k, prev.k + 1);
    }
}

#[test]
fn every_example_ends_exactly_on_its_end() {
    for p in PRESETS {
        let job = support::job(p.json);
        for method in [Method::Seed000, Method::Exact] {
            let (rows, reason) = run(&job, InterpOptions { method, ..InterpOptions::default() });
            assert_ne!(reason, StopReason::MaxSteps, "{}", p.id);
            assert_exact_end(&format!("{} {method:?}", p.id), &job, &rows, reason);
        }
    }
}

#[test]
fn an_end_three_periods_ahead_is_not_stepped_over() {
    // Issue 11: path.end three periods ahead of the start on the floor-and-round-wall crease
    // was ignored and a whole extra turn cut (2 828 rows).
    let mut job = preset("floor-round-wall");
    job.end = Some(DVec3::new(44.997, 0.2, 5.0));
    let (rows, reason) = run(&job, InterpOptions::default());
    assert_eq!(reason, StopReason::ReachedEnd);
    assert_eq!(rows.len(), 5, "row 0, three whole periods and the final one");
    assert_exact_end("end 3 periods ahead", &job, &rows, reason);
}

#[test]
fn closure_is_detected_for_any_feed_per_period() {
    // Issue 11: on the 164 mm crossing-cylinders crease at f = 20 mm closure was never
    // detected (200 000 periods, 4 km). The circle of the floor and round wall (282.7 mm)
    // from a hundredth of a millimetre per period to a tenth of the loop.
    for (id, feeds) in
        [("crossing-cylinders", &[20.0, 11.0, 3.7, 0.31][..]), ("floor-round-wall", &[28.0, 9.0, 1.3, 0.07, 0.013][..])]
    {
        for &f in feeds {
            let job = with_feed(preset(id), f);
            let r = run_to_end(job.clone(), InterpOptions::default());
            let reason = match r.outcome {
                Ok(reason) => reason,
                // A feed far too long for the curvature may be refused, never run on.
                Err(e) => {
                    assert!(e.to_string().contains("lower motion.feed"), "{id} f = {f}: {e}");
                    continue;
                }
            };
            assert_eq!(reason, StopReason::Closed { turns: 1 }, "{id} f = {f}");
            let length: f64 = r.rows.windows(2).map(|w| (w[1].p - w[0].p).length()).sum();
            assert!(r.rows.len() <= 3 + (300.0 / f) as usize, "{id} f = {f}: {} rows, {length} mm", r.rows.len());
            assert_exact_end(&format!("{id} f = {f}"), &job, &r.rows, reason);
        }
    }
}

#[test]
fn a_tiny_closed_crease_closes() {
    // Issue 11: a 0.63 mm closed crease at f = 0.1 mm ran 200 000 periods. A round hole of
    // radius 5.1 mm in a floor cut by a ball of 5 mm: the centre circles at radius 0.1 mm.
    let json = PRESETS
        .iter()
        .find(|p| p.id == "floor-round-wall")
        .expect("preset")
        .json
        .replace("\"radius\": 50.0", "\"radius\": 5.1")
        .replace("[44.8, 0.5, 5.2]", "[0.1, 0.0, 5.0]");
    let job = support::job(&json);
    let (rows, reason) = run(&job, InterpOptions::default());
    assert_eq!(reason, StopReason::Closed { turns: 1 });
    assert!(rows.len() <= 9, "{} rows for a 0.63 mm loop at f = 0.1 mm", rows.len());
    assert_exact_end("tiny loop", &job, &rows, reason);
    // Several turns: each is counted once, the last ends on the first point.
    let (rows, reason) = run(&job, InterpOptions { turns: 3, ..InterpOptions::default() });
    assert_eq!(reason, StopReason::Closed { turns: 3 });
    assert!(rows.len() <= 22, "{}", rows.len());
    assert_eq!(rows[rows.len() - 1].p, rows[0].p);
}

#[test]
fn an_end_at_random_places_on_the_circle_is_met_exactly() {
    // path.end anywhere on the floor-and-round-wall circle (radius 45 at z = 5), at feeds
    // from 0.05 to 7 mm per period: the run stops on its crease point, never a turn later.
    let mut rng = support::Rng::new(11);
    for _ in 0..40 {
        let f = rng.range(0.05, 7.0);
        let a = rng.range(0.0, std::f64::consts::TAU);
        let mut job = with_feed(preset("floor-round-wall"), f);
        job.end = Some(DVec3::new(45.0 * a.cos(), 45.0 * a.sin(), 5.0));
        let (rows, reason) = run(&job, InterpOptions::default());
        assert_eq!(reason, StopReason::ReachedEnd, "f = {f}, angle {a}");
        // The arc from the start (angle ≈ 0.011 rad) to the end, covered once.
        let start = rows[0].p.y.atan2(rows[0].p.x);
        let sense =
            if (rows[1].p - rows[0].p).dot(DVec3::new(-start.sin(), start.cos(), 0.0)) > 0.0 { 1.0 } else { -1.0 };
        let arc = (sense * (a - start)).rem_euclid(std::f64::consts::TAU) * 45.0;
        // Each whole period is a chord f of the circle: an arc of 2·45·asin(f/90).
        let per = 90.0 * (f / 90.0).asin();
        let whole = rows.len() - 2;
        assert!(
            (whole as f64) * per <= arc + 1e-6 && arc <= (whole as f64 + 1.0) * per + 1e-6,
            "f = {f}: {whole} periods for {arc} mm"
        );
        assert_exact_end("random end", &job, &rows, reason);
    }
}
