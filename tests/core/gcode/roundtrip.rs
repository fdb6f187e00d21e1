//! Programs out and back in: every written program is read by a small reader written here
//! (not the library's parser), G06.2 curves are evaluated by the textbook Cox–de Boor
//! recursion, and the result is measured against closed forms — the way an outside checker
//! would see our programs.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::float_cmp,
    reason = "tests: a failure should fail the test; some values are exact"
)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use crate::support::outside::{RawNurbs, feed_move, parabola_distance, seg_dist};

use glam::DVec3;
use interpolab::chords::equal_error_chords;
use interpolab::gcode::{
    CompareOptions, DesignBuilder, ProgramError, ProgramKind, ProgramOptions, ProgrammedPoint, Segment, compare,
    compare_row, crease_design, realtime_stats, write_program,
};
use interpolab::geom::Curve3;
use interpolab::nurbs_path::measure::nearest_on_curve;
use interpolab::nurbs_path::{Parabola, interpolate_realtime};

const RES: f64 = 0.001;

/// Points along the feed moves of a program (G01, G02/G03 in G17/G18/G19, G06.2), at most
/// `step` mm apart, read with a deliberately simple reader: whitespace-separated words,
/// comments in parentheses dropped, modal motion and plane, absolute coordinates.
fn read_feed_points(text: &str, step: f64) -> (Vec<DVec3>, Vec<RawNurbs>, Vec<(f64, f64)>) {
    let mut pos = DVec3::ZERO;
    let mut motion = 0.0;
    let mut plane = 17;
    let mut out = Vec::new();
    let mut curves = Vec::new();
    let mut radii = Vec::new();
    let mut nurbs: Option<RawNurbs> = None;
    let mut closing = 0;
    for raw in text.lines() {
        let line: String = {
            let mut s = String::new();
            let mut depth = 0;
            for c in raw.chars() {
                match c {
                    '(' => depth += 1,
                    ')' => depth -= 1,
                    _ if depth == 0 => s.push(c),
                    _ => {}
                }
            }
            s
        };
        let words: Vec<(char, f64)> = line
            .split_whitespace()
            .filter(|w| w.len() > 1)
            .map(|w| (w.as_bytes()[0] as char, w[1..].parse::<f64>().expect("number")))
            .collect();
        let get = |l: char| words.iter().find(|w| w.0 == l).map(|w| w.1);
        for &(l, v) in &words {
            if l == 'G' {
                match (v * 10.0).round() as i64 {
                    0 | 10 | 20 | 30 | 62 => motion = v,
                    170 => plane = 17,
                    180 => plane = 18,
                    190 => plane = 19,
                    _ => {}
                }
            }
        }
        if let Some(n) = nurbs.as_mut() {
            if words.iter().all(|w| w.0 == 'K') && !words.is_empty() {
                n.knots.push(get('K').expect("knot"));
                closing += 1;
                if closing == n.order {
                    let done = nurbs.take().expect("curve");
                    let (a, b) = (done.knots[0], done.knots[done.knots.len() - 1]);
                    let m = ((b - a) / step).ceil() as usize * 4;
                    out.extend((0..=m).map(|i| done.point(a + (b - a) * i as f64 / m as f64)));
                    pos = done.points[done.points.len() - 1];
                    curves.push(done);
                }
                continue;
            }
            if let Some(k) = get('K') {
                n.knots.push(k);
                n.points.push(DVec3::new(get('X').expect("X"), get('Y').expect("Y"), get('Z').expect("Z")));
                n.weights.push(get('R').unwrap_or(1.0));
                continue;
            }
        }
        if (motion * 10.0_f64).round() as i64 == 62 && get('P').is_some() {
            nurbs = Some(RawNurbs {
                order: get('P').expect("order") as usize,
                knots: vec![get('K').expect("knot")],
                points: vec![DVec3::new(get('X').expect("X"), get('Y').expect("Y"), get('Z').expect("Z"))],
                weights: vec![get('R').unwrap_or(1.0)],
            });
            closing = 0;
            continue;
        }
        if !words.iter().any(|w| matches!(w.0, 'X' | 'Y' | 'Z')) {
            continue;
        }
        let end = DVec3::new(get('X').unwrap_or(pos.x), get('Y').unwrap_or(pos.y), get('Z').unwrap_or(pos.z));
        let m = (motion * 10.0_f64).round() as i64;
        let ijk = [get('I').unwrap_or(0.0), get('J').unwrap_or(0.0), get('K').unwrap_or(0.0)];
        if let Some(r) = feed_move(&mut out, pos, end, m, plane, ijk, step) {
            radii.push(r);
        }
        pos = end;
    }
    (out, curves, radii)
}

/// Largest distance from the design to the polyline of program points.
fn design_to_polyline(design: &dyn Curve3, poly: &[DVec3], n: usize) -> f64 {
    let (a, b) = design.range();
    let mut worst = 0.0_f64;
    let mut j = 0usize;
    for i in 0..=n {
        let x = design.point_at(a + (b - a) * i as f64 / n as f64);
        // The program runs along the design: search near the previous match, widening.
        let mut best = f64::INFINITY;
        let mut best_j = j;
        for k in j.saturating_sub(50)..(j + 400).min(poly.len() - 1) {
            let d = seg_dist(x, poly[k], poly[k + 1]);
            if d < best {
                best = d;
                best_j = k;
            }
        }
        j = best_j;
        worst = worst.max(best);
    }
    worst
}

#[test]
fn every_program_is_within_tolerance_of_the_parabola_for_an_outside_reader() {
    let para = Parabola::paper_like();
    for tol in [0.01, 0.004] {
        for kind in ProgramKind::ALL {
            let p = write_program(kind, &para, tol, &ProgramOptions::default()).expect("program");
            let (pts, _, _) = read_feed_points(&p.text, 0.02);
            let worst = pts.iter().map(|x| parabola_distance(&para, *x)).fold(0.0, f64::max);
            assert!(worst <= tol, "{} at {tol}: a program point is {worst} mm from the parabola", kind.label());
            let back = design_to_polyline(&para, &pts, 6000);
            assert!(back <= tol, "{} at {tol}: the parabola is {back} mm from the program", kind.label());
            // The library's own measure agrees with the outside one.
            assert!(
                (p.deviation.max_mm() - worst.max(back)).abs() < 0.05 * tol,
                "{}: library {} vs outside {}",
                kind.label(),
                p.deviation.max_mm(),
                worst.max(back)
            );
        }
    }
}

#[test]
fn every_program_of_a_crease_is_within_tolerance_for_an_outside_reader() {
    for json in [
        include_str!("../../../examples/crossing-cylinders.json"),
        include_str!("../../../examples/bspline-floor-wall.json"),
    ] {
        let job = support::job(json);
        let design = crease_design(&job).expect("crease");
        let (ta, tb) = design.range();
        let dense: Vec<(f64, DVec3)> =
            (0..=4000).map(|i| ta + (tb - ta) * i as f64 / 4000.0).map(|t| (t, design.point_at(t))).collect();
        let tol = 0.01;
        for kind in ProgramKind::ALL {
            let p = write_program(kind, &design, tol, &ProgramOptions::default()).expect("program");
            let (pts, _, _) = read_feed_points(&p.text, 0.1);
            let mut worst = 0.0_f64;
            for x in &pts {
                // Foot points from the nearest sample and from the nearest sample of another
                // branch (the crease is closed: its start and end meet).
                let d = |i: usize| (dense[i].1 - *x).length();
                let i = (0..dense.len()).min_by(|&a, &b| d(a).total_cmp(&d(b))).expect("samples");
                let j = (0..dense.len())
                    .filter(|&k| k.abs_diff(i) > 10)
                    .min_by(|&a, &b| d(a).total_cmp(&d(b)))
                    .expect("samples");
                let foot = |i: usize| {
                    let lo = dense[i.saturating_sub(1)].0;
                    let hi = dense[(i + 1).min(dense.len() - 1)].0;
                    nearest_on_curve(&design, *x, dense[i].0, lo, hi).dist
                };
                worst = worst.max(foot(i).min(foot(j)));
            }
            assert!(worst <= tol, "{} ({}): {worst}", kind.label(), job.feed_mm_per_s);
            let back = design_to_polyline(&design, &pts, 3000);
            assert!(back <= tol, "{}: back {back}", kind.label());
        }
    }
}

#[test]
fn nurbs_program_read_back_reproduces_the_fitted_curve_to_the_resolution() {
    let para = Parabola::paper_like();
    let job = support::job(include_str!("../../../examples/torus-plane.json"));
    let torus = crease_design(&job).expect("crease");
    for design in [&para as &dyn Curve3, &torus] {
        let p = write_program(ProgramKind::Nurbs, design, 0.01, &ProgramOptions::default()).expect("program");
        let fitted = p.nurbs.as_ref().expect("fitted curve");
        let (_, curves, _) = read_feed_points(&p.text, 0.1);
        assert_eq!(curves.len(), 1);
        let raw = &curves[0];
        assert_eq!(raw.points.len(), fitted.len());
        assert_eq!(raw.knots.len(), fitted.len() + raw.order);
        for (k, f) in raw.knots.iter().zip(fitted.knots()) {
            assert!((k - f).abs() < 1e-9, "knot {k} vs fitted {f}: knots are fitted at the resolution");
        }
        // Control points moved by rounding at most res·√3/2, so the curve (a convex
        // combination) moves no more.
        let (a, b) = fitted.range();
        let mut worst = 0.0_f64;
        for i in 0..=5000 {
            let u = a + (b - a) * i as f64 / 5000.0;
            worst = worst.max((raw.point(u) - fitted.point_at(u)).length());
            // The library's reader gives the same curve as the textbook evaluation.
            let Segment::Nurbs(ours) = &p.parsed.toolpath.cuts().next().expect("cut").segment else {
                panic!("not a NURBS")
            };
            assert!((ours.point_at(u) - raw.point(u)).length() < 1e-9);
        }
        assert!(worst <= RES * 3f64.sqrt() / 2.0 + 1e-12, "read-back curve differs by {worst} mm");
        assert!(worst > 0.0, "rounding must show");
    }
}

#[test]
fn written_g06_2_follows_the_fanuc_rules() {
    let p =
        write_program(ProgramKind::Nurbs, &Parabola::paper_like(), 0.01, &ProgramOptions::default()).expect("program");
    let lines: Vec<&str> = p.text.lines().collect();
    let first = lines.iter().position(|l| l.starts_with("G06.2")).expect("a G06.2 block");
    assert!(
        lines[first].starts_with("G06.2 P4 K") && lines[first].contains(" F") && lines[first].contains(" R1.0"),
        "{}",
        lines[first]
    );
    // The block before positions at the first control point.
    let xyz = |l: &str| -> Vec<String> {
        l.split_whitespace().filter(|w| matches!(w.as_bytes()[0], b'X' | b'Y' | b'Z')).map(str::to_owned).collect()
    };
    let approach: Vec<String> = lines[first - 2..first].iter().flat_map(|l| xyz(l)).collect();
    for w in xyz(lines[first]) {
        assert!(approach.contains(&w), "first control point {w} is not the approach position {approach:?}");
    }
    let (_, curves, _) = read_feed_points(&p.text, 0.1);
    let c = &curves[0];
    let k = &c.knots;
    assert_eq!(c.order, 4);
    assert!(k.windows(2).all(|w| w[0] <= w[1]), "knots non-decreasing");
    assert!(k[..4].iter().all(|&x| x == k[0]) && k[k.len() - 4..].iter().all(|&x| x == k[k.len() - 1]), "clamped ends");
    assert!(k[4..k.len() - 4].windows(2).all(|w| w[0] < w[1]) && k[4] > k[0], "interior knots simple");
    // Exactly `order` closing blocks with only K, right after the last control point.
    let closing: Vec<&&str> = lines
        .iter()
        .skip(first)
        .take_while(|l| l.starts_with('K') || l.starts_with("G06.2"))
        .filter(|l| !l.contains('X'))
        .collect();
    assert_eq!(closing.len(), 4);
    assert!(c.weights.iter().all(|&w| w == 1.0));
}

#[test]
fn arc_programs_have_consistent_centres_and_radii() {
    let para = Parabola::paper_like();
    let job = support::job(include_str!("../../../examples/crossing-cylinders.json"));
    let cyl = crease_design(&job).expect("crease");
    for design in [&para as &dyn Curve3, &cyl] {
        let p = write_program(ProgramKind::Arcs, design, 0.01, &ProgramOptions::default()).expect("program");
        let (_, _, radii) = read_feed_points(&p.text, 0.1);
        assert!(!radii.is_empty());
        for (rs, re) in &radii {
            // Start and end on one circle: rounding the end and the centre offsets moves the
            // radii apart by at most res·√2.
            assert!((rs - re).abs() <= RES * 2f64.sqrt() + 1e-12, "radius {rs} at the start, {re} at the end");
        }
    }
    // The crossing cylinders' crease is a space curve: arcs there are helical or in G18/G19.
    let p = write_program(ProgramKind::Arcs, &cyl, 0.01, &ProgramOptions::default()).expect("program");
    assert!(
        p.text.contains("G18")
            || p.text.contains("G19")
            || p.text.lines().filter(|l| l.contains("G02") || l.contains("G03")).any(|l| l.contains('Z'))
    );
}

#[test]
fn g01_blocks_are_the_equal_error_chords() {
    let para = Parabola::paper_like();
    let p = write_program(ProgramKind::Lines, &para, 0.01, &ProgramOptions::default()).expect("program");
    let nodes = equal_error_chords(&para, p.fit_tol_mm).expect("chords");
    assert_eq!(p.path_blocks, nodes.len() - 1);
    assert_eq!(p.text.lines().filter(|l| l.starts_with("G01")).count(), nodes.len() - 1);
}

#[test]
fn tip_program_is_the_centre_program_lowered_by_the_ball_radius() {
    let job = support::job(include_str!("../../../examples/bspline-floor-wall.json"));
    let design = crease_design(&job).expect("crease");
    let r = job.ball_radius_mm;
    let centre = write_program(ProgramKind::Nurbs, &design, 0.01, &ProgramOptions::default()).expect("program");
    let tip = write_program(
        ProgramKind::Nurbs,
        &design,
        0.01,
        &ProgramOptions::default().with_point(ProgrammedPoint::BallTip { radius_mm: r }),
    )
    .expect("program");
    let marker = format!("(PROGRAMMED POINT: BALL TIP = BALL CENTRE - Z {})", interpolab::report::fmt_fixed(r, 6));
    assert!(tip.text.contains(&marker), "{}", tip.text);
    let (_, cc, _) = read_feed_points(&centre.text, 0.1);
    let (_, tc, _) = read_feed_points(&tip.text, 0.1);
    assert_eq!(cc[0].points.len(), tc[0].points.len());
    for (a, b) in cc[0].points.iter().zip(&tc[0].points) {
        assert!((*a - DVec3::new(0.0, 0.0, r) - *b).length() < 1e-9, "{a} vs {b}");
    }
    assert!(tip.deviation.max_mm() <= 0.01);
}

#[test]
fn numbers_are_written_at_the_resolution_with_a_decimal_point() {
    let para = Parabola::paper_like();
    for kind in ProgramKind::ALL {
        let p = write_program(kind, &para, 0.01, &ProgramOptions::default()).expect("program");
        for line in p.text.lines().filter(|l| !l.starts_with('(') && !l.starts_with('%')) {
            for w in line.split_whitespace() {
                let (l, v) = w.split_at(1);
                if matches!(l, "X" | "Y" | "Z" | "I" | "J" | "K" | "F" | "R") {
                    let dot = v.find('.').unwrap_or_else(|| panic!("{w} in '{line}' has no decimal point"));
                    assert!(v.len() - dot - 1 <= 3, "{w} has more decimals than the resolution");
                    assert!(v != "-0.0", "negative zero in '{line}'");
                }
            }
        }
    }
}

#[test]
fn programs_are_deterministic() {
    let para = Parabola::paper_like();
    for kind in ProgramKind::ALL {
        let a = write_program(kind, &para, 0.005, &ProgramOptions::default()).expect("program");
        let b = write_program(kind, &para, 0.005, &ProgramOptions::default()).expect("program");
        assert_eq!(a.text, b.text);
    }
}

#[test]
fn golden_g06_2_program_of_the_parabola() {
    let p = write_program(
        ProgramKind::Nurbs,
        &Parabola::paper_like(),
        0.01,
        &ProgramOptions::default().with_title("parabola y = x^2/40, x from -60 to 60 mm"),
    )
    .expect("program");
    assert_eq!(p.text, include_str!("../../data/gcode/parabola/g06_2_tol0.01.nc"));
}

#[test]
fn impossible_requests_are_refused_with_the_fix() {
    let para = Parabola::paper_like();
    let e = write_program(ProgramKind::Lines, &para, 0.0015, &ProgramOptions::default()).unwrap_err();
    assert!(matches!(e, ProgramError::BelowResolution { .. }) && e.to_string().contains("at least 0.002"), "{e}");
    let e =
        write_program(ProgramKind::Nurbs, &para, 0.01, &ProgramOptions::default().with_resolution(0.002)).unwrap_err();
    assert!(matches!(e, ProgramError::BadResolution(_)), "{e}");
    let e = write_program(ProgramKind::Nurbs, &para, 0.01, &ProgramOptions::default().with_degree(4)).unwrap_err();
    assert!(matches!(e, ProgramError::Degree(4)) && e.to_string().contains("P2 to P4"), "{e}");
    let e = write_program(ProgramKind::Arcs, &para, -1.0, &ProgramOptions::default()).unwrap_err();
    assert!(matches!(e, ProgramError::BadTolerance(_)), "{e}");
    // A finer resolution admits a finer tolerance.
    let p = write_program(ProgramKind::Nurbs, &para, 0.0015, &ProgramOptions::default().with_resolution(0.0001))
        .expect("program");
    assert!(p.deviation.max_mm() <= 0.0015);
}

#[test]
fn comparison_rows_match_their_programs() {
    let para = Parabola::paper_like();
    let c = compare(&para, 0.01, &CompareOptions::default()).expect("comparison");
    assert_eq!(c.rows.len(), 3);
    for r in &c.rows {
        assert_eq!(r.path_blocks, r.program.parsed.path_blocks(), "{}", r.kind.label());
        assert_eq!(r.bytes, r.program.text.len());
        assert!(r.deviation_mm <= 0.01);
    }
    let blocks: Vec<usize> = c.rows.iter().map(|r| r.path_blocks).collect();
    // Seed 004: the NURBS program is 50–80 % shorter than the G01 program.
    let saving = 1.0 - blocks[2] as f64 / blocks[0] as f64;
    assert!((0.5..=0.8).contains(&saving), "G06.2 saves {:.0} % of the G01 blocks ({blocks:?})", 100.0 * saving);
    // A C² curve has no junctions; a polyline turns at every one.
    assert_eq!(c.rows[2].junctions.count, 0);
    assert!(c.rows[0].junctions.max_turn_deg > 1.0);
    assert_eq!(c.realtime.len(), 3);
    assert!(
        c.realtime[2].max_fluctuation < c.realtime[1].max_fluctuation
            && c.realtime[1].max_fluctuation < c.realtime[0].max_fluctuation
    );
}

/// The app runs the comparison one program per frame; the steps must give what `compare`
/// gives in one call.
#[test]
fn comparison_run_step_by_step_equals_the_one_call() {
    let para = Parabola::paper_like();
    let delta = 2e-5;
    let opts = CompareOptions { chord_tol_mm: Some(delta), ..CompareOptions::default() };
    let whole = compare(&para, 0.02, &opts).expect("comparison");
    let mut realtime = Vec::new();
    for (kind, row) in ProgramKind::ALL.into_iter().zip(&whole.rows) {
        let step = compare_row(kind, &para, 0.02, &opts).expect("row");
        assert_eq!(step.kind, row.kind);
        assert_eq!(step.program.text, row.program.text, "{}", kind.label());
        assert_eq!((step.path_blocks, step.total_blocks, step.bytes), (row.path_blocks, row.total_blocks, row.bytes));
        assert_eq!(step.deviation_mm, row.deviation_mm);
        assert_eq!(step.junctions, row.junctions);
        let stats = realtime_stats(&step.program, &opts);
        // Only the G06.2 program has a curve to run, one entry per update.
        assert_eq!(stats.len(), if kind == ProgramKind::Nurbs { 3 } else { 0 }, "{}", kind.label());
        assert_eq!(step.program.read_back_curves().count(), usize::from(kind == ProgramKind::Nurbs));
        realtime.extend(stats);
    }
    assert_eq!(realtime, whole.realtime);
    // The run with kept samples (what the app plots) has the table's statistics.
    let curve = whole.rows[2].program.read_back_curves().next().expect("a G06.2 curve");
    for s in &whole.realtime {
        let run = interpolate_realtime(curve, &opts.realtime(s.update).with_samples(true)).expect("runs");
        assert_eq!(run.stats, *s, "{}", s.update.as_str());
        assert_eq!(run.samples.len() as u64, s.periods);
    }
    // The chord tolerance reaches the runs: at the parabola's vertex (radius 20 mm) a step of
    // f = 0.1 mm errs by f²/(8ρ) = 6.25e-5 mm, so δ = 2e-5 mm lowers the feed there, and the
    // limit holds the chord error to δ.
    for s in &whole.realtime {
        assert!(s.limited_periods > 0, "{}", s.update.as_str());
        assert!(s.max_chord_error_mm <= 1.01 * delta, "{}: {}", s.update.as_str(), s.max_chord_error_mm);
    }
}

/// The reported line of the largest deviation is a cutting block of the final text (the
/// header comment that reports the deviation must not shift it).
#[test]
fn the_worst_deviation_line_is_a_cutting_block_of_the_text() {
    let para = Parabola::paper_like();
    for numbered in [false, true] {
        let opts = ProgramOptions::default().with_line_numbers(numbered);
        for kind in ProgramKind::ALL {
            let p = write_program(kind, &para, 0.01, &opts).expect("program");
            let line = p.deviation.program_line;
            let text = p.text.lines().nth(line - 1).expect("the line exists");
            let cut = p.parsed.toolpath.cuts().any(|b| b.line == line);
            assert!(cut, "{} (numbered {numbered}): line {line} is '{text}'", kind.label());
            let code = match kind {
                ProgramKind::Lines => "G01",
                ProgramKind::Arcs => "G0",
                ProgramKind::Nurbs => "G06.2",
            };
            assert!(text.contains(code), "{}: line {line} is '{text}'", kind.label());
        }
    }
}

/// The app builds the design path a few thousand periods per frame: the result is the one
/// `crease_design` (and so the command line) gives.
#[test]
fn the_design_built_in_steps_is_the_crease_design() {
    let job = support::job(include_str!("../../../examples/sphere-plane.json"));
    let whole = crease_design(&job).expect("design");
    let mut builder = DesignBuilder::new(&job).expect("starts");
    let mut calls = 0;
    let built = loop {
        if let Some(d) = builder.advance(250) {
            break d.expect("design");
        }
        calls += 1;
        assert_eq!(builder.periods(), 250 * calls);
    };
    assert!(calls > 3, "the run took {calls} calls");
    assert_eq!(built.path(), whole.path());
}
