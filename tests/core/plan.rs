//! The planned interpolator checked from its periods alone, with code that shares nothing
//! with the planner but the canonical motions: every joint's velocity, acceleration and jerk
//! by differences of the positions (`plan::check`, which reads only positions and limits),
//! every period within the contour tolerance of the *programmed* path (distances computed
//! here from the canonical motions), and the end at rest exactly on the programmed end.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use interpolab::gcode::interp::{Canon, Interpreter, Options};
use interpolab::gcode::{ProgramKind, ProgramOptions, write_program};
use interpolab::nurbs_path::Parabola;
use interpolab::plan::{Dynamics, LimitChecker, Period, canon_of_toolpath, time_program};

fn programs() -> Vec<(String, Vec<Canon>)> {
    let mut out = Vec::new();
    let design = Parabola::paper_like();
    for kind in ProgramKind::ALL {
        let p = write_program(kind, &design, 0.01, &ProgramOptions::default().with_feed(1500.0)).expect("program");
        out.push((format!("parabola {kind:?}"), canon_of_toolpath(&p.parsed.toolpath)));
    }
    for (name, text) in [
        ("corners", include_str!("../data/plan/corners.nc")),
        ("5axis-rotary", include_str!("../data/plan/5axis-rotary.nc")),
    ] {
        let canon: Vec<Canon> = Interpreter::from_text(text, Options::default()).map(|c| c.expect("reads")).collect();
        out.push((name.to_owned(), canon));
    }
    out
}

/// The programmed path as a dense polyline per motion (lines exact; arcs and splines with
/// chords below 1e-5 mm of sagitta), to measure distances from.
fn programmed(canon: &[Canon]) -> Vec<Vec<DVec3>> {
    let mut pos = DVec3::ZERO;
    let mut out = Vec::new();
    for c in canon {
        match c {
            Canon::Traverse { end, .. } | Canon::Line { end, .. } => {
                out.push(vec![pos, end.xyz]);
                pos = end.xyz;
            }
            Canon::Arc { end, center, plane, turns, .. } => {
                let (ia, ib, inn) = plane.axes();
                let a0 = (pos[ib] - center[ib]).atan2(pos[ia] - center[ia]);
                let a1 = (end.xyz[ib] - center[ib]).atan2(end.xyz[ia] - center[ia]);
                let tau = std::f64::consts::TAU;
                let mut sweep = if *turns > 0 { (a1 - a0).rem_euclid(tau) } else { -(a0 - a1).rem_euclid(tau) };
                if sweep.abs() < 1e-12 {
                    sweep = tau * f64::from(turns.signum());
                }
                sweep += f64::from(turns.unsigned_abs() - 1) * tau * f64::from(turns.signum());
                let r0 = ((pos[ia] - center[ia]).powi(2) + (pos[ib] - center[ib]).powi(2)).sqrt();
                let r1 = ((end.xyz[ia] - center[ia]).powi(2) + (end.xyz[ib] - center[ib]).powi(2)).sqrt();
                let n = ((sweep.abs() * r0.max(r1)) / 0.05).ceil().max(4.0) as usize;
                let mut pts = Vec::with_capacity(n + 1);
                for k in 0..=n {
                    let t = k as f64 / n as f64;
                    let th = a0 + sweep * t;
                    let r = r0 + (r1 - r0) * t;
                    let mut p = DVec3::ZERO;
                    p[ia] = center[ia] + r * th.cos();
                    p[ib] = center[ib] + r * th.sin();
                    p[inn] = pos[inn] + (end.xyz[inn] - pos[inn]) * t;
                    pts.push(p);
                }
                out.push(pts);
                pos = end.xyz;
            }
            Canon::Spline { curve, end, .. } => {
                let (u0, u1) = curve.range();
                let n = 20_000;
                out.push((0..=n).map(|k| curve.point_at(u0 + (u1 - u0) * k as f64 / n as f64)).collect());
                pos = end.xyz;
            }
            _ => {}
        }
    }
    out
}

fn dist_seg(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 { ((p - a).dot(ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
    (a + ab * t - p).length()
}

#[test]
fn every_period_is_within_the_limits_the_tolerance_and_ends_at_rest_on_the_end() {
    for (name, canon) in programs() {
        let moves = programmed(&canon);
        let end = canon.iter().rev().find_map(Canon::end).expect("moves");
        for mname in ["hobby-router", "vmc", "table-ac"] {
            for jerk in [true, false] {
                let mut m = Dynamics::preset(mname).expect("preset");
                if !jerk {
                    m = m.without_jerk();
                }
                let t = time_program(canon.iter().cloned(), &m).expect("plans");
                let lim = m.joint_limits();
                let mut check = LimitChecker::new(lim, m.period_s(), 1e-10);
                let mut s = t.sampler();
                let mut p = Period::default();
                let mut worst_dev: f64 = 0.0;
                let mut near = 0usize;
                let mut last = p;
                while s.next_period(&mut p) {
                    check.push(&p.q);
                    // Distance to the programmed path: the nearest of the motions around the
                    // last nearest one (the tool moves forward along the program).
                    let x = DVec3::new(p.q[0], p.q[1], p.q[2]);
                    let mut best = (f64::INFINITY, near);
                    for (i, mv) in moves.iter().enumerate().skip(near.saturating_sub(2)).take(6) {
                        for w in mv.windows(2) {
                            let d = dist_seg(x, w[0], w[1]);
                            if d < best.0 {
                                best = (d, i);
                            }
                        }
                    }
                    near = best.1;
                    worst_dev = worst_dev.max(best.0);
                    last = p;
                }
                let rep = check.finish();
                assert!(rep.within(), "{name} on {mname} (jerk {jerk}): a joint limit broken: {rep:?}");
                assert!(
                    worst_dev <= m.tolerance_mm + 2e-5,
                    "{name} on {mname}: a period {worst_dev} mm from the programmed path (P = {})",
                    m.tolerance_mm
                );
                let r = std::f64::consts::PI / 180.0;
                let want = [end.xyz.x, end.xyz.y, end.xyz.z, end.abc.x * r, end.abc.y * r, end.abc.z * r];
                assert_eq!(last.q, want, "{name} on {mname}: the last period is not on the programmed end");
                assert_eq!(rep.end_rates, [0.0, 0.0], "{name}: not at rest at the end");
                assert!(t.total_s() > 0.0 && t.block_time_s.iter().all(|b| *b >= 0.0));
                let sum: f64 = t.block_time_s.iter().sum();
                assert!(
                    (sum - t.total_s()).abs() < 1e-9 * t.total_s(),
                    "{name}: block times {sum} vs total {}",
                    t.total_s()
                );
            }
        }
    }
}

#[test]
fn a_short_window_is_never_faster_and_the_whole_program_is_the_fastest() {
    let (_, canon) = programs().swap_remove(0);
    let base = Dynamics::preset("hobby-router").expect("preset");
    let whole = time_program(canon.iter().cloned(), &base).expect("plans").total_s();
    let mut prev = f64::INFINITY;
    for w in [1usize, 2, 5, 20, 200] {
        let mut m = base.clone();
        m.window_blocks = Some(w);
        let t = time_program(canon.iter().cloned(), &m).expect("plans").total_s();
        assert!(t >= whole - 1e-9, "window {w}: {t} s faster than the whole program's {whole} s");
        assert!(t <= prev + 1e-9, "window {w}: {t} s slower than a shorter window's {prev} s");
        prev = t;
    }
}

#[test]
fn exact_stop_is_slower_than_blending_and_stops_at_every_corner() {
    let (_, canon) = programs().swap_remove(0);
    let m = Dynamics::preset("vmc").expect("preset");
    let blended = time_program(canon.iter().cloned(), &m).expect("plans");
    let mut stop = m.clone();
    stop.exact_stop = true;
    let stopped = time_program(canon.iter().cloned(), &stop).expect("plans");
    assert!(stopped.total_s() > blended.total_s());
    assert_eq!(stopped.path.blends, 0);
    assert!(stopped.path.corner_stops >= blended.path.blends);
}

#[test]
fn bad_machines_are_refused_naming_the_key() {
    let mut m = Dynamics::preset("vmc").expect("preset");
    m.axes[1].acceleration = -3.0;
    let e = m.validate().expect_err("refused");
    assert_eq!(e.path, "axes.y.acceleration");
    m.axes[1].acceleration = f64::NAN;
    assert!(m.validate().is_err());
    let mut m = Dynamics::preset("vmc").expect("preset");
    m.tolerance_mm = 1e6;
    assert_eq!(m.validate().expect_err("refused").path, "tolerance");
    for bad in [
        r#"{"axes": {"q": {}}}"#,
        r#"{"axes": {"x": {"jerk": 0}}}"#,
        r#"{"period": 0}"#,
        r#"{"lookahead": 0}"#,
        r#"{"preset": "mill"}"#,
    ] {
        let v: serde_json::Value = serde_json::from_str(bad).expect("json");
        let e = Dynamics::from_value(&v).expect_err(bad);
        assert!(
            !e.to_string().contains('\n') && e.to_string().contains("give") || e.to_string().contains("use"),
            "{e}"
        );
    }
    // A machine read back from its own JSON is the same machine.
    for p in interpolab::plan::PRESETS {
        let m = Dynamics::preset(p).expect("preset");
        assert_eq!(Dynamics::from_value(&m.to_value()).expect("reads"), m);
    }
}

#[test]
fn a_scene_carries_its_machine_dynamics_and_old_scenes_still_read() {
    use interpolab::scene::Scene;
    let base = include_str!("../../examples/torus-plane.json");
    let old = Scene::from_json(base).expect("an example without dynamics still reads");
    assert_eq!(old.dynamics, None);
    let mut v: serde_json::Value = serde_json::from_str(base).expect("json");
    v["dynamics"] = serde_json::json!({ "preset": "hobby-router", "axes": { "x": { "jerk": null } }, "tolerance": 0.02, "lookahead": 40 });
    let s = Scene::from_json(&v.to_string()).expect("reads");
    let d = s.dynamics.clone().expect("dynamics");
    assert_eq!(
        (d.name.as_str(), d.axes[0].jerk, d.tolerance_mm, d.window_blocks),
        ("hobby-router", None, 0.02, Some(40))
    );
    // Written and read back: the same scene.
    assert_eq!(Scene::from_json(&s.to_json()).expect("round trip"), s);
    v["dynamics"]["axes"]["y"] = serde_json::json!({ "acceleration": -3 });
    let e = Scene::from_json(&v.to_string()).expect_err("refused");
    assert!(e.to_string().starts_with("dynamics.axes.y.acceleration: must be > 0"), "{e}");
}

/// A zig-zag of `n` G1 moves alternating ±50° from X (every corner turns 100°), after a
/// rapid to the start; the first feed move is on line 4.
fn zigzag(n: usize) -> String {
    let (c, s) = (50f64.to_radians().cos(), 50f64.to_radians().sin());
    let mut text = String::from("G21 G90 G64 P0.01\nG0 X0 Y0 Z1\nF3000\n");
    let mut y = 0.0;
    for k in 0..n {
        y += if k % 2 == 0 { s } else { -s };
        text.push_str(&format!("G1 X{:.6} Y{y:.6}\n", c * (k + 1) as f64));
    }
    text
}

fn read(text: &str) -> Vec<Canon> {
    Interpreter::from_text(text, Options::default()).map(|c| c.expect("reads")).collect()
}

#[test]
fn the_pieces_counted_while_reading_bound_the_path_and_equal_it_on_blended_lines() {
    let mut programs = programs();
    programs.push(("zig-zag".to_owned(), read(&zigzag(40))));
    // Corners of whole 15° steps (45°, 90°, 135°), where the blend's turn and the corner's
    // may differ in their last bit.
    let steps = "G21 G90 G0 X0 Y0\nG1 F2000 X10\nX20 Y10\nY20\nX10 Y10\nX0 Y20\nX-10 Y20\nY0\nX0 Y-10\n";
    programs.push(("whole steps".to_owned(), read(steps)));
    for (name, canon) in programs {
        for mname in ["hobby-router", "vmc", "table-ac"] {
            for (jerk, exact) in [(true, false), (false, false), (true, true)] {
                let mut m = Dynamics::preset(mname).expect("preset");
                m.exact_stop = exact;
                if !jerk {
                    m = m.without_jerk();
                }
                let t = time_program(canon.iter().cloned(), &m).expect("plans");
                let (n, bound) = (t.path.pieces.len(), t.path.pieces_bound);
                assert!(n <= bound, "{name} on {mname} (exact stop {exact}): {n} pieces over the bound {bound}");
                if name == "zig-zag" {
                    // 1 for the rapid, then 1 a line and, unless stopped, 1 + ⌈100°/15°⌉ = 8
                    // for each of the 39 corners, all blended on these machines.
                    let want = 1 + 40 + if exact { 0 } else { 39 * 8 };
                    assert_eq!((n, bound), (want, want), "{name} on {mname} (exact stop {exact})");
                }
            }
        }
    }
}

#[test]
fn a_program_past_the_piece_cap_is_refused_at_the_line_that_passes_it() {
    use interpolab::plan::PlanError;
    use interpolab::plan::path::MAX_PIECES;
    // Each move after the first adds 9 pieces: past the cap at move k when 1 + 1 + 9(k−1)
    // passes it.
    let k = (MAX_PIECES - 2) / 9 + 2;
    let text = zigzag(k + 10);
    let m = Dynamics::preset("vmc").expect("preset");
    let err = time_program(read(&text), &m).expect_err("over the cap");
    let line = 3 + k as u32;
    assert_eq!(err, PlanError::TooLarge { line, max: MAX_PIECES });
    assert!(err.to_string().starts_with(&format!("line {line}: ")), "{err}");
    // One move fewer is a path (built, not planned: the plan of 1.5 million pieces is the
    // benchmark's work, not a test's).
    let rules = interpolab::plan::JunctionRules { tol_mm: m.tolerance_mm, exact_stop: false, jerk_limited: true };
    let path = interpolab::plan::path::build(read(&zigzag(k - 1)), &rules).expect("a path");
    assert_eq!(path.pieces.len(), path.pieces_bound);
    assert!(path.pieces_bound <= MAX_PIECES && path.pieces_bound + 9 > MAX_PIECES);
}

#[test]
fn a_program_read_as_it_is_planned_times_the_same_and_stops_at_the_first_read_error() {
    use interpolab::plan::{Stopped, time_read};
    let m = Dynamics::preset("vmc").expect("preset");
    let text = include_str!("../data/plan/corners.nc");
    let whole = time_program(read(text), &m).expect("plans");
    let streamed = time_read(Interpreter::from_text(text, Options::default()), &m).expect("plans");
    assert_eq!(streamed.total_s().to_bits(), whole.total_s().to_bits());
    assert_eq!(streamed.block_time_s, whole.block_time_s);
    // A bad word on line 9: the interpreter's error, with its line, and nothing planned.
    let bad = text.replacen("G01 X10.0\n", "G01 X10.0 X11.0\n", 1);
    match time_read(Interpreter::from_text(&bad, Options::default()), &m) {
        Err(Stopped::Read(e)) => assert_eq!(e.loc.line, 9, "{e}"),
        other => panic!("expected the reader's error, got {other:?}"),
    }
}

/// The planner's cube root is `f64::cbrt` bit for bit: on random doubles over the whole
/// exponent range, exact cubes, inputs next to the cubes of midpoints between doubles (where
/// rounding is closest to a tie), and the special values; and it rarely needs the fallback.
#[test]
fn the_planners_cube_root_is_f64_cbrt_bit_for_bit() {
    use interpolab::plan::scurve::cbrt;
    let same = |x: f64| {
        let (a, b) = (cbrt(x), x.cbrt());
        assert!(a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan()), "cbrt({x:e}): {a:e}, f64::cbrt {b:e}");
    };
    for x in [0.0, -0.0, 1.0, 8.0, 27.0, 0.125, f64::MIN_POSITIVE, 5e-324, f64::MAX, f64::INFINITY, f64::NAN, -8.0] {
        same(x);
        same(-x);
    }
    let mut seed = 0x9E37_79B9_7F4A_7C15u64;
    let mut next = || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        seed
    };
    for _ in 0..30_000 {
        // Any positive normal double, and one in the planner's range (1e-6 to 1e12).
        same(f64::from_bits(next() % 0x7FF0_0000_0000_0000));
        let x = 10f64.powf(-6.0 + 18.0 * (next() >> 11) as f64 / (1u64 << 53) as f64);
        same(x);
        // Near exact cubes and near the cubes of midpoints: y³ and (y + ulp/2)³, rounded,
        // and their neighbours.
        let y = 1.0 + (next() >> 12) as f64 / (1u64 << 52) as f64;
        // (y + ulp/2)³ = y³ + 1.5·y²·ulp + O(ulp²), ulp = 2^-52 on [1, 2).
        let mid = y * y * y + 1.5 * y * y * f64::EPSILON;
        for c in [y * y * y, mid, 8.0 * mid, 4.0 * mid, 3.0 * y * y * y * 1.000_000_1] {
            let b = c.to_bits();
            for d in 0..3 {
                same(f64::from_bits(b + d));
                same(f64::from_bits(b - d));
            }
        }
    }
}

/// An arc's length as the path builds it (its pieces' table, from the speed along the arc
/// without a sine or cosine) against closed forms: a helix of two turns, r = 5 mm, rising
/// 3 mm, is √((2·2π·5)² + 3²); a half turn whose radius grows from 5 to 5.004 mm (an end
/// point off the circle, as rounded programs have, within the interpreter's tolerance) is the integral of √(dr² + r(t)²·π²)
/// over t, summed here by Simpson's rule on 20 000 intervals.
#[test]
fn arc_lengths_match_their_closed_forms() {
    let rules = interpolab::plan::JunctionRules { tol_mm: 0.01, exact_stop: true, jerk_limited: true };
    let text = "G21 G90 G17\nG0 X5 Y0 Z0\nG3 X5 Y0 Z3 I-5 J0 P2 F600\nM30\n";
    let path = interpolab::plan::path::build(read(text), &rules).expect("a path");
    let helix = (2.0 * std::f64::consts::TAU * 5.0f64).hypot(3.0);
    let arc = path.blocks.iter().find(|b| !b.rapid).expect("the arc's block");
    assert!((arc.len - helix).abs() < 1e-9 * helix, "{} against {helix}", arc.len);

    let text = "G21 G90 G17\nG0 X5 Y0 Z0\nG3 X-5.004 Y0 I-5 J0 F600\nM30\n";
    let path = interpolab::plan::path::build(read(text), &rules).expect("a path");
    let (dr, sweep) = (0.004f64, std::f64::consts::PI);
    let speed = |t: f64| (dr * dr + ((5.0 + dr * t) * sweep).powi(2)).sqrt();
    let n = 20_000;
    let h = 1.0 / f64::from(n);
    let simpson = (0..=n)
        .map(|k| {
            let w = if k == 0 || k == n {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * speed(f64::from(k) * h)
        })
        .sum::<f64>()
        * h
        / 3.0;
    let arc = path.blocks.iter().find(|b| !b.rapid).expect("the arc's block");
    assert!((arc.len - simpson).abs() < 1e-9 * simpson, "{} against {simpson}", arc.len);
}
