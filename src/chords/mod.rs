//! Seed 003: equal-error chord approximation of curves — nodes on a curve such that every
//! chord (straight G01 segment between consecutive nodes) deviates from the curve by exactly
//! the tolerance d, the last by at most d.
//!
//! Glossary:
//! - *node*: a point of the curve where one straight segment ends and the next begins;
//! - *chord*: the straight segment between two consecutive nodes;
//! - *chord error* (chord deviation): the largest distance from the arc between two nodes to
//!   their chord ([`chord_deviation`]).
//!
//! [`equal_error_chords`] works on any [`Curve3`] (space curves, the crease, planar curves in
//! z = 0). Each next node is found by seed 002's bracketing and root search ([`search`]), so
//! the same machinery and the same [`RootMethod`]s serve the five-axis step selection.

pub mod deviation;
pub mod expr;
pub mod planar;

use thiserror::Error;

use crate::geom::Curve3;

pub use deviation::{ChordDeviation, DeviationOptions, chord_deviation};
// The helpers this paper used to own, now on the numerics floor; re-exported so the
// public paths (`chords::maximise::MaxOptions`, `chords::RootMethod`, …) stay.
pub use crate::numerics::maximise;
pub use crate::numerics::measure::distance_to_segment;
pub use crate::numerics::roots as search;
pub use crate::numerics::roots::{FoundNode, RootMethod, SearchFailure, SearchOptions, next_node};

/// Why equal-error chords could not be computed. Every message says what to change.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ChordError {
    /// The tolerance is not a positive finite length.
    #[error("the chord tolerance must be a positive length in mm, got {tol_mm}; give e.g. 0.01")]
    BadTolerance {
        /// The value given.
        tol_mm: f64,
    },
    /// The curve's parameter range is empty or not finite.
    #[error("the curve's parameter range [{start}, {end}] is empty or not finite; give a curve with start < end")]
    EmptyCurve {
        /// Start of the range.
        start: f64,
        /// End of the range.
        end: f64,
    },
    /// The curve evaluated to NaN or infinity.
    #[error("the curve is not finite at parameter {s}; check the curve's definition there")]
    NotFinite {
        /// Where.
        s: f64,
    },
    /// More nodes than allowed would be needed.
    #[error(
        "a tolerance of {tol_mm} mm needs more than {max_nodes} nodes on this curve (stopped at parameter {s} of [{start}, {end}]); raise the tolerance"
    )]
    TooManyNodes {
        /// The tolerance.
        tol_mm: f64,
        /// The limit ([`ChordOptions::max_nodes`]).
        max_nodes: usize,
        /// How far the nodes got.
        s: f64,
        /// Start of the range.
        start: f64,
        /// End of the range.
        end: f64,
    },
    /// Even the shortest representable chord after a node deviates by more than the
    /// tolerance (the tolerance is below the rounding of the curve's coordinates, or the
    /// curve jumps there).
    #[error(
        "at parameter {s} even the shortest chord deviates by {error_mm:e} mm, more than the tolerance {tol_mm} mm; raise the tolerance (the steps underflow) or check the curve for a jump"
    )]
    Underflow {
        /// Where.
        s: f64,
        /// Deviation of the shortest chord tried (mm).
        error_mm: f64,
        /// The tolerance.
        tol_mm: f64,
    },
    /// The root search did not converge.
    #[error(
        "the search for the chord after parameter {s} did not converge in {evaluations} evaluations; raise the tolerance or smooth the curve"
    )]
    NoConvergence {
        /// Where.
        s: f64,
        /// Evaluations spent.
        evaluations: u32,
    },
}

/// Settings of [`equal_error_chords_with`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChordOptions {
    /// Bracketing and root search (default: [`SearchOptions::default`] with
    /// [`RootMethod::AndersonBjorck`], the fastest here).
    pub search: SearchOptions,
    /// Deviation search; `floor_mm` is replaced by `deviation_floor_rel`·d (default
    /// [`DeviationOptions::default`]).
    pub deviation: DeviationOptions,
    /// Sagittas below this fraction of d are not resolved (default 1e-3).
    pub deviation_floor_rel: f64,
    /// Most nodes before giving up with [`ChordError::TooManyNodes`] (default 1 000 000).
    pub max_nodes: usize,
}

impl Default for ChordOptions {
    fn default() -> Self {
        Self {
            search: SearchOptions::default().with_method(RootMethod::AndersonBjorck),
            deviation: DeviationOptions::default(),
            deviation_floor_rel: crate::numerics::tolerance::CHORD_DEVIATION_FLOOR_REL,
            max_nodes: 1_000_000,
        }
    }
}

/// Nodes of an equal-error chord approximation with their chords' errors.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ChordNodes {
    /// Curve parameter of each node; first = curve start, last = curve end.
    pub params: Vec<f64>,
    /// `errors_mm[i]`: deviation of the chord from node i to node i + 1 (mm).
    pub errors_mm: Vec<f64>,
    /// Deviation evaluations spent per chord (bracketing included).
    pub evaluations: Vec<u32>,
}

impl ChordNodes {
    /// Number of nodes.
    #[must_use]
    pub fn len(&self) -> usize {
        self.params.len()
    }

    /// No nodes at all (never returned by a successful search).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.params.is_empty()
    }

    /// The largest chord error (mm).
    #[must_use]
    pub fn worst_error_mm(&self) -> f64 {
        self.errors_mm.iter().copied().fold(0.0, f64::max)
    }

    /// All deviation evaluations.
    #[must_use]
    pub fn total_evaluations(&self) -> u64 {
        self.evaluations.iter().map(|&e| u64::from(e)).sum()
    }
}

/// Seed 002's first trial step, `Δl = √(8ρE)` converted to a parameter step `Δl/|C'(s)|`
/// (ρ = 1/κ, the radius of curvature at s). A straight or singular point gives `None` (try
/// the whole remaining range).
#[must_use]
pub fn first_step_estimate(curve: &dyn Curve3, s: f64, tol_mm: f64) -> Option<f64> {
    let [_, d1, d2] = curve.derivatives_at(s);
    let speed = d1.length();
    let kappa = if speed > 0.0 { d1.cross(d2).length() / (speed * speed * speed) } else { 0.0 };
    if !(kappa > 0.0 && speed > 0.0) {
        return None;
    }
    let dl = (8.0 * tol_mm / kappa).sqrt();
    let ds = dl / speed;
    ds.is_finite().then_some(ds)
}

/// Parameters of the nodes of an equal-error chord approximation of `curve`: the first is
/// the curve's start, the last its end, and the chord between consecutive nodes deviates from
/// the curve by `tol_mm` (to within `[tol − ε, tol]`, ε = min(1e-6 mm, 1e-3·tol)); the last
/// chord by at most `tol_mm`.
///
/// The deviation of a chord is the largest distance from the arc to the chord *segment*
/// ([`chord_deviation`]), found by sampling and refinement, so inflections, non-convex arcs
/// and space curves are handled. For a circle of radius ρ each chord spans the angle
/// θ = 2·acos(1 − d/ρ) (sagitta ρ(1 − cos(θ/2)) = d).
///
/// ```
/// # use interpolab::chords::equal_error_chords;
/// # use interpolab::geom::HermitePath;
/// # use glam::DVec3;
/// let line = HermitePath::new(vec![DVec3::ZERO, DVec3::X * 10.0], vec![DVec3::X, DVec3::X]).unwrap();
/// // A straight curve needs one chord whatever the tolerance.
/// assert_eq!(equal_error_chords(&line, 0.01).unwrap(), vec![0.0, 10.0]);
/// ```
///
/// # Errors
/// [`ChordError`]: a tolerance that is not positive, an empty curve, a curve that is not
/// finite, a tolerance so small that the steps underflow or the node count explodes.
pub fn equal_error_chords(curve: &dyn Curve3, tol_mm: f64) -> Result<Vec<f64>, ChordError> {
    equal_error_chords_with(curve, tol_mm, &ChordOptions::default()).map(|n| n.params)
}

/// [`equal_error_chords`] with settings, returning each chord's error and evaluation count.
///
/// # Errors
/// As [`equal_error_chords`].
pub fn equal_error_chords_with(curve: &dyn Curve3, tol_mm: f64, opts: &ChordOptions) -> Result<ChordNodes, ChordError> {
    if !(tol_mm > 0.0 && tol_mm.is_finite()) {
        return Err(ChordError::BadTolerance { tol_mm });
    }
    let (start, end) = curve.range();
    if !(start.is_finite() && end.is_finite() && end > start) {
        return Err(ChordError::EmptyCurve { start, end });
    }
    for s in [start, end] {
        if !curve.point_at(s).is_finite() {
            return Err(ChordError::NotFinite { s });
        }
    }
    let dev_opts = DeviationOptions { floor_mm: opts.deviation_floor_rel * tol_mm, ..opts.deviation };
    let mut out = ChordNodes { params: vec![start], ..ChordNodes::default() };
    let mut s = start;
    let mut step = first_step_estimate(curve, start, tol_mm);
    while s < end {
        if out.params.len() >= opts.max_nodes {
            return Err(ChordError::TooManyNodes { tol_mm, max_nodes: opts.max_nodes, s, start, end });
        }
        let from = s;
        let error = |x: f64| -> Result<f64, ChordError> {
            let d = chord_deviation(curve, from, x, &dev_opts);
            if d.max_mm.is_finite() { Ok(d.max_mm) } else { Err(ChordError::NotFinite { s: x }) }
        };
        let node =
            next_node(error, from, end, step.unwrap_or(end - from), tol_mm, &opts.search).map_err(|e| match e {
                SearchFailure::Eval(e) => e,
                SearchFailure::NotFinite { s } => ChordError::NotFinite { s },
                SearchFailure::Underflow { s_from, error_mm } => ChordError::Underflow { s: s_from, error_mm, tol_mm },
                SearchFailure::NoConvergence { s_from, evaluations } => {
                    ChordError::NoConvergence { s: s_from, evaluations }
                }
            })?;
        out.params.push(node.s);
        out.errors_mm.push(node.error_mm);
        out.evaluations.push(node.evaluations);
        // Seed 002: later trial steps are the previous parameter step.
        step = Some(node.s - from);
        s = node.s;
    }
    Ok(out)
}
