//! The cycles against closed forms; `tests/reference/cycles.rs` checks them against LinuxCNC's
//! `rs274` move for move.

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
