//! Reading G-code: hand-written programs (comments, line numbers, modal words, R and IJK
//! arcs in all three planes, helices, incremental and inch moves, G06.2), unsupported words
//! reported with their lines, and malformed programs refused with the line and the fix.
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::float_cmp,
    reason = "tests: a failure should fail the test; some values are exact"
)]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use interpolab::gcode::interp::Options;
use interpolab::gcode::{ArcMove, Dialect, Motion, ParseError, Plane, Segment, parse_program, read_program};
use interpolab::geom::Curve3;

fn arc_of(seg: &Segment) -> ArcMove {
    match seg {
        Segment::Arc(a) => *a,
        other => panic!("expected an arc, got {other:?}"),
    }
}

fn close(a: DVec3, b: DVec3) -> bool {
    (a - b).length() < 1e-9
}

#[test]
fn reads_a_hand_written_program() {
    let p = parse_program(include_str!("../../data/gcode/hand_written/program.nc")).expect("valid program");
    assert!(p.unsupported.is_empty(), "{:?}", p.unsupported);
    let b = &p.toolpath.blocks;
    let kinds: Vec<Motion> = b.iter().map(|x| x.motion).collect();
    use Motion::*;
    assert_eq!(
        kinds,
        vec![Rapid, Rapid, Linear, Linear, Linear, ArcCw, ArcCcw, Linear, ArcCcw, ArcCw, Linear, Linear, ArcCcw, Rapid]
    );
    // N80 G2 X30 Y20 R10 from (20, 10, 0): centre (30, 10), a clockwise quarter turn.
    let a = arc_of(&b[5].segment);
    assert!(close(a.center, DVec3::new(30.0, 10.0, 0.0)) && !a.ccw, "{a:?}");
    interpolab::assert_near!(a.sweep(), -std::f64::consts::FRAC_PI_2, 1e-12);
    assert!(close(
        a.point_at(0.5),
        DVec3::new(30.0 - 10.0 * std::f64::consts::FRAC_1_SQRT_2, 10.0 + 10.0 * std::f64::consts::FRAC_1_SQRT_2, 0.0)
    ));
    // N90 G03 … I10 J0: centre (40, 20).
    let a = arc_of(&b[6].segment);
    assert!(close(a.center, DVec3::new(40.0, 20.0, 0.0)) && a.ccw);
    // N100 incremental: (40, 30) + (−5, 5).
    assert!(close(b[7].segment.end(), DVec3::new(35.0, 35.0, 0.0)));
    // N120 G18 G03 X40 Z5 I5 K0 from (35, 35, 0): centre X40 Z0, positive about +Y.
    let a = arc_of(&b[8].segment);
    assert_eq!(a.plane, Plane::Zx);
    assert!(close(a.center, DVec3::new(40.0, 35.0, 0.0)));
    interpolab::assert_near!(a.sweep(), std::f64::consts::FRAC_PI_2, 1e-12);
    // Halfway the point has turned 45° about +Y from (−5, 0, 0) relative to the centre:
    // R_y(θ)·(x, z) = (x cos θ + z sin θ, −x sin θ + z cos θ).
    let mid = a.point_at(0.5) - DVec3::new(40.0, 35.0, 0.0);
    let expected = DVec3::new(-5.0 * std::f64::consts::FRAC_1_SQRT_2, 0.0, 5.0 * std::f64::consts::FRAC_1_SQRT_2);
    assert!(close(mid, expected), "{mid} vs {expected}");
    // N130 helix about Z, clockwise from (40, 35, 5) to (35, 30, 9): Z in proportion to the angle.
    let a = arc_of(&b[9].segment);
    assert_eq!(a.plane, Plane::Xy);
    interpolab::assert_near!(a.sweep(), -std::f64::consts::FRAC_PI_2, 1e-12);
    interpolab::assert_near!(a.point_at(0.25).z, 6.0, 1e-12);
    // Block delete: N140 is read (switch off).
    assert!(
        close(b[10].segment.start(), DVec3::new(35.0, 30.0, 9.0))
            && close(b[10].segment.end(), DVec3::new(36.0, 30.0, 9.0))
    );
    assert!(close(b[11].segment.end(), DVec3::new(35.0, 35.0, 0.0)));
    // N160 full circle.
    let a = arc_of(&b[12].segment);
    interpolab::assert_near!(a.sweep(), std::f64::consts::TAU, 1e-12);
    assert_eq!(b[3].feed_mm_per_min, Some(600.0));
    assert_eq!(b[2].line, 8, "lines are counted in the file, comments and all");
    assert!(p.comments.iter().any(|(l, c)| *l == 3 && c.contains("semicolon")));
}

#[test]
fn r_format_arcs_take_the_short_or_the_long_way() {
    for (r, ccw, expect) in [(10.0, true, 0.5), (-10.0, true, 1.5), (10.0, false, -0.5), (-10.0, false, -1.5)] {
        let code = if ccw { "G03" } else { "G02" };
        let text = format!("G0 X10 Y0\nG1 F100\n{code} X0 Y10 R{r}\n");
        let p = parse_program(&text).expect("valid");
        let a = arc_of(&p.toolpath.blocks[1].segment);
        interpolab::assert_near!(a.sweep(), expect * std::f64::consts::PI, 1e-12, "{code} R{r}");
        interpolab::assert_near!(a.radius_start(), 10.0, 1e-12);
    }
}

#[test]
fn arcs_turn_positively_about_the_plane_normal_for_g03() {
    // A quarter turn from the first in-plane axis toward the second in every plane.
    let cases = [
        ("G17", "G0 X10 Y0 Z0", "X0 Y10 I-10 J0", DVec3::new(10.0, 0.0, 0.0), DVec3::Z),
        ("G18", "G0 X0 Y0 Z10", "X10 Z0 I0 K-10", DVec3::new(0.0, 0.0, 10.0), DVec3::Y),
        ("G19", "G0 X0 Y10 Z0", "Y0 Z10 J-10 K0", DVec3::new(0.0, 10.0, 0.0), DVec3::X),
    ];
    for (plane, start, words, s, normal) in cases {
        let p = parse_program(&format!("{start}\n{plane} G03 {words} F100\n")).expect("valid");
        let a = arc_of(&p.toolpath.blocks[1].segment);
        // Positive rotation about the normal: (start × point) points along +normal.
        let mid = a.point_at(0.5);
        assert!(s.cross(mid).dot(normal) > 0.0, "{plane}: midpoint {mid}");
        interpolab::assert_near!(mid.length(), 10.0, 1e-12, "{plane}");
        let p = parse_program(&format!("{start}\n{plane} G02 {words} F100\n")).expect("valid");
        let a = arc_of(&p.toolpath.blocks[1].segment);
        interpolab::assert_near!(a.sweep(), -1.5 * std::f64::consts::PI, 1e-12, "{plane} G02 goes the long way");
    }
}

#[test]
fn incremental_and_inch_programs_become_millimetres() {
    let p = parse_program("G20 G91\nG0 X1 Y1\nG1 X1 F10\n").expect("valid");
    let b = &p.toolpath.blocks;
    assert!(close(b[0].segment.end(), DVec3::new(25.4, 25.4, 0.0)));
    assert!(close(b[1].segment.end(), DVec3::new(50.8, 25.4, 0.0)));
    assert_eq!(b[1].feed_mm_per_min, Some(254.0));
}

#[test]
fn g06_2_blocks_follow_the_fanuc_rules() {
    // Order omitted (4), first knot omitted (taken from the second block), axes omitted in a
    // later block keep the previous control point's value, weights default to 1.
    let text =
        "G0 X0 Y0 Z9\nG0 Z0\nG06.2 X0 Y0 Z0 F500\nK0 X10 Y5\nK0 X20 Z1 R2\nK0 X30 Y0 Z0\nK1\nK1\nK1\nK1\nG0 Z5\n";
    let p = parse_program(text).expect("valid");
    let b = &p.toolpath.blocks;
    let Segment::Nurbs(c) = &b[2].segment else { panic!("expected a NURBS") };
    assert_eq!(c.degree(), 3);
    assert_eq!(c.knots(), &[0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]);
    assert!(close(c.control_point(2), DVec3::new(20.0, 5.0, 1.0)));
    interpolab::assert_near!(c.weight(2), 2.0, 0.0);
    interpolab::assert_near!(c.weight(1), 1.0, 0.0);
    assert!(close(b[3].segment.start(), DVec3::new(30.0, 0.0, 0.0)), "the next move starts at the curve's end");
    assert_eq!(p.path_blocks(), 8);
}

#[test]
fn unsupported_words_are_reported_with_their_lines() {
    // What the interpreter cannot model is reported once per code with its first line (a
    // user's program read leniently), and the rest of the path is still read.
    let text = "G0 X0 Y0\nG38.2 Z-5 F100\nM100 P1\nG1 X10 E5\nG1 X20 U3\nM100\n";
    let p = read_program(text, Dialect::Fanuc, &Options::default()).expect("readable");
    let found: Vec<(usize, String)> = p.unsupported.iter().map(|u| (u.line, u.word.clone())).collect();
    for (line, word) in [(2, "G38.2"), (3, "M100"), (4, "E"), (5, "U")] {
        assert!(found.contains(&(line, word.to_owned())), "{word} on line {line} not reported: {found:?}");
    }
    assert!(p.unsupported.iter().all(|u| !u.reason.is_empty()));
    assert_eq!(p.unsupported.iter().find(|u| u.word == "M100").map(|u| u.count), Some(2));
    assert!(close(p.toolpath.blocks.last().expect("moves").segment.end(), DVec3::new(20.0, 0.0, -4.746)));
    // Read strictly (as the product's own programs are), the user's M code is refused.
    assert!(parse_program(text).is_err());
}

#[test]
fn harmless_words_are_accepted_silently() {
    let p = parse_program(
        "%\nO0001\nG21 G40 G49 G80 G94 G54 G64\nM3 S1000 T2 M6 M8\nG04 P500\nG05 P10000\nG0 X1\nM9 M5 M30\n%\n",
    )
    .expect("valid");
    assert!(p.unsupported.is_empty(), "{:?}", p.unsupported);
    assert_eq!(p.toolpath.blocks.len(), 1);
}

#[test]
fn malformed_programs_are_refused_naming_the_line_and_the_fix() {
    let cases: &[(&str, usize, &str)] = &[
        ("G0 X0\n(open comment\n", 2, "not closed"),
        ("G0 X1.2.3\n", 1, "not a number"),
        ("G0 X\n", 1, "has no value"),
        ("G0 X#<depth>\n", 1, "no value yet"),
        ("G0 X1 X2\n", 1, "twice"),
        ("G0 G1 X1 F10\n", 1, "same block"),
        ("X1 Y2\n", 1, "no motion mode"),
        ("G0 X0\nG1 X10\n", 2, "without a feed"),
        ("G1 X1 F0\n", 1, "must be positive"),
        ("G0 X0\nG2 X10 F100\n", 2, "centre"),
        ("G0 X0 Y0\nG2 X10 Y0 I4 J0 F100\n", 2, "not on its circle"),
        ("G0 X0\nG2 X10 R2 F100\n", 2, "smaller than half"),
        ("G0 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 F10\nK0 X1\nK-1 X2\n", 4, "non-decreasing"),
        ("G0 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 F10\nK0 X1\nK0 X2\nK0 X3\nK1\nK1\nG1 X0\n", 2, "closing knot"),
        ("G0 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 F10\nK0 X1\nK0.5 X2\nK0.5 X3\nK1\nK1\nK1\nK1\n", 2, "must be equal"),
        ("G0 X0 Y0 Z0\nG06.2 P4 K0 X1 Y0 Z0 F10\n", 2, "current position"),
        ("G0 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 R0 F10\n", 2, "must be positive"),
        ("G91 G0 X0\nG06.2 P4 K0 F10\n", 2, "G90"),
        ("G0 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 F10\nK0 X1\nK0 X2\nK0 X3\nK1\nK1 X4\n", 7, "after the closing"),
        ("G0 X0 Y0 Z0\nG06.2 P1 K0 X0 Y0 Z0 F10\n", 2, "P2"),
        ("G0 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 F10\nX1 Y1\n", 3, "without a knot"),
    ];
    for (text, line, needle) in cases {
        let e = parse_program(text).expect_err(text);
        let msg = e.to_string();
        assert!(msg.starts_with(&format!("line {line}:")), "{text:?}: {msg}");
        assert_eq!(e.line(), *line, "{text:?}: {msg}");
        assert!(msg.contains(needle), "{text:?}: {msg} (expected '{needle}')");
    }
    let e = parse_program("G0 X0\nG1 X1 F1\nG2 X1 Y0 I0 J0\n").unwrap_err();
    assert!(matches!(e, ParseError::Interp(_)) && e.line() == 3 && e.to_string().contains("zero-radius"), "{e}");
}
