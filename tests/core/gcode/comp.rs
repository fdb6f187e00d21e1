//! Cutter radius compensation against closed forms and against LinuxCNC's own interpreter.
//!
//! A tiny driver reads test programs with plain numbers (G0–G4, G17/G18/G19, G20/G21,
//! G40–G42.1, M0/M1/M2/M6/M30, T, D, L, P, X Y Z A B C I J K R) and feeds [`CutterComp`]; the
//! same programs go through `rs274 -g` (LinuxCNC 2.9's standalone interpreter), and the
//! motions (and the line and kind of a refusal) must agree to rs274's printed precision.

// On wasm32 only the closed-form tests run; the rs274 driver and generators stay unused.
#![cfg_attr(target_arch = "wasm32", allow(dead_code))]

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use std::collections::HashMap;

use glam::{DVec2, DVec3};

use interpolab::gcode::Plane;
use interpolab::gcode::interp::comp::*;
use interpolab::gcode::interp::{Loc, Origin};

/// A non-motion call in the tests.
#[derive(Clone, Debug, PartialEq)]
enum Call {
    /// G4 P (s).
    Dwell(f64),
}

type Comp = CutterComp<(), Call>;

/// One canonical call as rs274 prints it (program units).
#[derive(Clone, Debug, PartialEq)]
enum Rec {
    /// X Y Z A B C.
    Traverse([f64; 6]),
    /// X Y Z A B C.
    Feed([f64; 6]),
    /// First end, second end, first centre, second centre; turn; normal end, A, B, C.
    Arc([f64; 4], i32, [f64; 4]),
    /// Seconds.
    Dwell(f64),
}

/// A tool table entry as rs274's standalone canon reads it: diameter in inches.
#[derive(Clone, Copy, Debug)]
struct Tool {
    diameter_inch: f64,
    orientation: u8,
}

/// The driver's outcome: the calls made, and the refusal (1-based line) if any.
#[derive(Debug)]
struct Run {
    recs: Vec<Rec>,
    err: Option<(u32, CompError)>,
}

fn words(line: &str) -> Vec<(char, f64)> {
    let mut text = String::new();
    let mut depth = 0;
    for ch in line.chars() {
        match ch {
            '(' => depth += 1,
            ')' => depth -= 1,
            ';' if depth == 0 => break,
            _ if depth == 0 && !ch.is_whitespace() => text.push(ch.to_ascii_uppercase()),
            _ => {}
        }
    }
    let chars: Vec<char> = text.chars().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let letter = chars[i];
        i += 1;
        let from = i;
        while i < chars.len() && (chars[i].is_ascii_digit() || matches!(chars[i], '.' | '-' | '+')) {
            i += 1;
        }
        let num: String = chars[from..i].iter().collect();
        assert!(letter.is_ascii_alphabetic(), "test program: bad word in '{line}'");
        out.push((letter, num.parse().unwrap_or_else(|_| panic!("test program: bad number in '{line}'"))));
    }
    out
}

struct Driver<'a> {
    tools: &'a HashMap<i32, Tool>,
    comp: Comp,
    plane: Plane,
    /// mm per program unit.
    scale: f64,
    /// Programmed position (mm).
    pos: DVec3,
    abc: DVec3,
    motion: Option<i32>,
    spindle_tool: i32,
    next_tool: i32,
    out: Vec<Emit<(), Call>>,
    recs: Vec<Rec>,
}

impl Driver<'_> {
    fn record(&mut self) {
        for e in self.out.drain(..) {
            let rec = match e {
                Emit::Pass(Call::Dwell(s)) => Rec::Dwell(s),
                Emit::Move { mv, .. } => {
                    let e = mv.end / self.scale;
                    match mv.kind {
                        MoveKind::Traverse => Rec::Traverse([e.x, e.y, e.z, mv.abc.x, mv.abc.y, mv.abc.z]),
                        MoveKind::Feed => Rec::Feed([e.x, e.y, e.z, mv.abc.x, mv.abc.y, mv.abc.z]),
                        MoveKind::Arc { center, turns } => {
                            let (a, b, n) = self.plane.split(e);
                            let (ca, cb, _) = self.plane.split(center / self.scale);
                            Rec::Arc([a, b, ca, cb], turns, [n, mv.abc.x, mv.abc.y, mv.abc.z])
                        }
                    }
                }
            };
            self.recs.push(rec);
        }
    }

    /// Executes one block; `Ok(false)` at the program's end.
    fn block(&mut self, line: &str, loc: Loc) -> Result<bool, CompError> {
        let w = words(line);
        let get = |c: char| w.iter().find(|(l, _)| *l == c).map(|(_, v)| *v);
        let gs: Vec<i32> = w.iter().filter(|(l, _)| *l == 'G').map(|(_, v)| (v * 10.0).round() as i32).collect();
        let ms: Vec<i32> = w.iter().filter(|(l, _)| *l == 'M').map(|(_, v)| v.round() as i32).collect();
        if let Some(t) = get('T') {
            self.next_tool = t as i32;
        }
        if ms.contains(&6) {
            self.comp.refuse_if_on(Refusal::ToolChange, loc)?;
            self.spindle_tool = self.next_tool;
        }
        if gs.contains(&40) {
            let p = get('P').unwrap_or(0.0);
            self.comp.pass(Call::Dwell(p), loc, &mut self.out)?;
        }
        for g in &gs {
            match g {
                170 | 180 | 190 => {
                    let plane = match g {
                        170 => Plane::Xy,
                        180 => Plane::Zx,
                        _ => Plane::Yz,
                    };
                    self.comp.set_plane(plane, loc)?;
                    self.plane = plane;
                }
                200 => {
                    self.scale = 25.4;
                    self.comp.set_inch(true);
                }
                210 => {
                    self.scale = 1.0;
                    self.comp.set_inch(false);
                }
                _ => {}
            }
        }
        for g in &gs {
            match g {
                400 => self.comp.stop(loc, &mut self.out)?,
                410 | 420 => {
                    let side = if *g == 410 { Side::Left } else { Side::Right };
                    let tool = get('D').map_or(self.spindle_tool, |d| d as i32);
                    let t = self.tools.get(&tool).copied().unwrap_or(Tool { diameter_inch: 0.0, orientation: 0 });
                    let radius = t.diameter_inch * 25.4 / 2.0;
                    self.comp.start_with_orientation(side, radius, t.orientation, self.pos, loc)?;
                }
                411 | 421 => {
                    let side = if *g == 411 { Side::Left } else { Side::Right };
                    let d = get('D').expect("test program: G41.1 needs D");
                    let orientation = get('L').map_or(0, |l| l as u8);
                    self.comp.start_with_orientation(side, d * self.scale / 2.0, orientation, self.pos, loc)?;
                }
                0 | 10 | 20 | 30 => self.motion = Some(*g),
                40 | 170 | 180 | 190 | 200 | 210 | 430 | 490 | 540 | 610 | 640 | 800 | 900 | 940 => {}
                _ => panic!("test program: G{} is not in the test driver", f64::from(*g) / 10.0),
            }
        }
        // A G2/G3 with only a centre is a full circle.
        let axis = ['X', 'Y', 'Z', 'A', 'B', 'C'].iter().any(|c| get(*c).is_some())
            || (matches!(self.motion, Some(20 | 30)) && ['I', 'J', 'K'].iter().any(|c| get(*c).is_some()));
        if axis {
            let mut end = self.pos;
            for (i, c) in ['X', 'Y', 'Z'].iter().enumerate() {
                if let Some(v) = get(*c) {
                    end[i] = v * self.scale;
                }
            }
            let mut abc = self.abc;
            for (i, c) in ['A', 'B', 'C'].iter().enumerate() {
                if let Some(v) = get(*c) {
                    abc[i] = v;
                }
            }
            let kind = match self.motion.expect("test program: motion without a mode") {
                0 => MoveKind::Traverse,
                10 => MoveKind::Feed,
                g => {
                    let p = get('P').map_or(1, |p| p as i32);
                    let turns = if g == 30 { p } else { -p };
                    let (sa, sb, sn) = self.plane.split(self.pos);
                    let (ea, eb, _) = self.plane.split(end);
                    let (ia, ib) = match self.plane {
                        Plane::Xy => (get('I'), get('J')),
                        Plane::Zx => (get('K'), get('I')),
                        Plane::Yz => (get('J'), get('K')),
                    };
                    let (ca, cb) = if let Some(r) = get('R') {
                        r_center(DVec2::new(sa, sb), DVec2::new(ea, eb), r * self.scale, g == 30)
                    } else {
                        (sa + ia.unwrap_or(0.0) * self.scale, sb + ib.unwrap_or(0.0) * self.scale)
                    };
                    MoveKind::Arc { center: self.plane.join(ca, cb, sn), turns }
                }
            };
            self.comp.push(ProgMove { kind, end, abc, loc, tag: () }, &mut self.out)?;
            self.pos = end;
            self.abc = abc;
        }
        if ms.contains(&0) || ms.contains(&1) {
            self.comp.flush(loc, &mut self.out)?;
        }
        if ms.contains(&2) || ms.contains(&30) {
            self.comp.end_program(loc, &mut self.out)?;
            return Ok(false);
        }
        Ok(true)
    }
}

/// The centre of an R-format arc from `s` to `e` (radius `r`, negative for more than half a
/// turn): on the chord's perpendicular bisector, left of the chord for G3 with R > 0 or G2
/// with R < 0.
fn r_center(s: DVec2, e: DVec2, r: f64, ccw: bool) -> (f64, f64) {
    let mid = (s + e) / 2.0;
    let half = (e - mid).length().min(r.abs());
    let along = (e - s).normalize();
    let left = DVec2::new(-along.y, along.x);
    let toward = if ccw == (r > 0.0) { left } else { -left };
    let off = (r * r - half * half).max(0.0).sqrt();
    let c = mid + off * toward;
    (c.x, c.y)
}

fn drive(text: &str, tools: &HashMap<i32, Tool>) -> Run {
    let mut d = Driver {
        tools,
        comp: Comp::new(Plane::Xy),
        plane: Plane::Xy,
        scale: 1.0,
        pos: DVec3::ZERO,
        abc: DVec3::ZERO,
        motion: None,
        spindle_tool: 0,
        next_tool: 0,
        out: Vec::new(),
        recs: Vec::new(),
    };
    let mut err = None;
    for (i, line) in text.lines().enumerate() {
        if line.trim().starts_with('%') {
            continue;
        }
        let loc = Loc::main(i as u32 + 1);
        let r = d.block(line, loc);
        d.record();
        match r {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => {
                err = Some((loc.line, e));
                break;
            }
        }
    }
    Run { recs: d.recs, err }
}

/// LinuxCNC's message for each refusal.
fn linuxcnc_message(e: &CompError) -> &'static str {
    match e {
        CompError::PlaneNotSupported { .. } => "Cutter radius compensation allowed only in XY, XZ planes",
        CompError::AlreadyOn { .. } => "Cannot turn cutter radius comp on when on",
        CompError::PlaneChange { .. } => "Cannot change planes with cutter radius compensation on",
        CompError::BadOrientation { .. } => "with lathe tool, but plane is not G18",
        CompError::EntryTooShort { .. } => {
            "Length of cutter compensation entry move is not greater than the tool radius"
        }
        CompError::EntryArcTooShort { .. } => {
            "Radius of cutter compensation entry arc is not greater than the tool radius"
        }
        CompError::ToolTooBigForArc { .. } => "Tool radius not less than arc radius with comp",
        CompError::ArcAfterExit { .. } => {
            "The move just after exiting cutter compensation mode must be straight, not an arc"
        }
        CompError::ConcaveLineGouge { traverse: true, .. } => {
            "Straight traverse in concave corner cannot be reached by the tool without gouging"
        }
        CompError::ConcaveLineGouge { traverse: false, .. } => {
            "Straight feed in concave corner cannot be reached by the tool without gouging"
        }
        CompError::ConcaveArcGouge { .. } => "Arc move in concave corner cannot be reached by the tool without gouging",
        CompError::ArcToLineGouge { .. } => {
            "Arc to straight motion makes a corner the compensated tool can't fit in without gouging"
        }
        CompError::ArcToArcGouge { .. } => {
            "Arc to arc motion makes a corner the compensated tool can't fit in without gouging"
        }
        CompError::ArcToArcSameCenter { .. } => "Arc to arc motion is invalid because the arcs have the same center",
        CompError::ZeroDegreeCorner { .. } => "Zero degree inside corner is invalid for cutter compensation",
        CompError::Construction { .. } => "ug",
        CompError::Refused { what: Refusal::ToolChange, .. } => {
            "Cannot change tools with cutter radius compensation on"
        }
        _ => "(no LinuxCNC counterpart)",
    }
}

// ---------------------------------------------------------------------------------------
// Closed forms.

fn feed(p: DVec3, line: u32) -> ProgMove<()> {
    ProgMove { kind: MoveKind::Feed, end: p, abc: DVec3::ZERO, loc: Loc::main(line), tag: () }
}

fn arc(p: DVec3, center: DVec3, turns: i32, line: u32) -> ProgMove<()> {
    ProgMove { kind: MoveKind::Arc { center, turns }, end: p, abc: DVec3::ZERO, loc: Loc::main(line), tag: () }
}

fn moves(out: &[Emit<(), Call>]) -> Vec<(ProgMove<()>, Origin)> {
    out.iter()
        .filter_map(|e| match e {
            Emit::Move { mv, origin } => Some((mv.clone(), *origin)),
            Emit::Pass(_) => None,
        })
        .collect()
}

fn xy(x: f64, y: f64) -> DVec3 {
    DVec3::new(x, y, 0.0)
}

/// A circle of radius R made of four quarter arcs, compensated inside and outside: the
/// tool runs on circles of R − r and R + r around the same centre.
#[test]
fn offset_of_a_circle_is_a_circle_of_r_plus_or_minus_tool_radius() {
    let (big_r, r) = (20.0, 3.0);
    for (side, ccw, expect) in [
        (Side::Left, true, big_r - r),
        (Side::Right, true, big_r + r),
        (Side::Left, false, big_r + r),
        (Side::Right, false, big_r - r),
    ] {
        let turns = if ccw { 1 } else { -1 };
        let mut comp = Comp::new(Plane::Xy);
        let mut out = Vec::new();
        comp.start(side, r, xy(50.0, 0.0), Loc::main(1)).unwrap();
        comp.push(feed(xy(big_r, 0.0), 2), &mut out).unwrap();
        let quarter = if ccw {
            [(0.0, 20.0), (-20.0, 0.0), (0.0, -20.0), (20.0, 0.0)]
        } else {
            [(0.0, -20.0), (-20.0, 0.0), (0.0, 20.0), (20.0, 0.0)]
        };
        for (i, (x, y)) in quarter.iter().enumerate() {
            comp.push(arc(xy(*x, *y), DVec3::ZERO, turns, 3 + i as u32), &mut out).unwrap();
        }
        comp.stop(Loc::main(7), &mut out).unwrap();
        let ms = moves(&out);
        let arcs: Vec<_> =
            ms.iter().filter(|(m, o)| matches!(m.kind, MoveKind::Arc { .. }) && *o == Origin::Programmed).collect();
        assert_eq!(arcs.len(), 4, "{side:?} ccw {ccw}: {ms:?}");
        for (m, _) in arcs {
            let MoveKind::Arc { center, turns: t } = m.kind else { unreachable!() };
            assert!(center.length() < 1e-12, "centre moved: {center}");
            assert_eq!(t, turns);
            assert!(
                (m.end.length() - expect).abs() < 1e-9,
                "{side:?} ccw {ccw}: radius {} not {expect}",
                m.end.length()
            );
        }
    }
}

/// Around a convex polygon with the tool outside, every compensated straight move lies one
/// radius from its programmed line and every corner is an arc of the tool radius around the
/// programmed vertex.
#[test]
fn offset_lines_lie_one_radius_away_and_convex_corners_are_arcs_around_the_vertex() {
    let r = 2.5;
    // A clockwise pentagon: the tool on the left is outside.
    let pts = [xy(0.0, 0.0), xy(-5.0, 20.0), xy(15.0, 35.0), xy(40.0, 18.0), xy(30.0, -6.0)];
    let mut comp = Comp::new(Plane::Xy);
    let mut out = Vec::new();
    comp.start(Side::Left, r, xy(-10.0, -15.0), Loc::main(1)).unwrap();
    for i in 0..=pts.len() + 1 {
        comp.push(feed(pts[i % pts.len()], 2 + i as u32), &mut out).unwrap();
    }
    comp.stop(Loc::main(20), &mut out).unwrap();
    let ms = moves(&out);
    let mut start = ms[0].0.end; // after the entry move
    let mut corners = 0;
    let mut lines = 0;
    for (m, origin) in &ms[1..] {
        match (m.kind, origin) {
            (MoveKind::Arc { center, turns }, Origin::Compensation) => {
                assert!(pts.iter().any(|p| (*p - center).length() < 1e-12), "corner arc centre {center} is no vertex");
                assert!(((start - center).length() - r).abs() < 1e-9 && ((m.end - center).length() - r).abs() < 1e-9);
                assert_eq!(turns, -1, "G41 goes clockwise around a convex corner");
                corners += 1;
            }
            (MoveKind::Feed, Origin::Programmed) => {
                // Both ends at distance r from the programmed edge they belong to.
                let on_edge = (0..pts.len()).any(|i| {
                    let (a, b) = (pts[i], pts[(i + 1) % pts.len()]);
                    let dist = |q: DVec3| ((q - a).cross(b - a)).z.abs() / (b - a).length();
                    (dist(start) - r).abs() < 1e-9 && (dist(m.end) - r).abs() < 1e-9
                });
                assert!(on_edge, "line {start} → {} is not one radius from an edge", m.end);
                lines += 1;
            }
            other => panic!("unexpected {other:?}"),
        }
        start = m.end;
    }
    // Six lines along the edges; five convex corners (the corner after the entry move turns
    // left, toward the tool: concave, no arc).
    assert_eq!((corners, lines), (5, 6));
}

/// A square pocket cut inside (G41 counter-clockwise): the concave corners are where the
/// offset lines meet, the square inset by the radius; the entry move (down onto the bottom
/// edge, offset to x = 20 + r) meets the bottom edge's offset line at (20 + r, r).
#[test]
fn concave_corners_of_a_pocket_are_the_inset_square() {
    let (l, r) = (40.0, 4.0);
    let mut comp = Comp::new(Plane::Xy);
    let mut out = Vec::new();
    comp.start(Side::Left, r, xy(20.0, 20.0), Loc::main(1)).unwrap();
    comp.push(feed(xy(20.0, 0.0), 2), &mut out).unwrap(); // entry, square to the bottom edge
    for (i, p) in [xy(l, 0.0), xy(l, l), xy(0.0, l), xy(0.0, 0.0), xy(20.0, 0.0)].iter().enumerate() {
        comp.push(feed(*p, 3 + i as u32), &mut out).unwrap();
    }
    comp.stop(Loc::main(9), &mut out).unwrap();
    let ends: Vec<DVec3> = moves(&out).iter().map(|(m, _)| m.end).collect();
    let expect = [xy(20.0 + r, r), xy(l - r, r), xy(l - r, l - r), xy(r, l - r), xy(r, r), xy(20.0, r)];
    assert_eq!(ends.len(), expect.len(), "{ends:?}");
    for (e, x) in ends.iter().zip(expect) {
        assert!((*e - x).length() < 1e-9, "{e} not {x}");
    }
}

#[test]
fn negative_radius_is_the_other_side() {
    let run = |side, r| {
        let mut comp = Comp::new(Plane::Xy);
        let mut out = Vec::new();
        comp.start(side, r, xy(-10.0, -10.0), Loc::main(1)).unwrap();
        for (i, p) in [xy(0.0, 0.0), xy(30.0, 0.0), xy(30.0, 20.0), xy(0.0, 5.0)].iter().enumerate() {
            comp.push(feed(*p, 2 + i as u32), &mut out).unwrap();
        }
        comp.stop(Loc::main(9), &mut out).unwrap();
        out
    };
    assert_eq!(run(Side::Left, -3.0), run(Side::Right, 3.0));
    assert_ne!(run(Side::Left, 3.0), run(Side::Right, 3.0));
}

#[test]
fn zero_radius_passes_moves_unchanged() {
    let mut comp = Comp::new(Plane::Xy);
    let mut out = Vec::new();
    comp.start(Side::Left, 0.0, xy(0.0, 0.0), Loc::main(1)).unwrap();
    let m = [feed(xy(1.0, 0.0), 2), arc(xy(3.0, 0.0), xy(2.0, 0.0), 1, 3)];
    for mv in &m {
        comp.push(mv.clone(), &mut out).unwrap();
        assert_eq!(comp.held(), 0);
    }
    let got: Vec<_> = moves(&out).into_iter().map(|(m, _)| m).collect();
    assert_eq!(got, m.to_vec());
}

/// Moves without motion in the plane and dwells wait behind the held move and come out in
/// their order, at its (moved) end.
#[test]
fn plunges_and_dwells_wait_behind_the_held_move_in_order() {
    let mut comp = Comp::new(Plane::Xy);
    let mut out = Vec::new();
    comp.start(Side::Left, 2.0, xy(-10.0, 0.0), Loc::main(1)).unwrap();
    comp.push(feed(xy(0.0, 0.0), 2), &mut out).unwrap();
    comp.push(feed(xy(20.0, 0.0), 3), &mut out).unwrap();
    let n0 = out.len();
    comp.push(feed(DVec3::new(20.0, 0.0, -3.0), 4), &mut out).unwrap();
    comp.pass(Call::Dwell(0.5), Loc::main(5), &mut out).unwrap();
    comp.push(feed(DVec3::new(20.0, 0.0, 0.0), 6), &mut out).unwrap();
    assert_eq!(out.len(), n0, "nothing may come out before the corner is known");
    comp.push(feed(xy(20.0, 10.0), 7), &mut out).unwrap(); // concave corner (tool inside)
    let tail: Vec<_> = out[n0..].to_vec();
    assert_eq!(tail.len(), 4, "{tail:?}");
    let corner = xy(18.0, 2.0);
    let Emit::Move { mv: a, .. } = &tail[0] else { panic!() };
    let Emit::Move { mv: b, .. } = &tail[1] else { panic!() };
    let Emit::Move { mv: d, .. } = &tail[3] else { panic!() };
    assert!((a.end - corner).length() < 1e-9);
    assert!((b.end - DVec3::new(18.0, 2.0, -3.0)).length() < 1e-9);
    assert_eq!(tail[2], Emit::Pass(Call::Dwell(0.5)));
    assert!((d.end - corner).length() < 1e-9);
}

#[test]
fn refusals_name_their_line() {
    let mut comp = Comp::new(Plane::Yz);
    assert_eq!(
        comp.start(Side::Left, 1.0, DVec3::ZERO, Loc::main(3)),
        Err(CompError::PlaneNotSupported { at: Loc::main(3) })
    );
    comp.set_plane(Plane::Zx, Loc::main(4)).unwrap();
    comp.start(Side::Left, 1.0, DVec3::ZERO, Loc::main(5)).unwrap();
    assert_eq!(comp.start(Side::Left, 1.0, DVec3::ZERO, Loc::main(6)), Err(CompError::AlreadyOn { at: Loc::main(6) }));
    assert_eq!(comp.set_plane(Plane::Xy, Loc::main(7)), Err(CompError::PlaneChange { at: Loc::main(7) }));
    assert!(comp.set_plane(Plane::Zx, Loc::main(8)).is_ok());
    assert_eq!(
        comp.refuse_if_on(Refusal::CannedCycle, Loc::main(9)),
        Err(CompError::Refused { at: Loc::main(9), what: Refusal::CannedCycle })
    );
    let mut out = Vec::new();
    let e = comp.push(feed(DVec3::new(0.5, 0.0, 0.5), 10), &mut out).unwrap_err();
    assert!(matches!(e, CompError::EntryTooShort { at, .. } if at == Loc::main(10)));
    assert!(e.to_string().starts_with("line 10: "), "{e}");
    // A lathe tool outside G18.
    let mut comp = Comp::new(Plane::Xy);
    assert!(matches!(
        comp.start_with_orientation(Side::Left, 1.0, 2, DVec3::ZERO, Loc::main(1)),
        Err(CompError::BadOrientation { orientation: 2, .. })
    ));
    assert!(comp.start_with_orientation(Side::Left, 1.0, 9, DVec3::ZERO, Loc::main(1)).is_ok());
    // Not numbers.
    let mut comp = Comp::new(Plane::Xy);
    assert!(matches!(comp.start(Side::Left, f64::NAN, DVec3::ZERO, Loc::main(1)), Err(CompError::BadRadius { .. })));
    comp.start(Side::Left, 1.0, DVec3::ZERO, Loc::main(1)).unwrap();
    assert!(matches!(comp.push(feed(DVec3::splat(f64::INFINITY), 2), &mut out), Err(CompError::BadMove { .. })));
}

#[test]
fn an_arc_after_g40_is_refused_and_a_line_clears_the_rule() {
    let mut comp = Comp::new(Plane::Xy);
    let mut out = Vec::new();
    comp.start(Side::Right, 1.0, xy(-5.0, 0.0), Loc::main(1)).unwrap();
    comp.push(feed(xy(0.0, 0.0), 2), &mut out).unwrap();
    comp.push(feed(xy(10.0, 0.0), 3), &mut out).unwrap();
    comp.stop(Loc::main(4), &mut out).unwrap();
    assert!(!comp.is_on());
    assert_eq!(
        comp.push(arc(xy(20.0, 0.0), xy(15.0, 0.0), 1, 5), &mut out),
        Err(CompError::ArcAfterExit { at: Loc::main(5) })
    );
    comp.push(feed(xy(12.0, 0.0), 6), &mut out).unwrap();
    comp.push(arc(xy(20.0, 0.0), xy(16.0, 0.0), 1, 7), &mut out).unwrap();
}

#[test]
fn held_calls_are_capped() {
    let mut comp = Comp::new(Plane::Xy);
    let mut out = Vec::new();
    comp.start(Side::Left, 1.0, xy(-5.0, 0.0), Loc::main(1)).unwrap();
    comp.push(feed(xy(0.0, 0.0), 2), &mut out).unwrap();
    let mut err = None;
    for i in 0..=MAX_HELD {
        if let Err(e) = comp.push(feed(DVec3::new(0.0, 0.0, (i % 2) as f64), 3), &mut out) {
            err = Some(e);
            break;
        }
    }
    assert!(matches!(err, Some(CompError::TooManyHeld { cap: MAX_HELD, .. })), "{err:?}");
    assert_eq!(comp.held(), MAX_HELD);
}

// ---------------------------------------------------------------------------------------
// Against LinuxCNC's rs274.

#[cfg(not(target_arch = "wasm32"))]
mod rs274 {
    use std::process::{Command, Stdio};
    use std::sync::atomic::{AtomicUsize, Ordering};

    use super::*;

    /// rs274's printing precision (4 decimals) plus rounding slack.
    const TOL: f64 = 0.5e-4 + 1e-9;

    /// What rs274 made of a program: its motions and dwells, and its error (message, line).
    pub(super) struct Linuxcnc {
        recs: Vec<Rec>,
        err: Option<(String, String)>,
        stderr: String,
    }

    fn nums(args: &str) -> Vec<f64> {
        args.split(',').map(|s| s.trim().parse().unwrap_or(f64::NAN)).collect()
    }

    /// Runs rs274 on `program` with tool table `table`; `None` when rs274 is not installed.
    pub(super) fn rs274(program: &str, table: &str) -> Option<Linuxcnc> {
        static N: AtomicUsize = AtomicUsize::new(0);
        // rs274 keeps the tool table in a file mapped from $HOME/.tool.mmap, which the next
        // rs274 truncates: two at once die of SIGBUS. Each run gets its own HOME.
        let k = N.fetch_add(1, Ordering::Relaxed);
        let run = std::env::temp_dir().join(format!("interpolab-comp-{}-{k}", std::process::id()));
        std::fs::create_dir_all(&run).ok()?;
        let ngc = run.join("p.ngc");
        let tbl = run.join("p.tbl");
        std::fs::write(&ngc, program).ok()?;
        std::fs::write(&tbl, table).ok()?;
        let out = Command::new("rs274")
            .arg("-g")
            .arg("-t")
            .arg(&tbl)
            .arg(&ngc)
            .env("HOME", &run)
            .stdin(Stdio::null())
            .output()
            .ok()?;
        let _ = std::fs::remove_dir_all(&run);
        assert!(out.status.code().is_some(), "rs274 was killed ({:?}) on\n{program}", out.status);
        let stdout = String::from_utf8_lossy(&out.stdout);
        let mut recs = Vec::new();
        for line in stdout.lines() {
            let Some((_, rest)) = line.trim_start().split_once(' ') else { continue };
            let Some((_, call)) = rest.trim_start().split_once(' ') else { continue };
            let call = call.trim_start();
            let Some((name, args)) = call.split_once('(') else { continue };
            let args = args.trim_end_matches(')');
            let v = nums(args);
            let rec = match name {
                "STRAIGHT_TRAVERSE" => Rec::Traverse([v[0], v[1], v[2], v[3], v[4], v[5]]),
                "STRAIGHT_FEED" => Rec::Feed([v[0], v[1], v[2], v[3], v[4], v[5]]),
                "ARC_FEED" => Rec::Arc([v[0], v[1], v[2], v[3]], v[4] as i32, [v[5], v[6], v[7], v[8]]),
                "DWELL" => Rec::Dwell(v[0]),
                _ => continue,
            };
            recs.push(rec);
        }
        let stderr = String::from_utf8_lossy(&out.stderr);
        let msgs: Vec<&str> = stderr.lines().filter(|l| l.trim() != "executing" && !l.trim().is_empty()).collect();
        let err = (!msgs.is_empty()).then(|| (msgs[0].to_string(), msgs.get(1).unwrap_or(&"").trim().to_string()));
        Some(Linuxcnc { recs, err, stderr: stderr.into_owned() })
    }

    fn close(a: &Rec, b: &Rec) -> bool {
        let near = |x: &[f64], y: &[f64]| x.iter().zip(y).all(|(p, q)| (p - q).abs() <= TOL);
        match (a, b) {
            (Rec::Traverse(x), Rec::Traverse(y)) | (Rec::Feed(x), Rec::Feed(y)) => near(x, y),
            (Rec::Arc(x, t, u), Rec::Arc(y, s, w)) => t == s && near(x, y) && near(u, w),
            (Rec::Dwell(x), Rec::Dwell(y)) => (x - y).abs() <= TOL,
            _ => false,
        }
    }

    /// Compares the driver's run with rs274's; `Err` describes the first difference.
    pub(super) fn agree(program: &str, tools: &HashMap<i32, Tool>) -> Option<Result<Outcome, String>> {
        let table: String = tools
            .iter()
            .map(|(t, tool)| format!("T{t} P{t} D{} Q{}\n", tool.diameter_inch, tool.orientation))
            .collect();
        let theirs = rs274(program, &table)?;
        let mine = drive(program, tools);
        let lines: Vec<&str> = program.lines().collect();
        let show = || {
            format!(
                "program:\n{program}\nrs274: {:?}\n{:#?}\nrs274's stderr: {}\nours: {:?}\n{:#?}",
                theirs.err, theirs.recs, theirs.stderr, mine.err, mine.recs
            )
        };
        if mine.recs.len() != theirs.recs.len() {
            return Some(Err(format!("{} calls, rs274 {}\n{}", mine.recs.len(), theirs.recs.len(), show())));
        }
        for (i, (a, b)) in mine.recs.iter().zip(&theirs.recs).enumerate() {
            if !close(a, b) {
                return Some(Err(format!("call {i}: ours {a:?}, rs274 {b:?}\n{}", show())));
            }
        }
        match (&mine.err, &theirs.err) {
            (None, None) => Some(Ok(Outcome::Ran(mine.recs.len()))),
            (Some((line, e)), Some((msg, text))) => {
                let want = linuxcnc_message(e);
                if !msg.contains(want) {
                    return Some(Err(format!("ours {e}, rs274 '{msg}'\n{}", show())));
                }
                if lines[*line as usize - 1].trim() != text {
                    return Some(Err(format!("ours at line {line}, rs274 at '{text}'\n{}", show())));
                }
                Some(Ok(Outcome::Refused(e.clone())))
            }
            _ => Some(Err(format!("refusals differ\n{}", show()))),
        }
    }

    /// What a program did in both interpreters.
    #[derive(Debug)]
    pub(super) enum Outcome {
        /// Ran to its end with this many calls.
        Ran(usize),
        /// Both refused it at the same line for the same reason.
        Refused(CompError),
    }

    pub(super) fn have_rs274() -> bool {
        let ok = Command::new("rs274").arg("-h").stdin(Stdio::null()).output().is_ok();
        if !ok {
            eprintln!("SKIPPED: LinuxCNC's rs274 is not installed (Debian: linuxcnc-uspace); no comparison made");
        }
        ok
    }
}

/// A small deterministic generator (xorshift64*).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
    fn f(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }
    fn chance(&mut self, p: f64) -> bool {
        self.f(0.0, 1.0) < p
    }
    fn pick<'a, X>(&mut self, xs: &'a [X]) -> &'a X {
        &xs[(self.next() % xs.len() as u64) as usize]
    }
}

/// Writes blocks in one plane: in-plane coordinates (a, b) become X/Y (G17) or Z/X (G18).
struct Writer {
    plane: Plane,
    lines: Vec<String>,
    /// The programmed position in the plane as rs274 will read it (rounded to 4 decimals).
    at: DVec2,
}

fn r4(v: f64) -> f64 {
    (v * 1e4).round() / 1e4
}

impl Writer {
    fn line(&mut self, s: &str) {
        let n = 10 * (self.lines.len() + 1);
        self.lines.push(format!("N{n} {s}"));
    }
    fn words(&self, p: DVec2) -> String {
        match self.plane {
            Plane::Xy => format!("X{:.4} Y{:.4}", p.x, p.y),
            _ => format!("Z{:.4} X{:.4}", p.x, p.y),
        }
    }
    fn normal(&self) -> char {
        if self.plane == Plane::Xy { 'Z' } else { 'Y' }
    }
    fn go(&mut self, g: &str, p: DVec2) {
        let w = self.words(p);
        self.line(&format!("{g} {w}"));
        self.at = DVec2::new(r4(p.x), r4(p.y));
    }
    /// An arc to `p` around `c` (`ccw` for G3), by IJK or, when `use_r`, by R.
    fn arc(&mut self, p: DVec2, c: DVec2, ccw: bool, use_r: bool, extra: &str) {
        let g = if ccw { "G3" } else { "G2" };
        let w = self.words(p);
        let centre = if use_r {
            let sweep = {
                let a0 = (self.at - c).to_angle();
                let a1 = (p - c).to_angle();
                let d = if ccw { a1 - a0 } else { a0 - a1 };
                d.rem_euclid(std::f64::consts::TAU)
            };
            let r = (self.at - c).length();
            format!("R{:.4}", if sweep > std::f64::consts::PI { -r } else { r })
        } else {
            let d = c - self.at;
            match self.plane {
                Plane::Xy => format!("I{:.4} J{:.4}", d.x, d.y),
                _ => format!("K{:.4} I{:.4}", d.x, d.y),
            }
        };
        self.line(&format!("{g} {w} {centre}{extra}"));
        self.at = DVec2::new(r4(p.x), r4(p.y));
    }
}

/// A random closed contour (lines, arcs bulging either way, tangent arcs, plunges, dwells,
/// rapid moves) entered from outside at an angle, cut with G41 or G42 and left with G40.
fn random_contour(rng: &mut Rng, plane: Plane) -> String {
    let n = 3 + (rng.next() % 5) as usize;
    let mut angles: Vec<f64> = Vec::new();
    while angles.len() < n {
        let a = rng.f(0.0, std::f64::consts::TAU);
        if angles.iter().all(|b| {
            let d = (a - b).rem_euclid(std::f64::consts::TAU);
            d.min(std::f64::consts::TAU - d) > 0.35
        }) {
            angles.push(a);
        }
    }
    angles.sort_by(f64::total_cmp);
    let mut pts: Vec<DVec2> = angles.iter().map(|a| rng.f(15.0, 50.0) * DVec2::from_angle(*a)).collect();
    if rng.chance(0.5) {
        pts.reverse();
    }
    let mut w = Writer { plane, lines: Vec::new(), at: DVec2::ZERO };
    let nrm = w.normal();
    w.line(if plane == Plane::Xy { "G21 G17 G90 F500" } else { "G21 G18 G90 F500" });
    let v0 = pts[0];
    let entry_from = v0 + rng.f(6.0, 40.0) * DVec2::from_angle(rng.f(0.0, std::f64::consts::TAU));
    w.go("G0", entry_from);
    w.line(&format!("G1 {nrm}-1"));
    let diameter = *rng.pick(&[1.0, 3.0, 5.0, 8.0, 12.0, 17.0, 26.0]) + r4(rng.f(0.0, 1.0));
    let side = if rng.chance(0.5) { "G41" } else { "G42" };
    match rng.next() % 4 {
        0 => w.line(&format!("{side} D{}", 1 + rng.next() % 3)),
        _ => w.line(&format!("{side}.1 D{diameter:.4}")),
    }
    // The entry: a line (or a rapid), sometimes an arc.
    if rng.chance(0.15) {
        let c = (w.at + v0) / 2.0 + rng.f(-0.4, 0.4) * (v0 - w.at).perp();
        w.arc(v0, c, rng.chance(0.5), false, "");
    } else {
        w.go(if rng.chance(0.2) { "G0" } else { "G1" }, v0);
    }
    let mut heading = (v0 - entry_from).normalize();
    let laps = n + if rng.chance(0.7) { 1 } else { 0 };
    for i in 1..=laps {
        let target = pts[i % n];
        match rng.next() % 10 {
            0..=4 => {
                let from = w.at;
                w.go(if rng.chance(0.06) { "G0" } else { "G1" }, target);
                heading = (w.at - from).normalize();
            }
            5..=7 => {
                // An arc through the chord, bulging either way, up to most of a turn.
                let ccw = rng.chance(0.5);
                let mut sweep = rng.f(0.3, 4.6);
                let use_r = rng.chance(0.3);
                if use_r && (sweep - std::f64::consts::PI).abs() < 0.3 {
                    sweep += 0.6;
                }
                let chord = target - w.at;
                let rad = chord.length() / (2.0 * (sweep / 2.0).sin());
                let mid = (w.at + target) / 2.0;
                let left = chord.perp().normalize();
                let off = rad * (sweep / 2.0).cos();
                let c = if ccw { mid + off * left } else { mid - off * left };
                let helix = if rng.chance(0.1) { format!(" {nrm}{:.4}", rng.f(-3.0, -1.0)) } else { String::new() };
                w.arc(target, c, ccw, use_r, &helix);
                let t = (target - c).perp().normalize();
                heading = if ccw { t } else { -t };
            }
            _ => {
                // A tangent arc, then a line to the vertex.
                let ccw = rng.chance(0.5);
                let rho = rng.f(1.0, 15.0);
                let left = heading.perp();
                let c = if ccw { w.at + rho * left } else { w.at - rho * left };
                let psi = rng.f(0.2, 2.2);
                let start = (w.at - c).to_angle();
                let q = c + rho * DVec2::from_angle(if ccw { start + psi } else { start - psi });
                w.arc(q, c, ccw, false, "");
                let from = w.at;
                w.go("G1", target);
                heading = (w.at - from).normalize();
            }
        }
        match rng.next() % 25 {
            0 => {
                w.line(&format!("G1 {nrm}-2"));
                w.line(&format!("G1 {nrm}-1"));
            }
            1 => w.line("G4 P0.5"),
            2 => w.line("M1"),
            _ => {}
        }
    }
    // Leave.
    w.line("G40");
    let exit = w.at + rng.f(5.0, 40.0) * DVec2::from_angle(rng.f(0.0, std::f64::consts::TAU));
    if rng.chance(0.05) {
        let c = (w.at + exit) / 2.0;
        w.arc(exit, c, true, false, "");
    } else {
        w.go("G1", exit);
    }
    w.line(&format!("G0 {nrm}5"));
    w.line("M2");
    w.lines.join("\n") + "\n"
}

fn tools() -> HashMap<i32, Tool> {
    HashMap::from([
        (1, Tool { diameter_inch: 0.25, orientation: 0 }),
        (2, Tool { diameter_inch: 0.5, orientation: 0 }),
        (3, Tool { diameter_inch: -0.125, orientation: 0 }),
    ])
}

#[cfg(not(target_arch = "wasm32"))]
fn check_all(name: &str, programs: &[String], tools: &HashMap<i32, Tool>) -> (usize, usize) {
    let (mut ran, mut refused, mut calls) = (0, 0, 0);
    let mut kinds: HashMap<String, usize> = HashMap::new();
    for p in programs {
        match rs274::agree(p, tools) {
            None => return (0, 0),
            Some(Ok(rs274::Outcome::Ran(n))) => {
                ran += 1;
                calls += n;
            }
            Some(Ok(rs274::Outcome::Refused(e))) => {
                refused += 1;
                *kinds.entry(linuxcnc_message(&e).to_string()).or_default() += 1;
            }
            Some(Err(why)) => panic!("{name}: ours and rs274 differ: {why}"),
        }
    }
    eprintln!("{name}: {ran} programs ran alike ({calls} motions and dwells), {refused} refused alike: {kinds:?}");
    (ran, refused)
}

/// 400 random contours in XY and 150 in XZ, each through both interpreters.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn random_contours_match_rs274() {
    if !rs274::have_rs274() {
        return;
    }
    let mut rng = Rng(0x9E37_79B9_7F4A_7C15);
    let xy: Vec<String> = (0..400).map(|_| random_contour(&mut rng, Plane::Xy)).collect();
    let xz: Vec<String> = (0..150).map(|_| random_contour(&mut rng, Plane::Zx)).collect();
    let (ran, refused) = check_all("XY", &xy, &tools());
    assert!(ran >= 100 && refused >= 40, "too few of each kind: {ran} ran, {refused} refused");
    let (ran, refused) = check_all("XZ", &xz, &tools());
    assert!(ran >= 30 && refused >= 10, "too few of each kind: {ran} ran, {refused} refused");
}

/// What a rule program must do in both interpreters.
#[derive(Clone, Copy, Debug)]
enum Expect {
    /// Run to its end.
    Runs,
    /// Be refused with LinuxCNC's message containing this.
    Refused(&'static str),
    /// Either, as long as both agree (a combination of arcs whose corners may gouge).
    Agrees,
}

/// Programs written for one rule each (both directions, both sides where it matters), with
/// the outcome each must have.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn rule_programs_match_rs274() {
    if !rs274::have_rs274() {
        return;
    }
    let body = |s: &str| format!("G21 G17 G90 F300\n{}\nM2\n", s.trim());
    let mut progs: Vec<(String, Expect)> = Vec::new();
    // Square pocket and island, both directions, both sides, from outside at an angle.
    for (side, d) in [("G41", "D8"), ("G42", "D8"), ("G41", "D3.5"), ("G42", "D3.5")] {
        for ccw in [true, false] {
            let sq =
                if ccw { "X40 Y0\nX40 Y30\nX0 Y30\nX0 Y0\nX20 Y0" } else { "X0 Y30\nX40 Y30\nX40 Y0\nX0 Y0\nX0 Y15" };
            progs.push((
                body(&format!("G0 X-17 Y-11\nG1 Z-1\n{side}.1 {d}\nG1 X0 Y0\n{sq}\nG40\nG1 X-17 Y-11")),
                Expect::Runs,
            ));
            let from_inside = body(&format!("G0 X20 Y15\nG1 Z-1\n{side}.1 {d}\nG1 X20 Y0\n{sq}\nG40\nG0 X20 Y15"));
            progs.push((from_inside, Expect::Runs));
        }
    }
    // Lines meeting arcs, convex and concave, in both orders; arc to arc.
    for side in ["G41.1", "G42.1"] {
        for (g1, g2) in [("G2", "G3"), ("G3", "G2"), ("G2", "G2"), ("G3", "G3")] {
            progs.push((
                body(&format!(
                    "G0 X-10 Y-10\n{side} D4\nG1 X0 Y0\nG1 X20 Y0\n{g1} X30 Y10 R10\nG1 Y30\n{g2} X10 Y30 R10\n{g1} X0 Y20 I0 J-10\nG1 X0 Y0\nG1 X5 Y0\nG40\nG1 X-10 Y-10"
                )),
                Expect::Agrees,
            ));
            progs.push((
                body(&format!(
                    "G0 X-10 Y-10\n{side} D2\nG1 X0 Y0\n{g1} X20 Y0 R15\n{g2} X40 Y0 R12\n{g1} X40 Y20 I5 J10\n{g2} X20 Y20 R-11\nG1 X0 Y0\nG1 X0 Y-2\nG40\nG1 X-10 Y-10"
                )),
                Expect::Agrees,
            ));
        }
    }
    let ok: [&str; 7] = [
        // Two tangent arcs with the tool outside both, meeting in a cusp (the "m" shape).
        "G0 X-10 Y-10\nG42.1 D10\nG1 X0 Y0\nG3 X20 Y0 R10\nG3 X40 Y0 R10\nG1 X50 Y0\nG40\nG1 X50 Y-10",
        // The entry is an arc; rapid corners; a full turn and more (P2); reversing on a line
        // (a half-circle corner).
        "G0 X-20 Y0\nG41.1 D6\nG3 X0 Y20 I20 J0\nG1 X30 Y20\nG2 X30 Y-20 I0 J-20\nG1 X-20 Y-20\nG40\nG1 X-30 Y-30",
        "G0 X-20 Y0\nG42.1 D6\nG2 X0 Y20 I20 J0\nG0 X30 Y20\nG0 X30 Y0\nG1 X0 Y0\nG40\nG0 X-20 Y-5",
        "G0 X-20 Y0\nG41.1 D4\nG1 X0 Y0\nG2 X0 Y0 I10 J0 P2\nG1 X-5 Y-5\nG40\nG1 X-20 Y-20",
        "G0 X-10 Y-10\nG41.1 D4\nG1 X0 Y0\nG1 X20 Y0\nG1 X0 Y0\nG40\nG1 X-10 Y-10",
        // Plunges and dwells while on, a flush by M1, a helix, rotary axes.
        "G0 X-10 Y-10\nG41.1 D4\nG1 X0 Y0 A10\nG1 X30 Y0\nG1 Z-3\nG4 P1\nG1 Z0\nG1 X30 Y20 B5\nG3 X10 Y20 R10 Z-2 C7\nM1\nG1 X0 Y0\nG1 X10 Y0\nG40\nG1 X-10 Y-10",
        // G41 with no D and no tool: radius 0, so the arc after G40 is allowed.
        "G0 X-20 Y-20\nG41\nG1 X0 Y0\nG1 X40\nG2 X50 Y10 R10\nG40\nG2 X60 Y20 R10",
    ];
    progs.extend(ok.iter().map(|p| (body(p), Expect::Runs)));
    // G41 Dn from the tool table (inches in rs274's table), and a negative diameter.
    progs.push((body("G0 X-20 Y-20\nG41 D2\nG1 X0 Y0\nG1 X40\nG1 Y30\nG1 X0\nG1 Y0\nG40\nG1 X-20 Y-20"), Expect::Runs));
    progs.push((body("G0 X-20 Y-20\nG42 D3\nG1 X0 Y0\nG1 X40\nG1 Y30\nG1 X0\nG1 Y0\nG40\nG1 X-20 Y-20"), Expect::Runs));
    let refused: [(&str, &str); 14] = [
        (
            "G0 X-10 Y-10\nG41.1 D24\nG1 X0 Y0\nG1 X30 Y0\nG3 X30 Y20 R10\nG1 X0 Y20\nG40\nG1 X-10 Y-10",
            "Tool radius not less than arc radius",
        ),
        (
            "G0 X-10 Y-10\nG41.1 D10\nG1 X0 Y0\nG1 X30 Y0\nG1 X30 Y3\nG1 X0 Y3\nG1 X0 Y10\nG40\nG1 X-10 Y-10",
            "Straight feed in concave corner",
        ),
        (
            "G0 X-10 Y-10\nG41.1 D10\nG1 X0 Y0\nG0 X30 Y0\nG0 X30 Y3\nG1 X0 Y3\nG40\nG1 X-10 Y-10",
            "Straight traverse in concave corner",
        ),
        ("G0 X-1 Y-1\nG41.1 D4\nG1 X0 Y0\nG1 X10\nG40\nG1 X-10 Y-10", "entry move is not greater"),
        ("G0 X-10 Y-10\nG41.1 D4\nG1 Z-1\nG1 X0 Y0", "entry move is not greater"),
        ("G0 X-1 Y0\nG41.1 D4\nG2 X0 Y0 R1\nG1 X10\nG40\nG1 X-10 Y-10", "entry arc is not greater"),
        ("G0 X-10 Y0\nG41.1 D4\nG1 X0 Y0\nG1 X10\nG40\nG2 X20 Y0 R5", "must be straight, not an arc"),
        ("G0 X-10 Y0\nG41.1 D4\nG41.1 D3\nG1 X0 Y0", "Cannot turn cutter radius comp on when on"),
        ("G0 X-10 Y0\nG41.1 D4\nG1 X0 Y0\nG18\nG1 X10", "Cannot change planes"),
        ("G19\nG0 X-10 Y0\nG41.1 D4\nG1 X0 Y0", "allowed only in XY, XZ planes"),
        ("G0 X-10 Y0\nG41.1 D4\nG1 X0 Y0\nT1 M6\nG1 X10", "Cannot change tools"),
        (
            "G0 X0 Y-10\nG41.1 D8\nG1 X0 Y0\nG3 X5 Y5 I0 J5\nG1 X-20 Y8\nG1 X-30 Y8\nG40\nG1 X-40 Y0",
            "Arc to straight motion",
        ),
        (
            "G0 X-10 Y-10\nG42.1 D2\nG1 X0 Y0\nG2 X20 Y0 R15\nG2 X40 Y0 R12\nG2 X40 Y20 I5 J10\nG1 X0 Y0\nG40\nG1 X-10 Y-10",
            "Arc to arc motion makes a corner",
        ),
        ("G0 X-10 Y0\nG41.1 D2\nG1 X0 Y0\nG3 X10 Y10 I0 J10\nG2 X0 Y0 I-10 J0\nG40\nG1 X-10 Y0", "same center"),
    ];
    progs.extend(refused.iter().map(|(p, m)| (body(p), Expect::Refused(m))));
    // G18 (XZ): an island outside and inside, and a lathe tool (orientation 2).
    let xz = |s: &str| format!("G21 G18 G90 F300\n{}\nM2\n", s.trim());
    progs.push((
        xz("G0 X-10 Z-10\nG41.1 D4\nG1 X0 Z0\nG1 Z40\nG2 Z50 X10 R10\nG1 X30\nG1 Z0\nG1 X0\nG1 Z10\nG40\nG1 X-10 Z-10"),
        Expect::Runs,
    ));
    progs.push((
        xz("G0 X-10 Z-10\nG42.1 D4\nG1 X0 Z0\nG1 Z40\nG3 Z50 X10 R10\nG1 X30\nG1 Z0\nG1 X0\nG1 Z10\nG40\nG1 X-10 Z-10"),
        Expect::Runs,
    ));
    progs.push((
        xz("G0 X10 Z-5\nG42.1 D2 L2\nG1 X5 Z0\nG3 X0 Z5 R5\nG1 Z20\nG2 X-5 Z25 R5\nG1 Z30\nG40\nG0 X10"),
        Expect::Runs,
    ));
    progs.push((xz("G0 X10 Z-5\nG42.1 D2 L6\nG3 X0 Z5 R8\nG1 Z20\nG2 X-5 Z25 R5\nG1 Z30\nG40\nG0 X10"), Expect::Runs));
    let tools = tools();
    let (mut ran, mut stopped) = (0, 0);
    for (p, expect) in &progs {
        let got = rs274::agree(p, &tools)
            .expect("rs274 ran before")
            .unwrap_or_else(|why| panic!("ours and rs274 differ: {why}"));
        match (expect, got) {
            (Expect::Runs | Expect::Agrees, rs274::Outcome::Ran(n)) => {
                assert!(n >= 3, "{p}");
                ran += 1;
            }
            (Expect::Refused(m), rs274::Outcome::Refused(e)) => {
                assert!(linuxcnc_message(&e).contains(m), "{p}: {e}, not '{m}'");
                stopped += 1;
            }
            (Expect::Agrees, rs274::Outcome::Refused(_)) => stopped += 1,
            (e, g) => panic!("{p}: expected {e:?}, both gave {g:?}"),
        }
    }
    eprintln!("rules: {} programs agree with rs274: {ran} ran, {stopped} refused", progs.len());
}

/// LinuxCNC's sample programs that use compensation (all in inches), read by the test
/// driver: their motions equal rs274's.
#[cfg(not(target_arch = "wasm32"))]
#[test]
fn linuxcnc_sample_programs_match_rs274() {
    if !rs274::have_rs274() {
        return;
    }
    let dir = std::path::Path::new("/usr/share/linuxcnc/ncfiles");
    // A mill table (inches) with the 1" tool 4 that comp-g1.ngc asks for; LinuxCNC's lathe
    // table for lathecomp.ngc (tool n has orientation n).
    let mill: HashMap<i32, Tool> = [(1, 0.125), (2, 0.0625), (3, 0.201), (4, 1.0)]
        .into_iter()
        .map(|(t, d)| (t, Tool { diameter_inch: d, orientation: 0 }))
        .collect();
    let lathe: HashMap<i32, Tool> = (1..=9).map(|t| (t, Tool { diameter_inch: 0.1, orientation: t as u8 })).collect();
    let samples = [
        ("comp.ngc", &mill),
        ("comp-g1.ngc", &mill),
        ("comp311.ngc", &mill),
        ("comp311_2.ngc", &mill),
        ("cds.ngc", &mill),
        ("gmoccapy_2_tools_with_cutter_radius_compensation.ngc", &mill),
        ("lathecomp.ngc", &lathe),
    ];
    let mut read = 0;
    for (name, table) in samples {
        let Ok(text) = std::fs::read_to_string(dir.join(name)) else {
            eprintln!("SKIPPED: {name} is not installed");
            continue;
        };
        let got = rs274::agree(&text, table).expect("rs274 ran before").unwrap_or_else(|why| panic!("{name}: {why}"));
        let rs274::Outcome::Ran(n) = got else { panic!("{name}: refused by both: {got:?}") };
        eprintln!("{name}: {n} motions and dwells equal rs274's");
        assert!(n > 10, "{name}: only {n} motions");
        read += 1;
    }
    eprintln!("{read} of {} LinuxCNC samples compared", samples.len());
}
