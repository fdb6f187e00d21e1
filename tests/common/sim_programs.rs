//! The simulation benchmarks' programs, shared by `benches/simulate.rs` (criterion, native)
//! and `tests/bench_simulate.rs` (the same source natively and as wasm32 under Node), so both
//! time the same moves: a zigzag ball raster on a 51.2 × 51.2 mm block (tips at z = 17 mm,
//! rows 1 mm apart, 0.5 mm moves) and the same tips with the tool axis swinging ±15° about X
//! over 40 moves, joints from a table A/C machine's inverse kinematics.

use glam::DVec3;
use interpolab::fiveaxis::{Joints, Machine};
use interpolab::simulate::{MoveKind, Program, SimMove};

/// Side of the square block the programs cover (mm).
pub const SIDE_MM: f64 = 51.2;

/// Tip points of the zigzag raster (mm): `n_moves + 1` points.
pub fn raster_points(n_moves: usize) -> Vec<DVec3> {
    let mut pts = vec![DVec3::new(0.0, 0.0, 17.0)];
    let mut row = 0;
    while pts.len() <= n_moves {
        let y = f64::from(row) % SIDE_MM;
        for k in 1..=100 {
            let x = if row % 2 == 0 { 0.5 * f64::from(k) } else { SIDE_MM - 0.5 * f64::from(k) };
            pts.push(DVec3::new(x.clamp(0.0, SIDE_MM), y, 17.0));
        }
        row += 1;
        pts.push(DVec3::new(pts[pts.len() - 1].x, f64::from(row) % SIDE_MM, 17.0));
    }
    pts.truncate(n_moves + 1);
    pts
}

/// `n` straight 3-axis moves along the raster.
pub fn three_axis(n: usize) -> Program {
    let moves = raster_points(n)
        .windows(2)
        .map(|w| SimMove { kind: MoveKind::Line { from: w[0], to: w[1] }, line: 0, rapid: false })
        .collect();
    Program { moves, chord_error_mm: 0.0 }
}

/// The machine the 5-axis program runs on: the default table A/C machine without joint limits.
pub fn machine() -> Machine {
    Machine { limits_rad: [None, None], ..Machine::default() }
}

/// The tilt about X at raster point k (rad): 15° · sin(2πk/40).
pub fn tilt_rad(k: usize) -> f64 {
    15f64.to_radians() * (std::f64::consts::TAU * k as f64 / 40.0).sin()
}

/// Unit tool axis at raster point k: tilted about X by [`tilt_rad`].
pub fn axis(k: usize) -> DVec3 {
    let (sn, cs) = tilt_rad(k).sin_cos();
    DVec3::new(0.0, -sn, cs)
}

/// `n` 5-axis moves: the raster's tips with [`axis`], joints by the inverse kinematics (the
/// branch nearest the previous block), interpolated linearly by the simulation.
pub fn five_axis(n: usize) -> Program {
    let m = machine();
    let mut joints: Vec<Joints> = Vec::with_capacity(n + 1);
    for (k, p) in raster_points(n).iter().enumerate() {
        match m.joints_from_pose(*p, axis(k), joints.last()) {
            Ok(j) => joints.push(j),
            Err(e) => panic!("inverse kinematics at block {k}: {e}"),
        }
    }
    let moves = joints
        .windows(2)
        .map(|w| SimMove { kind: MoveKind::Joints { machine: m, from: w[0], to: w[1] }, line: 0, rapid: false })
        .collect();
    Program { moves, chord_error_mm: 0.0 }
}
