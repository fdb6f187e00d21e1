//! Seed 004 (Zhao, Huo & Song): NURBS tool paths — fitting a curve through points or to a
//! tolerance, and real-time NURBS interpolation (advancing the curve parameter each period).
//!
//! Glossary:
//! - *design curve*: the path the tool must follow (the crease's cutter-centre path, or any
//!   [`Curve3`](crate::geom::Curve3)); fits and programs are measured against it;
//! - *data points* Q_k with *parameters* ū_k; *knots* u_j; *control points* P_i; *order* =
//!   degree + 1 (FANUC's `P`);
//! - *deviation*: the two-sided (Hausdorff-style) distance between a fit and the design curve;
//! - *feed fluctuation*: relative error of the step made in one interpolation period.
//!
//! Modules: [`fit`] interpolation through points (parametrisations, end tangents, knot
//! averaging, banded solve); [`approx`] approximation to a tolerance (least squares with knot
//! refinement); [`realtime`] per-period parameter updates and their feed fluctuation and
//! chord error; [`measure`] (from the numerics floor) foot points, arc length,
//! maxima; the parabola-like comparison profile is [`crate::geom::Parabola`].
//!
//! Everything here is a pure function of (curve, tolerance, options), fast enough to rerun
//! while a tolerance slider moves (a few ms for a few-hundred-mm path).

pub mod approx;
mod band;
pub mod fit;
// Measuring helpers now on the numerics floor; the old path `nurbs_path::measure` stays.
pub use crate::numerics::measure;
pub mod realtime;

use thiserror::Error;

use crate::geom::NurbsError;

pub use crate::geom::Parabola;
pub use approx::{ApproxOptions, CurveFit, PointsFit, approximate_curve, approximate_points};
pub use fit::{EndCondition, InterpolateOptions, KnotRule, Parametrization, interpolate, parameters};
pub use measure::{ArcLengthTable, CurveFoot, Translated, nearest_on_curve};
pub use realtime::{
    FeedStats, PeriodSample, RealtimeError, RealtimeOptions, RealtimeRun, RealtimeStepper, Update, interpolate_realtime,
};

/// Why a curve could not be fitted. Every message says what to change.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum FitError {
    /// Degree outside 1 … 9.
    #[error("degree {0} is not supported; use 1 to 9 (3 for G06.2's usual order P4)")]
    Degree(usize),
    /// Not enough points.
    #[error(
        "{got} points are too few for degree {degree} (need at least {need}); give more points or lower the degree"
    )]
    TooFewPoints {
        /// Points given.
        got: usize,
        /// Points needed.
        need: usize,
        /// The degree.
        degree: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("point {index} is not finite; check its coordinates")]
    NotFinite {
        /// Index of the point.
        index: usize,
    },
    /// Two consecutive points coincide.
    #[error(
        "point {index} repeats the point before it; remove the duplicate (chord-length parameters need distinct consecutive points)"
    )]
    DuplicatePoint {
        /// Index of the second of the two.
        index: usize,
    },
    /// An end tangent is zero or not finite.
    #[error("the {end} tangent is zero or not finite; give a direction, or use estimated or free end conditions")]
    ZeroTangent {
        /// "start" or "end".
        end: &'static str,
    },
    /// Knots at the parameters do not fit this degree and end condition.
    #[error("knots at the parameters fit only a cubic with end tangents (or degree 1 without); degree {degree}{} needs knot averaging", if *tangents { " with end tangents" } else { " with free ends" })]
    KnotRule {
        /// The degree.
        degree: usize,
        /// Whether end tangents were asked for.
        tangents: bool,
    },
    /// The linear system is singular.
    #[error(
        "the fitting system is singular (a knot span holds no data); use knot averaging or more evenly spaced points"
    )]
    Singular,
    /// The result is not a valid NURBS.
    #[error("the fitted curve is not a valid NURBS: {0}")]
    Nurbs(NurbsError),
    /// Bad tolerance.
    #[error("the fitting tolerance must be a positive length in mm, got {tol_mm}; give e.g. 0.01")]
    BadTolerance {
        /// The value given.
        tol_mm: f64,
    },
    /// The design curve is empty.
    #[error("the design curve has no length; give a curve with distinct start and end")]
    EmptyCurve,
    /// Refinement could not reach the tolerance.
    #[error(
        "could not fit within {tol_mm} mm (best {achieved_mm:.6} mm with {control_points} control points): the curve needs knot spans shorter than the knot resolution or too many control points; raise the tolerance"
    )]
    NotConverged {
        /// The tolerance.
        tol_mm: f64,
        /// Best achieved.
        achieved_mm: f64,
        /// Control points at the end.
        control_points: usize,
    },
}
