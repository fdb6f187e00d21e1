//! Forward and inverse kinematics of the four machine structures: identities at random
//! poses, the documented rotation senses, branch choice, travel limits and bad input.
#![allow(
    clippy::unwrap_used,
    clippy::float_cmp,
    reason = "tests: an error should fail the test; exact float equality is what some assert"
)]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support::Rng;
use glam::DVec3;
use interpolab::assert_near;
use interpolab::fiveaxis::{Joints, KinematicsError, Machine, MachineKind};

fn deg(x: f64) -> f64 {
    x.to_radians()
}

/// A machine of this kind with random pivots and tool length, A/B within ±110°, C within
/// ±400° (so whole turns matter).
fn random_machine(kind: MachineKind, rng: &mut Rng) -> Machine {
    let mut v = || DVec3::new(rng.range(-80.0, 80.0), rng.range(-80.0, 80.0), rng.range(-120.0, 40.0));
    let pivots_mm = [v(), v()];
    Machine {
        kind,
        pivots_mm,
        tool_length_mm: 150.0,
        limits_rad: [Some([deg(-110.0), deg(110.0)]), Some([deg(-400.0), deg(400.0)])],
    }
}

fn assert_vec_near(a: DVec3, b: DVec3, tol: f64, what: &str) {
    assert!((a - b).length() <= tol, "{what}: {a:?} vs {b:?} (|diff| = {:e})", (a - b).length());
}

#[test]
fn inverse_of_forward_is_the_identity_for_every_machine() {
    let mut rng = Rng::new(7);
    for kind in MachineKind::ALL {
        for _ in 0..200 {
            let m = random_machine(kind, &mut rng);
            let j = Joints {
                xyz_mm: DVec3::new(rng.range(-300.0, 300.0), rng.range(-300.0, 300.0), rng.range(-300.0, 300.0)),
                // Tilt away from 0 so the pose is not on the singular direction.
                rotary_rad: [
                    deg(rng.range(5.0, 100.0)) * if rng.next_f64() < 0.5 { -1.0 } else { 1.0 },
                    deg(rng.range(-390.0, 390.0)),
                ],
            };
            let pose = m.pose_from_joints(&j);
            assert_near!(pose.axis_in_workpiece.length(), 1.0, 1e-12);
            // Seeded with the true joints, the nearest solution is the same joints.
            let back = m.joints_from_pose(pose.tip_in_workpiece, pose.axis_in_workpiece, Some(&j)).unwrap();
            assert_vec_near(back.xyz_mm, j.xyz_mm, 1e-9, kind.as_str());
            assert_near!(back.rotary_rad[0], j.rotary_rad[0], 1e-9, "{} tilt", kind.as_str());
            assert_near!(back.rotary_rad[1], j.rotary_rad[1], 1e-9, "{} C", kind.as_str());
        }
    }
}

#[test]
fn forward_of_inverse_reproduces_any_reachable_pose() {
    let mut rng = Rng::new(11);
    for kind in MachineKind::ALL {
        for _ in 0..200 {
            let m = random_machine(kind, &mut rng);
            let tip = DVec3::new(rng.range(-100.0, 100.0), rng.range(-100.0, 100.0), rng.range(-50.0, 100.0));
            // Axes within 100° of +Z, reachable with a tilt of ±110°.
            let polar = deg(rng.range(0.5, 100.0));
            let azimuth = deg(rng.range(-180.0, 180.0));
            let axis = DVec3::new(polar.sin() * azimuth.cos(), polar.sin() * azimuth.sin(), polar.cos());
            let j = m.joints_from_pose(tip, axis * 3.0, None).unwrap();
            assert!(m.within_travel(&j), "{} {j:?}", kind.as_str());
            let pose = m.pose_from_joints(&j);
            assert_vec_near(pose.tip_in_workpiece, tip, 1e-9, kind.as_str());
            assert_vec_near(pose.axis_in_workpiece, axis, 1e-12, kind.as_str());
        }
    }
}

#[test]
fn rotary_axes_turn_by_the_right_hand_rule() {
    // Documented in docs/fiveaxis.md: the moving element turns by +θ about +X/+Y/+Z.
    let at = |kind: MachineKind, tilt_deg: f64, c_deg: f64| {
        let m = Machine { kind, limits_rad: [None, None], ..Machine::default() };
        m.pose_from_joints(&Joints { xyz_mm: DVec3::ZERO, rotary_rad: [deg(tilt_deg), deg(c_deg)] }).axis_in_workpiece
    };
    // Table A +90°: the table's +Y comes up to machine +Z, so the tool (along Z_M) points
    // along workpiece +Y.
    assert_vec_near(at(MachineKind::TableAC, 90.0, 0.0), DVec3::Y, 1e-12, "table A");
    // Table B +90°: workpiece −X comes up to +Z.
    assert_vec_near(at(MachineKind::TableBC, 90.0, 0.0), -DVec3::X, 1e-12, "table B");
    // Table C +90° after A +90°: the table turns workpiece +X to where its +Y was, so the
    // tool now points along workpiece +X.
    assert_vec_near(at(MachineKind::TableAC, 90.0, 90.0), DVec3::X, 1e-12, "table C");
    // Head B +90°: the tool turns from +Z toward +X.
    assert_vec_near(at(MachineKind::HeadBC, 90.0, 0.0), DVec3::X, 1e-12, "head B");
    // Head C +90° with B +90°: the tool turns on from +X to +Y.
    assert_vec_near(at(MachineKind::HeadBC, 90.0, 90.0), DVec3::Y, 1e-12, "head C");
    // Head A +90°: the tool turns from +Z toward −Y.
    assert_vec_near(at(MachineKind::HeadATableC, 90.0, 0.0), -DVec3::Y, 1e-12, "head A");
    // ... and table C +90° turns workpiece −X to machine −Y, so in the workpiece the tool
    // points along −X.
    assert_vec_near(at(MachineKind::HeadATableC, 90.0, 90.0), -DVec3::X, 1e-12, "table C of head-a-table-c");
}

#[test]
fn head_control_point_is_tool_length_above_the_tip() {
    let m = Machine {
        kind: MachineKind::HeadBC,
        pivots_mm: [DVec3::new(0.0, 12.0, 0.0), DVec3::ZERO],
        tool_length_mm: 100.0,
        limits_rad: [None, None],
    };
    // At zero angles: tip = Q + o_B − L·Z.
    let pose = m.pose_from_joints(&Joints { xyz_mm: DVec3::new(1.0, 2.0, 3.0), rotary_rad: [0.0, 0.0] });
    assert_vec_near(pose.tip_in_workpiece, DVec3::new(1.0, 14.0, -97.0), 1e-12, "tip");
    // B = 90°: the tool swings about the B axis (through Q + o_B, along Y) to point along
    // +X, so the tip lies L along −X from that axis.
    let pose = m.pose_from_joints(&Joints { xyz_mm: DVec3::ZERO, rotary_rad: [deg(90.0), 0.0] });
    assert_vec_near(pose.tip_in_workpiece, DVec3::new(-100.0, 12.0, 0.0), 1e-12, "tip at B 90°");
}

#[test]
fn c_takes_the_whole_turn_nearest_the_previous_block() {
    let m = Machine::default();
    let tip = DVec3::new(10.0, 0.0, 5.0);
    let axis = DVec3::new(0.0, 1.0, 1.0);
    let first = m.joints_from_pose(tip, axis, None).unwrap();
    // Previous block with C three turns on: the same pose is reached three turns on.
    let prev =
        Joints { rotary_rad: [first.rotary_rad[0], first.rotary_rad[1] + 3.0 * std::f64::consts::TAU + 0.1], ..first };
    let next = m.joints_from_pose(tip, axis, Some(&prev)).unwrap();
    assert_near!(next.rotary_rad[1], first.rotary_rad[1] + 3.0 * std::f64::consts::TAU, 1e-9);
}

#[test]
fn tool_axis_along_c_keeps_the_previous_c() {
    let m = Machine::default();
    let prev = Joints { xyz_mm: DVec3::ZERO, rotary_rad: [deg(20.0), deg(123.0)] };
    let j = m.joints_from_pose(DVec3::new(3.0, 4.0, 5.0), DVec3::Z, Some(&prev)).unwrap();
    assert_near!(j.rotary_rad[0], 0.0, 1e-15);
    assert_near!(j.rotary_rad[1], deg(123.0), 1e-15);
}

#[test]
fn the_branch_within_travel_is_chosen() {
    // A limited to [-10°, 100°]: an axis tilted 60° toward workpiece −Y needs A = −60°
    // with C = 0 or A = +60° with C = 180°; only the second is within travel.
    let m = Machine { limits_rad: [Some([deg(-10.0), deg(100.0)]), None], ..Machine::default() };
    let axis = DVec3::new(0.0, -deg(60.0).sin(), deg(60.0).cos());
    let j = m.joints_from_pose(DVec3::ZERO, axis, None).unwrap();
    assert_near!(j.rotary_rad[0], deg(60.0), 1e-12);
    assert_near!(j.rotary_rad[1].abs(), deg(180.0), 1e-12);
}

#[test]
fn an_axis_outside_travel_names_the_axis_and_angles() {
    let m = Machine { limits_rad: [Some([deg(-30.0), deg(30.0)]), None], ..Machine::default() };
    let err = m.joints_from_pose(DVec3::ZERO, DVec3::Y, None).unwrap_err();
    match &err {
        KinematicsError::OutOfTravel { axis_name, needed_deg, .. } => {
            assert_eq!(*axis_name, "A");
            assert!(needed_deg.iter().all(|a| (a.abs() - 90.0).abs() < 1e-9), "{needed_deg:?}");
        }
        other => panic!("expected OutOfTravel, got {other:?}"),
    }
    let msg = err.to_string();
    assert!(msg.contains("A = 90.000°") && msg.contains("[-30.000°, 30.000°]"), "{msg}");
}

#[test]
fn degenerate_input_is_an_error_not_a_nan() {
    let m = Machine::default();
    assert!(matches!(m.joints_from_pose(DVec3::ZERO, DVec3::ZERO, None), Err(KinematicsError::DegenerateAxis { .. })));
    assert!(matches!(
        m.joints_from_pose(DVec3::ZERO, DVec3::new(f64::NAN, 0.0, 1.0), None),
        Err(KinematicsError::DegenerateAxis { .. })
    ));
    assert!(matches!(
        m.joints_from_pose(DVec3::new(f64::INFINITY, 0.0, 0.0), DVec3::Z, None),
        Err(KinematicsError::NonFinite { .. })
    ));
}

#[test]
fn machine_kinds_round_trip_their_names() {
    for k in MachineKind::ALL {
        assert_eq!(MachineKind::from_name(k.as_str()), Some(k));
    }
    assert_eq!(MachineKind::from_name("table-xy"), None);
}

/// `reaches_axis` says of a tool axis what the inverse kinematics finds, for every machine
/// kind with the tilt and C limited, at random axes and at axes within a hair of the tilt's
/// limit: with no margin, it reaches exactly where `joints_from_pose` finds joints (from any
/// previous block); with a margin m, it reaches only where the joints lie m inside the limits
/// — and then the axis reaches with no margin too.
#[test]
fn reaching_an_axis_is_what_the_inverse_kinematics_finds() {
    let mut rng = Rng::new(31);
    let margin = deg(0.5);
    for kind in MachineKind::ALL {
        let mut m = random_machine(kind, &mut rng);
        m.limits_rad = [Some([deg(-75.0), deg(100.0)]), Some([deg(-150.0), deg(170.0)])];
        let (mut reached, mut refused) = (0, 0);
        for i in 0..4000 {
            let axis = if i % 2 == 0 {
                // Uniform on the sphere.
                let z = rng.range(-1.0, 1.0);
                let phi = rng.range(-std::f64::consts::PI, std::f64::consts::PI);
                let r = (1.0 - z * z).sqrt();
                DVec3::new(r * phi.cos(), r * phi.sin(), z)
            } else {
                // Near a limit of the tilt, from the forward kinematics.
                let limit = if i % 4 == 1 { deg(100.0) } else { deg(-75.0) };
                let tilt = limit + rng.range(-deg(1.0), deg(1.0));
                let c = rng.range(deg(-150.0), deg(170.0));
                m.pose_from_joints(&Joints { xyz_mm: DVec3::ZERO, rotary_rad: [tilt, c] }).axis_in_workpiece
            };
            let prev = Joints { xyz_mm: DVec3::ZERO, rotary_rad: [rng.range(-1.0, 1.0), rng.range(-2.0, 2.0)] };
            let ik = m.joints_from_pose(DVec3::ZERO, axis, Some(&prev));
            let out = matches!(ik, Err(KinematicsError::OutOfTravel { .. }));
            assert_eq!(m.reaches_axis(axis, 0.0), !out, "{kind:?} axis {axis:?}: {ik:?}");
            assert_eq!(m.reaches_axis(3.0 * axis, 0.0), !out, "the axis' length matters");
            if m.reaches_axis(axis, margin) {
                assert!(!out, "{kind:?}: reached with a margin but not without");
                // Some branch lies the margin inside: the inverse kinematics within limits
                // shrunk by the margin still finds joints.
                let [[a0, a1], [c0, c1]] = [[deg(-75.0), deg(100.0)], [deg(-150.0), deg(170.0)]];
                let shrunk =
                    Machine { limits_rad: [Some([a0 + margin, a1 - margin]), Some([c0 + margin, c1 - margin])], ..m };
                assert!(shrunk.joints_from_pose(DVec3::ZERO, axis, None).is_ok(), "{kind:?} axis {axis:?}");
                reached += 1;
            } else {
                refused += 1;
            }
        }
        assert!(reached > 500 && refused > 500, "{kind:?}: {reached} reached, {refused} not");
    }
}
