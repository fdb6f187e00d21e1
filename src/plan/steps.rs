//! The time of a five-axis step plan (seed 002's blocks) on its machine: the blocks become
//! straight joint moves, one per segment, and [`super::time_program`] plans them within the
//! per-axis limits of the machine's [`Dynamics`] — so where the rotary axes cannot keep up with
//! the programmed feed, they set the time.
//!
//! How the feed F is meant ([`StepsFeed`]):
//! - [`StepsFeed::Tip`] (the 5-axis tab, `interpolab steps` and `example1`): F is the tool
//!   tip's speed relative to the workpiece, given to each block as an inverse time (G93), as a
//!   CAM post-processor writes five-axis moves for a machine without tool-centre-point
//!   control: block i is programmed to take `L_i / F`, L_i the tip chord between the two
//!   cutter locations (mm). A block whose tip stays put (a pure reorientation, chord below
//!   [`MIN_TIP_CHORD_MM`]) is programmed by its larger rotary move in degrees at F read as
//!   deg/min, as G94 reads a rotary-only move.
//! - [`StepsFeed::Joints`] (`interpolab time --steps`): G94, F along the X Y Z joints' path
//!   (deg/min on a move of the rotary axes alone), as the controller reads a plain five-axis
//!   program without tool-centre-point control.
//!
//! In both, the rotary joints are named by the structure ([`MachineKind::axis_names`]: the
//! tilt is A or B, the other C) and the controller blends the junctions within its contour
//! tolerance as for any program. The machine reaches the first block by a traverse, which is
//! not part of the plan's time. Units: mm, s, degrees in the canonical motions.

use glam::DVec3;
use thiserror::Error;

use super::{Dynamics, PlanError, time_program};
use crate::fiveaxis::{Block, Joints, MachineKind};
use crate::gcode::interp::{Canon, Feed, FeedMode, Loc, Origin, Pose};
use crate::numerics::format::fmt_num;
use crate::numerics::limits::MAX_FEED_MM_PER_MIN;

/// The feed (mm/min) used where a five-axis plan has none of its own: the paper's Example 1
/// and the blade section (a scene's crease uses the scene's `motion.feed`).
pub const DEFAULT_FEED_MM_PER_MIN: f64 = 1000.0;

/// Tip chords shorter than this (mm) count as no tip motion: such a block is programmed by
/// its rotary move ([`StepsFeed::Tip`]).
pub const MIN_TIP_CHORD_MM: f64 = 1e-6;

/// How the feed of a step plan is meant (module docs).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum StepsFeed {
    /// F is the tool tip's speed relative to the workpiece (inverse time per block, G93).
    #[default]
    Tip,
    /// F is along the X Y Z joints' path (G94).
    Joints,
}

/// Why a step plan cannot be timed.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum StepsTimeError {
    /// The feed is not a usable speed.
    #[error(
        "the feed must be more than 0 and at most {} mm/min, got {}; give e.g. {}",
        fmt_num(MAX_FEED_MM_PER_MIN),
        fmt_num(*feed_mm_per_min),
        fmt_num(DEFAULT_FEED_MM_PER_MIN)
    )]
    BadFeed {
        /// The feed given (mm/min).
        feed_mm_per_min: f64,
    },
    /// Fewer than two blocks: nothing moves.
    #[error("a plan of {blocks} block(s) has no segment to time; it needs at least two blocks")]
    TooFewBlocks {
        /// Blocks given.
        blocks: usize,
    },
    /// A block's joints or tip are NaN or infinite.
    #[error("block {block} has a joint value or tool tip that is not finite; the plan cannot be timed")]
    NotFinite {
        /// The block (0-based).
        block: usize,
    },
    /// The planner refused the motions (a bad machine, a plan beyond its caps).
    #[error("{0}")]
    Plan(#[from] PlanError),
}

/// A step plan timed on a machine.
#[derive(Clone, Debug, PartialEq)]
pub struct StepsTime {
    /// The machine's name (its [`Dynamics::name`]).
    pub machine: String,
    /// The feed F (mm/min; deg/min on rotary-only moves).
    pub feed_mm_per_min: f64,
    /// How F is meant.
    pub feed_along: StepsFeed,
    /// The cycle time (s): from rest at the first block to rest at the last, every joint within
    /// its velocity, acceleration and jerk limits (the traverse to the first block left out).
    pub cycle_s: f64,
    /// Time of each segment (s), in order (`blocks − 1` of them; a segment with no motion 0).
    /// A blended junction is split at the middle of its blend.
    pub segment_s: Vec<f64>,
    /// The programmed time Σ L_i / F (s): what the plan takes if every joint could follow the
    /// feed at once (the blends' shortcuts aside), a lower bound up to those shortcuts.
    pub feed_s: f64,
    /// The rotary axes' lower bound (s): for each rotary joint the shortest rest-to-rest move
    /// from its first value to its last within its velocity and acceleration limits; the larger
    /// of the two.
    pub rotary_bound_s: f64,
    /// The tip chords' total length (mm): the programmed tool tip path in the workpiece.
    pub tip_path_mm: f64,
    /// The X Y Z joints' path length (mm; blocks joined by straight lines).
    pub joint_path_mm: f64,
}

/// The dynamics preset of a five-axis structure: the preset named as the kind
/// (`table-ac`, `table-bc`, `head-bc`, `head-a-table-c`; [`Dynamics::preset`]).
#[must_use]
pub fn dynamics_of(kind: MachineKind) -> Dynamics {
    // Every kind has a preset of its name (tested); vmc is a fallback that cannot happen.
    Dynamics::preset(kind.as_str()).or_else(|| Dynamics::preset("vmc")).unwrap_or_else(|| Dynamics {
        name: kind.as_str().to_owned(),
        axes: [super::AxisLimits { velocity: 1000.0, acceleration: 100.0, jerk: None }; 6],
        tolerance_mm: 0.01,
        exact_stop: false,
        window_blocks: None,
        period_ms: 1.0,
    })
}

/// Index (0 A, 1 B, 2 C) of each of the structure's two rotary joints `[tilt, C]`.
#[must_use]
pub fn rotary_indices(kind: MachineKind) -> [usize; 2] {
    kind.axis_names().map(|n| match n {
        "A" => 0,
        "B" => 1,
        _ => 2,
    })
}

/// The canonical pose of joint values: X Y Z (mm) and the two rotary joints (degrees) on the
/// axes the structure names.
#[must_use]
pub fn pose_of(kind: MachineKind, j: &Joints) -> Pose {
    let mut abc = DVec3::ZERO;
    for (k, i) in rotary_indices(kind).into_iter().enumerate() {
        abc[i] = j.rotary_rad[k].to_degrees();
    }
    Pose { xyz: j.xyz_mm, abc }
}

fn check(blocks: &[Block], feed_mm_per_min: f64) -> Result<(), StepsTimeError> {
    if !(feed_mm_per_min > 0.0 && feed_mm_per_min <= MAX_FEED_MM_PER_MIN) {
        return Err(StepsTimeError::BadFeed { feed_mm_per_min });
    }
    if blocks.len() < 2 {
        return Err(StepsTimeError::TooFewBlocks { blocks: blocks.len() });
    }
    if let Some(i) = blocks.iter().position(|b| {
        !(b.joints.xyz_mm.is_finite()
            && b.joints.rotary_rad.iter().all(|r| r.is_finite())
            && b.location.tip.is_finite())
    }) {
        return Err(StepsTimeError::NotFinite { block: i });
    }
    Ok(())
}

/// The programmed length of segment `a → b` (mm; degrees on a pure reorientation) and whether
/// it is a tip length.
fn programmed_len(a: &Block, b: &Block, along: StepsFeed) -> f64 {
    let xyz = (b.joints.xyz_mm - a.joints.xyz_mm).length();
    let rot = (0..2).map(|k| (b.joints.rotary_rad[k] - a.joints.rotary_rad[k]).abs().to_degrees()).fold(0.0, f64::max);
    let main = match along {
        StepsFeed::Tip => (b.location.tip - a.location.tip).length(),
        StepsFeed::Joints => xyz,
    };
    if main >= MIN_TIP_CHORD_MM { main } else { rot }
}

/// The joint program of a step plan: a traverse to the first block, then one straight joint
/// move per segment (line numbers: block i is line i + 1) at feed F as `along` means it.
///
/// # Errors
/// [`StepsTimeError`]: a feed outside (0, 10⁶] mm/min, fewer than two blocks, a value that
/// is not finite.
pub fn steps_canon(
    kind: MachineKind,
    blocks: &[Block],
    feed_mm_per_min: f64,
    along: StepsFeed,
) -> Result<Vec<Canon>, StepsTimeError> {
    check(blocks, feed_mm_per_min)?;
    let per_minute = Feed { mode: FeedMode::PerMinute, rate: feed_mm_per_min, spindle_rpm: 0.0 };
    let mut out = Vec::with_capacity(blocks.len());
    for (i, b) in blocks.iter().enumerate() {
        let loc = Loc::main(u32::try_from(i + 1).unwrap_or(u32::MAX));
        let end = pose_of(kind, &b.joints);
        if i == 0 {
            out.push(Canon::Traverse { loc, end, origin: Origin::Programmed });
            continue;
        }
        let feed = match along {
            StepsFeed::Joints => per_minute,
            StepsFeed::Tip => {
                let len = programmed_len(&blocks[i - 1], b, along);
                if len >= MIN_TIP_CHORD_MM {
                    // The block takes len / F minutes: inverse time F / len (1/min).
                    Feed { mode: FeedMode::InverseTime, rate: feed_mm_per_min / len, spindle_rpm: 0.0 }
                } else {
                    per_minute
                }
            }
        };
        out.push(Canon::Line { loc, end, feed, origin: Origin::Programmed });
    }
    Ok(out)
}

/// The shortest rest-to-rest time (s) of a move of length `d` with speed limit `v` and
/// acceleration limit `a` (a trapezoid, or a triangle when the move is too short to reach v).
#[must_use]
pub fn rest_to_rest_s(d: f64, v: f64, a: f64) -> f64 {
    let d = d.abs();
    if d * a >= v * v { d / v + v / a } else { 2.0 * (d / a).sqrt() }
}

/// Times a step plan's blocks on a machine at feed F (mm/min) meant as `along`.
///
/// # Errors
/// [`StepsTimeError`]: a bad feed, fewer than two blocks, a value that is not finite, or the
/// planner's refusal (a bad machine).
pub fn time_steps(
    kind: MachineKind,
    blocks: &[Block],
    feed_mm_per_min: f64,
    along: StepsFeed,
    machine: &Dynamics,
) -> Result<StepsTime, StepsTimeError> {
    let canon = steps_canon(kind, blocks, feed_mm_per_min, along)?;
    let timing = time_program(canon, machine)?;
    let mut segment_s = vec![0.0; blocks.len() - 1];
    for (b, t) in timing.path.blocks.iter().zip(&timing.block_time_s) {
        // Line i + 1 ends block i: segment i − 1.
        if !b.rapid
            && let Some(s) = (b.line as usize).checked_sub(2).and_then(|k| segment_s.get_mut(k))
        {
            *s += t;
        }
    }
    let cycle_s = timing.feed_rapid_s().0;
    let f = feed_mm_per_min / 60.0;
    let mut feed_s = 0.0;
    let mut tip_path_mm = 0.0;
    let mut joint_path_mm = 0.0;
    for w in blocks.windows(2) {
        feed_s += programmed_len(&w[0], &w[1], along) / f;
        tip_path_mm += (w[1].location.tip - w[0].location.tip).length();
        joint_path_mm += (w[1].joints.xyz_mm - w[0].joints.xyz_mm).length();
    }
    let limits = machine.joint_limits();
    let (first, last) = (&blocks[0].joints, &blocks[blocks.len() - 1].joints);
    let rotary_bound_s = rotary_indices(kind)
        .into_iter()
        .enumerate()
        .map(|(k, i)| rest_to_rest_s(last.rotary_rad[k] - first.rotary_rad[k], limits.v[3 + i], limits.a[3 + i]))
        .fold(0.0, f64::max);
    Ok(StepsTime {
        machine: machine.name.clone(),
        feed_mm_per_min,
        feed_along: along,
        cycle_s,
        segment_s,
        feed_s,
        rotary_bound_s,
        tip_path_mm,
        joint_path_mm,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_structure_has_its_preset() {
        for k in MachineKind::ALL {
            assert_eq!(dynamics_of(k).name, k.as_str());
        }
    }

    #[test]
    fn the_rest_to_rest_time_is_continuous_where_the_triangle_becomes_a_trapezoid() {
        let (v, a) = (2.0, 4.0);
        let d = v * v / a;
        assert!((rest_to_rest_s(d * (1.0 - 1e-12), v, a) - rest_to_rest_s(d, v, a)).abs() < 1e-9);
        assert!((rest_to_rest_s(d, v, a) - 2.0 * v / a).abs() < 1e-12);
    }
}
