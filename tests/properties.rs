//! Property tests (issue 11) over random scenes, feeds, ends and G-code: no panic, work
//! bounded by an operation budget (periods allowed per millimetre of crease, not a clock),
//! exact ends within 1e-9 mm, closure detected for any feed per period, and one-line errors
//! that print no NaN, inf or runaway decimals. Case counts are modest so the suite stays fast;
//! `PROPTEST_CASES` raises them (README, "Fuzzing and property tests"), and `scripts/fuzz.py`
//! fuzzes the command line for as long as wanted.
#![cfg(not(target_arch = "wasm32"))]

mod support;

use std::f64::consts::TAU;

use glam::DVec3;
use interpolab::crease::{CreaseJob, InterpOptions, Location, StopReason, locate_crease_point, run_to_end};
use interpolab::gcode::{parse_program, summarize};
use interpolab::scene::{PRESETS, Scene};
use proptest::prelude::*;

fn preset_json(id: &str) -> &'static str {
    PRESETS.iter().find(|p| p.id == id).expect("preset").json
}

/// A one-line message without the values a message must never show.
fn assert_clean_message(msg: &str) {
    assert_eq!(msg.lines().count(), 1, "one line: {msg}");
    for bad in ["NaN", " inf", "-0.0000 ", "\0"] {
        assert!(!msg.contains(bad), "message shows {bad:?}: {msg}");
    }
    let longest_number = msg.split(|c: char| !(c.is_ascii_digit() || c == '.')).map(str::len).max().unwrap_or(0);
    assert!(longest_number <= 40, "runaway decimals in: {msg}");
}

/// The floor-and-round-wall scene with a wall of radius `rho` (mm), ball radius `r` (mm),
/// start angle `a` (rad) and feed per period `f` (mm): its crease is the circle of radius
/// rho − r at height r.
fn floor_wall(rho: f64, r: f64, a: f64, f: f64) -> CreaseJob {
    let json = preset_json("floor-round-wall");
    let mut v: serde_json::Value = serde_json::from_str(json).expect("json");
    v["surfaces"][1]["radius"] = rho.into();
    v["tool"]["radius"] = r.into();
    let c = rho - r;
    v["path"]["start"] = serde_json::json!([c * a.cos(), c * a.sin(), r]);
    v["motion"]["feed"] = (f / 4.0 * 60_000.0).into();
    v["motion"]["period"] = 4.0.into();
    let scene = Scene::from_json(&v.to_string()).expect("valid scene");
    CreaseJob::from_scene(&scene).expect("job")
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 48, failure_persistence: None, ..ProptestConfig::default() })]

    /// A closed crease closes exactly on its first point for any feed per period, within an
    /// operation budget of one loop's periods plus two.
    #[test]
    fn a_closed_crease_closes_for_any_feed(
        rho in 6.0f64..60.0, r_frac in 0.05f64..0.9, a in 0.0f64..TAU, f_frac in 1e-3f64..0.2,
    ) {
        let r = 5.0f64.min(r_frac * rho);
        let loop_mm = TAU * (rho - r);
        let f = f_frac * loop_mm;
        let mut job = floor_wall(rho, r, a, f);
        // The budget: a loop's worth of periods (chords are shorter than arcs) and two more.
        job.max_steps = (loop_mm / f).ceil() as u64 + 2;
        let res = run_to_end(job.clone(), InterpOptions::default());
        match res.outcome {
            Ok(reason) => {
                prop_assert_eq!(reason, StopReason::Closed { turns: 1 });
                prop_assert_eq!(res.rows[res.rows.len() - 1].p, res.rows[0].p);
            }
            // A feed too long for the curvature is refused with a message, never run on.
            Err(e) => {
                let msg = e.to_string();
                assert_clean_message(&msg);
                prop_assert!(msg.contains("lower motion.feed"), "{}", msg);
            }
        }
    }

    /// An end anywhere on the circle is met on its exact crease point, never a turn later.
    #[test]
    fn an_end_is_met_exactly(a_end in 0.0f64..TAU, f in 0.02f64..6.0) {
        let mut job = floor_wall(50.0, 5.0, 0.0, f);
        job.end = Some(DVec3::new(45.0 * a_end.cos(), 45.0 * a_end.sin(), 5.0 + 0.3));
        job.max_steps = (TAU * 45.0 / f).ceil() as u64 + 2;
        let res = run_to_end(job.clone(), InterpOptions::default());
        let reason = res.outcome.expect("runs");
        let end = locate_crease_point(&job, job.end.expect("end"), Location::End).expect("end");
        if (end.p - res.rows[0].p).length() > 1e-6 {
            prop_assert_eq!(reason, StopReason::ReachedEnd);
            let last = res.rows[res.rows.len() - 1];
            prop_assert!((last.p - end.p).length() <= 1e-9, "{} mm from the end", (last.p - end.p).length());
        }
    }

    /// Random bytes in a scene never panic, and a refusal is one clean line.
    #[test]
    fn mutated_scenes_never_panic(pos in 0usize..4000, bytes in proptest::collection::vec(any::<u8>(), 1..6)) {
        let json = preset_json("crossing-cylinders");
        let mut b = json.as_bytes().to_vec();
        let at = pos % b.len();
        b.splice(at..(at + bytes.len()).min(b.len()), bytes);
        if let Ok(text) = String::from_utf8(b) {
            match Scene::from_json(&text) {
                Err(e) => assert_clean_message(&e.to_string()),
                Ok(scene) => match CreaseJob::from_scene(&scene) {
                    Err(e) => assert_clean_message(&e.to_string()),
                    Ok(mut job) => {
                        job.max_steps = job.max_steps.min(3000);
                        if let Err(e) = run_to_end(job, InterpOptions::default()).outcome {
                            assert_clean_message(&e.to_string());
                        }
                    }
                },
            }
        }
    }

    /// Random G-code words never panic; what reads is finite, what does not is one clean line.
    #[test]
    fn random_gcode_never_panics(
        lines in proptest::collection::vec(
            ("[GXYZIJKRFPKM]", prop_oneof![
                Just("1".to_owned()), Just("0".to_owned()), Just("1.5".to_owned()), Just("-2".to_owned()),
                Just("9".repeat(400)), Just("1e5".to_owned()), Just("".to_owned()), Just("6.2".to_owned()),
                Just("99999999".to_owned()), Just("0.0000001".to_owned()), Just("-".to_owned()),
            ]),
            1..40,
        )
    ) {
        let mut text = String::from("G90 G21\nG00 X0 Y0 Z5\nG01 F100\n");
        for (i, (letter, value)) in lines.iter().enumerate() {
            text.push_str(&format!("{letter}{value}"));
            text.push(if i % 3 == 2 { '\n' } else { ' ' });
        }
        match parse_program(&text) {
            Ok(p) => {
                let s = summarize(&p.toolpath);
                prop_assert!(s.cut_length_mm.is_finite() && s.rapid_length_mm.is_finite());
            }
            Err(e) => assert_clean_message(&e.to_string()),
        }
    }
}
