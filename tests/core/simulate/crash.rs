//! The whole tool against the stock (`simulate::crash`): crashes of the holder, the shank, a
//! rapid and a plunge found at their lines with the depths their closed forms give, a tilted
//! holder on a 5-axis pose, no false alarm on a clean program, and a relief cut deeper than
//! the default flutes machined to an independent Z-map once its real flute length is given.
#![allow(
    clippy::unwrap_used,
    clippy::float_cmp,
    reason = "tests: an error should fail the test; exact float equality is what some assert"
)]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::DVec3;
use interpolab::fiveaxis::Joints;
use interpolab::gcode::interp::tools::{ToolTable, parse_tool_spec};
use interpolab::gcode::interp::{Interpreter, Options};
use interpolab::geom::{BodySpec, Cutter};
use interpolab::simulate::canon::{CanonBuilder, CanonOptions, CanonProgram, KinematicsChoice, MachineSetup};
use interpolab::simulate::{CrashKind, DexelStock, HeightMap, MoveKind, Program, SimMove, Simulation};

/// Reads a program through the interpreter with one cutter for every tool.
fn read(text: &str, cutter: Cutter) -> CanonProgram {
    let mut it = Interpreter::from_text(text, Options::default());
    let mut b = CanonBuilder::new(CanonOptions {
        machine: None,
        kinematics: KinematicsChoice::Auto,
        chord_tol_mm: 0.01,
        tools: ToolTable::new(),
        default_cutter: Some(cutter),
    });
    assert!(b.read(&mut it, |_| true).unwrap());
    b.finish()
}

/// Simulates a program on a block and returns the simulation.
fn simulate(text: &str, cutter: Cutter, lo: [f64; 3], hi: [f64; 3], pitch: f64) -> Simulation {
    let mut p = read(text, cutter);
    let mut sim = Simulation::new(DexelStock::block(lo, hi, pitch).unwrap(), &cutter);
    assert!(p.run(&mut sim, |_| true).unwrap());
    sim
}

fn tool(spec: &str) -> Cutter {
    match spec.split_once(':').unwrap() {
        ("flat", r) => Cutter::flat(r.parse().unwrap()).unwrap(),
        ("ball", r) => Cutter::ball(r.parse().unwrap()).unwrap(),
        _ => unreachable!(),
    }
}

fn body(words: &str) -> BodySpec {
    let mut b = BodySpec::default();
    for w in words.split(',') {
        assert!(b.word(w, 1.0).unwrap(), "{w}");
    }
    b
}

#[test]
fn a_holder_entering_a_hole_crashes_at_its_line_by_the_depth_it_enters() {
    // Flat R 3, flutes 25, shank R 3 × 5 (gauge 30), holder R 10 × 40. Plunged to z = −30
    // the holder's face sits on the stock's top (a touch); to −33 it enters 3 mm, around the
    // hole the flutes cut: one holder crash, on line 5, 3 mm deep, the ray's top at z = 0.
    let c = tool("flat:3").with_body(&body("flute=25,shank=3:5,holder=10:40")).unwrap();
    assert_eq!(c.gauge_length_mm, 30.0);
    let prog = "G21 G90\nG0 Z5\nG0 X30 Y30\nG1 Z-30 F100\nG1 Z-33\nG0 Z50\nM2\n";
    let sim = simulate(prog, c, [0.0, 0.0, -40.0], [60.0, 60.0, 0.0], 0.2);
    let log = sim.crashes();
    let holder: Vec<_> = log.list().iter().filter(|c| c.kind == CrashKind::Holder).collect();
    assert_eq!(holder.len(), 2, "{:?}", log.list());
    assert_eq!(holder[0].line, 5);
    assert!((holder[0].depth_mm - 3.0).abs() < 1e-9, "{}", holder[0].depth_mm);
    assert!(holder[0].at_mm.z.abs() < 1e-9);
    let rho = (holder[0].at_mm - DVec3::new(30.0, 30.0, 0.0)).truncate().length();
    assert!(rho > 3.0 - 0.2 && rho < 10.0 + 1e-9, "the holder met stock outside the hole: ρ {rho}");
    // The rapid retract drags the holder out through the same stock (line 6): a holder crash
    // and, any part of the tool entering stock in a G0, a rapid one; nothing else.
    assert_eq!(holder[1].line, 6);
    assert_eq!(log.count(CrashKind::Shank), 0);
    let rapid: Vec<_> = log.list().iter().filter(|c| c.kind == CrashKind::Rapid).collect();
    assert_eq!(rapid.len(), 1, "{:?}", log.list());
    assert_eq!((rapid[0].line, rapid[0].depth_mm), (6, holder[1].depth_mm));
    assert_eq!(log.total(), 3);
}

#[test]
fn a_shank_wider_than_the_flutes_rubs_the_wall_of_its_slot() {
    // Flat R 2 with flutes 5 and a shank R 3: a slot at z = −4 leaves the shank above the
    // stock; the second pass at −8 puts the shank's bottom at −3, between walls only 2 mm
    // from the axis: 3 mm of wall inside it on line 5, none on line 4.
    let c = tool("flat:2").with_body(&body("flute=5,shank=3:20,holder=8:30")).unwrap();
    let prog = "G21 G90\nG0 X-5 Y20 Z2\nG1 Z-4 F300\nG1 X45\nG1 Z-8\nG1 X-5\nG0 Z30\nM2\n";
    let sim = simulate(prog, c, [0.0, 0.0, -20.0], [40.0, 40.0, 0.0], 0.1);
    let log = sim.crashes();
    let shank: Vec<_> = log.list().iter().filter(|c| c.kind == CrashKind::Shank).collect();
    assert!(!shank.is_empty(), "{:?}", log.list());
    assert!(shank.iter().all(|c| c.line >= 6), "line 4 stays clear: {shank:?}");
    assert_eq!(shank[0].line, 6);
    assert!((shank[0].depth_mm - 3.0).abs() < 1e-9, "{}", shank[0].depth_mm);
    let d = (shank[0].at_mm.y - 20.0).abs();
    assert!((2.0 - 1e-9..=3.0).contains(&d), "on the wall between the flutes' and the shank's radius: {d}");
    assert_eq!(log.count(CrashKind::Holder), 0);
}

#[test]
fn a_rapid_into_the_stock_is_a_crash_as_deep_as_it_goes_and_a_touch_is_not() {
    // G0 down to the top (a touch), then 2 mm into the block; a feed move after is no crash.
    let c = tool("ball:2").with_body(&body("flute=20")).unwrap();
    let prog = "G21 G90\nG0 X10 Y10 Z5\nG0 Z0\nG0 Z-2\nG1 X20 F500\nG0 Z10\nM2\n";
    let sim = simulate(prog, c, [0.0, 0.0, -10.0], [30.0, 20.0, 0.0], 0.1);
    let log = sim.crashes();
    assert_eq!(log.total(), 1, "{:?}", log.list());
    let r = log.list()[0];
    assert_eq!((r.kind, r.line), (CrashKind::Rapid, 4));
    // The deepest ray is the one under the ball's bottom: 2 mm to within its sag at a
    // ray's distance (≤ √2·p/2 from the axis: ≤ 0.0025 mm for R 2, p 0.1).
    assert!(r.depth_mm <= 2.0 + 1e-9 && r.depth_mm > 2.0 - 0.003, "{}", r.depth_mm);
    assert_eq!(sim.counters().rapid_cuts, 1);
}

#[test]
fn a_pocket_within_the_flutes_with_touching_rapids_has_no_crash() {
    // A pocket 6 mm deep in three steps with a flute length of exactly 6 (the shank's face
    // reaches the top: a touch), rapids to the top and over it, a helix-free ramp in.
    let c = tool("flat:3").with_body(&body("flute=6,shank=3:10,holder=12:40")).unwrap();
    let mut prog = String::from("G21 G90\nG0 Z5\nG0 X10 Y10\nG0 Z0\n");
    for depth in [2.0, 4.0, 6.0] {
        prog.push_str(&format!("G1 X14 Y10 Z-{depth} F300\nG1 X30\nG1 Y14\nG1 X10\nG1 Y10\n"));
    }
    prog.push_str("G0 Z5\nG0 X40 Y40\nM2\n");
    let sim = simulate(&prog, c, [0.0, 0.0, -20.0], [45.0, 45.0, 0.0], 0.1);
    assert_eq!(sim.crashes().total(), 0, "{:?}", sim.crashes().list());
    assert!(sim.counters().removed_mm3 > 20.0 * 4.0 * 6.0);
    // The same program with the default body (flutes 3·R = 9 mm) is clean too; with flutes
    // of 1.5 mm each 2 mm step buries the shank 0.5 mm more, under the 0.5 mm the shank did
    // not cut on each step before (it never cuts): 1.5 mm at the third.
    let default = tool("flat:3");
    assert_eq!(simulate(&prog, default, [0.0, 0.0, -20.0], [45.0, 45.0, 0.0], 0.1).crashes().total(), 0);
    let short = tool("flat:3").with_body(&body("flute=1.5,shank=3:10,holder=12:40")).unwrap();
    let sim = simulate(&prog, short, [0.0, 0.0, -20.0], [45.0, 45.0, 0.0], 0.1);
    let deepest = sim.crashes().list().iter().map(|c| c.depth_mm).fold(0.0, f64::max);
    assert!(sim.crashes().count(CrashKind::Shank) >= 15, "{:?}", sim.crashes().summary());
    assert!((deepest - 1.5).abs() < 1e-9, "{deepest} {:?}", sim.crashes().list());
    let first_step = sim.crashes().list().iter().filter(|c| c.tip_mm.z == -2.0).map(|c| c.depth_mm);
    assert!(first_step.clone().count() >= 4 && first_step.fold(0.0, f64::max) == 0.5);
}

#[test]
fn a_tool_that_does_not_cut_at_its_centre_may_ramp_but_not_plunge() {
    let c = tool("flat:3").with_body(&body("flute=15,nocentre")).unwrap();
    assert!(!c.centre_cutting);
    // Line 3 plunges 3 mm into the top; line 5 ramps 1 mm down over 19 mm (3°).
    let prog = "G21 G90\nG0 X10 Y10 Z2\nG1 Z-3 F100\nG0 Z2\nG0 X10 Y30\nG1 Z0\nG1 X29 Z-1\nG0 Z20\nM2\n";
    let sim = simulate(prog, c, [0.0, 0.0, -10.0], [40.0, 40.0, 0.0], 0.1);
    let log = sim.crashes();
    assert_eq!(log.total(), 1, "{:?}", log.list());
    let p = log.list()[0];
    assert_eq!((p.kind, p.line), (CrashKind::Plunge, 3));
    assert!((p.depth_mm - 3.0).abs() < 1e-9, "{}", p.depth_mm);
    // A centre-cutting tool does the same without a crash.
    let c = tool("flat:3").with_body(&body("flute=15")).unwrap();
    assert_eq!(simulate(prog, c, [0.0, 0.0, -10.0], [40.0, 40.0, 0.0], 0.1).crashes().total(), 0);
}

#[test]
fn a_tilted_holder_dips_below_the_top_by_its_lowest_rim() {
    // A head tilted 60°: the tip 3 mm above the block, the flutes and shank clear
    // of it, the holder (R 14 from 15 mm up the axis) reaching below z = 0 by
    // −(c.z − R_h·sin θ), c its bottom centre: that is the deepest stock on one vertical
    // ray inside it (no ray enters it lower), to within the grid's reach of the lowest rim.
    let c = tool("flat:3").with_body(&body("flute=10,shank=3:5,holder=14:40")).unwrap();
    // A head machine with no length from the pivot to the tip: X Y Z are the tip.
    let setup = MachineSetup::from_name("head-bc", 0.0).unwrap();
    let m = setup.machine;
    let joints = |x: f64| Joints { xyz_mm: DVec3::new(x, 0.0, 3.0), rotary_rad: [60f64.to_radians(), 0.0] };
    let (from, to) = (joints(0.0), joints(1.0));
    let pose = m.pose_from_joints(&from);
    let (tip, axis) = (pose.tip_in_workpiece, pose.axis_in_workpiece.normalize());
    let sin = (1.0 - axis.z * axis.z).sqrt();
    assert!((sin - 60f64.to_radians().sin()).abs() < 1e-9);
    let centre = tip + 15.0 * axis;
    let want = -(centre.z - 14.0 * sin);
    assert!(want > 1.0, "the holder must reach the stock: {want}");
    assert!(tip.z - 3.0 * sin > 0.0 && tip.z + 10.0 * axis.z - 3.0 * sin > 0.0, "flutes and shank clear");
    let lowest_xy = (centre - 14.0 * DVec3::new(axis.x, axis.y, 0.0).normalize() * axis.z).truncate();
    let lo = [lowest_xy.x - 30.0, lowest_xy.y - 20.0, -10.0];
    let hi = [lowest_xy.x + 30.0, lowest_xy.y + 20.0, 0.0];
    let pitch = 0.05;
    let mut sim = Simulation::new(DexelStock::block(lo, hi, pitch).unwrap(), &c);
    sim.apply(&SimMove { kind: MoveKind::Joints { machine: m, from, to }, line: 7, rapid: false });
    let log = sim.crashes();
    assert_eq!(log.total(), 1, "{:?}", log.list());
    let h = log.list()[0];
    assert_eq!((h.kind, h.line), (CrashKind::Holder, 7));
    // A ray within p/√2 of the lowest rim point enters at most p/√2·(tan θ + 1) higher.
    let slack = pitch / 2f64.sqrt() * (60f64.to_radians().tan() + 1.0);
    assert!(h.depth_mm <= want + 1e-6 && h.depth_mm > want - slack, "{} vs {want}", h.depth_mm);
    assert_eq!(sim.counters().removed_mm3, 0.0, "the flutes stay above the block");
}

#[test]
fn crashes_are_reported_once_per_block_and_the_lines_of_a_program_in_memory_are_its_moves() {
    // Two moves of line 9 (an arc's chords) bury the shank 1 and 2 mm: one report, the
    // deepest; line 10 buries it 2 mm more.
    let c = tool("flat:2").with_body(&body("flute=3,shank=2:10,holder=6:20")).unwrap();
    let m = |from: [f64; 3], to: [f64; 3], line| SimMove {
        kind: MoveKind::Line { from: DVec3::from(from), to: DVec3::from(to) },
        line,
        rapid: false,
    };
    let moves = [
        m([-5.0, 5.0, -4.0], [5.0, 5.0, -4.0], 9),
        m([5.0, 5.0, -5.0], [15.0, 5.0, -5.0], 9),
        m([15.0, 5.0, -5.0], [15.0, 9.0, -5.0], 10),
    ];
    let mut sim = Simulation::new(DexelStock::block([0.0, 0.0, -10.0], [20.0, 10.0, 0.0], 0.1).unwrap(), &c);
    sim.run(&Program { moves: moves.to_vec(), chord_error_mm: 0.0 }).unwrap();
    let log = sim.crashes();
    let lines: Vec<_> = log.list().iter().map(|c| (c.line, c.kind)).collect();
    assert_eq!(lines, vec![(9, CrashKind::Shank), (10, CrashKind::Shank)], "{:?}", log.list());
    // The deeper of line 9's moves: the shank's face at −5 + 3 = −2 under a 0 top.
    assert!((log.list()[0].depth_mm - 2.0).abs() < 1e-9, "{}", log.list()[0].depth_mm);
    assert_eq!(log.list()[0].move_index, 0, "the block's first move");
    assert_eq!(log.counts(), [2, 0, 0, 0]);
    let csv = log.csv(|_| Some(4));
    let rows: Vec<&str> = csv.lines().collect();
    assert_eq!(rows.len(), 3);
    assert!(rows[1].starts_with("9,shank,\"the shank\",4,2,"), "{}", rows[1]);
    assert!(log.summary().unwrap().starts_with("2 crash(es) (2 shank); the first at line 9"));
}

#[test]
fn tool_specs_and_table_remarks_carry_the_body() {
    let t = parse_tool_spec("1:ball:6,flute=20,shank=2.5:30,holder=10:40,nocentre").unwrap();
    let c = t.cutter().unwrap().unwrap();
    assert_eq!((c.flute_length_mm, c.shank_radius_mm, c.gauge_length_mm), (20.0, 2.5, 50.0));
    assert_eq!((c.holder_radius_mm, c.holder_length_mm), (10.0, 40.0));
    assert!(!c.centre_cutting && c.body_given);
    assert_eq!(parse_tool_spec(&t.spec().unwrap()).unwrap().body, t.body, "the spec reads back");
    assert!(parse_tool_spec("1:ball:6,flute=-2").is_err());
    assert!(parse_tool_spec("1:ball:6,shank=3").unwrap_err().to_string().contains("radius:length"));
    assert!(parse_tool_spec("1:ball:6,lenght=3").unwrap_err().to_string().contains("not a body word"));
    // A flute length alone: the shank R × 3·R above it; nothing: the defaults, said so.
    let c = parse_tool_spec("2:flat:4,flute=12").unwrap().cutter().unwrap().unwrap();
    assert_eq!((c.gauge_length_mm, c.shank_radius_mm), (18.0, 2.0));
    let d = parse_tool_spec("3:flat:4").unwrap().cutter().unwrap().unwrap();
    assert!(!d.body_given && d.describe_body().contains("assumed"));
    assert_eq!((d.flute_length_mm, d.gauge_length_mm, d.holder_radius_mm), (6.0, 12.0, 5.0));
    // A LinuxCNC table in inches: the remark's words in the table's units.
    let table = ToolTable::from_linuxcnc(
        "T1 P1 D0.25 Z2 ;ball flute=1 shank=0.1:1 holder=0.5:2\n",
        interpolab::gcode::interp::tools::TableUnits::Inch,
    )
    .unwrap();
    let b = table.get(1).unwrap().body;
    assert_eq!(b.flute_mm, Some(25.4));
    assert!((b.shank_mm.unwrap().0 - 2.54).abs() < 1e-12 && (b.holder_mm.unwrap().1 - 50.8).abs() < 1e-12);
    assert!(
        ToolTable::from_linuxcnc("T1 D6 ;flat flute=x\n", interpolab::gcode::interp::tools::TableUnits::Mm).is_err()
    );
}

/// The tip height of the relief: a bowl 17.4 mm deep at (10, 10), 0 at 10 mm from it.
fn bowl(x: f64, y: f64) -> f64 {
    let r2 = (x - 10.0).powi(2) + (y - 10.0).powi(2);
    (-17.4 * (1.0 - r2 / 100.0)).min(0.0)
}

/// The lowest point of a ball of radius `r` whose tip runs straight from `a` to `b`, on the
/// vertical ray at (x, y) — written here apart from the product's sweep: the tip height
/// plus the ball's bottom at the ray's distance, minimised over the move by golden sections
/// (the sum is convex along the move).
fn ball_low(r: f64, a: DVec3, b: DVec3, x: f64, y: f64) -> Option<f64> {
    let f = |t: f64| {
        let p = a + t * (b - a);
        let rho2 = (x - p.x).powi(2) + (y - p.y).powi(2);
        if rho2 > r * r { f64::INFINITY } else { p.z + r - (r * r - rho2).sqrt() }
    };
    let (mut lo, mut hi) = (0.0f64, 1.0f64);
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..80 {
        let (c, d) = (hi - g * (hi - lo), lo + g * (hi - lo));
        // Outside the ball the function is +∞: keep the side that is finite.
        if f(c) <= f(d) { hi = d } else { lo = c }
    }
    let best = f(0.5 * (lo + hi)).min(f(0.0)).min(f(1.0));
    best.is_finite().then_some(best)
}

#[test]
fn a_relief_deeper_than_the_default_flutes_is_cut_whole_with_its_real_flute_length() {
    // A 1/8" ball (R 1.5875) finishing a bowl 17.4 mm deep in one raster: with its default
    // flutes (4.76 mm) the shank crashes and the stock above the flutes stays (a slab);
    // with flute=25 every ray is cut to the independent Z-map and nothing crashes.
    let r = 1.5875;
    let mut prog = String::from("G21 G90\nG0 Z5\n");
    let mut segs: Vec<(DVec3, DVec3)> = Vec::new();
    let mut y = 0.0;
    while y <= 20.0 + 1e-9 {
        prog.push_str(&format!("G0 X0 Y{y:.4} Z5\nG1 Z{:.6} F1000\n", bowl(0.0, y)));
        segs.push((DVec3::new(0.0, y, 5.0), DVec3::new(0.0, y, bowl(0.0, y))));
        let mut x = 0.0;
        while x < 20.0 - 1e-9 {
            let nx = x + 0.25;
            prog.push_str(&format!("G1 X{nx:.4} Z{:.6}\n", bowl(nx, y)));
            segs.push((DVec3::new(x, y, bowl(x, y)), DVec3::new(nx, y, bowl(nx, y))));
            x = nx;
        }
        prog.push_str("G1 Z5\n");
        segs.push((DVec3::new(20.0, y, bowl(20.0, y)), DVec3::new(20.0, y, 5.0)));
        y += 0.5;
    }
    prog.push_str("M2\n");
    let (lo, hi) = ([2.0, 2.0, -20.0], [18.0, 18.0, 0.0]);
    let short = tool(&format!("ball:{r}"));
    let sim = simulate(&prog, short, lo, hi, 0.1);
    assert!(sim.crashes().count(CrashKind::Shank) > 10, "{:?}", sim.crashes().summary());
    let slab = HeightMap::of(sim.stock());
    let long = tool(&format!("ball:{r}")).with_body(&body("flute=25,shank=1.5875:20,holder=10:40")).unwrap();
    let sim = simulate(&prog, long, lo, hi, 0.1);
    assert_eq!(sim.crashes().total(), 0, "{:?}", sim.crashes().summary());
    let map = HeightMap::of(sim.stock());
    let g = map.grid;
    let mut worst: f64 = 0.0;
    let mut slab_rays = 0;
    for k in (0..g.len()).step_by(11) {
        let (x, y) = (g.x_mm(k % g.nx), g.y_mm(k / g.nx));
        let want = segs
            .iter()
            .filter(|(a, b)| (a.y - y).abs() <= r && a.x.min(b.x) - r <= x && x <= a.x.max(b.x) + r)
            .filter_map(|(a, b)| ball_low(r, *a, *b, x, y))
            .fold(0.0_f64, f64::min);
        worst = worst.max((map.top_mm[k] - want).abs());
        if slab.top_mm[k] > want + 1.0 {
            slab_rays += 1;
        }
    }
    assert!(worst < 1e-6, "the deep relief against the independent Z-map: {worst} mm");
    assert!(slab_rays > 100, "the short flutes left a slab above them: {slab_rays} rays");
}
