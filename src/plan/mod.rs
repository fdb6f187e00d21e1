//! Feed planning: interpolation as a real controller does it — the machine's joint limits,
//! corners blended within the contour tolerance, look-ahead, jerk-limited (S-curve) feed,
//! positions every period, and the time a program takes.
//!
//! The pipeline is one function over one request ([`time_program`]): canonical motions
//! ([`crate::gcode::interp::Canon`], all six axes) → a joint-space [`path::Path`] (lines,
//! arcs, NURBS, blends; pieces with derivative bounds) → a [`feed::FeedPlan`] (phases of
//! constant jerk along the path) → [`sample::Sampler`] (periods) and block times. The
//! checker [`check::LimitChecker`] reads only periods and limits. [`steps`] times seed 002's
//! five-axis step plans through their machine's joints.
//!
//! Units inside: mm, s, rad (joints A B C), the path parameter s in mm of tool-tip travel
//! (degrees on moves of the rotary axes alone). Machine files and scenes give mm/min and
//! degrees ([`machine`]). Method, bounds and measurements: docs/feed-planning.md.

pub mod check;
pub mod feed;
pub mod machine;
pub mod path;
pub mod sample;
pub mod scurve;
pub mod steps;

use thiserror::Error;

use crate::gcode::interp::{Canon, Feed, FeedMode, Loc, Origin, Pose};
use crate::gcode::path::{Motion, Segment, Toolpath};

pub use check::{LimitChecker, LimitReport};
pub use feed::{FeedOptions, FeedPlan};
pub use machine::{AxisLimits, Dynamics, JointLimits, MachineError, PRESETS};
pub use path::{JunctionRules, Path};
pub use sample::{Period, Sampler};
pub use steps::{StepsFeed, StepsTime, StepsTimeError, time_steps};

/// Why a program cannot be planned.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum PlanError {
    /// A feed move without a usable feed rate.
    #[error(
        "line {line}: a feed move without a feed rate (F0, or G95 with the spindle stopped); give F in mm/min on this or an earlier line"
    )]
    NoFeed {
        /// Source line.
        line: u32,
    },
    /// The path passes [`path::MAX_PIECES`] pieces at this line.
    #[error(
        "line {line}: the program is too large to plan whole: more than {max} pieces up to here (a piece is a line, 5° of an arc or curve, 15° of a blended corner); split it"
    )]
    TooLarge {
        /// Source line of the move that passes the cap.
        line: u32,
        /// The cap (pieces).
        max: usize,
    },
    /// A bad machine value.
    #[error("{0}")]
    Machine(#[from] MachineError),
}

/// Why a program read as it is planned was not timed: its reader stopped (an interpreter's
/// error, or a job cancelled), or the planner refused it.
#[derive(Clone, Debug, PartialEq)]
pub enum Stopped<E> {
    /// The reader's error.
    Read(E),
    /// The planner's.
    Plan(PlanError),
}

impl<E> From<PlanError> for Stopped<E> {
    fn from(e: PlanError) -> Self {
        Self::Plan(e)
    }
}

/// A program timed on a machine.
#[derive(Clone, Debug)]
pub struct Timing {
    /// The path followed (blends included).
    pub path: Path,
    /// The feed plan.
    pub plan: FeedPlan,
    /// The machine.
    pub machine: Dynamics,
    /// Time per block (s; dwell after the block included), in block order.
    pub block_time_s: Vec<f64>,
}

impl Timing {
    /// Total time (s).
    #[must_use]
    pub fn total_s(&self) -> f64 {
        self.plan.duration
    }

    /// Time in feed moves and in rapids (s).
    #[must_use]
    pub fn feed_rapid_s(&self) -> (f64, f64) {
        let mut f = 0.0;
        let mut r = 0.0;
        for (b, t) in self.path.blocks.iter().zip(&self.block_time_s) {
            if b.rapid {
                r += t;
            } else {
                f += t;
            }
        }
        (f - self.path.dwell_s, r)
    }

    /// The periods of the plan.
    #[must_use]
    pub fn sampler(&self) -> Sampler<'_> {
        Sampler::new(&self.path, &self.plan, self.machine.period_s())
    }
}

/// Plans canonical motions on a machine.
///
/// # Errors
/// [`PlanError`]: a bad machine, a feed move without a feed, a program beyond the caps.
pub fn time_program<I>(canon: I, machine: &Dynamics) -> Result<Timing, PlanError>
where
    I: IntoIterator<Item = Canon>,
{
    time_read(canon.into_iter().map(Ok::<Canon, std::convert::Infallible>), machine).map_err(|e| match e {
        Stopped::Plan(e) => e,
        Stopped::Read(never) => match never {},
    })
}

/// As [`time_program`], over motions read as they are planned (an interpreter streaming a
/// file): the motions are never held as a list, and the first read error stops the work.
///
/// # Errors
/// [`Stopped::Read`] with the reader's error; [`Stopped::Plan`] as [`time_program`].
pub fn time_read<I, E>(canon: I, machine: &Dynamics) -> Result<Timing, Stopped<E>>
where
    I: IntoIterator<Item = Result<Canon, E>>,
{
    machine.validate().map_err(PlanError::from)?;
    let limits = machine.joint_limits();
    let rules = JunctionRules {
        tol_mm: machine.tolerance_mm,
        exact_stop: machine.exact_stop,
        jerk_limited: !limits.jerk_free(),
    };
    let path = path::build_read(canon, &rules)?;
    let plan = feed::plan(&path, &FeedOptions { limits, window: machine.window_blocks, tangent_share: 0.5 });
    let block_time_s = block_times(&path, &plan);
    Ok(Timing { path, plan, machine: machine.clone(), block_time_s })
}

/// The time (s) within phase `p` at which the path position reaches `s` (s ≥ p.s0, within
/// the phase): Newton on the cubic s(t), kept in a bracket.
fn time_in(p: &feed::TimedPhase, s: f64) -> f64 {
    let (mut lo, mut hi) = (p.t0, p.t0 + p.phase.dur);
    let mut t = if p.v0 > 0.0 { (p.t0 + (s - p.s0) / p.v0).clamp(lo, hi) } else { 0.5 * (lo + hi) };
    for _ in 0..60 {
        let (st, vt, _) = p.at(t);
        if st < s {
            lo = t;
        } else {
            hi = t;
        }
        let next = if vt > 0.0 { t - (st - s) / vt } else { f64::NAN };
        let next = if next > lo && next < hi { next } else { 0.5 * (lo + hi) };
        if (next - t).abs() <= crate::numerics::tolerance::NEWTON_STEP_REL * (1.0 + t.abs())
            || hi - lo <= crate::numerics::tolerance::NEWTON_STEP_REL * (1.0 + t.abs())
        {
            return next;
        }
        t = next;
    }
    t
}

/// Block times by one sweep over blocks and phases (both in order of s).
fn block_times(path: &Path, plan: &FeedPlan) -> Vec<f64> {
    let n = path.blocks.len();
    let ph = &plan.phases;
    let mut starts = Vec::with_capacity(n);
    let mut i = 0usize;
    for (b, blk) in path.blocks.iter().enumerate() {
        if b == 0 {
            starts.push(0.0);
            continue;
        }
        let s = blk.s_start;
        // The first phase whose end lies beyond s (a dwell's end does not: it stays).
        while i < ph.len() && ph[i].at(ph[i].t0 + ph[i].phase.dur).0 <= s {
            i += 1;
        }
        starts.push(match ph.get(i) {
            None => plan.duration,
            Some(p) if p.s0 >= s => p.t0,
            Some(p) => time_in(p, s),
        });
    }
    (0..n).map(|i| if i + 1 < n { starts[i + 1] - starts[i] } else { plan.duration - starts[i] }).collect()
}

/// The canonical motions of a toolpath (a program read by any dialect's reader): G00
/// traverses, G01 lines, G02/G03 arcs and NURBS curves at their feeds (mm/min); the rotary
/// axes at zero.
#[must_use]
pub fn canon_of_toolpath(tp: &Toolpath) -> Vec<Canon> {
    let mut out = Vec::with_capacity(tp.blocks.len());
    let mut pos = None;
    for b in &tp.blocks {
        let loc = Loc::main(u32::try_from(b.line).unwrap_or(u32::MAX));
        let start = b.segment.start();
        if pos.is_some_and(|p: glam::DVec3| (p - start).length() > path::MIN_MOVE)
            || (pos.is_none() && start.length() > 0.0)
        {
            // The reader's path jumps (it should not): join with a traverse.
            out.push(Canon::Traverse { loc, end: Pose::at(start), origin: Origin::Programmed });
        }
        let feed = Feed { mode: FeedMode::PerMinute, rate: b.feed_mm_per_min.unwrap_or(0.0), spindle_rpm: 0.0 };
        let end = Pose::at(b.segment.end());
        out.push(match (&b.segment, b.motion) {
            (_, Motion::Rapid) => Canon::Traverse { loc, end, origin: Origin::Programmed },
            (Segment::Line(_), _) => Canon::Line { loc, end, feed, origin: Origin::Programmed },
            (Segment::Arc(a), _) => Canon::Arc {
                loc,
                end,
                center: a.center,
                plane: a.plane,
                turns: if a.ccw { 1 } else { -1 },
                feed,
                origin: Origin::Programmed,
            },
            (Segment::Nurbs(c), _) => Canon::Spline { loc, curve: Box::new(c.clone()), end, feed },
        });
        pos = Some(b.segment.end());
    }
    out
}
