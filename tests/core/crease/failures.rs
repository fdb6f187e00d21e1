//! Creases that cannot be started or continued: each is reported with its cause, where it
//! arose and what to change — never a panic or a NaN — and rows computed before a failure
//! remain valid.
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use interpolab::crease::{CreaseError, InterpOptions, Interpolator, Location, Step, diagnose};

fn start_error(json: &str) -> CreaseError {
    match Interpolator::new(support::job(json), InterpOptions::default()) {
        Ok(_) => panic!("the start should fail"),
        Err(e) => e,
    }
}

const TWO_PLANES: &str = r#"{
  "format": "interpolab-scene/1", "name": "two planes",
  "surfaces": [
    { "type": "plane", "origin": [0, 0, 0], "normal": [0, 0, 1], "u_axis": [1, 0, 0], "domain": { "u": [-50, 50], "v": [-50, 50] } },
    { "type": "plane", "origin": [0, 0, 0], "normal": [NX, 0, NZ], "u_axis": [NZ, 0, MNX], "domain": { "u": [-50, 50], "v": [-50, 50] } }
  ],
  "tool": { "radius": 5, "allowance": 0 }, "motion": { "feed": 1500, "period": 4 },
  "tolerance": { "t1": 0.01, "t2": 0.01, "share": 0.5 },
  "path": { "start": [0, 0, 5], "end": null, "max_steps": 1000 }
}"#;

fn two_planes(angle_deg: f64) -> String {
    let (s, c) = angle_deg.to_radians().sin_cos();
    TWO_PLANES.replace("MNX", &(-s).to_string()).replace("NX", &s.to_string()).replace("NZ", &c.to_string())
}

#[test]
fn surfaces_meeting_at_a_grazing_angle_are_reported_as_tangential() {
    let e = start_error(&two_planes(0.2));
    match &e {
        CreaseError::Tangential { at: Location::Start, angle_deg, .. } => {
            assert!((angle_deg - 0.2).abs() < 1e-6, "reports the angle: {angle_deg}");
        }
        other => panic!("expected tangential contact, got {other:?}"),
    }
    let msg = e.to_string();
    assert!(msg.contains("path.start") && msg.contains("tangentially") && msg.contains("0.200°"), "{msg}");
    // At 30° the same scene is fine: a straight crease.
    assert!(Interpolator::new(support::job(&two_planes(30.0)), InterpOptions::default()).is_ok());
}

#[test]
fn a_start_far_from_any_crease_is_reported() {
    let json = r#"{
      "format": "interpolab-scene/1", "name": "apart",
      "surfaces": [
        { "type": "plane", "origin": [0, 0, 0], "normal": [1, 0, 0], "u_axis": [0, 1, 0], "domain": { "u": [-50, 50], "v": [-50, 50] } },
        { "type": "sphere", "center": [100, 0, 0], "radius": 10, "normal": "outward" }
      ],
      "tool": { "radius": 5, "allowance": 0 }, "motion": { "feed": 1500, "period": 4 },
      "tolerance": { "t1": 0.01, "t2": 0.01, "share": 0.5 },
      "path": { "start": [5, 0, 0], "end": null }
    }"#;
    let e = start_error(json);
    assert!(matches!(e, CreaseError::NoCrease { at: Location::Start, .. }), "{e:?}");
    let msg = e.to_string();
    assert!(msg.contains("no crease near path.start") && msg.contains("move path.start"), "{msg}");
}

#[test]
fn a_concave_radius_below_the_cutter_radius_is_a_fold() {
    // A bore of radius 4 mm with a 5 mm ball: the ball cannot reach the corner.
    let json = include_str!("../../../examples/floor-round-wall.json")
        .replace("\"radius\": 50.0", "\"radius\": 4.0")
        .replace("[44.8, 0.5, 5.2]", "[-1.0, 0.0, 5.0]");
    let e = start_error(&json);
    match &e {
        CreaseError::Fold { surface: 1, radius_mm, r_eff_mm, .. } => {
            assert!((radius_mm - 4.0).abs() < 1e-9 && (r_eff_mm - 5.0).abs() < 1e-12);
        }
        other => panic!("expected a fold, got {other:?}"),
    }
    let msg = e.to_string();
    assert!(msg.contains("surface 2") && msg.contains("tool.radius below 4.0000 mm"), "{msg}");
}

#[test]
fn a_crease_running_into_tangential_contact_stops_there_with_earlier_rows_intact() {
    // Two perpendicular cylinders of equal radius: their offset surfaces meet in two ellipses
    // that cross where both normals are ±y, so the crease runs into tangential contact.
    let json = include_str!("../../../examples/crossing-cylinders.json")
        .replace("\"radius\": 20.0", "\"radius\": 30.0")
        .replace("\"v\": [10, 80]", "\"v\": [-80, 80]")
        .replace("[25.0, 0.0, 35.0]", "[35.0, 0.0, 35.0]");
    let job = support::job(&json);
    let mut it = Interpolator::new(job.clone(), InterpOptions::default()).expect("starts well away from the crossing");
    let mut rows = vec![it.current()];
    let err = loop {
        match it.step() {
            Ok(Step::Row(r)) => rows.push(r),
            Ok(Step::Stopped(reason)) => panic!("should not end normally: {reason}"),
            Err(e) => break e,
        }
    };
    match &err {
        CreaseError::Tangential { at: Location::Period { k, .. }, angle_deg, .. } => {
            assert_eq!(*k as usize, rows.len(), "fails in the period after the last row");
            assert!(*angle_deg < 0.5);
        }
        // The correction may blow up first as the normals close in; either names the period.
        CreaseError::StepTooLong { at: Location::Period { k, .. }, .. } => assert_eq!(*k as usize, rows.len()),
        other => panic!("expected tangential contact, got {other:?}"),
    }
    assert!(rows.len() > 100, "ran {} periods before the crossing", rows.len());
    for row in &rows {
        assert!(row.p.is_finite());
        let d = diagnose(&job, row).expect("regular");
        assert!(d.measured[0].abs() < 0.01 && d.measured[1].abs() < 0.01, "row {}: {:?}", row.k, d.measured);
    }
    assert!(err.to_string().contains("period"), "names the period: {err}");
}

#[test]
fn a_feed_per_period_too_long_for_the_crease_is_refused() {
    // A 6 mm bore with a 5 mm ball: the centre circles on radius 1 mm; f = 1.5 mm per period.
    let json = include_str!("../../../examples/floor-round-wall.json")
        .replace("\"radius\": 50.0", "\"radius\": 6.0")
        .replace("\"feed\": 1500.0", "\"feed\": 22500.0")
        .replace("[44.8, 0.5, 5.2]", "[1.0, 0.0, 5.0]");
    let job = support::job(&json);
    let mut it = Interpolator::new(job, InterpOptions::default()).expect("starts");
    let e = loop {
        match it.step() {
            Ok(Step::Row(_)) => {}
            Ok(Step::Stopped(r)) => panic!("should fail, stopped: {r}"),
            Err(e) => break e,
        }
    };
    assert!(matches!(e, CreaseError::StepTooLong { .. }), "{e:?}");
    assert!(e.to_string().contains("lower motion.feed or motion.period"), "{e}");
}

#[test]
fn a_direction_across_the_crease_is_ambiguous() {
    let mut scene = support::scene(include_str!("../../../examples/floor-round-wall.json"));
    scene.path.direction = Some([0.0, 0.0, 1.0]);
    let job = interpolab::crease::CreaseJob::from_scene(&scene).expect("valid scene");
    let e = Interpolator::new(job, InterpOptions::default()).expect_err("ambiguous");
    assert_eq!(e, CreaseError::DirectionAmbiguous);
}

/// A straight V-groove along x between two planes at ±45°, from x = −40 toward x = +40. The
/// sense of n1 × n2 is −x, so without `path.direction` the run goes away from `path.end`.
fn groove(max_steps: u64, direction: Option<[f64; 3]>) -> String {
    let mut scene = support::scene(include_str!("../../data/groove-end-behind-start.json"));
    scene.path.max_steps = max_steps;
    scene.path.direction = direction;
    scene.to_json()
}

#[test]
fn a_run_going_away_from_path_end_says_which_direction_reaches_it() {
    let json = groove(100_000, None);
    let job = support::job(&json);
    let run = interpolab::crease::run_to_end(job, InterpOptions::default());
    assert!(matches!(run.outcome, Ok(interpolab::crease::StopReason::LeftDomain { .. })), "{:?}", run.outcome);
    let note = run.end_not_reached.expect("the end was not reached");
    let sense = note.away_from_end.expect("the run went away from path.end");
    assert!((sense - glam::DVec3::new(-1.0, 0.0, 0.0)).length() < 1e-9, "sense of n1 × n2: {sense}");
    // The last point is the domain's edge at u = −60 (minus less than one period), 100 mm from the end.
    assert!((note.distance_mm - 100.0).abs() < 0.1 + 1e-9, "{}", note.distance_mm);
    let text = note.to_string();
    assert!(text.contains("path.direction to [1.000, 0.000, 0.000]"), "{text}");

    // Following the advice reaches the end, and then there is no note.
    let job = support::job(&groove(100_000, Some([1.0, 0.0, 0.0])));
    let run = interpolab::crease::run_to_end(job, InterpOptions::default());
    assert_eq!(run.outcome, Ok(interpolab::crease::StopReason::ReachedEnd));
    assert!((run.rows.last().unwrap().p - glam::DVec3::new(40.0, 0.0, 4.0 * 2f64.sqrt())).length() < 0.05 + 1e-9);
    assert_eq!(run.end_not_reached, None);
}

#[test]
fn a_given_direction_away_from_path_end_is_pointed_out_too() {
    let job = support::job(&groove(100_000, Some([-1.0, 0.0, 0.2])));
    let run = interpolab::crease::run_to_end(job, InterpOptions::default());
    let note = run.end_not_reached.expect("the end was not reached");
    assert!(note.direction_given && note.away_from_end.is_some());
    let text = note.to_string();
    assert!(text.contains("in the sense of path.direction, away from path.end"), "{text}");
    assert!(text.contains("set path.direction to [1.000, 0.000, 0.000]"), "{text}");
}

#[test]
fn a_run_cut_short_by_max_steps_says_to_raise_it() {
    let json = groove(100, Some([1.0, 0.0, 0.0]));
    let job = support::job(&json);
    let run = interpolab::crease::run_to_end(job, InterpOptions::default());
    assert_eq!(run.outcome, Ok(interpolab::crease::StopReason::MaxSteps));
    let note = run.end_not_reached.expect("the end was not reached");
    assert_eq!(note.away_from_end, None, "the run went toward the end");
    assert!((note.distance_mm - 70.0).abs() < 1e-5, "80 mm minus 100 periods of 0.1 mm: {}", note.distance_mm);
    assert!(note.to_string().contains("raise path.max_steps"), "{note}");
}
