//! The reference side of issue 21's measurement: LinuxCNC's `rs274` run on programs, its output
//! read and normalised to our convention (tests/support/rs274.rs), checked here on its own
//! against positions computed independently from the programs' numbers, so that the
//! interpreter can later be compared with it call for call.

use std::path::{Path, PathBuf};

use crate::support::Rng;
use crate::support::rs274::{self, RefCall, RefKind, RefPose, RefRun, Rs274, compare, plane_axes};
use glam::DVec3;
use interpolab::gcode::Plane;
use interpolab::gcode::interp::{Canon, Feed, FeedMode, Loc, Origin, Pose};

fn run(text: &str) -> RefRun {
    rs274::require();
    match Rs274::default().run_text(text) {
        Ok(r) => r,
        Err(e) => panic!("rs274 did not run: {e}"),
    }
}

fn run_ok(text: &str) -> RefRun {
    let r = run(text);
    assert!(r.error.is_none(), "rs274 refused the program: {:?}\n{text}", r.error);
    assert!(r.unparsed.is_empty(), "lines not understood: {:?}", r.unparsed);
    r
}

fn motions(r: &RefRun) -> Vec<&RefCall> {
    r.motions().collect()
}

fn end_of(c: &RefCall) -> RefPose {
    match &c.kind {
        RefKind::Traverse { end } | RefKind::Line { end, .. } | RefKind::Arc { end, .. } | RefKind::Probe { end } => {
            *end
        }
        k => panic!("not a motion with an end: {k:?}"),
    }
}

fn assert_at(c: &RefCall, expected: DVec3, what: &str) {
    let end = end_of(c);
    let d = (end.pose.xyz - expected).abs().max_element();
    assert!(
        d <= end.tol_mm,
        "{what}: rs274 call {} (line {:?}) normalised to {:?}, expected {expected:?} (off by {d:.3e} mm, allowed {:.1e})",
        c.seq,
        c.line,
        end.pose.xyz,
        end.tol_mm
    );
    // The bound must be a real one: a few printed units, not a free pass.
    assert!(end.tol_mm < 0.01, "tolerance {} mm is too loose to check anything", end.tol_mm);
}

/// Rotates (x, y) by `deg` counter-clockwise.
fn rot(v: DVec3, deg: f64) -> DVec3 {
    let (s, c) = deg.to_radians().sin_cos();
    DVec3::new(v.x * c - v.y * s, v.x * s + v.y * c, v.z)
}

/// A number with at most 3 decimals, so that rs274 prints the programmed value exactly.
fn q(rng: &mut Rng, lo: f64, hi: f64) -> f64 {
    (rng.range(lo, hi) * 1000.0).round() / 1000.0
}

fn fmt3(v: f64) -> String {
    format!("{v:.3}")
}

const SYSTEMS: [&str; 9] = ["G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"];

#[test]
fn offsets_rotation_and_inches_normalise_to_machine_millimetres() {
    // Programs with a coordinate system set by G10 L2 (offset and XY rotation), G92, G20/G21:
    // every normalised end must be rotate(p + g92, R) + g5x (× 25.4 for inches), computed here
    // from the program's own numbers.
    let mut rng = Rng::new(21);
    for case in 0..16 {
        let inch = case % 2 == 1;
        let u = if inch { 25.4 } else { 1.0 };
        let p = 1 + (case % 9);
        let o = DVec3::new(q(&mut rng, -50.0, 50.0), q(&mut rng, -50.0, 50.0), q(&mut rng, -20.0, 20.0));
        let r = if case % 4 < 2 { q(&mut rng, -180.0, 180.0) } else { 0.0 };
        let a = DVec3::new(q(&mut rng, -30.0, 30.0), q(&mut rng, -30.0, 30.0), q(&mut rng, -5.0, 5.0));
        let g = DVec3::new(q(&mut rng, -10.0, 10.0), q(&mut rng, -10.0, 10.0), q(&mut rng, -5.0, 5.0));
        let targets: Vec<DVec3> = (0..5)
            .map(|_| DVec3::new(q(&mut rng, -40.0, 40.0), q(&mut rng, -40.0, 40.0), q(&mut rng, -10.0, 10.0)))
            .collect();
        let mut text = format!("{}\nG90 G17 F100\n", if inch { "G20" } else { "G21" });
        text += &format!("G10 L2 P{p} X{} Y{} Z{} R{}\n{}\n", fmt3(o.x), fmt3(o.y), fmt3(o.z), fmt3(r), SYSTEMS[p - 1]);
        text += &format!("G0 X{} Y{} Z{}\n", fmt3(a.x), fmt3(a.y), fmt3(a.z));
        text += &format!("G92 X{} Y{} Z{}\n", fmt3(g.x), fmt3(g.y), fmt3(g.z));
        for t in &targets {
            text += &format!("G1 X{} Y{} Z{}\n", fmt3(t.x), fmt3(t.y), fmt3(t.z));
        }
        text += "M2\n";
        let r_run = run_ok(&text);
        let m = motions(&r_run);
        assert_eq!(m.len(), 1 + targets.len(), "{text}");
        let machine = |prog: DVec3, g92: DVec3| {
            let v = prog + g92;
            (rot(DVec3::new(v.x, v.y, 0.0), r) + DVec3::new(0.0, 0.0, v.z) + o) * u
        };
        assert_at(m[0], machine(a, DVec3::ZERO), &format!("case {case}: the move before G92\n{text}"));
        // G92 makes the current point read `g`: its offset is a - g.
        for (c, t) in m[1..].iter().zip(&targets) {
            assert_at(c, machine(*t, a - g), &format!("case {case}: a move after G92\n{text}"));
        }
        // The calls name their lines: the first G1 is on line 7.
        assert_eq!(m[1].line, Some(7), "{text}");
        // The offsets in force for the moves come through in mm too (M2 resets them to G54's).
        let g5x = r_run.calls.iter().filter(|c| c.seq < m[1].seq).rev().find_map(|c| match &c.kind {
            RefKind::G5xOffset { index, offset } => Some((*index, offset.xyz)),
            _ => None,
        });
        let (index, off) = g5x.unwrap_or_else(|| panic!("no G5x offset in {}", rs274::describe(&r_run.calls)));
        assert_eq!(index, p as i32);
        assert!((off - o * u).abs().max_element() < 1e-9 * u.max(1.0) + 0.5e-4 * u, "{off:?} against {:?}", o * u);
    }
}

#[test]
fn the_first_move_starts_at_the_machine_origin_and_a_move_in_place_is_printed() {
    let r = run_ok("G21 G90\nG1 X0 Y0 Z0 F100\nG0 X0\nG1 X5\nG1 X5\nM2\n");
    let m = motions(&r);
    assert_eq!(m.len(), 4, "{}", rs274::describe(&r.calls));
    assert_at(m[0], DVec3::ZERO, "G1 to where it is");
    assert_at(m[3], DVec3::new(5.0, 0.0, 0.0), "the repeated G1");
    assert!(matches!(m[1].kind, RefKind::Traverse { .. }));
}

/// Points at distance 5 from the centre with integer offsets (a 3-4-5 triangle), so that arcs
/// end exactly on their circle.
const ON_CIRCLE: [(f64, f64); 12] = [
    (5.0, 0.0),
    (4.0, 3.0),
    (3.0, 4.0),
    (0.0, 5.0),
    (-3.0, 4.0),
    (-4.0, 3.0),
    (-5.0, 0.0),
    (-4.0, -3.0),
    (-3.0, -4.0),
    (0.0, -5.0),
    (3.0, -4.0),
    (4.0, -3.0),
];

#[test]
fn arcs_map_by_plane_to_their_programmed_centre_end_and_turns() {
    // For each plane: G2/G3 by IJK, with P turns and full circles, from a start in the plane
    // at a known point; the normalised centre must be start + (I, J, K) (so the plane's axes are
    // mapped right), the end the programmed one, start and end equidistant from the centre in
    // the plane, and the turns G3 +P, G2 −P.
    let mut rng = Rng::new(2101);
    for (plane, g) in [(Plane::Xy, "G17"), (Plane::Zx, "G18"), (Plane::Yz, "G19")] {
        let (i0, i1, n) = plane_axes(plane);
        for case in 0..8 {
            let scale = 1.0 + (case as f64) * 0.25;
            let c = DVec3::new(q(&mut rng, -20.0, 20.0), q(&mut rng, -20.0, 20.0), q(&mut rng, -20.0, 20.0));
            let (s_idx, e_idx) = (case % 12, (case * 5 + 3) % 12);
            let e_idx = if case == 3 { s_idx } else { e_idx }; // one full circle
            let mut start = c;
            start[i0] += ON_CIRCLE[s_idx].0 * scale;
            start[i1] += ON_CIRCLE[s_idx].1 * scale;
            let mut end = c;
            end[i0] += ON_CIRCLE[e_idx].0 * scale;
            end[i1] += ON_CIRCLE[e_idx].1 * scale;
            end[n] += if case % 2 == 0 { 0.0 } else { 1.5 }; // helix
            let cw = case % 3 == 0;
            let p = 1 + (case % 3) as i32;
            // The plane's first and second axes and its normal, and the centre words of the
            // first two (I for X, J for Y, K for Z).
            let axis = |k: usize| ["X", "Y", "Z"][k];
            let centre_words = |k: usize| ["I", "J", "K"][k];
            let text = format!(
                "G21 G90 F100\nG0 X{} Y{} Z{}\n{g} {} {}{} {}{} {}{} {}{} {}{} P{p}\nM2\n",
                fmt3(start.x),
                fmt3(start.y),
                fmt3(start.z),
                if cw { "G2" } else { "G3" },
                axis(i0),
                fmt3(end[i0]),
                axis(i1),
                fmt3(end[i1]),
                axis(n),
                fmt3(end[n]),
                centre_words(i0),
                fmt3(c[i0] - start[i0]),
                centre_words(i1),
                fmt3(c[i1] - start[i1]),
            );
            let r = run_ok(&text);
            let arc = r
                .calls
                .iter()
                .find_map(|c| match &c.kind {
                    RefKind::Arc { end, center, plane, turns, .. } => Some((*end, *center, *plane, *turns)),
                    _ => None,
                })
                .unwrap_or_else(|| panic!("no arc in\n{}\n{text}", rs274::describe(&r.calls)));
            let (e, centre, pl, turns) = arc;
            let tol = e.tol_mm;
            assert_eq!(pl, plane, "{text}");
            assert!((centre - c).abs().max_element() <= tol, "{g}: centre {centre:?}, programmed {c:?}\n{text}");
            assert!(
                (e.pose.xyz - end).abs().max_element() <= tol,
                "{g}: end {:?}, programmed {end:?}\n{text}",
                e.pose.xyz
            );
            let radius = |p: DVec3| (p[i0] - centre[i0]).hypot(p[i1] - centre[i1]);
            assert!(
                (radius(start) - radius(e.pose.xyz)).abs() <= 2.0 * tol,
                "{g}: radii {} and {}\n{text}",
                radius(start),
                radius(e.pose.xyz)
            );
            assert_eq!(turns, if cw { -p } else { p }, "{g} {}: turns\n{text}", if cw { "G2" } else { "G3" });
        }
    }
}

#[test]
fn r_arcs_under_offsets_and_rotation_keep_their_centre_equidistant() {
    // R-format arcs (LinuxCNC computes the centre) after G10 L2 offsets, rotation and G92, in
    // inches and mm: the normalised centre must lie at R from both ends, in machine mm.
    let mut rng = Rng::new(2102);
    for case in 0..12 {
        let inch = case % 2 == 0;
        let u = if inch { 25.4 } else { 1.0 };
        let r = q(&mut rng, -90.0, 90.0);
        let o = DVec3::new(q(&mut rng, -20.0, 20.0), q(&mut rng, -20.0, 20.0), q(&mut rng, -5.0, 5.0));
        let s = DVec3::new(q(&mut rng, -5.0, 5.0), q(&mut rng, -5.0, 5.0), 0.0);
        let e = DVec3::new(q(&mut rng, -5.0, 5.0), q(&mut rng, -5.0, 5.0), 0.0);
        let radius = ((e - s).length() / 2.0 + q(&mut rng, 0.2, 4.0) * 1.0).max(0.1);
        let radius = (radius * 1000.0).round() / 1000.0;
        let text = format!(
            "{}\nG90 G17 F10\nG10 L2 P1 X{} Y{} Z{} R{}\nG54\nG92 X1 Y-2\nG0 X{} Y{} Z0\n{} X{} Y{} R{}\nM2\n",
            if inch { "G20" } else { "G21" },
            fmt3(o.x),
            fmt3(o.y),
            fmt3(o.z),
            fmt3(r),
            fmt3(s.x),
            fmt3(s.y),
            if case % 3 == 0 { "G2" } else { "G3" },
            fmt3(e.x),
            fmt3(e.y),
            fmt3(radius),
        );
        let run = run_ok(&text);
        let m = motions(&run);
        let start = end_of(m[0]);
        let (end, centre) = match &m[1].kind {
            RefKind::Arc { end, center, .. } => (*end, *center),
            k => panic!("not an arc: {k:?}\n{text}"),
        };
        let d0 = (start.pose.xyz - centre).truncate().length();
        let d1 = (end.pose.xyz - centre).truncate().length();
        let want = radius * u;
        // The centre is computed by LinuxCNC from printed-precision numbers: a few tolerances.
        let tol = 4.0 * end.tol_mm;
        assert!(
            (d0 - want).abs() <= tol && (d1 - want).abs() <= tol,
            "case {case}: distances {d0} and {d1}, R = {want} mm\n{text}"
        );
        assert!((start.pose.xyz.z - centre.z).abs() <= end.tol_mm, "the centre's Z is the start's");
    }
}

#[test]
fn inverse_time_feeds_match_our_lengths_and_compare_accepts_them() {
    // G93: rs274 prints the per-minute rate max(0.1, length·F) before each move. Our
    // comparison computes that rate from our moves' lengths; here our calls are built from the
    // program's own numbers, so a wrong length formula (straight, arc, helix, rotary-only)
    // fails the comparison.
    let text = "G21 G90 G17\nG0 X0 Y0 Z0\nG93\nG1 X30 Y40 F2\nG2 X40 Y30 I0 J-10 F0.5\nG3 X40 Y30 Z-6 I-5 J0 P2 F1\nG1 A90 F3\nG1 X40.01 F0.1\nG94 G1 X0 F500\nM2\n";
    let r = run_ok(text);
    let at = |x: f64, y: f64, z: f64, a: f64| Pose { xyz: DVec3::new(x, y, z), abc: DVec3::new(a, 0.0, 0.0) };
    let inv = |rate: f64| Feed { mode: FeedMode::InverseTime, rate, spindle_rpm: 0.0 };
    let loc = |l: u32| Loc::main(l);
    let ours = vec![
        Canon::Traverse { loc: loc(2), end: at(0.0, 0.0, 0.0, 0.0), origin: Origin::Programmed },
        Canon::Line { loc: loc(4), end: at(30.0, 40.0, 0.0, 0.0), feed: inv(2.0), origin: Origin::Programmed },
        Canon::Arc {
            loc: loc(5),
            end: at(40.0, 30.0, 0.0, 0.0),
            center: DVec3::new(30.0, 30.0, 0.0),
            plane: Plane::Xy,
            turns: -1,
            feed: inv(0.5),
            origin: Origin::Programmed,
        },
        Canon::Arc {
            loc: loc(6),
            end: at(40.0, 30.0, -6.0, 0.0),
            center: DVec3::new(35.0, 30.0, 0.0),
            plane: Plane::Xy,
            turns: 2,
            feed: inv(1.0),
            origin: Origin::Programmed,
        },
        Canon::Line { loc: loc(7), end: at(40.0, 30.0, -6.0, 90.0), feed: inv(3.0), origin: Origin::Programmed },
        Canon::Line { loc: loc(8), end: at(40.01, 30.0, -6.0, 90.0), feed: inv(0.1), origin: Origin::Programmed },
        Canon::Line {
            loc: loc(9),
            end: at(0.0, 30.0, -6.0, 90.0),
            feed: Feed { mode: FeedMode::PerMinute, rate: 500.0, spindle_rpm: 0.0 },
            origin: Origin::Programmed,
        },
        Canon::Stop { loc: loc(10), end: true },
    ];
    if let Err(e) = compare(&ours, &r.calls) {
        panic!("{e}\n{}", rs274::describe(&r.calls));
    }
    // And the same with the first helix's feed off by 1 %: the comparison must say so.
    let mut wrong = ours.clone();
    if let Canon::Arc { feed, .. } = &mut wrong[3] {
        feed.rate *= 1.01;
    }
    let e = compare(&wrong, &r.calls).expect_err("a 1 % feed error must be reported");
    assert!(e.contains("feed") && e.contains("line 6"), "{e}");
}

/// Our canonical calls rebuilt from rs274's (what a perfect interpreter would emit).
fn as_ours(calls: &[RefCall]) -> Vec<Canon> {
    let mut out = Vec::new();
    let mut rpm_last = 0.0;
    for c in calls {
        let loc = Loc::main(c.line.unwrap_or(0));
        let feed = |f: &rs274::RefFeed| Feed {
            mode: if f.per_rev { FeedMode::PerRevolution } else { FeedMode::PerMinute },
            rate: f.rate,
            spindle_rpm: 0.0,
        };
        match &c.kind {
            RefKind::Traverse { end } => out.push(Canon::Traverse { loc, end: end.pose, origin: Origin::Programmed }),
            RefKind::Line { end, feed: f } => {
                out.push(Canon::Line { loc, end: end.pose, feed: feed(f), origin: Origin::Programmed })
            }
            RefKind::Probe { end } => {
                out.push(Canon::Line { loc, end: end.pose, feed: Feed::default(), origin: Origin::Probe });
            }
            RefKind::Arc { end, center, plane, turns, feed: f } => out.push(Canon::Arc {
                loc,
                end: end.pose,
                center: *center,
                plane: *plane,
                turns: *turns,
                feed: feed(f),
                origin: Origin::Programmed,
            }),
            RefKind::Dwell { seconds } => out.push(Canon::Dwell { loc, seconds: *seconds }),
            RefKind::ChangeTool { tool, .. } | RefKind::SetToolNumber { tool, .. } => {
                out.push(Canon::ToolChange { loc, tool: *tool })
            }
            RefKind::ToolLengthOffset { offset, .. } => out.push(Canon::ToolLengthOffset { loc, offset: *offset }),
            RefKind::Spindle { rpm } if *rpm != rpm_last => {
                rpm_last = *rpm;
                out.push(Canon::Spindle { loc, rpm: *rpm });
            }
            RefKind::Stop { end } => out.push(Canon::Stop { loc, end: *end }),
            _ => {}
        }
    }
    out
}

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/ngc").join(name)
}

fn run_file(name: &str) -> RefRun {
    rs274::require();
    let rs = Rs274 { subroutine_dirs: vec![data("")], tool_table: Some(data("tools.tbl")), ..Rs274::default() };
    rs.run(&data(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

#[test]
fn compare_accepts_rs274s_own_calls_and_names_the_first_difference() {
    let r = run_file("tools-offsets.ngc");
    assert!(r.error.is_none(), "{:?}", r.error);
    let ours = as_ours(&r.calls);
    assert!(ours.iter().any(|c| matches!(c, Canon::ToolChange { .. })), "the program changes tools");
    if let Err(e) = compare(&ours, &r.calls) {
        panic!("rs274's own calls must compare equal: {e}");
    }
    // Move one end by 1 µm: the comparison must name that call, its line and both values.
    let k = ours.iter().rposition(|c| matches!(c, Canon::Line { .. })).unwrap_or_else(|| panic!("no line"));
    let mut moved = ours.clone();
    let line = moved[k].loc().line;
    if let Canon::Line { end, .. } = &mut moved[k] {
        end.xyz.y += 1e-3;
    }
    let e = compare(&moved, &r.calls).expect_err("a 1 µm move must be found");
    assert!(e.contains(&format!("line {line}")) && e.contains("Y differs"), "{e}");
    // A missing tool change is a difference too, not skipped.
    let mut fewer = ours.clone();
    let t =
        fewer.iter().position(|c| matches!(c, Canon::ToolChange { .. })).unwrap_or_else(|| panic!("no tool change"));
    fewer.remove(t);
    assert!(compare(&fewer, &r.calls).is_err());
}

#[test]
fn errors_name_their_line_and_text() {
    let r = run("G21 G90\nG1 X1 F100\n(a comment)\n\nG1 X2 G2 Y3\nM2\n");
    let e = r.error.clone().unwrap_or_else(|| panic!("two motion words on a line must be refused"));
    assert_eq!(e.line, Some(5), "{e:?}");
    assert_eq!(e.source, "G1 X2 G2 Y3", "{e:?}");
    assert!(!e.text.is_empty());
    // The moves before it were printed and normalised.
    assert_eq!(r.motions().count(), 1);
}

#[test]
fn a_program_ending_without_m2_or_percent_is_reported_after_all_its_moves() {
    let r = run("G21 G90\nG1 X1 F100\nG1 X2\n");
    let e = r.error.clone().unwrap_or_else(|| panic!("rs274 wants a program end"));
    assert!(e.text.contains("no percent sign or program end"), "{e:?}");
    assert_eq!(r.motions().count(), 2);
}

#[test]
fn tool_table_lengths_are_read_as_inches() {
    rs274::require();
    let dir = std::env::temp_dir().join(format!("interpolab-tbl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let tbl = dir.join("t.tbl");
    std::fs::write(&tbl, "T1 P1 D0.25 Z2 ;\nT7 P3 D0.5 Z-1.5 ;\n").unwrap();
    let rs = Rs274 { tool_table: Some(tbl), ..Rs274::default() };
    let r = rs.run_text("G21\nT7 M6\nG43\nG20\nG43 H1\nM2\n").unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert!(r.error.is_none(), "{:?}", r.error);
    let offsets: Vec<f64> = r
        .calls
        .iter()
        .filter_map(|c| match &c.kind {
            RefKind::ToolLengthOffset { offset, .. } => Some(offset.z),
            _ => None,
        })
        .collect();
    assert_eq!(offsets.len(), 2, "{}", rs274::describe(&r.calls));
    assert!((offsets[0] - -1.5 * 25.4).abs() < 1e-9, "{offsets:?}");
    assert!((offsets[1] - 2.0 * 25.4).abs() < 1e-9, "{offsets:?}");
    let change = r.calls.iter().find_map(|c| match &c.kind {
        RefKind::ChangeTool { index, tool } => Some((*index, *tool)),
        _ => None,
    });
    assert_eq!(change.map(|c| c.1), Some(7));
}

#[test]
fn linuxcncs_samples_run_alike_numbered_or_not_and_their_arcs_close() {
    // The numbered copy is what gives every call its line; LinuxCNC must not notice it. And
    // over these programs, whatever they do between arcs, each normalised arc must start and
    // end on its circle (see `arcs_close`).
    rs274::require();
    let root = Path::new("/usr/share/linuxcnc/ncfiles");
    let mut files = Vec::new();
    collect_ngc(root, &mut files, 0);
    assert!(files.len() > 100, "LinuxCNC's samples are missing from {}", root.display());
    let plain = Rs274 { numbered: false, subroutine_dirs: vec![root.to_path_buf()], ..Rs274::default() };
    let numbered = Rs274 { numbered: true, ..plain.clone() };
    let (mut with_lines, mut arcs) = (0, 0);
    for f in &files {
        let (a, b) = match (plain.run(f), numbered.run(f)) {
            (Ok(a), Ok(b)) => (a, b),
            (a, b) => panic!("{}: {:?} / {:?}", f.display(), a.err(), b.err()),
        };
        let kinds = |r: &RefRun| r.calls.iter().map(|c| (c.seq, c.kind.clone())).collect::<Vec<_>>();
        assert_eq!(kinds(&a), kinds(&b), "{}: numbering changed the calls", f.display());
        assert_eq!(a.error.as_ref().map(|e| &e.text), b.error.as_ref().map(|e| &e.text), "{}", f.display());
        assert!(b.unparsed.is_empty(), "{}: lines not understood: {:?}", f.display(), b.unparsed);
        if b.calls.iter().any(|c| c.line.is_some()) {
            with_lines += 1;
        }
        arcs += arcs_close(f, &b);
    }
    assert!(with_lines > files.len() / 2, "only {with_lines} of {} named their lines", files.len());
    assert!(arcs > 1000, "only {arcs} arcs checked");
}

/// Each arc's centre is as far from the end of the motion before it as from its own end,
/// within LinuxCNC's own arc tolerance (0.002·√2 in, or 0.1 % of the radius) and the
/// printing's. Returns the number of arcs checked.
fn arcs_close(f: &Path, r: &RefRun) -> usize {
    let mut arcs = 0;
    let mut start: Option<DVec3> = None;
    for c in r.motions() {
        if let (RefKind::Arc { end, center, plane, .. }, Some(s)) = (&c.kind, start) {
            let (i, j, _) = plane_axes(*plane);
            let r0 = (s[i] - center[i]).hypot(s[j] - center[j]);
            let r1 = (end.pose.xyz[i] - center[i]).hypot(end.pose.xyz[j] - center[j]);
            let allowed = 2.0 * 0.001 * std::f64::consts::SQRT_2 * 25.4 + 0.001 * r0.max(r1) + 4.0 * end.tol_mm;
            assert!((r0 - r1).abs() <= allowed, "{} call {}: radii {r0} and {r1} mm", f.display(), c.seq);
            arcs += 1;
        }
        // After a probe rs274 backs off, and a NURBS_FEED does not print its end: the arc that
        // may follow them is not checked.
        start = match &c.kind {
            RefKind::Traverse { end } | RefKind::Line { end, .. } | RefKind::Arc { end, .. } => Some(end.pose.xyz),
            _ => None,
        };
    }
    arcs
}

fn collect_ngc(dir: &Path, out: &mut Vec<PathBuf>, depth: u32) {
    if depth > 4 {
        return;
    }
    let Ok(rd) = std::fs::read_dir(dir) else { return };
    let mut entries: Vec<PathBuf> = rd.filter_map(|e| e.ok().map(|e| e.path())).collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            collect_ngc(&p, out, depth + 1);
        } else if p.extension().is_some_and(|e| e == "ngc") {
            out.push(p);
        }
    }
}

#[test]
fn a_subroutine_file_is_found_on_the_search_path_only() {
    rs274::require();
    let found = run_file("sub-call.ngc");
    assert!(found.error.is_none(), "{:?}", found.error);
    // The subroutine's moves carry no main-program line.
    assert!(found.motions().any(|c| c.line.is_none()), "{}", rs274::describe(&found.calls));
    let alone = Rs274::default().run(&data("sub-call.ngc")).unwrap();
    assert!(alone.error.is_some(), "without the search path the call must fail");
}

/// The feature programs of tests/data/ngc: LinuxCNC reads each to its end, except the
/// `*-refused.ngc` ones, which it refuses (they test that we refuse them too).
#[test]
fn linuxcnc_reads_every_feature_program_and_refuses_the_refused_ones() {
    rs274::require();
    let mut files = Vec::new();
    collect_ngc(&data(""), &mut files, 0);
    assert!(files.len() >= 20, "feature programs missing");
    for f in files {
        let name = f.file_name().and_then(|n| n.to_str()).unwrap_or_default().to_owned();
        if rs274::is_subroutine_file(&f) {
            continue; // called by another program
        }
        let r = run_file(&name);
        assert!(r.unparsed.is_empty(), "{name}: {:?}", r.unparsed);
        if name.ends_with("-refused.ngc") {
            assert!(r.error.is_some(), "{name}: LinuxCNC should refuse it");
        } else {
            assert!(r.error.is_none(), "{name}: {:?}", r.error);
            assert!(r.motions().count() > 0, "{name}: no motion");
            assert!(r.calls.iter().any(|c| matches!(c.kind, RefKind::Stop { end: true })), "{name}: no end");
        }
    }
}

#[test]
fn parses_long_line_numbers_subroutine_lines_and_skips_other_calls() {
    // As rs274 prints them: `N` and the line's digits padded to 6 characters, or run into the
    // call's name when longer; `N.....` without a number.
    let out = "    1 N..... USE_LENGTH_UNITS(CANON_UNITS_INCHES)\n    2 N1000000007STRAIGHT_FEED(1.0000, 2.0000, 3.0000, 4.0000, 5.0000, 6.0000)\n    3 N12    STRAIGHT_TRAVERSE(0.5000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)\n    4 N..... COMMENT(\"a (comment), with commas\")\n    5 N1000000009DWELL(1.5000)\n";
    let r = rs274::parse_output(out, "", false, Vec::new());
    assert!(r.unparsed.is_empty(), "{:?}", r.unparsed);
    assert_eq!(r.calls.len(), 4, "{}", rs274::describe(&r.calls));
    assert_eq!(r.calls[1].line, Some(7));
    let line = end_of(&r.calls[1]);
    assert!((line.pose.xyz - DVec3::new(25.4, 50.8, 76.2)).length() < 1e-12, "{line:?}");
    assert_eq!(line.pose.abc, DVec3::new(4.0, 5.0, 6.0), "rotary axes are not scaled by G20");
    assert_eq!(r.calls[2].line, None, "a sub-program's own N12 is not a main-program line");
    assert!((end_of(&r.calls[2]).pose.xyz.x - 12.7).abs() < 1e-12);
    assert_eq!(r.calls[3].kind, RefKind::Dwell { seconds: 1.5 });
    assert_eq!(r.calls[3].line, Some(9));
}

#[test]
fn m61_names_the_tool_by_its_place_in_the_table() {
    // rs274 prints CHANGE_TOOL and CHANGE_TOOL_NUMBER with the tool's place in the table file
    // (1-based), not its number: the parser maps it back through the table.
    let r = run_file("tools-offsets.ngc");
    let set: Vec<(i32, i32)> = r
        .calls
        .iter()
        .filter_map(|c| match &c.kind {
            RefKind::SetToolNumber { index, tool } => Some((*index, *tool)),
            _ => None,
        })
        .collect();
    assert_eq!(set, vec![(3, 5)], "M61 Q5: tool 5 is the third entry of tools.tbl");
}
