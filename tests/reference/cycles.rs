//! The interpreter's parts against LinuxCNC's own interpreter: `rs274` (Debian's
//! `linuxcnc-uspace`, installed by `scripts/setup.sh test`) runs a program and prints its
//! canonical calls in program coordinates and units with four decimals; the canned cycles'
//! moves, the splines' ends and control-point counts and the tool table's length offsets must
//! equal them (within half a unit of the last printed decimal). Each test says "skipped" on
//! stderr and checks nothing when `rs274` is not installed. (Integration tests, because
//! running a program means writing it to a file, which the core's sources may not do.)
#![allow(
    clippy::unwrap_used,
    clippy::expect_used,
    clippy::float_cmp,
    reason = "tests: a failure should fail the test; some values are exact"
)]

use glam::DVec3;
use interpolab::gcode::Plane;
use interpolab::gcode::interp::Loc;
use interpolab::gcode::interp::cycles::{
    CycleInput, CycleKind, CycleMove, CycleState, CycleWords, Retract, SpindleDir, expand,
};
use interpolab::gcode::interp::splines::{BezierBlock, SplineBlock, SplineBuilder, SplineKind, SplineWords};
use interpolab::gcode::interp::tools::{TableUnits, ToolTable};

/// Runs `rs274` and reads what it prints.
mod rs274 {
    use std::path::PathBuf;
    use std::process::Command;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// One canonical call: its name and its arguments as printed.
    #[derive(Clone, Debug, PartialEq)]
    pub struct Call {
        /// `STRAIGHT_FEED`, `DWELL`, …
        pub name: String,
        /// The text between the parentheses, split at commas and trimmed.
        pub args: Vec<String>,
    }

    impl Call {
        /// The arguments as numbers (`None` for one that is not).
        pub fn numbers(&self) -> Vec<Option<f64>> {
            self.args.iter().map(|a| a.parse::<f64>().ok()).collect()
        }
    }

    static COUNTER: AtomicUsize = AtomicUsize::new(0);

    fn temp_path(ext: &str) -> PathBuf {
        let n = COUNTER.fetch_add(1, Ordering::Relaxed);
        std::env::temp_dir().join(format!("interpolab-rs274-{}-{n}.{ext}", std::process::id()))
    }

    /// Runs `rs274 -g` on `program` (with `-t` and the tool table's text when given). `None`
    /// when `rs274` is not installed; `Some(Err(stderr))` when it refuses the program.
    pub fn run(program: &str, tool_table: Option<&str>) -> Option<Result<Vec<Call>, String>> {
        let ngc = temp_path("ngc");
        std::fs::write(&ngc, program).ok()?;
        let tbl = tool_table.map(|t| {
            let p = temp_path("tbl");
            let _ = std::fs::write(&p, t);
            p
        });
        // rs274 keeps its tool table in `$HOME/.tool.mmap`, truncated by every run: give each
        // run a home of its own so that tests running side by side do not share it.
        let home = temp_path("home");
        let _ = std::fs::create_dir_all(&home);
        let mut cmd = Command::new("rs274");
        cmd.env("HOME", &home);
        if let Some(t) = &tbl {
            cmd.arg("-t").arg(t);
        }
        cmd.arg("-g").arg(&ngc);
        let output = cmd.output();
        let _ = std::fs::remove_file(&ngc);
        let _ = std::fs::remove_dir_all(&home);
        if let Some(t) = &tbl {
            let _ = std::fs::remove_file(t);
        }
        let output = match output {
            Ok(o) => o,
            Err(e) => {
                eprintln!("skipped: LinuxCNC's rs274 could not be run ({e}); `scripts/setup.sh test` installs it");
                return None;
            }
        };
        let stdout = String::from_utf8_lossy(&output.stdout);
        if !output.status.success() {
            return Some(Err(String::from_utf8_lossy(&output.stderr).into_owned()));
        }
        Some(Ok(stdout.lines().filter_map(parse_line).collect()))
    }

    /// `   12 N..... NAME(a, b)` → the call.
    fn parse_line(line: &str) -> Option<Call> {
        let rest = line.trim_start();
        let rest = rest.split_once(' ')?.1.trim_start();
        let rest = rest.strip_prefix('N')?.trim_start_matches(|c: char| c == '.' || c.is_ascii_digit()).trim_start();
        let open = rest.find('(')?;
        let close = rest.rfind(')')?;
        let name = rest[..open].to_owned();
        let inner = &rest[open + 1..close];
        let args =
            if inner.trim().is_empty() { Vec::new() } else { inner.split(',').map(|s| s.trim().to_owned()).collect() };
        Some(Call { name, args })
    }

    /// The calls strictly between the `DWELL` printed for `G4 P<start>` and the one for
    /// `G4 P<end>` (markers a test puts around the part it checks).
    pub fn between(calls: &[Call], start: f64, end: f64) -> Vec<Call> {
        let is = |c: &Call, v: f64| c.name == "DWELL" && c.numbers().first().copied().flatten() == Some(v);
        let from = calls.iter().position(|c| is(c, start)).map_or(calls.len(), |i| i + 1);
        let to = calls[from..].iter().position(|c| is(c, end)).map_or(calls.len(), |i| from + i);
        calls[from..to].to_vec()
    }

    #[test]
    fn printed_calls_are_parsed() {
        let c = parse_line("   17 N..... STRAIGHT_FEED(4.0000, 5.0000, -3.0000, 0.0000, 0.0000, 0.0000)");
        assert_eq!(
            c.map(|c| (c.name.clone(), c.numbers())),
            Some(("STRAIGHT_FEED".to_owned(), vec![Some(4.0), Some(5.0), Some(-3.0), Some(0.0), Some(0.0), Some(0.0)]))
        );
        assert_eq!(parse_line("   20 N..... PROGRAM_STOP()").map(|c| c.args.len()), Some(0));
        assert_eq!(parse_line("executing"), None);
    }
}

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

fn xyz(x: f64, y: f64, z: f64) -> DVec3 {
    DVec3::new(x, y, z)
}

// ---- Canned cycles -------------------------------------------------------------------------
//
// Every cycle × G90/G91 × G98/G99 × L1/L3 (G74: L1) × the three planes, two blocks each (the
// second with sticky words only), and the position after, from LinuxCNC.

/// Whether two lists agree, positions within `tol` (program units).
fn agree(a: &[Seen], b: &[Seen], tol: f64) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| match (x, y) {
            (Seen::Rapid(p), Seen::Rapid(q)) | (Seen::Feed(p), Seen::Feed(q)) => (*p - *q).abs().max_element() <= tol,
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
                    CycleKind::G86 | CycleKind::G87 | CycleKind::G88 if idx % 2 == 1 => SpindleDir::CounterClockwise,
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
    let w1 =
        CycleWords { z: Some(-3.0), r: Some(-2.0), l: Some(3.0), polar_angle_deg: Some(45.0), ..CycleWords::default() };
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

// ---- Splines ------------------------------------------------------------------------------

/// The control-point counts `rs274` prints for each NURBS_FEED, and where its position
/// is after the program (from a G91 G1 X0.1 that follows).
fn run(text: &str) -> Option<(Vec<usize>, DVec3)> {
    let calls = rs274::run(text, None)?.unwrap_or_else(|e| panic!("rs274 refused\n{text}\n{e}"));
    let counts = calls.iter().filter(|c| c.name == "NURBS_FEED").map(|c| c.args[0].parse().unwrap_or(0)).collect();
    let last = calls.iter().rev().find(|c| c.name == "STRAIGHT_FEED")?;
    let n = last.numbers();
    Some((counts, DVec3::new(n[0]?, n[1]?, n[2]?) - DVec3::new(0.1, 0.0, 0.0)))
}

#[test]
fn g5_and_g5_1_end_where_rs274_ends_with_as_many_control_points() {
    let text =
        "G21 G17 F100\nG0 X1 Y2 Z3\nG5 I0 J3 P1 Q-3 X4 Y5\nG5 P0 Q-1 X6 Y7\nG5.1 X8 Y6.5 I1 J-2\nG91 G1 X0.1\nM2\n";
    let Some((counts, end)) = run(text) else { return };
    let mut b = SplineBuilder::new();
    let blk = |position: DVec3, end_xy, i, j, p, q| BezierBlock {
        loc: Loc::main(1),
        position,
        end_xy,
        i,
        j,
        p,
        q,
        plane: Plane::Xy,
        other_axis: None,
        cutter_comp: false,
        feed_ok: true,
    };
    let c1 = b.cubic(&blk(DVec3::new(1.0, 2.0, 3.0), [4.0, 5.0], Some(0.0), Some(3.0), Some(1.0), Some(-3.0)));
    let c1 = c1.unwrap_or_else(|e| panic!("{e}"));
    let e1 = c1.point_at(c1.range().1);
    let c2 = b.cubic(&blk(e1, [6.0, 7.0], None, None, Some(0.0), Some(-1.0))).unwrap_or_else(|e| panic!("{e}"));
    let e2 = c2.point_at(c2.range().1);
    let c3 = b.quadratic(&blk(e2, [8.0, 6.5], Some(1.0), Some(-2.0), None, None)).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(counts, vec![c1.len(), c2.len(), c3.len()]);
    assert!((c3.point_at(c3.range().1) - end).length() < 0.5e-4, "{end}");
}

#[test]
fn g5_2_ends_where_rs274_ends_with_as_many_control_points() {
    // LinuxCNC's manual example, P on every point as its interpreter wants.
    let text = "G21 G17 F10\nG0 X1 Y2 Z3\nG5.2 P1 L3\nX0 Y1 P1\nX2 Y2 P1\nX2 Y0 P1\nX0 Y0 P2\nG5.3\nG91 G1 X0.1\nM2\n";
    let Some((counts, end)) = run(text) else { return };
    // The same blocks through the builder, as the executor hands them over.
    let mut b = SplineBuilder::new();
    let start = DVec3::new(1.0, 2.0, 3.0);
    let block = |line: u32, open, close, words| SplineBlock {
        loc: Loc::main(line),
        open,
        close,
        other_motion: None,
        position: start,
        absolute: true,
        plane: Plane::Xy,
        feed_set: true,
        inch: false,
        words,
    };
    let point = |x, y, p| SplineWords { x: Some(x), y: Some(y), p: Some(p), ..SplineWords::default() };
    let mut blocks = vec![block(
        3,
        Some(SplineKind::LinuxCnc),
        false,
        SplineWords { p: Some(1.0), l: Some(3.0), ..SplineWords::default() },
    )];
    for (i, (x, y, p)) in [(0.0, 1.0, 1.0), (2.0, 2.0, 1.0), (2.0, 0.0, 1.0), (0.0, 0.0, 2.0)].into_iter().enumerate() {
        blocks.push(block(4 + i as u32, None, false, point(x, y, p)));
    }
    blocks.push(block(8, None, true, SplineWords::default()));
    let mut finished = Vec::new();
    for blk in &blocks {
        let step = b.block(blk).unwrap_or_else(|e| panic!("{e}"));
        assert!(step.taken);
        finished.extend(step.finished);
    }
    assert_eq!(finished.len(), 1);
    let f = &finished[0];
    assert_eq!(counts, vec![f.curve.len()]);
    assert!((f.end - end).length() < 0.5e-4, "{} vs {end}", f.end);
    assert!((f.curve.point_at(f.curve.range().1) - end).length() < 0.5e-4, "the curve ends at its last point");
    assert_eq!(f.curve.control_point(0), start, "the curve starts at the position before G5.2");
}

#[test]
fn what_rs274_refuses_in_g5_is_refused() {
    type Edit = fn(&mut BezierBlock);
    let cases: [(&str, Edit); 4] = [
        ("G18 G5 I1 J1 P1 Q1 X1 Y1", |b: &mut BezierBlock| b.plane = Plane::Zx),
        ("G5 I1 P1 Q1 X1 Y1", |b: &mut BezierBlock| b.j = None),
        ("G5 I1 J1 X1 Y1", |b: &mut BezierBlock| b.q = None),
        ("G5 I1 J1 P1 Q1 X1 Y1 Z4", |b: &mut BezierBlock| b.other_axis = Some('Z')),
    ];
    for (block, edit) in cases {
        let Some(r) = rs274::run(&format!("G21 G17 F100\nG0 X0 Y0 Z3\n{block}\nM2\n"), None) else { return };
        assert!(r.is_err(), "rs274 accepted {block}");
        let mut blk = BezierBlock {
            loc: Loc::main(3),
            position: DVec3::new(0.0, 0.0, 3.0),
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
        edit(&mut blk);
        assert!(SplineBuilder::new().cubic(&blk).is_err(), "we accepted {block}");
    }
    for block in ["G5.1 X1 Y1 I1", "G19 G5.1 X1 Y1 I1 J1"] {
        let Some(r) = rs274::run(&format!("G21 G17 F100\nG0 X0 Y0 Z3\n{block}\nM2\n"), None) else { return };
        assert!(r.is_err(), "rs274 accepted {block}");
    }
}

// ---- Tool tables ---------------------------------------------------------------------------

#[test]
fn rs274_applies_the_same_length_offsets() {
    // rs274 reads its table in inches (its machine units) and prints mm in a G21 program.
    let text = "\
T1 P1 Z12.5 D0.25 ;ball
T2 P2 X0.5 Y-0.25 Z3.75 A10 B-20 C30 U1 V-2 W0.125 D0.5 ;bull r=0.0625
T3 P3 Z-1.0625 D0.125 ;drill
T5 P4 X-0.03125 Z7.5 ;v60
T40 P5 Z0.001 D0.01
";
    let table = ToolTable::from_linuxcnc(text, TableUnits::Inch).unwrap_or_else(|e| panic!("{e}"));
    let mut program = String::from("G21\n");
    for t in table.iter() {
        program.push_str(&format!("T{} M6 G43\n", t.number));
    }
    program.push_str("M2\n");
    let Some(calls) = rs274::run(&program, Some(text)) else { return };
    let calls = calls.unwrap_or_else(|e| panic!("rs274 refused:\n{e}"));
    let offsets: Vec<[DVec3; 3]> = calls
        .iter()
        .filter(|c| c.name == "USE_TOOL_LENGTH_OFFSET")
        .map(|c| {
            let v = |i: usize| {
                let n: Vec<f64> = c.args[i].split_whitespace().filter_map(|s| s.parse().ok()).collect();
                DVec3::new(n[0], n[1], n[2])
            };
            [v(0), v(1), v(2)]
        })
        .collect();
    assert_eq!(offsets.len(), table.len());
    for (t, [xyz, abc, uvw]) in table.iter().zip(offsets) {
        let near = |a: DVec3, b: DVec3| (a - b).abs().max_element() <= 0.5e-4 + 1e-9;
        assert!(near(t.offset_mm, xyz), "T{}: {} vs rs274 {xyz}", t.number, t.offset_mm);
        assert!(near(t.rotary_offset_deg, abc), "T{}: {} vs rs274 {abc}", t.number, t.rotary_offset_deg);
        assert!(near(t.uvw_offset_mm, uvw), "T{}: {} vs rs274 {uvw}", t.number, t.uvw_offset_mm);
    }
}
