//! Seed 000 (Zhou, Zhou, Zhou & Zhou, 1994): interpolating the cutter-centre path of a
//! ball-end mill along the *crease* where two surfaces meet, one period at a time.
//!
//! Glossary:
//! - *crease*: the curve where the two offset surfaces `S_i + R'·n_i` meet — the path of the
//!   centre of a ball of radius R' = R + C touching both surfaces;
//! - *period*: one interpolation period Ts; per period the centre advances by the *feed per
//!   period* f = F·Ts (eq. 2);
//! - *contact points* q1, q2 with parameters (u_i, v_i): where the ball touches S1, S2;
//! - *interpolation error* e_i: in the paper, the signed distance from the centre to S_i
//!   minus R' (negative: the ball cuts into S_i; positive: stock is left). The core's
//!   [`Diagnostics::measured`] is its negative, overcut positive as everywhere in the core
//!   ([`crate::numerics::sign`]); the printed `e1`, `e2` keep the paper's sign.
//!
//! Modules: [`newton`] finds exact crease points (start, end, the precise mode, the
//! truth the interpolator is measured against); [`interpolator`] is the per-period stepper
//! of the paper (track, correct, re-solve contacts) and the precise stepper; [`estimate`]
//! measures errors and evaluates the paper's estimates (11), (12) and (16).

pub mod curve;
pub mod estimate;
pub mod interpolator;
pub mod newton;

use std::fmt;

use glam::{DVec2, DVec3};
use thiserror::Error;

use crate::geom::{ParametricSurface, Surface};

pub use curve::{CreaseCurve, CreaseFrame};
pub use estimate::{Diagnostics, WorstError, diagnose, measured_errors};
pub use interpolator::{InterpOptions, Interpolator, Method, RunResult, Step, run_to_end};
pub use newton::{CreasePoint, NewtonOptions, crease_deviation, locate_crease_point};

/// Everything the crease interpolator needs, in internal units (mm, s, rad).
#[derive(Clone, Debug, PartialEq)]
pub struct CreaseJob {
    /// S1 and S2.
    pub surfaces: [Surface; 2],
    /// Ball radius R (mm).
    pub ball_radius_mm: f64,
    /// Effective radius R' = R + C: the centre's offset from both surfaces (mm).
    pub r_eff_mm: f64,
    /// Programmed feed F (mm/s; the scene gives mm/min, converted by
    /// [`crate::numerics::units`]).
    pub feed_mm_per_s: f64,
    /// Interpolation period Ts (s; the scene gives ms).
    pub period_s: f64,
    /// Feed per period f = F·Ts (mm), formed once from the scene's numbers
    /// ([`crate::numerics::units::mm_per_period`]) so every output keeps its last digit.
    pub feed_per_period_mm: f64,
    /// Tolerances T1, T2 (mm).
    pub tol_mm: [f64; 2],
    /// Share b of the tolerance given to interpolation.
    pub share: f64,
    /// Approximate start (mm).
    pub start: DVec3,
    /// Approximate end (mm), or run until closed / out of domain / `max_steps`.
    pub end: Option<DVec3>,
    /// Sense of travel at the start, or the sense of n1 × n2.
    pub direction: Option<DVec3>,
    /// Most periods to run.
    pub max_steps: u64,
}

impl CreaseJob {
    /// The interpolation's error budget on surface i, b·T_i (mm).
    #[must_use]
    pub fn allowed_error_mm(&self, i: usize) -> f64 {
        self.share * self.tol_mm[i]
    }

    /// Parameters of a row in file units (degrees for angles).
    #[must_use]
    pub fn params_to_file(&self, uv: [DVec2; 2]) -> [DVec2; 2] {
        [self.surfaces[0].domain().to_file(uv[0]), self.surfaces[1].domain().to_file(uv[1])]
    }
}

/// One interpolation period's output: the cutter centre and both contact parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Row {
    /// Period index, 0 for the corrected start point.
    pub k: u64,
    /// Time k·Ts (s); the final row of a run that ends on an exact point is shorter than a
    /// period (its time is the previous row's plus its chord at the feed).
    pub t_s: f64,
    /// Cutter centre (mm).
    pub p: DVec3,
    /// Contact parameters on S1 and S2 (internal units: rad for angles).
    pub uv: [DVec2; 2],
}

/// Where on the path something happened, for messages.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Location {
    /// While bringing `path.start` onto the crease.
    Start,
    /// While bringing `path.end` onto the crease.
    End,
    /// In the period that would produce row `k`.
    Period {
        /// Row index.
        k: u64,
        /// Its time (s).
        t_s: f64,
    },
}

/// Nanoseconds per millisecond: the resolution of a time printed in a message.
const MESSAGE_MS_PER_NS: f64 = 1e6;

impl fmt::Display for Location {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Start => write!(f, "path.start"),
            Self::End => write!(f, "path.end"),
            // Printed in ms, the scene's unit, rounded to 1 ns: k·Ts computed in seconds and
            // shown in ms would otherwise carry a last-bit tail (12.000000000000002 ms).
            Self::Period { k, t_s } => {
                let ms = (crate::numerics::units::ms_from_s(*t_s) * MESSAGE_MS_PER_NS).round() / MESSAGE_MS_PER_NS;
                write!(f, "period {k} (t = {} ms)", crate::numerics::format::fmt_num(ms))
            }
        }
    }
}

/// Why a run ended normally.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StopReason {
    /// Stopped at the row nearest `path.end`.
    ReachedEnd,
    /// A closed crease came back to its start the requested number of times.
    Closed {
        /// Full turns made.
        turns: u32,
    },
    /// The next contact point on a surface would leave its parameter domain.
    LeftDomain {
        /// 0 for S1, 1 for S2.
        surface: usize,
        /// `'u'` or `'v'`.
        param: char,
        /// The value it would have had (file units).
        value: f64,
        /// The domain's range (file units).
        range: [f64; 2],
    },
    /// `path.max_steps` periods were run.
    MaxSteps,
}

impl StopReason {
    /// Short machine-readable tag (`reached_end`, `closed`, `left_domain`, `max_steps`).
    #[must_use]
    pub fn tag(&self) -> &'static str {
        match self {
            Self::ReachedEnd => "reached_end",
            Self::Closed { .. } => "closed",
            Self::LeftDomain { .. } => "left_domain",
            Self::MaxSteps => "max_steps",
        }
    }
}

impl fmt::Display for StopReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::ReachedEnd => write!(f, "reached the point nearest path.end"),
            Self::Closed { turns: 1 } => {
                write!(f, "the crease closed on itself after one full turn")
            }
            Self::Closed { turns } => write!(f, "the crease closed on itself; {turns} turns made"),
            Self::LeftDomain { surface, param, value, range } => write!(
                f,
                "the contact point on surface {} would leave its domain ({param} = {} outside [{}, {}])",
                surface + 1,
                // Display range of a parameter in a message (fixed decimals inside it, an
                // exponent outside), not a tolerance.
                if (1e-4..1e9).contains(&value.abs()) {
                    format!("{value:.6}")
                } else {
                    crate::numerics::format::fmt_num(*value)
                },
                crate::numerics::format::fmt_num(range[0]),
                crate::numerics::format::fmt_num(range[1])
            ),
            Self::MaxSteps => write!(f, "path.max_steps periods were run"),
        }
    }
}

/// A run that stopped short of `path.end`: how far it was left, and whether the run went
/// the other way (the sense of n1 × n2, or the `path.direction` given, pointed away from the
/// end). Its `Display` is a note for the user naming what to change.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EndNotReached {
    /// Distance from the last centre point to `path.end` (mm).
    pub distance_mm: f64,
    /// Unit sense of travel at the start; `Some` when it pointed away from `path.end`.
    pub away_from_end: Option<DVec3>,
    /// Why the run stopped.
    pub reason: StopReason,
    /// Whether the scene's `path.direction` chose the sense (otherwise n1 × n2 did).
    pub direction_given: bool,
}

impl EndNotReached {
    /// Whether `reason` left `job.end` unreached, given the run's first centre point `first`
    /// (mm), its unit sense of travel there `sense`, and its last centre point `last` (mm).
    /// `None` when the scene has no end, the run reached or closed, or the last point is
    /// within two feeds per period of the end.
    #[must_use]
    pub fn check(job: &CreaseJob, reason: &StopReason, first: DVec3, sense: DVec3, last: DVec3) -> Option<Self> {
        let end = job.end?;
        if matches!(reason, StopReason::ReachedEnd | StopReason::Closed { .. }) {
            return None;
        }
        let distance_mm = (last - end).length();
        if distance_mm <= 2.0 * job.feed_per_period_mm {
            return None;
        }
        let away = (end - first).dot(sense) < 0.0;
        Some(Self {
            distance_mm,
            away_from_end: away.then_some(sense),
            reason: *reason,
            direction_given: job.direction.is_some(),
        })
    }
}

/// The `path.direction` that runs against the unit sense `sense`, rounded to 1e-6 (and −0
/// to 0) so a scene file reads cleanly.
#[must_use]
pub fn reversed_direction(sense: DVec3) -> [f64; 3] {
    (-sense).to_array().map(|x| (x * 1e6).round() / 1e6 + 0.0)
}

impl fmt::Display for EndNotReached {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "path.end was not reached ({:.3} mm from the last point)", self.distance_mm)?;
        match self.away_from_end {
            Some(s) => {
                let [x, y, z] = reversed_direction(s).map(|x| if x.abs() < 5e-4 { 0.0 } else { x });
                write!(
                    f,
                    ": the run followed the crease in the sense of {}, away from path.end; to run toward it set path.direction to [{:.3}, {:.3}, {:.3}]",
                    if self.direction_given { "path.direction" } else { "n1 × n2" },
                    x,
                    y,
                    z
                )
            }
            None if self.reason == StopReason::MaxSteps => {
                write!(f, "; raise path.max_steps to run further")
            }
            None => write!(
                f,
                "; it lies beyond where the run stopped, or on another branch of the intersection: move path.end onto this crease within both surfaces' domains"
            ),
        }
    }
}

/// A length for a message: four decimals, or three significant digits when tiny or huge
/// (below 1e-4 or from 1e6 mm: display ranges, not tolerances).
fn fmt_mm(x: f64) -> String {
    if x != 0.0 && !(1e-4..1e6).contains(&x.abs()) { format!("{x:.3e}") } else { format!("{x:.4}") }
}

fn fmt_correction(x: f64) -> String {
    if x.is_finite() { format!("{} mm", fmt_mm(x)) } else { "without bound".to_owned() }
}

/// Why the crease could not be started or continued. Every message names the problem,
/// where it arose and what to change.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum CreaseError {
    /// Newton could not bring a point onto the crease.
    #[error(
        "no crease near {at} ({detail}); move {at} to where the two surfaces meet (within a few mm), and check that the cutter is on the normal side of both surfaces"
    )]
    NoCrease {
        /// `path.start` or `path.end`.
        at: Location,
        /// What Newton saw.
        detail: String,
    },
    /// The surfaces touch tangentially: n1 × n2 vanishes.
    #[error(
        "at {at} the surfaces touch tangentially (angle between their normals {angle_deg:.3}°, below {min_deg}°): the crease is not defined there; end the path before this point (path.end) or change the surfaces so they meet at an angle"
    )]
    Tangential {
        /// Where.
        at: Location,
        /// Angle between the normals (deg).
        angle_deg: f64,
        /// The limit (deg).
        min_deg: f64,
    },
    /// A concave curvature radius smaller than R': the offset surface folds.
    #[error("at {at} surface {} is concave with radius {radius_mm:.4} mm, not larger than the cutter radius R' = {r_eff_mm} mm (1 − k·R' ≤ 0): the ball would gouge; use a tool.radius below {radius_mm:.4} mm or a surface with a larger fillet", surface + 1)]
    Fold {
        /// Where.
        at: Location,
        /// 0 for S1, 1 for S2.
        surface: usize,
        /// Smallest concave radius of curvature there (mm).
        radius_mm: f64,
        /// R' (mm).
        r_eff_mm: f64,
    },
    /// The parametrisation is singular at a contact point (sphere pole, collapsed edge).
    #[error("at {at} the contact point on surface {} is a singular point of its parametrisation (e.g. a sphere's pole), where no normal is defined; turn the surface's axis so the path does not cross it", surface + 1)]
    Singular {
        /// Where.
        at: Location,
        /// 0 for S1, 1 for S2.
        surface: usize,
    },
    /// The correction was too large relative to the feed per period.
    #[error(
        "at {at} the crease bends too sharply for a feed per period of {} mm (correction {}); lower motion.feed or motion.period", fmt_mm(*feed_mm), fmt_correction(*correction_mm)
    )]
    StepTooLong {
        /// Where.
        at: Location,
        /// f (mm).
        feed_mm: f64,
        /// |δp| (mm).
        correction_mm: f64,
    },
    /// `path.direction` is perpendicular to the crease.
    #[error(
        "path.direction is perpendicular to the crease at the start, so it does not choose a sense of travel; give a direction along the crease"
    )]
    DirectionAmbiguous,
    /// The precise (Newton) mode could not converge.
    #[error("at {at} Newton's method did not converge on the crease ({detail}); lower motion.feed or motion.period")]
    NewtonFailed {
        /// Where.
        at: Location,
        /// What Newton saw.
        detail: String,
    },
}
