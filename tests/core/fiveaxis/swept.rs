//! The swept tool between two blocks: closed forms for pure translation and for rotation
//! about one axis, the sign rule of chord and nonlinear errors, and the paper's Example 1
//! re-computed independently from the joint values.
#![allow(
    clippy::unwrap_used,
    clippy::float_cmp,
    reason = "tests: an error should fail the test; exact float equality is what some assert"
)]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support;

use crate::support::Rng;
use glam::{DMat3, DVec3};
use interpolab::assert_near;
use interpolab::chords::distance_to_segment;
use interpolab::crease::{CreaseCurve, InterpOptions, run_to_end};
use interpolab::fiveaxis::{
    CreasePath, DesignPath, Joints, Machine, MachineKind, ToolAxisRule, block_at, evaluate_nodes, example1,
    segment_report,
};

/// Largest distance of the swept tool tip from the chord of its end tips, by dense sampling
/// of the linearly interpolated joints.
fn tip_deviation(m: &Machine, a: &Joints, b: &Joints, n: usize) -> f64 {
    let ta = m.pose_from_joints(a).tip_in_workpiece;
    let tb = m.pose_from_joints(b).tip_in_workpiece;
    (0..=n)
        .map(|i| distance_to_segment(m.pose_from_joints(&a.lerp(b, i as f64 / n as f64)).tip_in_workpiece, ta, tb))
        .fold(0.0, f64::max)
}

#[test]
fn pure_translation_sweeps_exactly_the_chord() {
    let mut rng = Rng::new(3);
    for kind in MachineKind::ALL {
        let m = Machine {
            kind,
            pivots_mm: [DVec3::new(10.0, -20.0, -60.0), DVec3::new(-5.0, 7.0, 0.0)],
            tool_length_mm: 120.0,
            limits_rad: [None, None],
        };
        for _ in 0..20 {
            let axis = DVec3::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0), rng.range(0.2, 1.0)).normalize();
            let tip_a = DVec3::new(rng.range(-50.0, 50.0), rng.range(-50.0, 50.0), rng.range(0.0, 50.0));
            let tip_b = tip_a + DVec3::new(rng.range(-20.0, 20.0), rng.range(-20.0, 20.0), rng.range(-20.0, 20.0));
            let a = m.joints_from_pose(tip_a, axis, None).unwrap();
            let b = m.joints_from_pose(tip_b, axis, Some(&a)).unwrap();
            assert_eq!(a.rotary_rad, b.rotary_rad, "{}", kind.as_str());
            let dev = tip_deviation(&m, &a, &b, 200);
            assert!(dev < 1e-9, "{}: nonlinear error {dev} of a pure translation", kind.as_str());
        }
    }
}

#[test]
fn turning_c_alone_sweeps_a_circular_arc_with_the_closed_form_sagitta() {
    // Table A/C: the second pose is the first turned by −Δ about the C axis line (in the
    // workpiece, the line through the C pivot along Z). Then X, Y, Z and A are unchanged and
    // only C moves by Δ: the tip, fixed in the machine, sweeps an arc of radius r (its
    // distance from the C axis) in the workpiece. Its chord misses it by r(1 − cos(Δ/2)).
    let pivot_c = DVec3::new(15.0, -8.0, 0.0);
    let m = Machine { pivots_mm: [DVec3::new(0.0, 0.0, -70.0), pivot_c], ..Machine::default() };
    let tip = DVec3::new(60.0, 22.0, 35.0);
    let axis = DVec3::new(0.3, -0.5, 0.8).normalize();
    let r = (tip - pivot_c).truncate().length();
    for delta_deg in [2.0f64, 15.0, 60.0, 120.0] {
        let turn = DMat3::from_rotation_z(-delta_deg.to_radians());
        let tip_b = pivot_c + turn * (tip - pivot_c);
        let a = m.joints_from_pose(tip, axis, None).unwrap();
        let b = m.joints_from_pose(tip_b, turn * axis, Some(&a)).unwrap();
        assert!((a.xyz_mm - b.xyz_mm).length() < 1e-9 && (a.rotary_rad[0] - b.rotary_rad[0]).abs() < 1e-12);
        assert_near!(b.rotary_rad[1] - a.rotary_rad[1], delta_deg.to_radians(), 1e-12);
        let expected = r * (1.0 - (0.5 * delta_deg.to_radians()).cos());
        assert_near!(tip_deviation(&m, &a, &b, 20_000), expected, 1e-7 * r, "Δ = {delta_deg}°");
    }
}

#[test]
fn turning_a_head_b_alone_sweeps_an_arc_of_the_tool_length() {
    // Head B/C with tool length L: with X, Y, Z and C fixed, turning B swings the tip on a
    // circle of radius L about the B axis; the chord misses it by L(1 − cos(Δb/2)).
    let m = Machine {
        kind: MachineKind::HeadBC,
        pivots_mm: [DVec3::new(0.0, 30.0, 0.0), DVec3::ZERO],
        tool_length_mm: 180.0,
        limits_rad: [None, None],
    };
    let a = Joints { xyz_mm: DVec3::new(5.0, 6.0, 200.0), rotary_rad: [(-10f64).to_radians(), 0.7] };
    for delta_deg in [1.0f64, 20.0, 75.0] {
        let b = Joints { rotary_rad: [a.rotary_rad[0] + delta_deg.to_radians(), a.rotary_rad[1]], ..a };
        let expected = 180.0 * (1.0 - (0.5 * delta_deg.to_radians()).cos());
        assert_near!(tip_deviation(&m, &a, &b, 20_000), expected, 1e-6, "Δb = {delta_deg}°");
    }
}

#[test]
fn round_pocket_on_the_c_axis_nonlinear_error_cancels_the_chord_error() {
    // Floor and round wall (radius 50, ball 5): the centre runs on a circle of radius 45
    // about the Z axis, which is the default machine's C axis. With the bisector tool axis,
    // following the crease needs only C, so the swept ball stays on the crease: the total
    // error is zero, while the chord alone leaves stock 45(1 − cos(θ/2)) on the wall.
    let job = support::job(include_str!("../../../examples/floor-round-wall.json"));
    let curve = CreaseCurve::from_rows(&job, &run_to_end(job.clone(), InterpOptions::default()).rows).unwrap();
    let path = CreasePath::new(curve, ToolAxisRule::Bisector);
    let m = Machine::default();
    let a = block_at(&m, &path, 10.0, None).unwrap();
    for len in [0.5, 3.0, 20.0] {
        let b = block_at(&m, &path, 10.0 + len, Some(&a.joints)).unwrap();
        let rep = segment_report(&m, &path, &a, &b, &Default::default()).unwrap();
        let theta = 2.0 * ((b.location.centre - a.location.centre).length() / 90.0).asin();
        let stock = 45.0 * (1.0 - (0.5 * theta).cos());
        assert!(rep.total_mm.abs() < 1e-9, "total {} for a pure C turn", rep.total_mm);
        assert_near!(rep.worst_chord_mm, -stock, 1e-9 + 1e-6 * stock);
        assert!(rep.gouge_mm < 1e-9 && rep.stock_mm < 1e-9);
    }
}

#[test]
fn example1_chord_gouges_a_convex_cylinder_and_the_rotation_gouges_far_more() {
    let ex = example1();
    let (s0, s1) = ex.path.range();
    let nodes = evaluate_nodes(&ex.machine, &ex.path, &[s0, s1], &Default::default()).unwrap();
    let rep = nodes[1].report.unwrap();
    // The centre chord of the convex circle of radius 30 cuts in by 30(1 − cos(θ/2)).
    let [p1, p2] = ex.contacts;
    // P2 lies 1e-4 mm inside the circle (the paper's rounding); the arc ends at its polar angle.
    let theta = p1.y.atan2(p1.x) - p2.y.atan2(p2.x);
    assert_near!(rep.worst_chord_mm, 30.0 * (1.0 - (0.5 * theta).cos()), 1e-9);
    assert!(rep.worst_chord_mm > 0.0, "overcut is positive");
    // Independent re-computation from the joint values: swept ball centre = tip + 5·axis;
    // on the cylinder of radius 25 (tool outside) the error is e = 30 − |(x, y)|.
    let (ja, jb) = (nodes[0].block.joints, nodes[1].block.joints);
    let worst = (0..=20_000)
        .map(|i| {
            let pose = ex.machine.pose_from_joints(&ja.lerp(&jb, f64::from(i) / 20_000.0));
            30.0 - (pose.tip_in_workpiece + 5.0 * pose.axis_in_workpiece).truncate().length()
        })
        .fold(f64::NEG_INFINITY, f64::max);
    assert_near!(rep.total_mm, worst, 1e-7);
    assert!(rep.total_mm > 1.0, "the paper's 'huge deviation': {} mm", rep.total_mm);
    assert_near!(rep.chord_mm + rep.nonlinear_mm, rep.total_mm, 1e-12);
    // The machine's joints at the two blocks: A at 90°, C turned by about 94°.
    assert_near!(ja.rotary_rad[0].to_degrees(), 90.0, 1e-9);
    assert_near!((jb.rotary_rad[1] - ja.rotary_rad[1]).to_degrees(), 94.016, 1e-3);
}
