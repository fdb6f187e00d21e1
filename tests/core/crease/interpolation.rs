//! The seed-000 crease interpolator against closed forms, the exact crease, the paper's
//! bounds, and its stopping rules.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use glam::DVec3;
use interpolab::crease::{
    CreaseJob, InterpOptions, Interpolator, Location, Method, Row, Step, StopReason, crease_deviation, diagnose,
    locate_crease_point, run_to_end,
};
use interpolab::numerics::tolerance::MEASUREMENT_FLOOR_MM;
use interpolab::scene::PRESETS;

const FLOOR_WALL: &str = include_str!("../../../examples/floor-round-wall.json");
const SPHERE_PLANE: &str = include_str!("../../../examples/sphere-plane.json");

fn run(job: &CreaseJob, opts: InterpOptions) -> (Vec<Row>, StopReason) {
    let r = run_to_end(job.clone(), opts);
    match r.outcome {
        Ok(reason) => (r.rows, reason),
        Err(e) => panic!("run failed: {e}"),
    }
}

/// Every row within b·T of both surfaces (measured by foot-point projection).
fn assert_within_tolerance(name: &str, job: &CreaseJob, rows: &[Row]) {
    for row in rows {
        let d = diagnose(job, row).expect("regular");
        for i in 0..2 {
            assert!(
                d.measured[i].abs() <= job.allowed_error_mm(i),
                "{name}: row {} e{} = {:e} exceeds b·T = {}",
                row.k,
                i + 1,
                d.measured[i],
                job.allowed_error_mm(i)
            );
        }
    }
}

fn assert_steps_equal_feed(name: &str, job: &CreaseJob, rows: &[Row], rel: f64) {
    let f = job.feed_per_period_mm;
    for (i, w) in rows.windows(2).enumerate() {
        let step = (w[1].p - w[0].p).length();
        if i + 2 == rows.len() && (w[1].t_s - w[1].k as f64 * job.period_s).abs() > 1e-12 {
            // The final shorter period onto the exact end: its time is its chord at the feed.
            let expected = (w[1].t_s - w[0].t_s) / job.period_s * f;
            assert!(step <= f * (1.0 + rel) && (step - expected).abs() <= 1e-12, "{name}: final step {step}");
            continue;
        }
        assert!((step - f).abs() <= rel * f, "{name}: step {} at row {} differs from f = {f}", step, w[1].k);
    }
}

#[test]
fn floor_and_inward_wall_crease_is_the_circle_of_radius_rho_minus_r_at_height_r() {
    let job = support::job(FLOOR_WALL);
    let (rho, r) = (50.0, job.r_eff_mm);
    let (rows, reason) = run(&job, InterpOptions::default());
    assert_eq!(reason, StopReason::Closed { turns: 1 });
    for row in &rows {
        let radial = DVec3::new(row.p.x, row.p.y, 0.0).length();
        assert!((radial - (rho - r)).abs() < 1e-8, "row {}: radius {radial}", row.k);
        assert!((row.p.z - r).abs() < 1e-12, "row {}: height {}", row.k, row.p.z);
    }
    // One turn of the circle, to within one feed per period.
    let length = (rows.len() - 1) as f64 * job.feed_per_period_mm;
    assert!((length - std::f64::consts::TAU * (rho - r)).abs() <= job.feed_per_period_mm);
    assert_within_tolerance("floor-round-wall", &job, &rows);
    assert_steps_equal_feed("floor-round-wall", &job, &rows, 1e-6);
}

#[test]
fn sphere_and_plane_crease_is_a_circle() {
    let job = support::job(SPHERE_PLANE);
    // Dome centre (0, 0, −10), radius 40; floor z = 0. The centre runs at z = R' on the
    // sphere of radius 40 + R' about the dome's centre.
    let r = job.r_eff_mm;
    let radius = ((40.0 + r).powi(2) - (r + 10.0).powi(2)).sqrt();
    let (rows, reason) = run(&job, InterpOptions::default());
    assert_eq!(reason, StopReason::Closed { turns: 1 });
    for row in &rows {
        assert!((row.p.z - r).abs() < 1e-12);
        assert!((DVec3::new(row.p.x, row.p.y, 0.0).length() - radius).abs() < 1e-8, "row {}", row.k);
    }
    assert_within_tolerance("sphere-plane", &job, &rows);
    assert_steps_equal_feed("sphere-plane", &job, &rows, 1e-6);
}

#[test]
fn without_the_feed_rescale_steps_still_match_f_to_second_order() {
    // The paper's method as printed: the correction δp is not perpendicular to the chord, so
    // |Δp| = f only to O(f²k²). Its deviation stays far below what a machine would notice.
    let job = support::job(FLOOR_WALL);
    let (rows, _) = run(&job, InterpOptions { exact_feed: false, ..InterpOptions::default() });
    assert_steps_equal_feed("paper-pure", &job, &rows, 1e-5);
    assert_within_tolerance("paper-pure", &job, &rows);
}

#[test]
fn every_example_stays_within_tolerance_with_exact_feed_steps() {
    for (name, text) in PRESETS.iter().map(|p| (p.id, p.json)) {
        let job = support::job(text);
        let (rows, _) = run(&job, InterpOptions::default());
        assert!(rows.len() > 100, "{name}: only {} rows", rows.len());
        assert_within_tolerance(name, &job, &rows);
        assert_steps_equal_feed(name, &job, &rows, 1e-9);
    }
}

#[test]
fn measured_error_stays_below_the_steady_state_bound_16_on_every_example() {
    for (name, text) in PRESETS.iter().map(|p| (p.id, p.json)) {
        let job = support::job(text);
        let (rows, _) = run(&job, InterpOptions::default());
        let mut worst_measured = [0.0f64; 2];
        let mut worst_bound = [0.0f64; 2];
        for row in &rows {
            let d = diagnose(&job, row).expect("regular");
            for i in 0..2 {
                worst_measured[i] = worst_measured[i].max(d.measured[i].abs());
                let bound = d.est16[i].unwrap_or_else(|| panic!("{name}: (16) applies at row {}", row.k));
                worst_bound[i] = worst_bound[i].max(bound);
            }
        }
        for i in 0..2 {
            // The bound neglects the second-order remainder of linearising (4), ~|δp|²/2D,
            // about 1e-10 mm here; below MEASUREMENT_FLOOR_MM the comparison is not resolvable.
            assert!(
                worst_measured[i] <= worst_bound[i] + MEASUREMENT_FLOOR_MM,
                "{name}: S{} measured {:e} mm above bound (16) {:e} mm",
                i + 1,
                worst_measured[i],
                worst_bound[i]
            );
        }
    }
}

#[test]
fn interpolated_centres_stay_on_the_exact_crease_and_the_exact_mode_sits_on_it() {
    for (name, text) in PRESETS.iter().map(|p| (p.id, p.json)) {
        let job = support::job(text);
        let (rows, _) = run(&job, InterpOptions::default());
        let mut worst = 0.0f64;
        for row in rows.iter().step_by(7) {
            let (dev, _) = crease_deviation(&job, row.p, row.uv).expect("Newton converges near the crease");
            worst = worst.max(dev);
        }
        let budget = job.allowed_error_mm(0).min(job.allowed_error_mm(1));
        assert!(worst < budget, "{name}: centre {worst:e} mm off the exact crease");
        let exact = run_to_end(job.clone(), InterpOptions { method: Method::Exact, ..InterpOptions::default() });
        let exact_rows = exact.rows;
        assert!(exact.outcome.is_ok(), "{name}: exact mode failed: {:?}", exact.outcome);
        for row in exact_rows.iter().step_by(11) {
            let (dev, _) = crease_deviation(&job, row.p, row.uv).expect("converges");
            assert!(dev < 1e-8, "{name}: exact mode row {} is {dev:e} mm off", row.k);
        }
        assert_steps_equal_feed(name, &job, &exact_rows, 1e-8);
        // Both methods trace the same crease: same number of periods to within one.
        assert!(
            (exact_rows.len() as i64 - rows.len() as i64).abs() <= 1,
            "{name}: {} vs {}",
            exact_rows.len(),
            rows.len()
        );
    }
}

#[test]
fn ten_turns_of_a_closed_crease_do_not_accumulate_error() {
    // Crossing cylinders: a closed crease with curvature and torsion on both surfaces, so the
    // per-period error is well above rounding.
    let job = support::job(include_str!("../../../examples/crossing-cylinders.json"));
    let mut it =
        Interpolator::new(job.clone(), InterpOptions { turns: 10, ..InterpOptions::default() }).expect("starts");
    let mut worst = [0.0f64; 11];
    let mut record = |row: &Row, turn: usize| {
        let d = diagnose(&job, row).expect("regular");
        worst[turn] = worst[turn].max(d.measured[0].abs().max(d.measured[1].abs()));
    };
    record(&it.current(), 0);
    let reason = loop {
        let turn = it.turns_completed() as usize;
        match it.step().expect("continues") {
            Step::Row(r) => record(&r, turn.min(9)),
            Step::Stopped(reason) => break reason,
        }
    };
    assert_eq!(reason, StopReason::Closed { turns: 10 });
    let (first, tenth) = (worst[0], worst[9]);
    assert!(first > 1e-7, "the crease must have a measurable error ({first:e})");
    assert!(tenth <= 1.1 * first, "error grew: first turn {first:e} mm, tenth {tenth:e} mm");
}

#[test]
fn stops_at_the_period_nearest_path_end() {
    let job = support::job(include_str!("../../../examples/bspline-floor-wall.json"));
    let (rows, reason) = run(&job, InterpOptions::default());
    assert_eq!(reason, StopReason::ReachedEnd);
    let end = locate_crease_point(&job, job.end.expect("has an end"), Location::End).expect("end on the crease").p;
    let nearest = rows.iter().min_by(|a, b| (a.p - end).length().total_cmp(&(b.p - end).length())).expect("rows");
    assert_eq!(nearest.k, rows[rows.len() - 1].k, "the last row is the one nearest path.end");
    assert!((nearest.p - end).length() <= 0.5 * job.feed_per_period_mm + 1e-9);
}

#[test]
fn stops_before_a_contact_leaves_its_domain() {
    let job = support::job(include_str!("../../../examples/rational-nurbs-vault.json"));
    let (rows, reason) = run(&job, InterpOptions::default());
    match reason {
        StopReason::LeftDomain { surface: 0, param: 'u', value, range } => {
            assert!(value > range[1] && value < range[1] + 0.01, "just past the end: {value}");
        }
        other => panic!("expected a domain stop, got {other:?}"),
    }
    let last = rows[rows.len() - 1];
    assert!(last.uv[0].x <= 1.0 && last.uv[0].x > 0.99);
}

#[test]
fn max_steps_limits_the_run() {
    let mut scene = support::scene(FLOOR_WALL);
    scene.path.max_steps = 25;
    let job = CreaseJob::from_scene(&scene).expect("valid");
    let (rows, reason) = run(&job, InterpOptions::default());
    assert_eq!(reason, StopReason::MaxSteps);
    assert_eq!(rows.len(), 26, "row 0 plus 25 periods");
    assert_eq!(rows[25].k, 25);
    assert!((rows[25].t_s - 0.1).abs() < 1e-15, "t = k·Ts");
}

#[test]
fn path_direction_chooses_the_sense_of_travel() {
    let mut scene = support::scene(FLOOR_WALL);
    scene.path.max_steps = 3;
    let job = CreaseJob::from_scene(&scene).expect("valid");
    let (default_rows, _) = run(&job, InterpOptions::default());
    // n1 × n2 = z × (−radial) at (45, 0, 5) is −y: clockwise seen from above.
    assert!(default_rows[1].p.y < default_rows[0].p.y);
    scene.path.direction = Some([0.0, 1.0, 0.0]);
    let job = CreaseJob::from_scene(&scene).expect("valid");
    let (rows, _) = run(&job, InterpOptions::default());
    assert!(rows[1].p.y > rows[0].p.y, "direction +y reverses the travel");
}
