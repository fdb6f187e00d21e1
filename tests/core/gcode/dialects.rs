//! The three controller dialects (FANUC G06.2, Sinumerik 840D BSPLINE, LinuxCNC G5.2): every
//! program is re-read by a small reader written here from the controllers' rules (not the
//! library's parser) — Sinumerik knots from one `PL` per span, LinuxCNC knots by the rule of
//! its `nurbs_G5_knot_vector_creator` — evaluated by a textbook Cox–de Boor recursion, and
//! measured against closed forms and brute force.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::float_cmp,
    reason = "tests: a failure should fail the test; some values are exact"
)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support::outside::{RawNurbs, feed_move, parabola_distance, seg_dist};
use glam::DVec3;
use interpolab::gcode::{Dialect, ProgramError, ProgramKind, ProgramOptions, Segment, parse_program_in, write_program};
use interpolab::geom::Curve3;
use interpolab::nurbs_path::Parabola;

/// LinuxCNC's implied knots for `cps` control points of order k, written out as its source
/// builds them: index i from 0 to n + k (n = cps − 1) is 0 below k, i − k + 1 up to n, and
/// n − k + 2 after.
fn linuxcnc_knots(cps: usize, k: usize) -> Vec<f64> {
    let n = cps - 1;
    (0..=n + k)
        .map(|i| {
            if i < k {
                0.0
            } else if i <= n {
                (i - k + 1) as f64
            } else {
                (n - k + 2) as f64
            }
        })
        .collect()
}

/// Sinumerik knots for equal intervals `pl`: clamped, degree + 1 equal end knots.
fn sinumerik_knots(cps: usize, degree: usize, pl: f64) -> Vec<f64> {
    let spans = cps - degree;
    let mut k = vec![0.0; degree + 1];
    for j in 1..spans {
        k.push(j as f64 * pl);
    }
    k.extend(std::iter::repeat_n(spans as f64 * pl, degree + 1));
    k
}

/// Points along the feed moves of a program at most `step` mm apart, and its NURBS curves:
/// whitespace-separated words (`NAME=value` or letter + number), comments `( … )` and `; …`
/// dropped, modal motion and plane, absolute coordinates, IJK arc centres.
fn read_feed_points(text: &str, dialect: Dialect, step: f64) -> (Vec<DVec3>, Vec<RawNurbs>) {
    let mut pos = DVec3::ZERO;
    let mut motion = 0i64;
    let mut plane = 17;
    let mut out = Vec::new();
    let mut curves: Vec<RawNurbs> = Vec::new();
    // An open spline: degree, points, weights, PL.
    let mut spline: Option<(usize, Vec<DVec3>, Vec<f64>, f64)> = None;
    let mut close = |sp: (usize, Vec<DVec3>, Vec<f64>, f64), out: &mut Vec<DVec3>, pos: &mut DVec3| {
        let (degree, points, weights, pl) = sp;
        let knots = match dialect {
            Dialect::LinuxCnc => linuxcnc_knots(points.len(), degree + 1),
            _ => sinumerik_knots(points.len(), degree, pl),
        };
        let raw = RawNurbs { order: degree + 1, knots, points, weights };
        let (a, b) = raw.range();
        let m = 4000;
        out.extend((0..=m).map(|i| raw.point(a + (b - a) * i as f64 / m as f64)));
        *pos = raw.points[raw.points.len() - 1];
        curves.push(raw);
    };
    for raw_line in text.lines() {
        let mut line = String::new();
        let mut depth = 0;
        for c in raw_line.chars() {
            match c {
                ';' if depth == 0 => break,
                '(' => depth += 1,
                ')' => depth -= 1,
                _ if depth == 0 => line.push(c),
                _ => {}
            }
        }
        let words: Vec<(String, f64)> = line
            .split_whitespace()
            .filter(|w| *w != "%")
            .map(|w| match w.split_once('=') {
                Some((name, v)) => (name.to_owned(), v.parse::<f64>().expect("number")),
                None if w.chars().all(|c| c.is_ascii_alphabetic()) => (w.to_owned(), 0.0),
                None => (w[..1].to_owned(), w[1..].parse::<f64>().expect("number")),
            })
            .collect();
        let get = |l: &str| words.iter().find(|w| w.0 == l).map(|w| w.1);
        let mut new_motion = None;
        let mut opens = words.iter().any(|w| w.0 == "BSPLINE");
        let mut closes = false;
        for (l, v) in &words {
            if l == "G" {
                match (v * 10.0).round() as i64 {
                    m @ (0 | 10 | 20 | 30) => new_motion = Some(m),
                    52 => opens = true,
                    53 => closes = true,
                    170 => plane = 17,
                    180 => plane = 18,
                    190 => plane = 19,
                    _ => {}
                }
            }
        }
        if new_motion.is_some()
            && let Some(sp) = spline.take()
        {
            // A Sinumerik BSPLINE ends at the next motion command.
            close(sp, &mut out, &mut pos);
        }
        if let Some(m) = new_motion {
            motion = m;
        }
        if opens && spline.is_none() {
            let degree = match dialect {
                Dialect::LinuxCnc => get("L").unwrap_or(3.0) as usize - 1,
                _ => get("SD").unwrap_or(3.0) as usize,
            };
            spline = Some((degree, vec![pos], vec![1.0], 1.0));
        }
        if closes {
            close(spline.take().expect("G5.3 closes a G5.2 curve"), &mut out, &mut pos);
            continue;
        }
        if let Some(sp) = spline.as_mut() {
            if let Some(pl) = get("PL") {
                sp.3 = pl;
            }
            if ["X", "Y", "Z"].iter().any(|l| get(l).is_some()) {
                let last = sp.1[sp.1.len() - 1];
                sp.1.push(DVec3::new(
                    get("X").unwrap_or(last.x),
                    get("Y").unwrap_or(last.y),
                    get("Z").unwrap_or(last.z),
                ));
                sp.2.push(get("PW").or_else(|| get("P")).unwrap_or(1.0));
            }
            continue;
        }
        if !words.iter().any(|w| matches!(w.0.as_str(), "X" | "Y" | "Z")) {
            continue;
        }
        let end = DVec3::new(get("X").unwrap_or(pos.x), get("Y").unwrap_or(pos.y), get("Z").unwrap_or(pos.z));
        let ijk = [get("I").unwrap_or(0.0), get("J").unwrap_or(0.0), get("K").unwrap_or(0.0)];
        feed_move(&mut out, pos, end, motion, plane, ijk, step);
        pos = end;
    }
    if let Some(sp) = spline.take() {
        close(sp, &mut out, &mut pos);
    }
    (out, curves)
}

/// Largest distance from `n + 1` design points to the program polyline (brute force).
fn design_to_polyline(design: &dyn Curve3, poly: &[DVec3], n: usize) -> f64 {
    let (a, b) = design.range();
    (0..=n)
        .map(|i| {
            let x = design.point_at(a + (b - a) * i as f64 / n as f64);
            poly.windows(2).map(|w| seg_dist(x, w[0], w[1])).fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// A helix: radius 30 mm, rising 4 mm per radian, three quarters of a turn — a space curve
/// whose Z varies far beyond any tolerance.
struct Helix;

impl Curve3 for Helix {
    fn derivatives_at(&self, t: f64) -> [DVec3; 3] {
        let (s, c) = t.sin_cos();
        [
            DVec3::new(30.0 * c, 30.0 * s, 4.0 * t),
            DVec3::new(-30.0 * s, 30.0 * c, 4.0),
            DVec3::new(-30.0 * c, -30.0 * s, 0.0),
        ]
    }
    fn range(&self) -> (f64, f64) {
        (0.0, 1.5 * std::f64::consts::PI)
    }
}

/// Distance from p to the helix: the nearest of 4000 samples, then golden section between
/// its neighbours.
fn helix_distance(p: DVec3) -> f64 {
    let (a, b) = Helix.range();
    let n: usize = 4000;
    let d = |t: f64| (Helix.point_at(t) - p).length();
    let i =
        (0..=n).min_by(|&i, &j| d(a + (b - a) * i as f64 / n as f64).total_cmp(&d(a + (b - a) * j as f64 / n as f64)));
    let i = i.expect("samples");
    let (mut lo, mut hi) =
        (a + (b - a) * i.saturating_sub(1) as f64 / n as f64, a + (b - a) * (i + 1).min(n) as f64 / n as f64);
    for _ in 0..80 {
        let m1 = lo + (hi - lo) * 0.382;
        let m2 = lo + (hi - lo) * 0.618;
        if d(m1) <= d(m2) {
            hi = m2;
        } else {
            lo = m1;
        }
    }
    d(0.5 * (lo + hi))
}

fn opts(d: Dialect) -> ProgramOptions {
    ProgramOptions::default().with_dialect(d)
}

#[test]
fn every_dialect_program_is_within_tolerance_of_the_parabola_for_an_outside_reader() {
    let para = Parabola::paper_like();
    for tol in [0.01, 0.004] {
        for d in Dialect::ALL {
            for kind in ProgramKind::ALL {
                let label = format!("{} {} at {tol}", d.as_str(), d.kind_label(kind));
                let p = write_program(kind, &para, tol, &opts(d)).expect(&label);
                assert_eq!(p.parsed.dialect, d);
                let (pts, curves) = read_feed_points(&p.text, d, 0.02);
                assert_eq!(curves.len(), usize::from(kind == ProgramKind::Nurbs && d != Dialect::Fanuc), "{label}");
                if d == Dialect::Fanuc && kind == ProgramKind::Nurbs {
                    // FANUC's explicit knots are gcode_roundtrip's subject; here its text
                    // must be the default program's, byte for byte.
                    let default = write_program(kind, &para, tol, &ProgramOptions::default()).expect("default");
                    assert_eq!(p.text, default.text);
                    continue;
                }
                let worst = pts.iter().map(|x| parabola_distance(&para, *x)).fold(0.0, f64::max);
                assert!(worst <= tol, "{label}: a program point is {worst} mm from the parabola");
                let back = design_to_polyline(&para, &pts, 1500);
                assert!(back <= tol, "{label}: the parabola is {back} mm from the program");
                // The dialect's own reader measures what the outside reader sees.
                assert!(
                    (p.deviation.max_mm() - worst.max(back)).abs() < 0.05 * tol,
                    "{label}: library {} vs outside {}",
                    p.deviation.max_mm(),
                    worst.max(back)
                );
                // LinuxCNC's blending is budgeted: deviation + G64 P within E.
                if d == Dialect::LinuxCnc {
                    let b = p.blend_mm.unwrap_or(0.0);
                    assert!(p.deviation.max_mm() + b <= tol + 1e-12, "{label}: {} + {b}", p.deviation.max_mm());
                    assert!(p.text.contains("G64 P") || p.text.contains("G61"), "{label}");
                    assert!(p.text.trim_end().ends_with("M2\n%") || p.text.contains("\nM2\n"), "{label}");
                } else {
                    assert!(p.blend_mm.is_none());
                }
            }
        }
    }
}

#[test]
fn sinumerik_bspline_follows_a_space_curve_within_tolerance() {
    let tol = 0.01;
    let p = write_program(ProgramKind::Nurbs, &Helix, tol, &opts(Dialect::Sinumerik)).expect("BSPLINE program");
    let lines: Vec<&str> = p.text.lines().collect();
    assert!(lines.iter().all(|l| !l.contains('(')), "Sinumerik comments are ';'");
    assert!(lines.contains(&"G710 G90 G94 G17 G64") && lines.contains(&"M30"), "{}", p.text);
    let first = lines.iter().position(|l| l.starts_with("BSPLINE SD=3 ")).expect("BSPLINE block");
    // One PL for the whole curve, on every control-point block.
    let pls: Vec<&str> = lines.iter().filter_map(|l| l.split_whitespace().find(|w| w.starts_with("PL="))).collect();
    assert_eq!(pls.len(), p.path_blocks);
    assert!(pls.iter().all(|x| *x == pls[0]), "{pls:?}");
    assert!(lines[first..first + p.path_blocks].iter().all(|l| l.contains("PW=1.0") && l.contains(" Z")));
    let (pts, curves) = read_feed_points(&p.text, Dialect::Sinumerik, 0.05);
    assert_eq!(curves.len(), 1);
    assert_eq!(curves[0].points.len(), p.path_blocks + 1, "the start point is the first control point");
    let worst = pts.iter().map(|x| helix_distance(*x)).fold(0.0, f64::max);
    assert!(worst <= tol, "a BSPLINE point is {worst} mm from the helix");
    let back = design_to_polyline(&Helix, &pts, 800);
    assert!(back <= tol, "the helix is {back} mm from the BSPLINE");
    assert!((p.deviation.max_mm() - worst.max(back)).abs() < 0.05 * tol);
    // The library's reader builds the same curve as the outside one.
    let Segment::Nurbs(ours) = &p.parsed.toolpath.cuts().next().expect("cut").segment else { panic!("not a NURBS") };
    let (a, b) = ours.range();
    let (ra, rb) = curves[0].range();
    for i in 0..=500 {
        let f = i as f64 / 500.0;
        assert!((ours.point_at(a + (b - a) * f) - curves[0].point(ra + (rb - ra) * f)).length() < 1e-9);
    }
}

#[test]
fn linuxcnc_refuses_g5_2_for_a_path_not_planar_in_xy_and_writes_lines_and_arcs() {
    let tol = 0.01;
    let e = write_program(ProgramKind::Nurbs, &Helix, tol, &opts(Dialect::LinuxCnc)).expect_err("not planar");
    let ProgramError::NotPlanar { dz_mm, .. } = e else { panic!("{e}") };
    // Z runs from 0 to 4·1.5π.
    assert!((dz_mm - 6.0 * std::f64::consts::PI).abs() < 1e-6, "{dz_mm}");
    let msg = e.to_string();
    assert!(msg.contains("XY") && msg.contains("--kind g01") && msg.contains("--kind arcs"), "{msg}");
    // The same path as G1 and G2/G3 is fine.
    for kind in [ProgramKind::Lines, ProgramKind::Arcs] {
        let p = write_program(kind, &Helix, tol, &opts(Dialect::LinuxCnc)).expect("G1/G2/G3 program");
        let (pts, _) = read_feed_points(&p.text, Dialect::LinuxCnc, 0.05);
        let worst = pts.iter().step_by(7).map(|x| helix_distance(*x)).fold(0.0, f64::max);
        assert!(worst <= tol, "{}: {worst}", kind.label());
    }
    // A path that rises by less than half the tolerance is still a G5.2 program.
    struct Tilted;
    impl Curve3 for Tilted {
        fn derivatives_at(&self, t: f64) -> [DVec3; 3] {
            let [p, d1, d2] = Parabola::paper_like().derivatives_at(t);
            [p + DVec3::Z * 0.003 * (t - 60.0) / 120.0, d1 + DVec3::Z * 0.003 / 120.0, d2]
        }
        fn range(&self) -> (f64, f64) {
            Parabola::paper_like().range()
        }
    }
    let p = write_program(ProgramKind::Nurbs, &Tilted, tol, &opts(Dialect::LinuxCnc)).expect("nearly planar");
    assert!(p.deviation.max_mm() + p.blend_mm.unwrap_or(0.0) <= tol);
    let e = write_program(ProgramKind::Nurbs, &Tilted, 0.004, &opts(Dialect::LinuxCnc)).expect_err("0.003 > 0.002");
    assert!(matches!(e, ProgramError::NotPlanar { .. }), "{e}");
}

#[test]
fn linuxcnc_reader_implies_uniform_knots_and_refuses_z_inside_the_curve() {
    // Three control points of order 3: a quadratic Bézier, whose middle is
    // (P0 + 2·P1 + P2)/4 = (10, 5) at the current Z.
    let text = "%\nG21 G90 G17\nG0 X0 Y0 Z1.5\nF100\nG5.2 X10 Y10 P1 L3\nX20 Y0 P1\nG5.3\nM2\n%\n";
    let p = parse_program_in(text, Dialect::LinuxCnc).expect("program");
    let Segment::Nurbs(c) = &p.toolpath.cuts().next().expect("cut").segment else { panic!("not a NURBS") };
    let (a, b) = c.range();
    assert!((c.point_at(0.5 * (a + b)) - DVec3::new(10.0, 5.0, 1.5)).length() < 1e-12);
    assert_eq!(p.path_blocks(), 3);
    // Six control points of order 4, one weighted: LinuxCNC's knots 0,0,0,0,1,2,3,3,3,3.
    let pts = [(0.0, 0.0), (5.0, 8.0), (12.0, -3.0), (20.0, 6.0), (26.0, 1.0), (30.0, 9.0)];
    let mut text = String::from("G90 G17\nG0 X0 Y0 Z2\nG5.2 X5 Y8 P1 L4 F200\n");
    for (x, y) in &pts[2..] {
        let w = if *x == 20.0 { 2.5 } else { 1.0 };
        text.push_str(&format!("X{x} Y{y} P{w}\n"));
    }
    text.push_str("G5.3\nG1 X0 Y0\n");
    let p = parse_program_in(&text, Dialect::LinuxCnc).expect("program");
    let Segment::Nurbs(c) = &p.toolpath.cuts().next().expect("cut").segment else { panic!("not a NURBS") };
    let raw = RawNurbs {
        order: 4,
        knots: linuxcnc_knots(6, 4),
        points: pts.iter().map(|(x, y)| DVec3::new(*x, *y, 2.0)).collect(),
        weights: vec![1.0, 1.0, 1.0, 2.5, 1.0, 1.0],
    };
    assert_eq!(raw.knots, vec![0.0, 0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0, 3.0]);
    for i in 0..=300 {
        let u = 3.0 * i as f64 / 300.0;
        assert!((c.point_at(u) - raw.point(u)).length() < 1e-12, "u = {u}");
    }
    // What a G5.2 block may not hold, each named with its line.
    for (bad, line, needle) in [
        ("G0 X0 Y0 Z0\nG5.2 X1 Y1 Z1 L3 F100\nX2 Y0\nG5.3\n", 2, "planar in XY"),
        ("G0 X0 Y0 Z0\nG5.2 X1 Y1 L3 F100\nG1 X2 Y0\n", 3, "close the curve with G5.3"),
        ("G0 X0 Y0 Z0\nG5.2 X1 Y1 L3 F100\nX2 Y0\n", 2, "not closed"),
        ("G0 X0 Y0 Z0\nG5.2 X1 Y1 L2 F100\nX2 Y0\nG5.3\n", 2, "use L3"),
        ("G0 X0 Y0 Z0\nG5.3\n", 2, "without an open G5.2"),
    ] {
        let e = parse_program_in(bad, Dialect::LinuxCnc).expect_err(bad);
        assert_eq!(e.line(), line, "{bad}: {e}");
        assert!(e.to_string().contains(needle), "{bad}: {e}");
    }
}

#[test]
fn sinumerik_reader_takes_degree_weights_and_one_knot_interval() {
    // A rational quadratic with weights 1, √2/2, 1 is a quarter circle: every point at the
    // radius (PW written to the manual's 4 decimals moves it by far less than 1e-4 mm).
    let text = "; QUARTER CIRCLE\nG710 G90 G17 G64\nG0 X20.0 Y0.0 Z0.0\nBSPLINE SD=2 X20.0 Y20.0 PW=0.7071 PL=5.0 F500\nX0.0 Y20.0 PW=1.0 PL=5.0\nG1 X0 Y30\nM30\n";
    let p = parse_program_in(text, Dialect::Sinumerik).expect("program");
    assert!(p.unsupported.is_empty(), "{:?}", p.unsupported);
    let cuts: Vec<_> = p.toolpath.cuts().collect();
    assert_eq!(cuts.len(), 2, "the G1 ends the BSPLINE");
    let Segment::Nurbs(c) = &cuts[0].segment else { panic!("not a NURBS") };
    assert_eq!((c.degree(), c.len()), (2, 3));
    let (a, b) = c.range();
    assert_eq!((a, b), (0.0, 5.0), "one span of PL = 5");
    for i in 0..=100 {
        let r = c.point_at(a + (b - a) * i as f64 / 100.0).truncate().length();
        assert!((r - 20.0).abs() < 1e-4, "radius {r}");
    }
    // Different PL: refused with the fix; no PL: read with equal spacing and reported.
    let e = parse_program_in(
        "G0 X0 Y0 Z0\nBSPLINE SD=2 X1 Y1 PL=2.0 F100\nX2 Y0 PL=3.0\nX3 Y1 PL=2.0\n",
        Dialect::Sinumerik,
    )
    .expect_err("two PL values");
    assert_eq!(e.line(), 3);
    assert!(e.to_string().contains("same PL"), "{e}");
    let p = parse_program_in("G0 X0 Y0 Z0\nBSPLINE X1 Y1 F100\nX2 Y0\nX3 Y1\n", Dialect::Sinumerik).expect("no PL");
    assert_eq!(p.unsupported.len(), 1);
    assert!(p.unsupported[0].reason.contains("PL"), "{:?}", p.unsupported);
    for (bad, line, needle) in [
        ("G0 X0 Y0 Z0\nBSPLINE SD=4 X1 Y1 F100\n", 2, "SD=2 or SD=3"),
        ("G0 X0 Y0 Z0\nBSPLINE SD=3 X1 Y1 PW=3.5 F100\nX2 Y2\nX3 Y3\n", 2, "0 < PW"),
        ("G0 X0 Y0 Z0\nBSPLINE SD=3 X1 Y1 F100\nX2 Y2\nG1 X5\n", 2, "at least 4"),
        ("G0 X0 Y0 Z0\nBSPLINE SD=3 X1 Y1 SD=2 F100\n", 2, "twice"),
    ] {
        let e = parse_program_in(bad, Dialect::Sinumerik).expect_err(bad);
        assert_eq!(e.line(), line, "{bad}: {e}");
        assert!(e.to_string().contains(needle), "{bad}: {e}");
    }
    // In FANUC's reader the same text is malformed, not silently misread.
    let e = parse_program_in(text, Dialect::Fanuc).expect_err("not FANUC");
    assert!(e.line() == 2 && e.to_string().contains("G710"), "{e}");
}

#[test]
fn dialect_names_are_checked_and_programs_say_their_dialect() {
    for d in Dialect::ALL {
        assert_eq!(d.as_str().parse::<Dialect>(), Ok(d));
        assert_eq!(d.as_str().to_uppercase().parse::<Dialect>(), Ok(d));
        let p = write_program(ProgramKind::Nurbs, &Parabola::paper_like(), 0.01, &opts(d)).expect("program");
        assert_eq!(Dialect::guess(&p.text), d, "{}", p.text);
    }
    assert_eq!(ProgramOptions::default().dialect, Dialect::Fanuc);
    let e = "heidenhain".parse::<Dialect>().expect_err("not ours");
    let msg = e.to_string();
    assert!(msg.contains("heidenhain") && msg.contains("fanuc, sinumerik, linuxcnc"), "{msg}");
    // Hand-written programs, without our header.
    assert_eq!(Dialect::guess("G0 X0 Y0\nBSPLINE SD=3\nX1 Y2\n"), Dialect::Sinumerik);
    assert_eq!(Dialect::guess("G0 X0 Y0\nG5.2 X1 Y1 L4 F100\nX2 Y0\nG5.3\nM2\n"), Dialect::LinuxCnc);
    assert_eq!(Dialect::guess("G0 X0 Y0\nG01 X1 F100 (BSPLINE in a comment)\nM02\n"), Dialect::Fanuc);
}

#[cfg(not(target_arch = "wasm32"))]
mod cli {
    use std::process::Command;

    fn run(args: &[&str]) -> (i32, String, String) {
        let o = Command::new(env!("CARGO_BIN_EXE_interpolab")).args(args).output().expect("the binary runs");
        (
            o.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&o.stdout).into_owned(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    }

    #[test]
    fn unknown_dialects_are_refused_listing_the_valid_ones() {
        for args in [
            vec!["gcode", "--profile", "parabola", "--kind", "nurbs", "--tolerance", "0.01", "--dialect", "okuma"],
            vec!["replay", "/nonexistent.nc", "--dialect", "okuma"],
        ] {
            let (code, _, err) = run(&args);
            assert_eq!(code, 2, "{err}");
            assert!(err.contains("'okuma'") && err.contains("fanuc, sinumerik, linuxcnc"), "{err}");
        }
        let (code, _, err) =
            run(&["gcode", "--profile", "parabola", "--kind", "g01", "--tolerance", "0.01", "--dialect", "all"]);
        assert_eq!(code, 2);
        assert!(err.contains("--dialect all is for compare"), "{err}");
    }

    #[test]
    fn replay_guesses_the_dialect_and_counts_linuxcnc_blending_against_the_tolerance() {
        let dir = std::env::temp_dir().join(format!("interpolab-dialects-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let out = dir.join("parabola-g52.ngc");
        let out_s = out.to_str().expect("path");
        let (code, _, err) = run(&[
            "gcode",
            "--profile",
            "parabola",
            "--kind",
            "nurbs",
            "--tolerance",
            "0.01",
            "--dialect",
            "linuxcnc",
            "--out",
            out_s,
        ]);
        assert_eq!(code, 0, "{err}");
        assert!(err.contains("G5.2 program") && err.contains("G64 P"), "{err}");
        let (code, text, _) = run(&["replay", out_s, "--profile", "parabola", "--tolerance", "0.01"]);
        assert_eq!(code, 0, "{text}");
        assert!(text.contains("dialect      linuxcnc (LinuxCNC), guessed from the text"), "{text}");
        assert!(text.contains("G5.2 curves 1"), "{text}");
        // The geometry alone is within 0.009 mm, but with the blending it may reach more.
        let dev: f64 = text
            .lines()
            .find_map(|l| l.strip_prefix("deviation    "))
            .and_then(|l| l.split_whitespace().next())
            .and_then(|v| v.parse().ok())
            .expect("deviation");
        let blend: f64 = std::fs::read_to_string(&out)
            .expect("program")
            .lines()
            .find_map(|l| l.strip_prefix("G64 P"))
            .and_then(|v| v.parse().ok())
            .expect("G64 P");
        let tight = format!("{}", dev + 0.5 * blend);
        let (code, text, _) = run(&["replay", out_s, "--profile", "parabola", "--tolerance", &tight]);
        assert_eq!(code, 1, "{text}");
        assert!(text.contains("EXCEEDS"), "{text}");
        // compare --dialect all: one row per dialect and kind, the dialect in the last column.
        let (code, table, err) = run(&["compare", "--profile", "parabola", "--tolerance", "0.01", "--dialect", "all"]);
        assert_eq!(code, 0, "{err}");
        for needle in ["| G06.2 |", "| BSPLINE |", "| G5.2 |", "| fanuc |", "| sinumerik |", "| linuxcnc |"] {
            assert!(table.contains(needle), "{needle}:\n{table}");
        }
    }
}
