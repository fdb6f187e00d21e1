//! The spline builder against our reader (the dialect reader `parse::parse_dialect_reader`: the same curves and errors on
//! the programs the writers make and the reader's own tests use), G5/G5.1 against the Bézier
//! closed forms (`tests/reference/cycles.rs` checks them against LinuxCNC's `rs274`).

use glam::DVec3;

use super::*;
use crate::gcode::{Dialect, ParseError, ProgramKind, ProgramOptions, Segment, write_program};
use crate::geom::Curve3;
use crate::nurbs_path::Parabola;

/// A small program driver written for this test: comments, `%`, N words, letters and
/// numbers, Sinumerik `NAME=value` words and `BSPLINE`, G0–G3 moves, G17–G19, G20/G21
/// (G70/G71/G700/G710 for Sinumerik), G90/G91, F — enough to hand every block to the builder
/// as an executor would.
fn drive(text: &str, dialect: Dialect) -> Result<Vec<FinishedSpline>, String> {
    let mut b = SplineBuilder::new();
    let mut out = Vec::new();
    let mut pos = DVec3::ZERO;
    let (mut absolute, mut plane, mut inch, mut feed, mut motion) = (true, Plane::Xy, false, false, None::<&str>);
    let fail = |e: SplineError| format!("line {}: {e}", e.loc().line);
    for (idx, raw) in text.lines().enumerate() {
        let loc = Loc::main(idx as u32 + 1);
        let mut line = String::new();
        let mut depth = 0;
        for c in raw.chars() {
            match c {
                '(' => depth += 1,
                ')' => depth -= 1,
                ';' if depth == 0 => break,
                _ if depth == 0 => line.push(c.to_ascii_uppercase()),
                _ => {}
            }
        }
        let line = line.trim();
        if line.is_empty() || line == "%" {
            continue;
        }
        // Words: (name, value).
        let chars: Vec<char> = line.chars().collect();
        let mut words: Vec<(String, f64)> = Vec::new();
        let mut i = 0;
        while i < chars.len() {
            if chars[i].is_whitespace() {
                i += 1;
                continue;
            }
            let start = i;
            while i < chars.len() && chars[i].is_ascii_alphabetic() {
                i += 1;
            }
            let name: String = chars[start..i].iter().collect();
            if i < chars.len() && chars[i] == '=' {
                i += 1;
            }
            let vs = i;
            while i < chars.len()
                && (chars[i].is_ascii_digit() || chars[i] == '.' || ((chars[i] == '-' || chars[i] == '+') && i == vs))
            {
                i += 1;
            }
            let value: String = chars[vs..i].iter().collect();
            words.push((name, value.parse().unwrap_or(0.0)));
        }
        let mut w = SplineWords::default();
        let (mut open, mut close, mut other) = (None, false, None);
        let mut any = false;
        // G20/G21 act before the block's coordinates are read.
        for (name, v) in &words {
            if name == "G" {
                match (v * 10.0).round() as i64 {
                    200 => inch = true,
                    210 => inch = false,
                    700 | 7000 if dialect == Dialect::Sinumerik => inch = true,
                    710 | 7100 if dialect == Dialect::Sinumerik => inch = false,
                    _ => {}
                }
            }
        }
        let scale = if inch { 25.4 } else { 1.0 };
        for (name, v) in &words {
            match name.as_str() {
                "G" => match (v * 10.0).round() as i64 {
                    0 => other = Some("G00"),
                    10 => other = Some("G01"),
                    20 => other = Some("G02"),
                    30 => other = Some("G03"),
                    62 => open = Some(SplineKind::Fanuc),
                    52 if dialect == Dialect::LinuxCnc => open = Some(SplineKind::LinuxCnc),
                    53 if dialect == Dialect::LinuxCnc => close = true,
                    170 => plane = Plane::Xy,
                    180 => plane = Plane::Zx,
                    190 => plane = Plane::Yz,
                    900 => absolute = true,
                    910 => absolute = false,
                    _ => {}
                },
                "BSPLINE" if dialect == Dialect::Sinumerik => open = Some(SplineKind::Sinumerik),
                "F" => feed = true,
                "X" => (w.x, any) = (Some(v * scale), true),
                "Y" => (w.y, any) = (Some(v * scale), true),
                "Z" => (w.z, any) = (Some(v * scale), true),
                "K" => w.k = Some(*v),
                "R" => w.r = Some(*v),
                "P" => w.p = Some(*v),
                "L" => w.l = Some(*v),
                "SD" => w.sd = Some(*v),
                "PL" => w.pl = Some(*v),
                "PW" => w.pw = Some(*v),
                _ => {}
            }
        }
        if other.is_some() {
            motion = other;
        }
        if b.is_active() || open.is_some() || close {
            let block = SplineBlock {
                loc,
                open,
                close,
                other_motion: other,
                position: pos,
                absolute,
                plane,
                feed_set: feed,
                inch,
                words: w,
            };
            let step = b.block(&block).map_err(fail)?;
            if let Some(f) = step.finished {
                pos = f.end;
                out.push(f);
            }
            if close || open == Some(SplineKind::LinuxCnc) {
                motion = None;
            }
            if open.is_some() {
                motion = Some("spline");
            }
            if step.taken {
                continue;
            }
        }
        if any && matches!(motion, Some("G00" | "G01" | "G02" | "G03")) {
            let mut end = if absolute { pos } else { DVec3::ZERO };
            for (i, v) in [w.x, w.y, w.z].into_iter().enumerate() {
                if let Some(v) = v {
                    end[i] = v;
                }
            }
            pos = if absolute { end } else { pos + end };
        }
    }
    if let Some(f) = b.end_of_program().map_err(fail)? {
        out.push(f);
    }
    Ok(out)
}

/// The reader's curves, or its error as text.
fn reader(text: &str, dialect: Dialect) -> Result<Vec<NurbsCurve>, String> {
    let p = crate::gcode::parse::parse_dialect_reader(text, dialect).map_err(|e: ParseError| e.to_string())?;
    Ok(p.toolpath
        .blocks
        .iter()
        .filter_map(|b| if let Segment::Nurbs(c) = &b.segment { Some(c.clone()) } else { None })
        .collect())
}

fn same_as_reader(text: &str, dialect: Dialect) {
    let ours = drive(text, dialect).map(|v| v.into_iter().map(|f| f.curve).collect::<Vec<_>>());
    let theirs = reader(text, dialect);
    assert_eq!(ours, theirs, "{dialect:?}:\n{text}");
}

/// A helix of radius 30 mm rising 4 mm per radian (a space curve for FANUC and Sinumerik).
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

#[test]
fn the_writers_programs_read_back_to_the_same_curves() {
    let para = Parabola::paper_like();
    let mut curves = 0;
    for d in Dialect::ALL {
        for tol in [0.01, 0.004] {
            let opts = ProgramOptions::default().with_dialect(d);
            let p = write_program(ProgramKind::Nurbs, &para, tol, &opts).unwrap_or_else(|e| panic!("{e}"));
            same_as_reader(&p.text, d);
            curves += drive(&p.text, d).map_or(0, |v| v.len());
            if d != Dialect::LinuxCnc {
                let p = write_program(ProgramKind::Nurbs, &Helix, tol, &opts).unwrap_or_else(|e| panic!("{e}"));
                same_as_reader(&p.text, d);
                curves += drive(&p.text, d).map_or(0, |v| v.len());
            }
        }
    }
    assert!(curves >= 10, "the programs hold curves: {curves}");
}

#[test]
fn the_readers_test_programs_give_the_same_curves_and_errors() {
    let fanuc = [
        "G0 X0 Y0 Z9\nG0 Z0\nG06.2 X0 Y0 Z0 F500\nK0 X10 Y5\nK0 X20 Z1 R2\nK0 X30 Y0 Z0\nK1\nK1\nK1\nK1\nG0 Z5\n",
        "G20 G0 X0 Y0 Z0\nG06.2 P3 K0 X0 Y0 Z0 F10\nK0 X1 Y1\nK0 X2 Y0 R0.5\nK1\nK1\nK1\nG1 X3\n",
        "G0 X0 Y0 Z0\nG06.2 P4 X0 Y0 Z0 F10\nK0 X1\nK0 X2\nK0 X3\nK1\nK1\nK1\nK1\nG06.2 P2 K0 X3 F10\nK0 X4\nK1\nK1\n",
        "G0 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 F10\nK0 X1\nK-1 X2\n",
        "G0 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 F10\nK0 X1\nK0 X2\nK0 X3\nK1\nK1\nG1 X0\n",
        "G0 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 F10\nK0 X1\nK0.5 X2\nK0.5 X3\nK1\nK1\nK1\nK1\n",
        "G0 X0 Y0 Z0\nG06.2 P4 K0 X1 Y0 Z0 F10\n",
        "G0 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 R0 F10\n",
        "G91 G0 X0\nG06.2 P4 K0 F10\n",
        "G0 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 F10\nK0 X1\nK0 X2\nK0 X3\nK1\nK1 X4\n",
        "G0 X0 Y0 Z0\nG06.2 P1 K0 X0 Y0 Z0 F10\n",
        "G0 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0 F10\nX1 Y1\n",
        "G0 X0 Y0 Z0\nG06.2 P4 K0 X0 Y0 Z0\n",
        "G0 X0 Y0 Z0\nG06.2 P2 K0 X0 Y0 Z0 F10\nK0 X1\nK1\nK1\nX2\n",
        "G0 X0 Y0 Z0\nG06.2 P2 K0 X0 Y0 Z0 F10\nK0 X1\nK1\nK1\nK2\n",
        "G0 X0 Y0 Z0\nG06.2 P2 K0 X0 Y0 Z0 F10\nK0 X1\nK1\nK1\nG06.2 P2 K0 X1 Y0 Z0\nK1 X2 Y2\nK2\nK2\n",
    ];
    let linuxcnc = [
        "%\nG21 G90 G17\nG0 X0 Y0 Z1.5\nF100\nG5.2 X10 Y10 P1 L3\nX20 Y0 P1\nG5.3\nM2\n%\n",
        "G90 G17\nG0 X0 Y0 Z2\nG5.2 X5 Y8 P1 L4 F200\nX12 Y-3\nX20 Y6 P2.5\nX26 Y1\nX30 Y9\nG5.3\nG1 X0 Y0\n",
        "G0 X0 Y0 Z0\nF10\nG5.2 P2 L3\nX1 Y1 P1\nX2 Y0\nG5.2 X3 Y1\nG5.3\n",
        "G0 X0 Y0 Z0\nG5.2 X1 Y1 Z1 L3 F100\nX2 Y0\nG5.3\n",
        "G0 X0 Y0 Z0\nG5.2 X1 Y1 L3 F100\nG1 X2 Y0\n",
        "G0 X0 Y0 Z0\nG5.2 X1 Y1 L3 F100\nX2 Y0\n",
        "G0 X0 Y0 Z0\nG5.2 X1 Y1 L2 F100\nX2 Y0\nG5.3\n",
        "G0 X0 Y0 Z0\nG5.3\n",
        "G0 X0 Y0 Z0\nG18 G5.2 X1 Y1 F10\nG5.3\n",
        "G0 X0 Y0 Z0\nG5.2 X1 Y1 L4 F10\nX2 Y1 L3\nG5.3\n",
        "G0 X0 Y0 Z0\nG5.2 X1 Y1 L4 F10\nX2 Y1\nG5.3\n",
        "G0 X0 Y0 Z0\nG5.2 X1 Y1 F10\nX2 Y1 P-1\nG5.3\n",
    ];
    let sinumerik = [
        "; QUARTER CIRCLE\nG710 G90 G17 G64\nG0 X20.0 Y0.0 Z0.0\nBSPLINE SD=2 X20.0 Y20.0 PW=0.7071 PL=5.0 F500\nX0.0 Y20.0 PW=1.0 PL=5.0\nG1 X0 Y30\nM30\n",
        "G0 X0 Y0 Z0\nBSPLINE SD=2 X1 Y1 PL=2.0 F100\nX2 Y0 PL=3.0\nX3 Y1 PL=2.0\n",
        "G0 X0 Y0 Z0\nBSPLINE X1 Y1 F100\nX2 Y0\nX3 Y1\n",
        "G0 X0 Y0 Z0\nBSPLINE SD=4 X1 Y1 F100\n",
        "G0 X0 Y0 Z0\nBSPLINE SD=3 X1 Y1 PW=3.5 F100\nX2 Y2\nX3 Y3\n",
        "G0 X0 Y0 Z0\nBSPLINE SD=3 X1 Y1 F100\nX2 Y2\nG1 X5\n",
        "G70 G0 X0 Y0 Z0\nBSPLINE SD=2 X1 Y1 F100\nX2 Y0 Z1\nBSPLINE X3 Y1\nX4 Y4\nX5 Y0\nX6 Y2\n",
        "G0 X0 Y0 Z0\nBSPLINE SD=2 X1 Y1 F100\nPW=2\n",
        "G0 X0 Y0 Z0\nBSPLINE SD=2 X1 Y1 F100\nX2 Y0\nG06.2 P2 K0 X2 Y0 Z0\nK1 X3\nK2\nK2\n",
        "G91 G0 X0 Y0 Z0\nBSPLINE SD=2 X1 Y1 F100\n",
    ];
    let mut errors = 0;
    for (texts, d) in
        [(&fanuc[..], Dialect::Fanuc), (&linuxcnc[..], Dialect::LinuxCnc), (&sinumerik[..], Dialect::Sinumerik)]
    {
        for t in texts {
            same_as_reader(t, d);
            errors += usize::from(reader(t, d).is_err());
        }
    }
    assert!(errors >= 20, "the list exercises the errors: {errors}");
}

#[test]
fn g5_is_the_cubic_bezier_of_linuxcncs_construction_and_continues_smoothly() {
    let mut b = SplineBuilder::new();
    let start = DVec3::new(1.0, 2.0, 3.0);
    let blk = BezierBlock {
        loc: Loc::main(1),
        position: start,
        end_xy: [4.0, 5.0],
        i: Some(0.0),
        j: Some(3.0),
        p: Some(1.0),
        q: Some(-3.0),
        plane: Plane::Xy,
        other_axis: None,
        cutter_comp: false,
        feed_ok: true,
    };
    let c = b.cubic(&blk).unwrap_or_else(|e| panic!("{e}"));
    let cps: Vec<DVec3> = (0..c.len()).map(|i| c.control_point(i)).collect();
    let want = [start, DVec3::new(1.0, 5.0, 3.0), DVec3::new(5.0, 2.0, 3.0), DVec3::new(4.0, 5.0, 3.0)];
    assert_eq!(cps, want);
    // Bernstein form: C(½) = (P0 + 3 P1 + 3 P2 + P3) / 8, C'(0) = 3 (P1 − P0), C'(1) = 3 (P3 − P2).
    let (u0, u1) = c.range();
    let mid = (want[0] + 3.0 * want[1] + 3.0 * want[2] + want[3]) / 8.0;
    assert!((c.point_at(0.5 * (u0 + u1)) - mid).length() < 1e-14);
    let d0 = c.derivatives_at(u0)[1];
    let d1 = c.derivatives_at(u1)[1];
    assert!((d0 - 3.0 * (want[1] - want[0])).length() < 1e-13 && (d1 - 3.0 * (want[3] - want[2])).length() < 1e-13);
    // Without I J the next G5 starts along the previous end tangent: its first control
    // offset is −(P, Q).
    let next =
        BezierBlock { position: want[3], end_xy: [6.0, 7.0], i: None, j: None, p: Some(0.0), q: Some(-1.0), ..blk };
    let c2 = b.cubic(&next).unwrap_or_else(|e| panic!("{e}"));
    let t2 = c2.derivatives_at(c2.range().0)[1];
    assert!((t2 - d1).length() < 1e-13, "{t2} vs {d1}");
    // G5.1: S, S + (I, J), E; the parabola of LinuxCNC's manual through the origin.
    let q = b
        .quadratic(&BezierBlock {
            position: DVec3::new(-2.0, 4.0, 0.0),
            end_xy: [2.0, 4.0],
            i: Some(2.0),
            j: Some(-8.0),
            p: None,
            q: None,
            ..blk
        })
        .unwrap_or_else(|e| panic!("{e}"));
    let (a, z) = q.range();
    assert!(q.point_at(0.5 * (a + z)).length() < 1e-14, "the vertex is the origin");
    for k in 0..=20 {
        let p = q.point_at(a + (z - a) * f64::from(k) / 20.0);
        assert!((p.y - p.x * p.x).abs() < 1e-12, "y = x² at {p}");
    }
}

#[test]
fn g5_refusals_are_linuxcncs() {
    let mut b = SplineBuilder::new();
    let blk = BezierBlock {
        loc: Loc::main(3),
        position: DVec3::ZERO,
        end_xy: [1.0, 1.0],
        i: Some(1.0),
        j: Some(1.0),
        p: Some(1.0),
        q: Some(1.0),
        plane: Plane::Xy,
        other_axis: None,
        cutter_comp: false,
        feed_ok: true,
    };
    for (edit, want) in [
        (BezierBlock { plane: Plane::Zx, ..blk }, "XY plane"),
        (BezierBlock { other_axis: Some('Z'), ..blk }, "X and Y only"),
        (BezierBlock { j: None, ..blk }, "both I and J, or neither"),
        (BezierBlock { q: None, ..blk }, "both P and Q"),
        (BezierBlock { cutter_comp: true, ..blk }, "G40"),
        (BezierBlock { feed_ok: false, ..blk }, "feed"),
    ] {
        let e = b.cubic(&edit).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.starts_with("G5:") && e.contains(want), "{e:?} lacks {want:?}");
    }
    let e = b.quadratic(&BezierBlock { j: None, ..blk }).err().map(|e| e.to_string()).unwrap_or_default();
    assert!(e.contains("both I and J"), "{e}");
}
