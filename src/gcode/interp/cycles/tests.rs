//! The cycles against closed forms and, natively, against LinuxCNC's `rs274` move for move.

use glam::DVec3;

use super::*;

/// What a test compares: the canonical calls of a cycle, in program units.
#[derive(Clone, Debug, PartialEq)]
enum Seen {
    Rapid(DVec3),
    Feed(DVec3),
    Dwell(f64),
    Stop,
    Start(bool),
    Orient,
    ProgramStop,
}

fn seen(moves: &[CycleMove], unit: f64) -> Vec<Seen> {
    moves
        .iter()
        .filter_map(|m| match *m {
            CycleMove::Rapid(p) => Some(Seen::Rapid(p / unit)),
            CycleMove::Feed(p) => Some(Seen::Feed(p / unit)),
            CycleMove::Dwell { seconds } => Some(Seen::Dwell(seconds)),
            CycleMove::SpindleStop => Some(Seen::Stop),
            CycleMove::SpindleStart { clockwise } => Some(Seen::Start(clockwise)),
            CycleMove::SpindleOrient { .. } => Some(Seen::Orient),
            CycleMove::ProgramStop => Some(Seen::ProgramStop),
            CycleMove::OperatorRetract(_) => None,
        })
        .collect()
}

fn input(kind: CycleKind, plane: Plane, position: DVec3, words: CycleWords) -> CycleInput {
    CycleInput {
        kind,
        plane,
        position,
        incremental: false,
        retract: Retract::OldZ,
        spindle: SpindleDir::Clockwise,
        feed_rate: 100.0,
        inverse_time: false,
        cutter_comp: false,
        unit_mm: 1.0,
        words,
    }
}

fn run(inp: &CycleInput, st: &mut CycleState) -> (Vec<CycleMove>, CycleOutcome) {
    let mut out = Vec::new();
    let o = expand(inp, st, &mut out).unwrap_or_else(|e| panic!("{e}"));
    (out, o)
}

fn xyz(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

#[test]
fn g81_with_g98_drills_and_returns_to_the_initial_level() {
    let w = CycleWords { x: Some(4.0), y: Some(5.0), z: Some(-3.0), r: Some(2.0), ..CycleWords::default() };
    let mut st = CycleState::new();
    let (m, o) = run(&input(CycleKind::G81, Plane::Xy, xyz(1.0, 2.0, 10.0), w), &mut st);
    let r = CycleMove::Rapid;
    assert_eq!(
        m,
        vec![
            r(xyz(4.0, 5.0, 10.0)),
            r(xyz(4.0, 5.0, 2.0)),
            CycleMove::Feed(xyz(4.0, 5.0, -3.0)),
            r(xyz(4.0, 5.0, 10.0))
        ]
    );
    assert_eq!(o.end, xyz(4.0, 5.0, 10.0));
    assert_eq!(st.initial_level(), Some(10.0));
    // The next block of the same cycle keeps R, Z and the initial level.
    let (m, o) =
        run(&input(CycleKind::G81, Plane::Xy, o.end, CycleWords { x: Some(7.0), ..CycleWords::default() }), &mut st);
    assert_eq!(
        m,
        vec![
            r(xyz(7.0, 5.0, 10.0)),
            r(xyz(7.0, 5.0, 2.0)),
            CycleMove::Feed(xyz(7.0, 5.0, -3.0)),
            r(xyz(7.0, 5.0, 10.0))
        ]
    );
    assert_eq!(o.end, xyz(7.0, 5.0, 10.0));
}

#[test]
fn a_start_below_r_rises_to_r_once_and_g99_stays_there() {
    let w = CycleWords { x: Some(4.0), z: Some(-3.0), r: Some(2.0), l: Some(3.0), ..CycleWords::default() };
    let mut inp = input(CycleKind::G81, Plane::Xy, xyz(0.0, 0.0, 1.0), w);
    inp.incremental = true;
    inp.retract = Retract::RPlane;
    inp.words.r = Some(1.0); // R = initial level 1 + 1 = 2; bottom = 2 - 3 = -1.
    let mut st = CycleState::new();
    let (m, o) = run(&inp, &mut st);
    let rapids_to_r = m.iter().filter(|m| matches!(m, CycleMove::Rapid(p) if p.x == 0.0)).count();
    assert_eq!(rapids_to_r, 1, "{m:?}");
    assert_eq!(m[0], CycleMove::Rapid(xyz(0.0, 0.0, 2.0)));
    let feeds: Vec<DVec3> = m.iter().filter_map(|m| if let CycleMove::Feed(p) = m { Some(*p) } else { None }).collect();
    assert_eq!(feeds, vec![xyz(4.0, 0.0, -1.0), xyz(8.0, 0.0, -1.0), xyz(12.0, 0.0, -1.0)]);
    assert_eq!(o.end, xyz(12.0, 0.0, 2.0));
}

#[test]
fn g91_r_is_measured_from_the_initial_level_not_the_current_one() {
    // First block from Z10 with G99: the tool ends at R = 10 - 8 = 2. The second block's R-8
    // is again from the initial level 10, not from the current 2.
    let w = CycleWords { x: Some(1.0), z: Some(-5.0), r: Some(-8.0), ..CycleWords::default() };
    let mut inp = input(CycleKind::G81, Plane::Xy, xyz(0.0, 0.0, 10.0), w);
    inp.incremental = true;
    inp.retract = Retract::RPlane;
    let mut st = CycleState::new();
    let (_, o) = run(&inp, &mut st);
    assert_eq!(o.end, xyz(1.0, 0.0, 2.0));
    inp.position = o.end;
    inp.words = CycleWords { x: Some(1.0), r: Some(-8.0), ..CycleWords::default() };
    let (m, o) = run(&inp, &mut st);
    assert!(m.contains(&CycleMove::Feed(xyz(2.0, 0.0, -3.0))), "{m:?}");
    assert_eq!(o.end, xyz(2.0, 0.0, 2.0));
    // Leaving the cycle forgets the level: from Z2 the same words now mean R = 2 - 8 = -6
    // and a bottom of -11.
    st.leave();
    inp.position = o.end;
    inp.words.z = Some(-5.0);
    inp.words.x = None;
    let (m, o) = run(&inp, &mut st);
    assert!(m.contains(&CycleMove::Feed(xyz(2.0, 0.0, -11.0))), "X0 adds nothing: {m:?}");
    assert_eq!(o.end, xyz(2.0, 0.0, -6.0));
    assert_eq!(st.initial_level(), Some(2.0));
}

#[test]
fn g83_pecks_by_q_and_backs_off_0_254_mm_above_each_depth() {
    let w = CycleWords { z: Some(-3.0), r: Some(2.0), q: Some(1.5), ..CycleWords::default() };
    let mut st = CycleState::new();
    let mut inp = input(CycleKind::G83, Plane::Xy, xyz(0.0, 0.0, 2.0), w);
    inp.retract = Retract::RPlane;
    let (m, _) = run(&inp, &mut st);
    // Depths 0.5, -1.0, -2.5, then the bottom -3.
    let f = |z| CycleMove::Feed(xyz(0.0, 0.0, z));
    let r = |z| CycleMove::Rapid(xyz(0.0, 0.0, z));
    let back = PECK_CLEARANCE_INCH * 25.4;
    assert_eq!(
        m,
        vec![
            r(2.0),
            f(0.5),
            r(2.0),
            r(0.5 + back),
            f(-1.0),
            r(2.0),
            r(-1.0 + back),
            f(-2.5),
            r(2.0),
            r(-2.5 + back),
            f(-3.0),
            r(2.0)
        ]
    );
    // G73 only backs off.
    let mut st = CycleState::new();
    inp.kind = CycleKind::G73;
    let (m, _) = run(&inp, &mut st);
    assert_eq!(
        m,
        vec![r(2.0), f(0.5), r(0.5 + back), f(-1.0), r(-1.0 + back), f(-2.5), r(-2.5 + back), f(-3.0), r(2.0)]
    );
}

#[test]
fn inch_programs_back_off_0_010_inch_and_move_in_mm() {
    let inch = 25.4;
    let w = CycleWords { z: Some(-0.3 * inch), r: Some(0.1 * inch), q: Some(0.2 * inch), ..CycleWords::default() };
    let mut inp = input(CycleKind::G73, Plane::Xy, xyz(0.0, 0.0, 0.1 * inch), w);
    inp.unit_mm = inch;
    let (m, _) = run(&inp, &mut CycleState::new());
    let got: Vec<f64> = m
        .iter()
        .map(|m| if let CycleMove::Rapid(p) | CycleMove::Feed(p) = m { p.z / inch } else { f64::NAN })
        .collect();
    let want = [0.1, -0.1, -0.1 + 0.01, -0.3, 0.1];
    assert_eq!(got.len(), want.len(), "{got:?}");
    assert!(got.iter().zip(want).all(|(g, w)| (g - w).abs() < 1e-12), "{got:?}");
}

#[test]
fn g87_backbores_through_the_offset_and_g88_stops_for_the_operator() {
    let w = CycleWords {
        x: Some(4.0),
        y: Some(5.0),
        z: Some(-3.0),
        r: Some(2.0),
        i: Some(1.0),
        j: Some(-2.0),
        k: Some(-1.0),
        ..CycleWords::default()
    };
    let mut inp = input(CycleKind::G87, Plane::Xy, xyz(1.0, 2.0, 10.0), w);
    inp.spindle = SpindleDir::CounterClockwise;
    let (m, o) = run(&inp, &mut CycleState::new());
    let s = seen(&m, 1.0);
    use Seen::*;
    assert_eq!(
        s,
        vec![
            Rapid(xyz(4.0, 5.0, 10.0)),
            Rapid(xyz(4.0, 5.0, 2.0)),
            Rapid(xyz(5.0, 3.0, 2.0)),
            Stop,
            Orient,
            Rapid(xyz(5.0, 3.0, -3.0)),
            Rapid(xyz(4.0, 5.0, -3.0)),
            Start(false),
            Feed(xyz(4.0, 5.0, -1.0)),
            Feed(xyz(4.0, 5.0, -3.0)),
            Stop,
            Orient,
            Rapid(xyz(5.0, 3.0, -3.0)),
            Rapid(xyz(5.0, 3.0, 10.0)),
            Rapid(xyz(4.0, 5.0, 10.0)),
            Start(false),
        ]
    );
    assert_eq!(o.end, xyz(4.0, 5.0, 10.0));

    let w = CycleWords { x: Some(4.0), z: Some(-3.0), r: Some(2.0), p: Some(2.0), ..CycleWords::default() };
    let (m, o) = run(&input(CycleKind::G88, Plane::Xy, xyz(0.0, 0.0, 10.0), w), &mut CycleState::new());
    let stop = m.iter().position(|m| *m == CycleMove::ProgramStop).unwrap_or(usize::MAX);
    assert_eq!(m.get(stop + 1), Some(&CycleMove::OperatorRetract(xyz(4.0, 0.0, 10.0))));
    assert_eq!(o.end, xyz(4.0, 0.0, 10.0));
}

#[test]
fn other_planes_drill_along_their_normal() {
    // G18: (a, b | n) = (Z, X | Y); G19: (Y, Z | X).
    let w = CycleWords { x: Some(4.0), y: Some(-3.0), z: Some(5.0), r: Some(2.0), ..CycleWords::default() };
    let (m, _) = run(&input(CycleKind::G81, Plane::Zx, xyz(1.0, 10.0, 2.0), w), &mut CycleState::new());
    assert_eq!(m[2], CycleMove::Feed(xyz(4.0, -3.0, 5.0)));
    let w = CycleWords { x: Some(-3.0), y: Some(4.0), z: Some(5.0), r: Some(2.0), ..CycleWords::default() };
    let (m, _) = run(&input(CycleKind::G81, Plane::Yz, xyz(10.0, 1.0, 2.0), w), &mut CycleState::new());
    assert_eq!(m[2], CycleMove::Feed(xyz(-3.0, 4.0, 5.0)));
    // Tapping in G19 feeds where LinuxCNC feeds (axes exchanged) and says so.
    let mut inp = input(CycleKind::G84, Plane::Yz, xyz(10.0, 1.0, 2.0), w);
    inp.words.p = Some(0.5);
    let (m, o) = run(&inp, &mut CycleState::new());
    assert_eq!(m[2], CycleMove::Feed(xyz(5.0, -3.0, 4.0)));
    assert_eq!(o.note, Some(CycleNote::TappingAxesExchanged));
}

#[test]
fn polar_repeats_turn_about_the_origin_in_g91() {
    let w =
        CycleWords { z: Some(-3.0), r: Some(-2.0), l: Some(4.0), polar_angle_deg: Some(90.0), ..CycleWords::default() };
    let mut inp = input(CycleKind::G81, Plane::Xy, xyz(10.0, 0.0, 5.0), w);
    inp.incremental = true;
    let (m, o) = run(&inp, &mut CycleState::new());
    let holes: Vec<DVec3> = m.iter().filter_map(|m| if let CycleMove::Feed(p) = m { Some(*p) } else { None }).collect();
    let want = [xyz(0.0, 10.0, 0.0), xyz(-10.0, 0.0, 0.0), xyz(0.0, -10.0, 0.0), xyz(10.0, 0.0, 0.0)];
    assert!(holes.len() == 4 && holes.iter().zip(want).all(|(h, w)| (*h - w).length() < 1e-12), "{holes:?}");
    assert!((o.end - xyz(10.0, 0.0, 5.0)).length() < 1e-12);
}

#[test]
fn refusals_name_the_word_and_what_to_write() {
    let base = CycleWords { x: Some(1.0), z: Some(-1.0), r: Some(2.0), ..CycleWords::default() };
    let pos = xyz(0.0, 0.0, 10.0);
    let check = |kind: CycleKind, edit: &dyn Fn(&mut CycleInput), want: &str| {
        let mut inp = input(kind, Plane::Xy, pos, base);
        edit(&mut inp);
        let mut st = CycleState::new();
        let mut out = Vec::new();
        let e = expand(&inp, &mut st, &mut out).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.contains(want), "{kind:?}: {e:?} lacks {want:?}");
        assert!(out.is_empty() && st == CycleState::new(), "refused before any move");
    };
    check(CycleKind::G81, &|i| i.words.r = None, "needs R");
    check(CycleKind::G81, &|i| i.words.z = None, "needs Z");
    check(CycleKind::G81, &|i| i.words.z = Some(3.0), "R less than Z");
    check(CycleKind::G81, &|i| i.words.l = Some(0.0), "positive whole number");
    check(CycleKind::G81, &|i| i.words.l = Some(1.5), "positive whole number");
    check(CycleKind::G81, &|i| i.words.l = Some(-2.0), "positive whole number");
    check(CycleKind::G81, &|i| i.words.l = Some(1e9), "split the holes");
    check(CycleKind::G74, &|i| i.words.l = Some(2.0), "G74 takes no L");
    check(CycleKind::G83, &|_| {}, "needs Q");
    check(CycleKind::G73, &|i| i.words.q = Some(0.0), "must be positive");
    check(CycleKind::G83, &|i| i.words.q = Some(1e-7), "pecks");
    check(CycleKind::G83, &|i| (i.words.q, i.words.l) = (Some(1e-3), Some(1e5)), "moves");
    check(CycleKind::G82, &|_| {}, "needs P");
    check(CycleKind::G89, &|i| i.words.p = Some(-1.0), "zero or more");
    check(CycleKind::G87, &|i| (i.words.i, i.words.j) = (Some(1.0), Some(1.0)), "needs K");
    check(CycleKind::G86, &|i| (i.words.p, i.spindle) = (Some(1.0), SpindleDir::Stopped), "M3");
    check(CycleKind::G84, &|i| i.spindle = SpindleDir::CounterClockwise, "program M3");
    check(CycleKind::G74, &|_| {}, "program M4");
    check(CycleKind::G81, &|i| i.cutter_comp = true, "G40");
    check(CycleKind::G81, &|i| i.inverse_time = true, "G94");
    check(CycleKind::G81, &|i| i.feed_rate = 0.0, "feed rate F");
    check(CycleKind::G81, &|i| i.words.rotary = Some('A'), "A word");
    check(
        CycleKind::G81,
        &|i| (i.plane, i.words.polar_radius, i.words.y) = (Plane::Zx, Some(1.0), Some(-1.0)),
        "G17 plane only",
    );
    check(CycleKind::G81, &|i| i.words.polar_radius = Some(1.0), "and X in one block");
}

#[test]
fn a_new_cycle_code_needs_its_words_again_but_p_carries_to_tapping() {
    let mut st = CycleState::new();
    let w = CycleWords { z: Some(-1.0), r: Some(2.0), p: Some(0.75), ..CycleWords::default() };
    run(&input(CycleKind::G82, Plane::Xy, xyz(0.0, 0.0, 5.0), w), &mut st);
    let mut out = Vec::new();
    let e = expand(&input(CycleKind::G81, Plane::Xy, xyz(0.0, 0.0, 5.0), CycleWords::default()), &mut st, &mut out);
    assert!(matches!(e, Err(CycleError::MissingR { .. })), "{e:?}");
    st.leave();
    let w = CycleWords { z: Some(-1.0), r: Some(2.0), ..CycleWords::default() };
    let (m, _) = run(&input(CycleKind::G84, Plane::Xy, xyz(0.0, 0.0, 5.0), w), &mut st);
    assert!(m.contains(&CycleMove::Dwell { seconds: 0.75 }), "G84 dwells the last P of any cycle: {m:?}");
}

/// The rs274 comparison: every cycle × G90/G91 × G98/G99 × L1/L3 (G74: L1) × the three
/// planes, two blocks each (the second sticky), and the position after, from LinuxCNC.
#[cfg(not(target_arch = "wasm32"))]
mod against_rs274 {
    use super::*;
    use crate::gcode::interp::cycles::rs274;

    /// Whether two lists agree, positions within `tol` (program units).
    fn agree(a: &[Seen], b: &[Seen], tol: f64) -> bool {
        a.len() == b.len()
            && a.iter().zip(b).all(|(x, y)| match (x, y) {
                (Seen::Rapid(p), Seen::Rapid(q)) | (Seen::Feed(p), Seen::Feed(q)) => {
                    (*p - *q).abs().max_element() <= tol
                }
                (Seen::Dwell(s), Seen::Dwell(t)) => (s - t).abs() <= tol,
                _ => x == y,
            })
    }

    /// One case: a start, the modes, the words of the two blocks.
    struct Case {
        text: String,
        inputs: Vec<CycleInput>,
    }

    fn fmt_words(w: &CycleWords) -> String {
        let mut s = String::new();
        let mut put = |l: char, v: Option<f64>| {
            if let Some(v) = v {
                s.push_str(&format!(" {l}{v}"));
            }
        };
        put('X', w.x);
        put('Y', w.y);
        put('Z', w.z);
        put('R', w.r);
        put('Q', w.q);
        put('P', w.p);
        put('I', w.i);
        put('J', w.j);
        put('K', w.k);
        put('L', w.l);
        if let Some(v) = w.polar_radius {
            s.push_str(&format!(" @{v}"));
        }
        if let Some(v) = w.polar_angle_deg {
            s.push_str(&format!(" ^{v}"));
        }
        s
    }

    /// Words of a cycle block in the plane's (a, b | n) terms.
    fn words(
        plane: Plane,
        a: Option<f64>,
        b: Option<f64>,
        n: Option<f64>,
        r: Option<f64>,
        ijk: Option<[f64; 3]>,
    ) -> CycleWords {
        let (ia, ib, inn) = plane.axes();
        let mut v = [None; 3];
        v[ia] = a;
        v[ib] = b;
        v[inn] = n;
        let mut w = CycleWords { x: v[0], y: v[1], z: v[2], r, ..CycleWords::default() };
        if let Some(t) = ijk {
            let mut o = [0.0; 3];
            o[ia] = t[0];
            o[ib] = t[1];
            o[inn] = t[2];
            (w.i, w.j, w.k) = (Some(o[0]), Some(o[1]), Some(o[2]));
        }
        w
    }

    fn cases(plane: Plane, kind: CycleKind, unit: f64) -> Vec<Case> {
        let mut out = Vec::new();
        let mut idx = 0;
        for incremental in [false, true] {
            for retract in [Retract::OldZ, Retract::RPlane] {
                for l in [1.0, 3.0] {
                    if kind == CycleKind::G74 && l > 1.0 {
                        continue;
                    }
                    idx += 1;
                    // Start above R, below R, or at R (a tie LinuxCNC resolves by `<`).
                    let start_n = [10.0, 1.0, 2.0][idx % 3];
                    let start = plane.join(1.0, 2.0, start_n);
                    let spindle = match kind {
                        CycleKind::G74 => SpindleDir::CounterClockwise,
                        CycleKind::G86 | CycleKind::G87 | CycleKind::G88 if idx % 2 == 1 => {
                            SpindleDir::CounterClockwise
                        }
                        _ => SpindleDir::Clockwise,
                    };
                    let (r, bottom, a1, b1, a2) =
                        if incremental { (2.0 - start_n, -5.0, 2.0, 1.0, -1.5) } else { (2.0, -3.0, 4.0, 5.0, 7.0) };
                    let top = if incremental { 2.0 } else { -1.0 };
                    let ijk = (kind == CycleKind::G87).then_some([1.0, -1.5, top]);
                    let mut w1 = words(plane, Some(a1), Some(b1), Some(bottom), Some(r), ijk);
                    let mut w2 = words(plane, Some(a2), None, None, None, None);
                    w1.l = (l > 1.0).then_some(l);
                    w2.l = w1.l;
                    match kind {
                        CycleKind::G73 | CycleKind::G83 => w1.q = Some(1.5),
                        CycleKind::G82 | CycleKind::G86 | CycleKind::G88 | CycleKind::G89 => w1.p = Some(0.5),
                        CycleKind::G74 | CycleKind::G84 => w2.p = Some(0.25),
                        _ => {}
                    }
                    let m = if spindle == SpindleDir::Clockwise { "M3" } else { "M4" };
                    let (ga, gr) =
                        (if incremental { "G91" } else { "G90" }, if retract == Retract::OldZ { "G98" } else { "G99" });
                    let at = start;
                    let text = format!(
                        "G80 G90 {m} S1000\nG0 X{} Y{} Z{}\nG4 P{}\n{ga} {gr} {}{}\n{}\nG80\nG91 G1 X0 Y0 Z0\nG90\nG4 P{}\n",
                        at.x,
                        at.y,
                        at.z,
                        1000 + 2 * idx,
                        kind.name(),
                        fmt_words(&w1),
                        fmt_words(&w2).trim_start(),
                        1001 + 2 * idx,
                    );
                    let mk = |words: CycleWords, position: DVec3| {
                        let scale = |v: Option<f64>| v.map(|v| v * unit);
                        let mut w = words;
                        (w.x, w.y, w.z, w.r, w.q, w.i, w.j, w.k) = (
                            scale(w.x),
                            scale(w.y),
                            scale(w.z),
                            scale(w.r),
                            scale(w.q),
                            scale(w.i),
                            scale(w.j),
                            scale(w.k),
                        );
                        CycleInput {
                            kind,
                            plane,
                            position: position * unit,
                            incremental,
                            retract,
                            spindle,
                            feed_rate: 100.0,
                            inverse_time: false,
                            cutter_comp: false,
                            unit_mm: unit,
                            words: w,
                        }
                    };
                    out.push(Case { text, inputs: vec![mk(w1, start), mk(w2, DVec3::NAN)] });
                }
            }
        }
        out
    }

    fn from_calls(calls: &[rs274::Call]) -> Vec<Seen> {
        calls
            .iter()
            .filter_map(|c| {
                let n = c.numbers();
                let p = || DVec3::new(n[0].unwrap_or(f64::NAN), n[1].unwrap_or(f64::NAN), n[2].unwrap_or(f64::NAN));
                Some(match c.name.as_str() {
                    "STRAIGHT_TRAVERSE" => Seen::Rapid(p()),
                    "STRAIGHT_FEED" => Seen::Feed(p()),
                    "DWELL" => Seen::Dwell(n[0].unwrap_or(f64::NAN)),
                    "STOP_SPINDLE_TURNING" => Seen::Stop,
                    "START_SPINDLE_CLOCKWISE" => Seen::Start(true),
                    "START_SPINDLE_COUNTERCLOCKWISE" => Seen::Start(false),
                    "ORIENT_SPINDLE" => Seen::Orient,
                    "PROGRAM_STOP" => Seen::ProgramStop,
                    _ => return None,
                })
            })
            .collect()
    }

    fn check_plane(plane: Plane, unit: f64) {
        let units = if unit == 1.0 { "G21" } else { "G20" };
        for kind in CycleKind::ALL {
            let cases = cases(plane, kind, unit);
            let mut text = format!("{units} {} F100\n", plane.gcode());
            for c in &cases {
                text.push_str(&c.text);
            }
            text.push_str("M2\n");
            let Some(calls) = rs274::run(&text, None) else { return };
            let calls = calls.unwrap_or_else(|e| panic!("rs274 refused:\n{text}\n{e}"));
            let mut st = CycleState::new();
            for (i, c) in cases.iter().enumerate() {
                let idx = i + 1;
                let theirs = from_calls(&rs274::between(&calls, (1000 + 2 * idx) as f64, (1001 + 2 * idx) as f64));
                st.leave();
                let mut moves = Vec::new();
                let first = expand(&c.inputs[0], &mut st, &mut moves).unwrap_or_else(|e| panic!("{e}\n{}", c.text));
                let mut second = c.inputs[1];
                second.position = first.end;
                let last = expand(&second, &mut st, &mut moves).unwrap_or_else(|e| panic!("{e}\n{}", c.text));
                let mut ours = seen(&moves, unit);
                ours.push(Seen::Feed(last.end / unit));
                assert!(
                    agree(&ours, &theirs, 0.5e-4 + 1e-9),
                    "{} {units}: case\n{}\nours   {ours:?}\nrs274  {theirs:?}",
                    plane.gcode(),
                    c.text
                );
            }
        }
    }

    #[test]
    fn every_cycle_in_g17_moves_as_rs274() {
        check_plane(Plane::Xy, 1.0);
    }

    #[test]
    fn every_cycle_in_g18_moves_as_rs274() {
        check_plane(Plane::Zx, 1.0);
    }

    #[test]
    fn every_cycle_in_g19_moves_as_rs274() {
        check_plane(Plane::Yz, 1.0);
    }

    #[test]
    fn inch_cycles_move_as_rs274() {
        check_plane(Plane::Xy, 25.4);
    }

    #[test]
    fn polar_cycles_move_as_rs274() {
        let text = "G21 G17 F100 M3 S1000\nG0 X10 Y0 Z5\nG4 P1\nG91 G98 G81 ^45 Z-3 R-2 L3\n@2 ^-30 L2\nG80\nG91 G1 X0 Y0 Z0\nG90\nG4 P2\nG90 G0 X3 Y4 Z5\nG4 P3\nG99 G82 @7 ^120 Z-1 R1 P0.5\n@8\nG80\nG91 G1 X0 Y0 Z0\nG4 P4\nM2\n";
        let Some(calls) = rs274::run(text, None) else { return };
        let calls = calls.unwrap_or_else(|e| panic!("{e}"));
        let w1 = CycleWords {
            z: Some(-3.0),
            r: Some(-2.0),
            l: Some(3.0),
            polar_angle_deg: Some(45.0),
            ..CycleWords::default()
        };
        let w2 =
            CycleWords { l: Some(2.0), polar_radius: Some(2.0), polar_angle_deg: Some(-30.0), ..CycleWords::default() };
        let mut st = CycleState::new();
        let mut inp = input(CycleKind::G81, Plane::Xy, xyz(10.0, 0.0, 5.0), w1);
        inp.incremental = true;
        let mut moves = Vec::new();
        let o = expand(&inp, &mut st, &mut moves).unwrap_or_else(|e| panic!("{e}"));
        inp.words = w2;
        inp.position = o.end;
        let o = expand(&inp, &mut st, &mut moves).unwrap_or_else(|e| panic!("{e}"));
        let mut ours = seen(&moves, 1.0);
        ours.push(Seen::Feed(o.end));
        let theirs = from_calls(&rs274::between(&calls, 1.0, 2.0));
        assert!(agree(&ours, &theirs, 0.5e-4 + 1e-9), "ours {ours:?}\nrs274 {theirs:?}");

        st.leave();
        let w1 = CycleWords {
            z: Some(-1.0),
            r: Some(1.0),
            p: Some(0.5),
            polar_radius: Some(7.0),
            polar_angle_deg: Some(120.0),
            ..CycleWords::default()
        };
        let mut inp = input(CycleKind::G82, Plane::Xy, xyz(3.0, 4.0, 5.0), w1);
        inp.retract = Retract::RPlane;
        let mut moves = Vec::new();
        let o = expand(&inp, &mut st, &mut moves).unwrap_or_else(|e| panic!("{e}"));
        inp.words = CycleWords { polar_radius: Some(8.0), ..CycleWords::default() };
        inp.position = o.end;
        let o = expand(&inp, &mut st, &mut moves).unwrap_or_else(|e| panic!("{e}"));
        let mut ours = seen(&moves, 1.0);
        ours.push(Seen::Feed(o.end));
        let theirs = from_calls(&rs274::between(&calls, 3.0, 4.0));
        assert!(agree(&ours, &theirs, 0.5e-4 + 1e-9), "ours {ours:?}\nrs274 {theirs:?}");
    }

    #[test]
    fn what_rs274_refuses_is_refused() {
        let head = "G21 G17 F100 S1000 M3\nG0 X1 Y2 Z10\n";
        let bad: [(&str, CycleKind, CycleWords); 8] = [
            (
                "G81 X1 Z-1 R2 L0",
                CycleKind::G81,
                CycleWords { x: Some(1.0), z: Some(-1.0), r: Some(2.0), l: Some(0.0), ..CycleWords::default() },
            ),
            (
                "G81 X1 Z-1 R2 L1.5",
                CycleKind::G81,
                CycleWords { x: Some(1.0), z: Some(-1.0), r: Some(2.0), l: Some(1.5), ..CycleWords::default() },
            ),
            (
                "G83 X1 Z-1 R2 Q0",
                CycleKind::G83,
                CycleWords { x: Some(1.0), z: Some(-1.0), r: Some(2.0), q: Some(0.0), ..CycleWords::default() },
            ),
            (
                "G73 X1 Z-1 R2",
                CycleKind::G73,
                CycleWords { x: Some(1.0), z: Some(-1.0), r: Some(2.0), ..CycleWords::default() },
            ),
            (
                "G82 X1 Z-1 R2",
                CycleKind::G82,
                CycleWords { x: Some(1.0), z: Some(-1.0), r: Some(2.0), ..CycleWords::default() },
            ),
            (
                "G81 X1 Z3 R2",
                CycleKind::G81,
                CycleWords { x: Some(1.0), z: Some(3.0), r: Some(2.0), ..CycleWords::default() },
            ),
            ("G81 X1 Z-1", CycleKind::G81, CycleWords { x: Some(1.0), z: Some(-1.0), ..CycleWords::default() }),
            (
                "G87 X1 Z-1 R2 I1 J1",
                CycleKind::G87,
                CycleWords {
                    x: Some(1.0),
                    z: Some(-1.0),
                    r: Some(2.0),
                    i: Some(1.0),
                    j: Some(1.0),
                    ..CycleWords::default()
                },
            ),
        ];
        for (block, kind, w) in bad {
            let Some(r) = rs274::run(&format!("{head}{block}\nM2\n"), None) else { return };
            assert!(r.is_err(), "rs274 accepted {block}");
            let mut out = Vec::new();
            let e = expand(&input(kind, Plane::Xy, xyz(1.0, 2.0, 10.0), w), &mut CycleState::new(), &mut out);
            assert!(e.is_err(), "we accepted {block}");
        }
        // And rs274 refuses L on G74, as we do.
        let Some(r) = rs274::run("G21 F100 S100 M4\nG0 Z5\nG74 X1 Z-1 R2 L2\nM2\n", None) else { return };
        assert!(r.is_err());
    }
}
