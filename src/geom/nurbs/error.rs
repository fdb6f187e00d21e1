//! What is wrong with a NURBS definition: its degree, knots, control net or weights.

use thiserror::Error;

use super::MAX_DEGREE;

/// What is wrong with a NURBS definition. Indices are 0-based, as in the JSON arrays.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum NurbsError {
    /// Degree outside 1..=MAX_DEGREE.
    #[error("degree {0} is not supported (use 1 to {MAX_DEGREE})")]
    Degree(usize),
    /// Fewer control points than degree + 1.
    #[error("{got} control points are too few for degree {degree} (need at least {})", degree + 1)]
    TooFewPoints {
        /// Points given.
        got: usize,
        /// The degree.
        degree: usize,
    },
    /// Knot count does not match points + degree + 1.
    #[error("{got} knots given, but {points} control points of degree {degree} need {expected}")]
    KnotCount {
        /// Knots given.
        got: usize,
        /// Knots needed.
        expected: usize,
        /// Control points.
        points: usize,
        /// Degree.
        degree: usize,
    },
    /// A knot is smaller than its predecessor.
    #[error("knot {index} ({value}) is smaller than the knot before it; knots must be non-decreasing")]
    Decreasing {
        /// Index of the offending knot.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// The first or last degree + 1 knots are not all equal.
    #[error("the knot vector is not clamped at its {end}: the {end} {count} knots must be equal")]
    NotClamped {
        /// "start" or "end".
        end: &'static str,
        /// degree + 1.
        count: usize,
    },
    /// An interior knot repeats more than degree times (the curve would break apart).
    #[error("interior knot {value} repeats {multiplicity} times; at most the degree ({degree}) is allowed")]
    Multiplicity {
        /// Knot value.
        value: f64,
        /// How often it repeats.
        multiplicity: usize,
        /// The degree.
        degree: usize,
    },
    /// An end knot repeats more than degree + 1 times.
    #[error("the knot vector repeats its {end} value more than degree + 1 = {count} times")]
    EndRepeated {
        /// "start" or "end".
        end: &'static str,
        /// degree + 1.
        count: usize,
    },
    /// First and last knot coincide.
    #[error("the knot range is empty (first and last knot are equal)")]
    EmptyRange,
    /// A weight is not a positive finite number.
    #[error("weight {index} is {value}; weights must be > 0")]
    Weight {
        /// Flat index of the weight.
        index: usize,
        /// Its value.
        value: f64,
    },
    /// Shapes of points and weights differ.
    #[error("weights have a different shape than the control points")]
    WeightShape,
    /// A row of the control net has the wrong length.
    #[error("row {row} has {got} points but row 0 has {expected}; the control net must be rectangular")]
    Ragged {
        /// Row index.
        row: usize,
        /// Its length.
        got: usize,
        /// Length of row 0.
        expected: usize,
    },
}
