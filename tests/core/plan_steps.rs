//! `plan::steps`: seed 002's step plans timed through their machine's joints. Every bound
//! here is computed in this file from the blocks and the preset's printed numbers, and the
//! canonical motions the time is compared with are written here too, not taken from the code
//! under test.

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use glam::{DVec2, DVec3};
use interpolab::fiveaxis::{
    Block, CutterLocation, DesignPath, Joints, MachineKind, StepOptions, evaluate_nodes, example1, plan_steps,
};
use interpolab::gcode::interp::{Canon, Feed, FeedMode, Loc, Origin, Pose};
use interpolab::plan::steps::{DEFAULT_FEED_MM_PER_MIN, dynamics_of};
use interpolab::plan::{Dynamics, StepsFeed, StepsTimeError, time_program, time_steps};

/// Example 1's blocks before (P1 → P2) and after the steps (E = 0.01 mm).
fn example1_blocks() -> (Vec<Block>, Vec<Block>) {
    let ex = example1();
    let (a, b) = ex.path.range();
    let before = evaluate_nodes(&ex.machine, &ex.path, &[a, b], &Default::default()).expect("before");
    let after = plan_steps(&ex.machine, &ex.path, &StepOptions::new(ex.tol_mm)).expect("after");
    (before.iter().map(|n| n.block).collect(), after.nodes.iter().map(|n| n.block).collect())
}

/// The rotary table's printed limits (`Dynamics::preset` docs): 7200 deg/min, 900 deg/s²,
/// 9000 deg/s³.
const TABLE_V_DEG_S: f64 = 7200.0 / 60.0;
const TABLE_A_DEG_S2: f64 = 900.0;
const TABLE_J_DEG_S3: f64 = 9000.0;

/// Shortest rest-to-rest time of a move of `d` within speed v and acceleration a.
fn trapezoid(d: f64, v: f64, a: f64) -> f64 {
    if d >= v * v / a { d / v + v / a } else { 2.0 * (d / a).sqrt() }
}

/// The tip chords' length (mm).
fn tip_path(blocks: &[Block]) -> f64 {
    blocks.windows(2).map(|w| w[0].location.tip.distance(w[1].location.tip)).sum()
}

/// The canonical motions of a table-ac plan written out by hand: G0 to the first block, then
/// G93 lines taking tip chord / F each.
fn canon_by_hand(blocks: &[Block], feed: f64) -> Vec<Canon> {
    let pose = |j: &Joints| Pose {
        xyz: j.xyz_mm,
        abc: DVec3::new(j.rotary_rad[0].to_degrees(), 0.0, j.rotary_rad[1].to_degrees()),
    };
    let mut out = vec![Canon::Traverse { loc: Loc::main(1), end: pose(&blocks[0].joints), origin: Origin::Programmed }];
    for (i, w) in blocks.windows(2).enumerate() {
        let minutes = w[0].location.tip.distance(w[1].location.tip) / feed;
        out.push(Canon::Line {
            loc: Loc::main(i as u32 + 2),
            end: pose(&w[1].joints),
            feed: Feed { mode: FeedMode::InverseTime, rate: 1.0 / minutes, spindle_rpm: 0.0 },
            origin: Origin::Programmed,
        });
    }
    out
}

#[test]
fn example1_before_and_after_take_at_least_what_the_feed_and_the_c_table_allow() {
    let (before, after) = example1_blocks();
    assert_eq!((before.len(), after.len()), (2, 32));
    let machine = dynamics_of(MachineKind::TableAC);
    let f = DEFAULT_FEED_MM_PER_MIN;
    for (name, blocks) in [("before", &before), ("after", &after)] {
        let t = time_steps(MachineKind::TableAC, blocks, f, StepsFeed::Tip, &machine).expect("timed");
        assert!(t.cycle_s.is_finite() && t.segment_s.iter().all(|s| s.is_finite() && *s >= 0.0), "{name}: {t:?}");
        assert_eq!(t.segment_s.len(), blocks.len() - 1);
        let sum: f64 = t.segment_s.iter().sum();
        assert!((sum - t.cycle_s).abs() <= 1e-9 * t.cycle_s, "{name}: segments {sum} vs {}", t.cycle_s);
        // The feed: the tip moves its chords at F at most.
        let by_feed = tip_path(blocks) / (f / 60.0);
        assert!(t.cycle_s >= by_feed, "{name}: {} s < {by_feed} s by the feed", t.cycle_s);
        // The C table: from rest to rest over its whole turn (A stays at 90°).
        let dc = (blocks[blocks.len() - 1].joints.rotary_rad[1] - blocks[0].joints.rotary_rad[1]).abs().to_degrees();
        assert!((dc - 94.016).abs() < 1e-3, "{name}: C turns {dc}°");
        let by_c = trapezoid(dc, TABLE_V_DEG_S, TABLE_A_DEG_S2);
        assert!(t.cycle_s >= by_c, "{name}: {} s < {by_c} s of the C table", t.cycle_s);
        // Rotary-limited: the feed alone would take a fraction of it.
        assert!(by_c > 2.0 * by_feed, "{name}: {by_c} vs {by_feed}");
        // The same motions written here, planned by time_program: the same time.
        let by_hand = time_program(canon_by_hand(blocks, f), &machine).expect("plans");
        assert_eq!(t.cycle_s, by_hand.feed_rapid_s().0, "{name}");
        eprintln!("example 1 {name}: {:.4} s (feed {by_feed:.4} s, C {by_c:.4} s)", t.cycle_s);
    }
}

#[test]
fn the_after_plan_is_never_faster_than_the_bound_of_its_joints() {
    // The bound computed here: every joint's shortest rest-to-rest move from first to last
    // value, and the feed over the tip chords.
    let (_, after) = example1_blocks();
    for (machine, limits_deg) in [
        (dynamics_of(MachineKind::TableAC), (TABLE_V_DEG_S, TABLE_A_DEG_S2)),
        (dynamics_of(MachineKind::TableAC).without_jerk(), (TABLE_V_DEG_S, TABLE_A_DEG_S2)),
    ] {
        for f in [100.0, 1000.0, 20_000.0] {
            let t = time_steps(MachineKind::TableAC, &after, f, StepsFeed::Tip, &machine).expect("timed");
            let first = &after[0].joints;
            let last = &after[after.len() - 1].joints;
            let mut bound = tip_path(&after) / (f / 60.0);
            for k in 0..2 {
                let d = (last.rotary_rad[k] - first.rotary_rad[k]).abs().to_degrees();
                bound = bound.max(trapezoid(d, limits_deg.0, limits_deg.1));
            }
            for i in 0..3 {
                let d = (last.xyz_mm[i] - first.xyz_mm[i]).abs();
                bound = bound.max(trapezoid(d, 30_000.0 / 60.0, 3000.0));
            }
            assert!(t.cycle_s >= bound, "F {f}: {} s < bound {bound} s", t.cycle_s);
            assert!(t.rotary_bound_s <= t.cycle_s && t.feed_s <= t.cycle_s, "{t:?}");
        }
    }
}

/// A block whose tip is at `tip` with joints X Y Z = `xyz` and rotary joints `rot_deg`.
fn block(tip: DVec3, xyz: DVec3, rot_deg: [f64; 2]) -> Block {
    Block {
        location: CutterLocation {
            s: 0.0,
            centre: tip + DVec3::Z,
            axis: DVec3::Z,
            tip,
            normals: [DVec3::Z; 2],
            travel: DVec3::X,
            hints: [DVec2::ZERO; 2],
        },
        joints: Joints { xyz_mm: xyz, rotary_rad: rot_deg.map(f64::to_radians) },
    }
}

#[test]
fn a_pure_rotation_takes_the_c_tables_closed_form_time() {
    // C turns 90° with the tip (on the C axis) standing still: programmed in deg/min.
    let p = DVec3::new(0.0, 0.0, 10.0);
    let blocks = [block(p, p, [0.0, 0.0]), block(p, p, [0.0, 90.0])];
    let machine = dynamics_of(MachineKind::TableAC);
    // Fast feed: the table's limits set the time. Jerk-limited rest to rest over 90° with v
    // 120°/s, a 900°/s², j 9000°/s³ (both v and a are reached): D/v + v/a + a/j.
    let t = time_steps(MachineKind::TableAC, &blocks, 1e6, StepsFeed::Tip, &machine).expect("timed");
    let (v, a, j) = (TABLE_V_DEG_S, TABLE_A_DEG_S2, TABLE_J_DEG_S3);
    assert!(v >= a * a / j && 90.0 >= v * (v / a + a / j));
    let closed = 90.0 / v + v / a + a / j;
    assert!(t.cycle_s >= closed - 1e-9, "{} s < {closed} s", t.cycle_s);
    assert!(t.cycle_s <= 1.02 * closed, "{} s, closed form {closed} s", t.cycle_s);
    assert!(t.cycle_s >= trapezoid(90.0, v, a) && t.rotary_bound_s == trapezoid(90.0, v, a), "{t:?}");
    // Without jerk limits: the trapezoid exactly.
    let t =
        time_steps(MachineKind::TableAC, &blocks, 1e6, StepsFeed::Tip, &machine.clone().without_jerk()).expect("timed");
    assert!((t.cycle_s - trapezoid(90.0, v, a)).abs() <= 1e-6, "{} s", t.cycle_s);
    // A slow feed, 600 deg/min, 10°/s: the feed sets it.
    let t = time_steps(MachineKind::TableAC, &blocks, 600.0, StepsFeed::Tip, &machine).expect("timed");
    assert!(t.cycle_s >= 9.0 && t.cycle_s <= 9.2, "{} s", t.cycle_s);
    assert_eq!(t.tip_path_mm, 0.0);
}

#[test]
fn along_the_joints_the_feed_is_read_on_the_xyz_path() {
    // A straight X move of 50 mm at 600 mm/min: at least 5 s, and the tip chord is not read.
    let blocks = [
        block(DVec3::ZERO, DVec3::new(10.0, 0.0, 0.0), [0.0, 0.0]),
        block(DVec3::new(1.0, 0.0, 0.0), DVec3::new(60.0, 0.0, 0.0), [0.0, 0.0]),
    ];
    let machine = Dynamics::preset("table-bc").expect("preset");
    let t = time_steps(MachineKind::TableBC, &blocks, 600.0, StepsFeed::Joints, &machine).expect("timed");
    assert!(t.cycle_s >= 5.0 && t.cycle_s < 5.1, "{t:?}");
    assert_eq!((t.joint_path_mm, t.tip_path_mm), (50.0, 1.0));
    let tip = time_steps(MachineKind::TableBC, &blocks, 600.0, StepsFeed::Tip, &machine).expect("timed");
    assert!(tip.cycle_s < 0.5 && tip.cycle_s >= 0.1, "{tip:?}");
}

#[test]
fn bad_feeds_and_plans_are_refused_with_a_message() {
    let (before, _) = example1_blocks();
    let m = dynamics_of(MachineKind::TableAC);
    for f in [0.0, -1.0, f64::NAN, f64::INFINITY, 2e6] {
        let e = time_steps(MachineKind::TableAC, &before, f, StepsFeed::Tip, &m).expect_err("refused");
        assert!(matches!(e, StepsTimeError::BadFeed { .. }), "{e:?}");
        assert!(e.to_string().contains("give e.g. 1000"), "{e}");
    }
    let e = time_steps(MachineKind::TableAC, &before[..1], 1000.0, StepsFeed::Tip, &m).expect_err("one block");
    assert!(e.to_string().contains("at least two blocks"), "{e}");
    let mut nan = before.clone();
    nan[1].joints.rotary_rad[1] = f64::NAN;
    let e = time_steps(MachineKind::TableAC, &nan, 1000.0, StepsFeed::Tip, &m).expect_err("NaN");
    assert_eq!(e, StepsTimeError::NotFinite { block: 1 });
    let mut bad = m.clone();
    bad.axes[5].velocity = 0.0;
    let e = time_steps(MachineKind::TableAC, &before, 1000.0, StepsFeed::Tip, &bad).expect_err("bad machine");
    assert!(e.to_string().contains("axes.c.velocity"), "{e}");
}
