//! A user's rotary program through a machine: a joint program's tip path against forward
//! kinematics written here from each machine's geometry; TCP programs keep the tip on the
//! programmed chord; LinuxCNC's `xyzac-trt` and `xyzbc-trt` kinematics (their formulas, with
//! their offsets) are our table machines; LinuxCNC's 5-axis demos (impeller, boat) read,
//! timed, simulated and their nonlinear error per block checked against an independent
//! inverse + forward kinematics.
#![allow(
    clippy::unwrap_used,
    clippy::float_cmp,
    reason = "tests: an error should fail the test; exact float equality is what some assert"
)]
#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

use crate::support::Rng;
use glam::DVec3;
use interpolab::fiveaxis::{Joints, Machine, MachineKind};
use interpolab::gcode::interp::tools::{ToolEntry, ToolShape as TableShape, ToolTable};
use interpolab::gcode::interp::{Interpreter, Options};
use interpolab::geom::Cutter;
use interpolab::numerics::measure::distance_to_segment;
use interpolab::simulate::canon::{
    CanonBuilder, CanonOptions, CanonProgram, KinematicsChoice, MachineSetup, RotaryMode,
};
use interpolab::simulate::{MoveKind, SimMove};

// Rotations written out, right-handed, angle in radians.
fn rx(t: f64, v: DVec3) -> DVec3 {
    DVec3::new(v.x, t.cos() * v.y - t.sin() * v.z, t.sin() * v.y + t.cos() * v.z)
}
fn ry(t: f64, v: DVec3) -> DVec3 {
    DVec3::new(t.cos() * v.x + t.sin() * v.z, v.y, -t.sin() * v.x + t.cos() * v.z)
}
fn rz(t: f64, v: DVec3) -> DVec3 {
    DVec3::new(t.cos() * v.x - t.sin() * v.y, t.sin() * v.x + t.cos() * v.y, v.z)
}

/// Forward kinematics from the machine's geometry (docs/fiveaxis.md): the tip and the unit
/// tool axis in the workpiece for joints (X, Y, Z mm; tilt, C rad).
fn fk(m: &Machine, xyz: DVec3, tilt: f64, c: f64) -> (DVec3, DVec3) {
    let [p0, p1] = m.pivots_mm;
    let l = m.tool_length_mm;
    match m.kind {
        // The table turns the part: x_M = p_T + R_T(tilt)(p_C + Rz(c)(x_W − p_C) − p_T).
        MachineKind::TableAC => {
            let tip = p1 + rz(-c, p0 + rx(-tilt, xyz - p0) - p1);
            (tip, rz(-c, rx(-tilt, DVec3::Z)))
        }
        MachineKind::TableBC => {
            let tip = p1 + rz(-c, p0 + ry(-tilt, xyz - p0) - p1);
            (tip, rz(-c, ry(-tilt, DVec3::Z)))
        }
        // The head carries the tool: T = Rz(c)Ry(b)Z, tip = Q + Rz(c)·o_B − L·T.
        MachineKind::HeadBC => {
            let t = rz(c, ry(tilt, DVec3::Z));
            (xyz + rz(c, p0) - l * t, t)
        }
        // Head A, table C: tip_M = Q + o_A − L·Rx(a)Z, x_W = p_C + Rz(−c)(x_M − p_C).
        MachineKind::HeadATableC => {
            let t = rx(tilt, DVec3::Z);
            let tip_m = xyz + p0 - l * t;
            (p1 + rz(-c, tip_m - p1), rz(-c, t))
        }
    }
}

fn read(text: &str, machine: MachineSetup, kin: KinematicsChoice, tools: &ToolTable) -> CanonProgram {
    let mut it = Interpreter::from_text(text, Options { tools: tools.clone(), ..Options::default() });
    let mut b = CanonBuilder::new(CanonOptions {
        machine: Some(machine),
        kinematics: kin,
        chord_tol_mm: 0.01,
        tools: tools.clone(),
        default_cutter: Some(Cutter::ball(1.0).unwrap()),
    });
    assert!(b.read(&mut it, |_| true).unwrap());
    b.finish()
}

/// The largest distance of the swept tip from the chord, sampled densely.
fn dense_error(tip: impl Fn(f64) -> DVec3, n: usize) -> f64 {
    let (a, b) = (tip(0.0), tip(1.0));
    (0..=n).map(|k| distance_to_segment(tip(k as f64 / n as f64), a, b)).fold(0.0, f64::max)
}

fn random_pivot(rng: &mut Rng) -> DVec3 {
    DVec3::new(rng.range(-30.0, 30.0), rng.range(-30.0, 30.0), rng.range(-20.0, 20.0))
}

#[test]
fn a_joint_program_sweeps_the_tip_its_machine_s_forward_kinematics_gives() {
    let mut rng = Rng::new(2202);
    for name in MachineSetup::NAMES {
        let mut setup = MachineSetup::from_name(name, 35.0).unwrap();
        setup.machine.pivots_mm = [random_pivot(&mut rng), random_pivot(&mut rng)];
        let [tw, cw] = setup.words().map(|i| ['A', 'B', 'C'][i]);
        let mut text = String::from("G21 G90 G94\nG0 X0 Y0 Z40\n");
        let mut joints = Vec::new();
        for _ in 0..14 {
            let j = (
                DVec3::new(rng.range(-20.0, 20.0), rng.range(-20.0, 20.0), rng.range(-10.0, 10.0)),
                rng.range(-60.0, 60.0),
                if setup.four_axis { 0.0 } else { rng.range(-120.0, 120.0) },
            );
            let c_word = if setup.four_axis { String::new() } else { format!(" {cw}{:.4}", j.2) };
            text.push_str(&format!("G1 X{:.4} Y{:.4} Z{:.4} {tw}{:.4}{c_word} F500\n", j.0.x, j.0.y, j.0.z, j.1));
            joints.push(j);
        }
        text.push_str("M30\n");
        let p = read(&text, setup, KinematicsChoice::Joints, &ToolTable::new());
        let m = setup.machine;
        let round = |v: f64| (v * 1e4).round() / 1e4;
        let jr = |j: &(DVec3, f64, f64)| (j.0.map(round), round(j.1).to_radians(), round(j.2).to_radians());
        assert_eq!(p.blocks.len(), joints.len() + 1, "{name}");
        for (k, b) in p.blocks.iter().skip(1).enumerate() {
            let (xyz, t, c) = jr(&joints[k]);
            let (tip, _) = fk(&m, xyz, t, c);
            assert!((b.end_tip - tip).length() < 1e-9, "{name} block {k}: {} vs {tip}", b.end_tip);
            // The swept tool of each move is the machine's joints interpolated linearly.
            let moves: &[SimMove] = &p.program.moves[b.moves.0 as usize..b.moves.1 as usize];
            assert!(!moves.is_empty(), "{name} block {k}");
            for mv in moves {
                let MoveKind::Joints { machine, from, to } = mv.kind else {
                    panic!("{name} block {k}: a rotary move as a 3-axis line");
                };
                for s in 0..=8 {
                    let tau = f64::from(s) / 8.0;
                    let j = from.lerp(&to, tau);
                    let pose = machine.pose_from_joints(&j);
                    let (tip, axis) = fk(&m, j.xyz_mm, j.rotary_rad[0], j.rotary_rad[1]);
                    assert!((pose.tip_in_workpiece - tip).length() < 1e-9, "{name} block {k} τ {tau}");
                    assert!((pose.axis_in_workpiece - axis).length() < 1e-12, "{name} block {k} τ {tau}");
                }
            }
            if k == 0 {
                continue;
            }
            // Seed 002's nonlinear error against a dense sampling of the same FK.
            let (x0, t0, c0) = jr(&joints[k - 1]);
            let r = b.rotary.unwrap();
            let got = r.nonlinear_mm.unwrap();
            let want = dense_error(|tau| fk(&m, x0.lerp(xyz, tau), t0 + tau * (t - t0), c0 + tau * (c - c0)).0, 4000);
            assert!(got >= want - 1e-9 && got - want < 1e-6 * want.max(1.0), "{name} block {k}: {got} vs {want}");
            assert_eq!(r.mode, RotaryMode::Joints);
        }
        let worst = p.blocks.iter().filter_map(|b| b.rotary.and_then(|r| r.nonlinear_mm)).fold(0.0, f64::max);
        assert!(worst > 0.1, "{name}: these blocks turn tens of degrees: {worst}");
    }
}

#[test]
fn a_tcp_program_keeps_the_tip_on_the_programmed_chord() {
    let mut rng = Rng::new(4304);
    for (name, word) in [("table-ac", "A"), ("table-bc", "B"), ("head-bc", "B"), ("head-a-table-c", "A")] {
        let mut setup = MachineSetup::from_name(name, 30.0).unwrap();
        setup.machine.pivots_mm = [random_pivot(&mut rng), random_pivot(&mut rng)];
        let mut text = String::from("G21 G90 G94\nM428\nG0 X0 Y0 Z40\n");
        let mut poses = vec![(DVec3::new(0.0, 0.0, 40.0), 0.0, 0.0)];
        for _ in 0..10 {
            let q = (
                DVec3::new(rng.range(-20.0, 20.0), rng.range(-20.0, 20.0), rng.range(-10.0, 10.0)),
                rng.range(-40.0, 40.0),
                rng.range(-90.0, 90.0),
            );
            text.push_str(&format!("G1 X{:.4} Y{:.4} Z{:.4} {word}{:.4} C{:.4} F500\n", q.0.x, q.0.y, q.0.z, q.1, q.2));
            poses.push(q);
        }
        text.push_str("M429\nM30\n");
        let p = read(&text, setup, KinematicsChoice::Auto, &ToolTable::new());
        let m = setup.machine;
        let round = |v: f64| (v * 1e4).round() / 1e4;
        for (k, b) in p.blocks.iter().enumerate().skip(2) {
            let (a0, a1) = (poses[k - 1], poses[k]);
            let (p0, p1) = (a0.0.map(round), a1.0.map(round));
            let r = b.rotary.unwrap();
            assert_eq!(r.mode, RotaryMode::Tcp, "{name}: M428 turns TCP on");
            assert!((b.end_tip - p1).length() < 1e-9, "{name} block {k}");
            let moves = &p.program.moves[b.moves.0 as usize..b.moves.1 as usize];
            for mv in moves {
                let MoveKind::Joints { machine, from, to } = mv.kind else { panic!("{name}: a 3-axis line") };
                for s in 0..=4 {
                    let pose = machine.pose_from_joints(&from.lerp(&to, f64::from(s) / 4.0));
                    let d = distance_to_segment(pose.tip_in_workpiece, p0, p1);
                    // Move ends on the chord; between them within the chord tolerance.
                    let tol = if s % 4 == 0 { 1e-9 } else { 0.01 + 1e-9 };
                    assert!(d <= tol, "{name} block {k}: {d}");
                    // The axis is the machine's at the angles (linear in the move).
                    let (_, axis) = fk(
                        &m,
                        DVec3::ZERO,
                        from.lerp(&to, f64::from(s) / 4.0).rotary_rad[0],
                        from.lerp(&to, f64::from(s) / 4.0).rotary_rad[1],
                    );
                    assert!((pose.axis_in_workpiece - axis).length() < 1e-12);
                }
            }
            // Its error as seed 002 would see the same poses posted as joints.
            let (t0, c0, t1, c1) = (
                round(a0.1).to_radians(),
                round(a0.2).to_radians(),
                round(a1.1).to_radians(),
                round(a1.2).to_radians(),
            );
            let j0 = m.joints_at_angles(p0, [t0, c0]);
            let j1 = m.joints_at_angles(p1, [t1, c1]);
            // The joints put the tip where it was programmed (FK written here).
            assert!((fk(&m, j0.xyz_mm, t0, c0).0 - p0).length() < 1e-9);
            assert!((fk(&m, j1.xyz_mm, t1, c1).0 - p1).length() < 1e-9);
            let want = dense_error(
                |tau| fk(&m, j0.xyz_mm.lerp(j1.xyz_mm, tau), t0 + tau * (t1 - t0), c0 + tau * (c1 - c0)).0,
                4000,
            );
            let got = r.nonlinear_mm.unwrap();
            assert!(got >= want - 1e-9 && got - want < 1e-6 * want.max(1.0), "{name} block {k}: {got} vs {want}");
        }
    }
}

/// LinuxCNC's `xyzac-trt` forward kinematics (src/emc/kinematics/trtfuncs.c, its default
/// directions: `conventional-directions` false), rewritten: joints (X, Y, Z mm, A, C deg),
/// rotation point, the A axis' offsets (y, z) from it.
fn linuxcnc_xyzac(j: [f64; 5], rot: DVec3, dy: f64, dz: f64) -> DVec3 {
    let (a, c) = (j[3].to_radians(), j[4].to_radians());
    let (x, y, z) = (j[0] - rot.x, j[1] - dy - rot.y, j[2] - dz - rot.z);
    DVec3::new(
        c.cos() * x + c.sin() * a.cos() * y + c.sin() * a.sin() * z + c.sin() * dy + rot.x,
        -c.sin() * x + c.cos() * a.cos() * y + c.cos() * a.sin() * z + c.cos() * dy + rot.y,
        -a.sin() * y + a.cos() * z + dz + rot.z,
    )
}

/// LinuxCNC's `xyzbc-trt` forward kinematics, as above (the B axis' offsets x, z).
fn linuxcnc_xyzbc(j: [f64; 5], rot: DVec3, dx: f64, dz: f64) -> DVec3 {
    let (b, c) = (j[3].to_radians(), j[4].to_radians());
    let (x, y, z) = (j[0] - dx - rot.x, j[1] - rot.y, j[2] - dz - rot.z);
    DVec3::new(
        c.cos() * b.cos() * x + c.sin() * y - c.cos() * b.sin() * z + c.cos() * dx + rot.x,
        -c.sin() * b.cos() * x + c.cos() * y + c.sin() * b.sin() * z - c.sin() * dx + rot.y,
        b.sin() * x + b.cos() * z + dz + rot.z,
    )
}

#[test]
fn linuxcnc_s_trt_kinematics_are_our_table_machines_with_their_offsets() {
    let mut rng = Rng::new(9);
    for _ in 0..500 {
        let rot = random_pivot(&mut rng);
        let (d1, d2) = (rng.range(-30.0, 30.0), rng.range(-30.0, 30.0));
        let j = [
            rng.range(-50.0, 50.0),
            rng.range(-50.0, 50.0),
            rng.range(-50.0, 50.0),
            rng.range(-120.0, 120.0),
            rng.range(-400.0, 400.0),
        ];
        let joints =
            Joints { xyz_mm: DVec3::new(j[0], j[1], j[2]), rotary_rad: [j[3].to_radians(), j[4].to_radians()] };
        // A: the A axis through (·, y_rot + dy, z_rot + dz); C through (x_rot, y_rot).
        let mut ac = MachineSetup::from_name("table-ac", 0.0).unwrap().machine;
        ac.pivots_mm = [DVec3::new(0.0, rot.y + d1, rot.z + d2), rot];
        let ours = ac.pose_from_joints(&joints).tip_in_workpiece;
        let theirs = linuxcnc_xyzac(j, rot, d1, d2);
        assert!((ours - theirs).length() < 1e-9, "xyzac {j:?}: {ours} vs {theirs}");
        // B: the B axis through (x_rot + dx, ·, z_rot + dz).
        let mut bc = MachineSetup::from_name("table-bc", 0.0).unwrap().machine;
        bc.pivots_mm = [DVec3::new(rot.x + d1, 0.0, rot.z + d2), rot];
        let ours = bc.pose_from_joints(&joints).tip_in_workpiece;
        let theirs = linuxcnc_xyzbc(j, rot, d1, d2);
        assert!((ours - theirs).length() < 1e-9, "xyzbc {j:?}: {ours} vs {theirs}");
    }
}

/// LinuxCNC's samples directory of the switchable table-rotary-tilting machines.
#[cfg(not(target_arch = "wasm32"))]
const DEMOS: &str = "/usr/share/doc/linuxcnc/examples/sample-configs/sim/axis/vismach/5axis/table-rotary-tilting";

/// The words of a line with their numbers (`G1  X  16.339` → G 1, X 16.339).
#[cfg(not(target_arch = "wasm32"))]
fn words(line: &str) -> Vec<(char, f64)> {
    let code = line.split([';', '(']).next().unwrap_or("");
    let s: String = code.chars().filter(|c| !c.is_whitespace()).collect();
    let mut out = Vec::new();
    let mut chars = s.char_indices().peekable();
    while let Some((i, c)) = chars.next() {
        if c.is_ascii_alphabetic() {
            let mut end = i + 1;
            while let Some(&(j, d)) = chars.peek() {
                if d.is_ascii_digit() || d == '.' || d == '-' || d == '+' {
                    end = j + d.len_utf8();
                    chars.next();
                } else {
                    break;
                }
            }
            if let Ok(v) = s[i + 1..end].parse::<f64>() {
                out.push((c.to_ascii_uppercase(), v));
            }
        }
    }
    out
}

#[cfg(not(target_arch = "wasm32"))]
#[test]
fn linuxcnc_s_impeller_is_read_timed_simulated_and_its_nonlinear_error_measured() {
    let path = std::path::Path::new(DEMOS).join("demos/impeller-7bl-xyzac.ngc");
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (scripts/setup.sh test installs linuxcnc-uspace)", path.display()));
    // The machine of LinuxCNC's xyzac-trt sample: the A axis 20 mm in y and 10 mm in z from
    // the C axis (xyzac-trt.ini), tool offset 0.
    let mut setup = MachineSetup::from_name("table-ac", 0.0).unwrap();
    setup.machine.pivots_mm = [DVec3::new(0.0, 20.0, 10.0), DVec3::ZERO];
    let mut tools = ToolTable::new();
    tools.insert(ToolEntry::new(1, TableShape::Ball, 3.0), "test").unwrap();
    let mut p = read(&text, setup, KinematicsChoice::Auto, &tools);
    // Every motion line is a block (G0/G1 with all five axes on every line).
    let motions: Vec<(usize, Vec<(char, f64)>)> = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, words(l)))
        .filter(|(_, w)| w.iter().any(|&(c, v)| c == 'G' && (v == 0.0 || v == 1.0)))
        .collect();
    assert_eq!(p.blocks.len(), motions.len());
    // G93 throughout: each G1 takes 1/F minutes.
    let want: f64 = motions
        .iter()
        .filter(|(_, w)| w.contains(&('G', 1.0)))
        .map(|(_, w)| 1.0 / w.iter().find(|(c, _)| *c == 'F').unwrap().1)
        .sum();
    let got: f64 = p.tools.iter().map(|t| t.feed_min).sum();
    assert!((got - want).abs() < 1e-9 * want, "{got} vs {want} min");
    // M428 on line 4 puts every rotary block under TCP; M429 on line 4509 ends it.
    let rotary: Vec<_> = p.blocks.iter().filter(|b| b.rotary.is_some()).collect();
    assert!(rotary.len() > 4000 && rotary.iter().all(|b| b.rotary.unwrap().mode == RotaryMode::Tcp));
    // The nonlinear error of each measured block: LinuxCNC's inverse kinematics for the
    // two programmed poses (the inverse of the forward map above), the joints interpolated,
    // the tip from the forward map, sampled densely.
    let inverse = |tip: DVec3, a: f64, c: f64| -> DVec3 {
        // x_M = p_A + Rx(a)(Rz(c)·x_W − p_A) with p_C = 0 (xyzac-trt's inverse, directions as above).
        let pa = DVec3::new(0.0, 20.0, 10.0);
        pa + rx(a, rz(c, tip) - pa)
    };
    let mut prev = (DVec3::ZERO, 0.0, 0.0);
    let mut checked = 0;
    let mut worst: (f64, usize) = (0.0, 0);
    for (b, (line, w)) in p.blocks.iter().zip(&motions) {
        let get = |l: char| w.iter().find(|(c, _)| *c == l).map(|&(_, v)| v);
        // Words left out keep their values (modal axes).
        let pose = (
            DVec3::new(get('X').unwrap_or(prev.0.x), get('Y').unwrap_or(prev.0.y), get('Z').unwrap_or(prev.0.z)),
            get('A').map_or(prev.1, f64::to_radians),
            get('C').map_or(prev.2, f64::to_radians),
        );
        assert_eq!(b.loc.line as usize, *line);
        if let Some(e) = b.rotary.and_then(|r| r.nonlinear_mm) {
            let (j0, j1) = (inverse(prev.0, prev.1, prev.2), inverse(pose.0, pose.1, pose.2));
            let lin = |tau: f64| {
                let j = j0.lerp(j1, tau);
                let (a, c) = (prev.1 + tau * (pose.1 - prev.1), prev.2 + tau * (pose.2 - prev.2));
                linuxcnc_xyzac([j.x, j.y, j.z, a.to_degrees(), c.to_degrees()], DVec3::ZERO, 20.0, 10.0)
            };
            assert!((lin(0.0) - prev.0).length() < 1e-9 && (lin(1.0) - pose.0).length() < 1e-9);
            let want = dense_error(lin, 2000);
            assert!(e >= want - 1e-9 && e - want < 1e-6 * want.max(1.0), "line {line}: {e} vs {want}");
            checked += 1;
            if e > worst.0 {
                worst = (e, *line);
            }
        }
        prev = pose;
    }
    assert!(checked > 4000, "{checked}");
    assert!(worst.0 > 0.1, "{worst:?}");
    assert_eq!(p.over_tolerance(worst.0 - 1e-9).next().map(|b| b.loc.line as usize), Some(worst.1));
    // Simulated with a 3 mm ball on a block: material removed, every tool's share summing to
    // the whole, the TCP moves within the chord tolerance.
    let stock = interpolab::simulate::DexelStock::block([-45.0, -45.0, -5.0], [45.0, 45.0, 40.0], 0.5).unwrap();
    let mut sim = interpolab::simulate::Simulation::new(stock, &p.tools[0].cutter);
    assert!(p.run(&mut sim, |_| true).unwrap());
    let total = sim.counters().removed_mm3;
    assert!(total > 1000.0, "{total}");
    assert!((p.tools.iter().map(|t| t.removed_mm3).sum::<f64>() - total).abs() < 1e-6 * total);
    assert!(p.program.chord_error_mm <= 0.01 + 1e-12, "{}", p.program.chord_error_mm);
}

#[cfg(not(target_arch = "wasm32"))]
#[test]
fn linuxcnc_s_boats_are_read_with_their_tool_and_measured_on_both_machines() {
    for (file, name, pivot) in [
        ("boat-xyzac.ngc", "table-ac", DVec3::new(0.0, 20.0, 10.0)),
        ("boat-xyzbc.ngc", "table-bc", DVec3::new(-20.0, 0.0, -15.0)),
    ] {
        let path = std::path::Path::new(DEMOS).join("demos").join(file);
        let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let mut setup = MachineSetup::from_name(name, 0.0).unwrap();
        setup.machine.pivots_mm = [pivot, DVec3::ZERO];
        // The program's own comment names its tool: T1, a 10 mm end mill.
        let mut tools = ToolTable::new();
        tools.insert(ToolEntry::new(1, TableShape::Flat, 10.0), "test").unwrap();
        let p = read(&text, setup, KinematicsChoice::Auto, &tools);
        assert_eq!(p.tools.last().map(|t| t.number), Some(1), "{file}");
        let rotary: Vec<_> = p.blocks.iter().filter_map(|b| b.rotary).collect();
        assert!(rotary.len() > 1000 && rotary.iter().all(|r| r.mode == RotaryMode::Tcp), "{file}: {}", rotary.len());
        // Every measured block's error is seed 002's with the joints this machine commands.
        for b in p.blocks.iter().filter(|b| b.rotary.is_some_and(|r| r.nonlinear_mm.is_some())).take(300) {
            let r = b.rotary.unwrap();
            let m = setup.machine;
            let want = dense_error(
                |tau| {
                    let j = r.from.lerp(&r.to, tau);
                    fk(&m, j.xyz_mm, j.rotary_rad[0], j.rotary_rad[1]).0
                },
                2000,
            );
            let got = r.nonlinear_mm.unwrap();
            assert!(
                got >= want - 1e-9 && got - want < 1e-6 * want.max(1.0),
                "{file} line {}: {got} vs {want}",
                b.loc.line
            );
            assert!((fk(&m, r.to.xyz_mm, r.to.rotary_rad[0], r.to.rotary_rad[1]).0 - b.end_tip).length() < 1e-9);
        }
        // The rotary word of the other machine never appears.
        assert!(!p.notes.iter().any(|n| n.text.contains("has no")), "{file}: {:?}", p.notes);
        // G93 blocks are timed by their inverse-time F: some of the boat's are.
        assert!(
            p.blocks
                .iter()
                .any(|b| b.feed.mode == interpolab::gcode::interp::FeedMode::InverseTime && b.time_min.is_some())
        );
    }
}
