//! Programs the simulation runs: straight 3-axis moves of the tool tip (G00/G01, and the
//! chords of G02/G03 arcs and G06.2 curves) and 5-axis moves between two joint vectors of a
//! seed-002 machine.
//!
//! # Chords of arcs and NURBS
//!
//! A curved move is cut as chords whose distance from the curve is at most the *chord
//! tolerance* e (default a tenth of the pitch, [`DEFAULT_CHORD_FRACTION`]): the swept
//! envelope of the chords lies within e of the exact one (Hausdorff distance). For an arc
//! or helix of radius ρ the in-plane sagitta ρ(1 − cos(Δθ/2)) is the exact chord error
//! (the helix' normal motion is linear in the angle, as along the chord), so
//! Δθ = 2·acos(1 − e/ρ). For a NURBS span the chord error of a parameter step Δu is at most
//! Δu²·max|C''|/8; max|C''| is estimated from 9 samples per span and raised by half, and
//! the deviation of each chord's midpoint from the curve is measured and reported
//! ([`Program::chord_error_mm`]).

use glam::DVec3;

use super::SimError;
use crate::fiveaxis::{Block, Joints, Machine};
use crate::gcode::{Motion, Segment, Toolpath};
use crate::geom::NurbsCurve;

/// Default chord tolerance as a fraction of the pitch.
pub const DEFAULT_CHORD_FRACTION: f64 = 0.1;

/// Largest number of moves (after arcs and NURBS are cut into chords) a program may have.
pub const MAX_MOVES: usize = 2_000_000;

/// Most chords one arc or NURBS move may become; a tighter chord tolerance is refused.
pub const MAX_CHORDS_PER_MOVE: usize = 100_000;

/// What a move does geometrically.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MoveKind {
    /// The tool tip moves straight from `from` to `to` (mm), the tool axis stays +Z.
    Line {
        /// Start tip (mm).
        from: DVec3,
        /// End tip (mm).
        to: DVec3,
    },
    /// A 5-axis move: the machine's joints run linearly from `from` to `to`; the tool pose
    /// comes from the machine's forward kinematics.
    Joints {
        /// The machine.
        machine: Machine,
        /// Start joints.
        from: Joints,
        /// End joints.
        to: Joints,
    },
}

/// One move of a program.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SimMove {
    /// Geometry.
    pub kind: MoveKind,
    /// 1-based line of the program it comes from (0 for in-memory programs).
    pub line: usize,
    /// Whether it is a rapid (G00): rapids are simulated too, and one that removes material
    /// is reported.
    pub rapid: bool,
}

/// A program ready to simulate.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Program {
    /// The moves in order.
    pub moves: Vec<SimMove>,
    /// Largest measured distance (mm) of a chord's midpoint from its arc or NURBS curve; 0
    /// when the program has none.
    pub chord_error_mm: f64,
}

impl Program {
    /// The moves of a G-code tool path, each point shifted by `tip_offset` to give the tool
    /// tip (e.g. (0, 0, −R) for a program of ball centres), arcs and NURBS cut into chords
    /// within `chord_tol_mm`.
    ///
    /// # Errors
    /// [`SimError::Program`] for a chord tolerance that is not a positive length, a curve
    /// needing more than [`MAX_CHORDS_PER_MOVE`] chords, or more than [`MAX_MOVES`] moves.
    pub fn from_toolpath(path: &Toolpath, tip_offset: DVec3, chord_tol_mm: f64) -> Result<Self, SimError> {
        if !(chord_tol_mm > 0.0 && chord_tol_mm.is_finite()) {
            return Err(SimError::Program(format!(
                "the chord tolerance must be a positive length in mm, got {chord_tol_mm}"
            )));
        }
        let mut out = Self::default();
        // Before its first move a program's position is unknown (the reader starts at the
        // origin): a leading rapid only brings the tool to its first point, and is skipped.
        let skip = usize::from(path.blocks.first().is_some_and(|b| b.motion == Motion::Rapid));
        let moves = count_moves(&path.blocks[skip..], chord_tol_mm)?;
        out.moves.reserve_exact(moves);
        for b in &path.blocks[skip..] {
            let rapid = b.motion == Motion::Rapid;
            let points = out.segment_points(&b.segment, b.line, chord_tol_mm)?;
            for w in points.windows(2) {
                out.push(SimMove {
                    kind: MoveKind::Line { from: w[0] + tip_offset, to: w[1] + tip_offset },
                    line: b.line,
                    rapid,
                })?;
            }
        }
        Ok(out)
    }

    /// The 5-axis moves between consecutive blocks of a seed-002 plan (e.g. the nodes of
    /// [`crate::fiveaxis::plan_steps`]), joints interpolated linearly on `machine`.
    ///
    /// # Errors
    /// [`SimError::Program`] above [`MAX_MOVES`] moves.
    pub fn from_blocks(machine: &Machine, blocks: &[Block]) -> Result<Self, SimError> {
        let mut out = Self::default();
        for w in blocks.windows(2) {
            out.push(SimMove {
                kind: MoveKind::Joints { machine: *machine, from: w[0].joints, to: w[1].joints },
                line: 0,
                rapid: false,
            })?;
        }
        Ok(out)
    }

    /// Appends a move.
    ///
    /// # Errors
    /// [`SimError::Program`] above [`MAX_MOVES`] moves.
    pub fn push(&mut self, m: SimMove) -> Result<(), SimError> {
        if self.moves.len() >= MAX_MOVES {
            return Err(too_many_moves());
        }
        self.moves.push(m);
        Ok(())
    }

    /// The points of a path segment's chords (its two ends for a line), arcs and NURBS cut
    /// within `chord_tol_mm` (module docs); the chord error measured is kept in
    /// [`Self::chord_error_mm`].
    ///
    /// # Errors
    /// [`SimError::Program`] for a curve needing more than [`MAX_CHORDS_PER_MOVE`] chords.
    pub(crate) fn segment_points(
        &mut self,
        segment: &Segment,
        line: usize,
        chord_tol_mm: f64,
    ) -> Result<Vec<DVec3>, SimError> {
        Ok(match segment {
            Segment::Line(l) => vec![l.start, l.end],
            Segment::Arc(a) => {
                let n = arc_chords(a, chord_tol_mm, line)?;
                let c = segment.curve();
                let pts: Vec<DVec3> = (0..=n).map(|i| c.point_at(i as f64 / n as f64)).collect();
                self.measure(&pts, |k| c.point_at((k as f64 + 0.5) / n as f64));
                pts
            }
            Segment::Nurbs(c) => {
                let params = nurbs_params(c, chord_tol_mm, line)?;
                let pts: Vec<DVec3> = params.iter().map(|&u| c.point_at(u)).collect();
                self.measure(&pts, |k| c.point_at(0.5 * (params[k] + params[k + 1])));
                pts
            }
        })
    }

    /// Raises [`Self::chord_error_mm`] to a deviation measured elsewhere (mm).
    pub(crate) fn note_chord_error(&mut self, mm: f64) {
        self.chord_error_mm = self.chord_error_mm.max(mm);
    }

    fn measure(&mut self, pts: &[DVec3], mid: impl Fn(usize) -> DVec3) {
        for k in 0..pts.len().saturating_sub(1) {
            let d = crate::numerics::measure::distance_to_segment(mid(k), pts[k], pts[k + 1]);
            self.chord_error_mm = self.chord_error_mm.max(d);
        }
    }
}

/// The moves [`Program::from_toolpath`] makes of `blocks`, counted before any is made, so a
/// program that makes too many is refused without building (and holding) the moves first:
/// the same error at the same block — a curve's own chord cap, or [`MAX_MOVES`] passed
/// within this block — as the moves made one by one would give.
fn count_moves(blocks: &[crate::gcode::PathBlock], chord_tol_mm: f64) -> Result<usize, SimError> {
    let mut total = 0usize;
    for b in blocks {
        let n = match &b.segment {
            Segment::Line(_) => 1,
            Segment::Arc(a) => arc_chords(a, chord_tol_mm, b.line)?,
            Segment::Nurbs(c) => nurbs_params(c, chord_tol_mm, b.line)?.len() - 1,
        };
        if total + n > MAX_MOVES {
            return Err(too_many_moves());
        }
        total += n;
    }
    Ok(total)
}

fn too_many_moves() -> SimError {
    SimError::Program(format!(
        "the program has more than {MAX_MOVES} moves (after cutting arcs and NURBS into chords); raise the chord tolerance or split the program"
    ))
}

/// The chords of an arc or helix of radius ρ: steps of Δθ = 2·acos(1 − e/ρ) (module docs).
fn arc_chords(a: &crate::gcode::ArcMove, chord_tol_mm: f64, line: usize) -> Result<usize, SimError> {
    let rho = a.radius_start().max(a.radius_end());
    let sweep = a.sweep().abs();
    let step = if chord_tol_mm >= rho { sweep } else { 2.0 * (1.0 - chord_tol_mm / rho).acos() };
    chord_count(sweep / step, line)
}

fn chord_count(x: f64, line: usize) -> Result<usize, SimError> {
    let n = x.ceil().max(1.0);
    if !(n <= MAX_CHORDS_PER_MOVE as f64) {
        return Err(SimError::Program(format!(
            "line {line}: the curve needs more than {MAX_CHORDS_PER_MOVE} chords at this chord tolerance; raise the pitch or the chord tolerance"
        )));
    }
    // A whole number in [1, MAX_CHORDS_PER_MOVE].
    Ok(n as usize)
}

/// Parameters of the chords of a NURBS curve: per knot span, equal steps with
/// Δu²·max|C''|/8 ≤ e (max|C''| from 9 samples, raised by half).
fn nurbs_params(c: &NurbsCurve, tol: f64, line: usize) -> Result<Vec<f64>, SimError> {
    let p = c.degree();
    let k = c.knots();
    let mut breaks: Vec<f64> = Vec::new();
    for &x in &k[p..k.len() - p] {
        if breaks.last().is_none_or(|&l| x > l) {
            breaks.push(x);
        }
    }
    let mut out = vec![breaks.first().copied().unwrap_or(0.0)];
    for w in breaks.windows(2) {
        let (u0, u1) = (w[0], w[1]);
        let d2 = (0..=8).map(|i| c.derivatives_at(u0 + (u1 - u0) * f64::from(i) / 8.0)[2].length()).fold(0.0, f64::max)
            * 1.5;
        let du = if d2 > 0.0 { (8.0 * tol / d2).sqrt() } else { u1 - u0 };
        let n = chord_count((u1 - u0) / du, line)?;
        if out.len() + n > MAX_CHORDS_PER_MOVE {
            return Err(SimError::Program(format!(
                "line {line}: the curve needs more than {MAX_CHORDS_PER_MOVE} chords at this chord tolerance; raise the pitch or the chord tolerance"
            )));
        }
        for i in 1..=n {
            out.push(u0 + (u1 - u0) * i as f64 / n as f64);
        }
    }
    Ok(out)
}
