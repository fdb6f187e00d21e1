//! The simulation's benchmark programs, built from a few numbers: a zigzag ball raster on a
//! 51.2 × 51.2 mm block (tips at z = 17 mm, rows 1 mm apart, 0.5 mm moves) as 3-axis lines,
//! and the same tips with the tool axis swinging ±15° about X over 40 moves as 5-axis moves
//! (joints from a table A/C machine's inverse kinematics, interpolated linearly).
//!
//! The native benchmarks (`benches/simulate.rs`, `benches/native_and_wasm/simulate.rs`), the command line
//! (`interpolab simulate --benchmark five-axis:N`) and the app's simulation tab
//! (`set_option("benchmark", "five-axis:N")`, built in its Web Worker) all run these, so a
//! browser measurement times the same moves as the native one without a 10 000-line program
//! handed to the page.

use glam::DVec3;

use super::{MoveKind, Program, SimError, SimMove};
use crate::fiveaxis::{Joints, Machine};

/// Side of the square block the programs cover (mm): 512 rays at pitch 0.1.
pub const SIDE_MM: f64 = 51.2;
/// Height of the block's top (mm); the tips run 3 mm below it.
pub const BLOCK_TOP_MM: f64 = 20.0;
/// Height of the raster's tips (mm).
pub const TIP_Z_MM: f64 = 17.0;
/// The ball radius the benchmarks cut with (mm).
pub const BALL_MM: f64 = 3.0;
/// The pitch of the benchmarks' 512 × 512 grid (mm).
pub const PITCH_MM: f64 = 0.1;
/// Most moves a benchmark program may have (the tab and the command line refuse more
/// before building anything).
pub const MAX_BENCH_MOVES: usize = 1_000_000;
/// Length of one raster move along a row (mm).
const STEP_MM: f64 = 0.5;
/// Moves per raster row (51.2 mm / 0.5 mm, rounded up to whole moves, then clamped).
const MOVES_PER_ROW: u32 = 100;
/// Moves per swing of the tool axis.
const SWING_MOVES: f64 = 40.0;
/// Amplitude of the swing (degrees).
const SWING_DEG: f64 = 15.0;

/// The benchmark programs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BenchKind {
    /// Straight 3-axis moves along the raster.
    ThreeAxis,
    /// The raster's tips with the tool axis swinging about X: 5-axis joint moves.
    FiveAxis,
}

impl BenchKind {
    /// The name in `--benchmark` and `set_option("benchmark", …)`.
    #[must_use]
    pub fn key(self) -> &'static str {
        match self {
            Self::ThreeAxis => "three-axis",
            Self::FiveAxis => "five-axis",
        }
    }

    /// Reads `three-axis:N` or `five-axis:N` (N moves, 1 to [`MAX_BENCH_MOVES`]).
    ///
    /// # Errors
    /// A one-line message naming what to write instead.
    pub fn parse(text: &str) -> Result<(Self, usize), String> {
        let bad = || {
            format!(
                "benchmark `{text}`: give five-axis:N or three-axis:N with N moves from 1 to {MAX_BENCH_MOVES}, e.g. five-axis:10000"
            )
        };
        let (kind, n) = text.trim().split_once(':').ok_or_else(bad)?;
        let kind = [Self::ThreeAxis, Self::FiveAxis].into_iter().find(|k| k.key() == kind.trim()).ok_or_else(bad)?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if !(1..=MAX_BENCH_MOVES).contains(&n) {
            return Err(bad());
        }
        Ok((kind, n))
    }

    /// The program of `n` moves.
    ///
    /// # Errors
    /// [`SimError::Program`] above [`MAX_BENCH_MOVES`] moves, or where the inverse
    /// kinematics finds no joints (not for the default machine).
    pub fn program(self, n: usize) -> Result<Program, SimError> {
        match self {
            Self::ThreeAxis => three_axis(n),
            Self::FiveAxis => five_axis(n),
        }
    }

    /// The block the benchmarks cut: `x0, y0, z0, x1, y1, z1` (mm).
    #[must_use]
    pub fn stock_mm() -> [f64; 6] {
        [0.0, 0.0, 0.0, SIDE_MM, SIDE_MM, BLOCK_TOP_MM]
    }
}

fn check_count(n: usize) -> Result<(), SimError> {
    if n > MAX_BENCH_MOVES {
        return Err(SimError::Program(format!(
            "a benchmark program of {n} moves is more than the {MAX_BENCH_MOVES} offered; ask for fewer"
        )));
    }
    Ok(())
}

/// Tip points of the zigzag raster (mm): `n_moves + 1` points (none above
/// [`MAX_BENCH_MOVES`] moves).
#[must_use]
pub fn raster_points(n_moves: usize) -> Vec<DVec3> {
    let n_moves = n_moves.min(MAX_BENCH_MOVES);
    let mut pts = Vec::with_capacity(n_moves + 1);
    pts.push(DVec3::new(0.0, 0.0, TIP_Z_MM));
    let mut row = 0_u32;
    while pts.len() <= n_moves {
        let y = f64::from(row) % SIDE_MM;
        for k in 1..=MOVES_PER_ROW {
            let x = if row.is_multiple_of(2) { STEP_MM * f64::from(k) } else { SIDE_MM - STEP_MM * f64::from(k) };
            pts.push(DVec3::new(x.clamp(0.0, SIDE_MM), y, TIP_Z_MM));
        }
        row += 1;
        let last_x = pts[pts.len() - 1].x;
        pts.push(DVec3::new(last_x, f64::from(row) % SIDE_MM, TIP_Z_MM));
    }
    pts.truncate(n_moves + 1);
    pts
}

/// `n` straight 3-axis moves along the raster.
///
/// # Errors
/// [`SimError::Program`] above [`MAX_BENCH_MOVES`] moves.
pub fn three_axis(n: usize) -> Result<Program, SimError> {
    check_count(n)?;
    let moves = raster_points(n)
        .windows(2)
        .map(|w| SimMove { kind: MoveKind::Line { from: w[0], to: w[1] }, line: 0, rapid: false })
        .collect();
    Ok(Program { moves, chord_error_mm: 0.0 })
}

/// The machine the 5-axis program runs on: the default table A/C machine without joint limits.
#[must_use]
pub fn machine() -> Machine {
    Machine { limits_rad: [None, None], ..Machine::default() }
}

/// The tilt about X at raster point k (rad): 15° · sin(2πk/40).
#[must_use]
pub fn tilt_rad(k: usize) -> f64 {
    SWING_DEG.to_radians() * (std::f64::consts::TAU * k as f64 / SWING_MOVES).sin()
}

/// Unit tool axis at raster point k: tilted about X by [`tilt_rad`].
#[must_use]
pub fn axis(k: usize) -> DVec3 {
    let (sn, cs) = tilt_rad(k).sin_cos();
    DVec3::new(0.0, -sn, cs)
}

/// `n` 5-axis moves: the raster's tips with [`axis`], joints by the inverse kinematics (the
/// branch nearest the previous block), interpolated linearly by the simulation.
///
/// # Errors
/// [`SimError::Program`] above [`MAX_BENCH_MOVES`] moves or where the inverse kinematics
/// finds no joints.
pub fn five_axis(n: usize) -> Result<Program, SimError> {
    check_count(n)?;
    let m = machine();
    let mut joints: Vec<Joints> = Vec::with_capacity(n + 1);
    for (k, p) in raster_points(n).iter().enumerate() {
        let j = m
            .joints_from_pose(*p, axis(k), joints.last())
            .map_err(|e| SimError::Program(format!("benchmark block {k}: {e}")))?;
        joints.push(j);
    }
    let moves = joints
        .windows(2)
        .map(|w| SimMove { kind: MoveKind::Joints { machine: m, from: w[0], to: w[1] }, line: 0, rapid: false })
        .collect();
    Ok(Program { moves, chord_error_mm: 0.0 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_and_bad_ones_are_refused() {
        assert_eq!(BenchKind::parse("five-axis:10000"), Ok((BenchKind::FiveAxis, 10_000)));
        assert_eq!(BenchKind::parse(" three-axis : 7 "), Ok((BenchKind::ThreeAxis, 7)));
        for bad in ["five-axis", "five-axis:0", "five-axis:1000001", "four-axis:5", "five-axis:-3", ""] {
            let e = BenchKind::parse(bad).expect_err(bad);
            assert!(e.contains("five-axis:N"), "{e}");
        }
        assert!(three_axis(MAX_BENCH_MOVES + 1).is_err());
    }

    #[test]
    fn the_raster_has_its_moves_and_the_five_axis_program_follows_its_tips() {
        let pts = raster_points(250);
        assert_eq!(pts.len(), 251);
        // Row 0 runs +x in 0.5 mm steps, then one move of 1 mm in y, then row 1 runs −x.
        assert_eq!(pts[100], DVec3::new(50.0, 0.0, TIP_Z_MM));
        assert_eq!(pts[101], DVec3::new(50.0, 1.0, TIP_Z_MM));
        assert_eq!(pts[102], DVec3::new(SIDE_MM - 0.5, 1.0, TIP_Z_MM));
        let p = five_axis(250).expect("program");
        assert_eq!(p.moves.len(), 250);
        let m = machine();
        for (k, mv) in p.moves.iter().enumerate() {
            let MoveKind::Joints { to, .. } = mv.kind else { panic!("move {k} is not a joint move") };
            let pose = m.pose_from_joints(&to);
            let (tip, ax) = (pose.tip_in_workpiece, pose.axis_in_workpiece);
            assert!((tip - pts[k + 1]).length() < 1e-9, "tip of block {}: {tip} vs {}", k + 1, pts[k + 1]);
            assert!((ax - axis(k + 1)).length() < 1e-9, "axis of block {}", k + 1);
        }
    }
}
