//! The knot vector: the rules a clamped one keeps, and the span a parameter falls in.

use super::{MAX_DEGREE, NurbsError};
use crate::numerics::tolerance;

/// Checks a knot vector for `n_points` control points of degree `p`.
///
/// # Errors
/// The first rule the vector breaks, as a [`NurbsError`].
pub fn validate_knots(knots: &[f64], n_points: usize, p: usize) -> Result<(), NurbsError> {
    if p == 0 || p > MAX_DEGREE {
        return Err(NurbsError::Degree(p));
    }
    if n_points < p + 1 {
        return Err(NurbsError::TooFewPoints { got: n_points, degree: p });
    }
    let expected = n_points + p + 1;
    if knots.len() != expected {
        return Err(NurbsError::KnotCount { got: knots.len(), expected, points: n_points, degree: p });
    }
    for i in 1..knots.len() {
        if knots[i] < knots[i - 1] {
            return Err(NurbsError::Decreasing { index: i, value: knots[i] });
        }
    }
    let lo = knots[0];
    let hi = knots[knots.len() - 1];
    if !(hi > lo) {
        return Err(NurbsError::EmptyRange);
    }
    let eq = tolerance::KNOT_EQUAL_REL * (hi - lo);
    if knots[..=p].iter().any(|&k| (k - lo).abs() > eq) {
        return Err(NurbsError::NotClamped { end: "start", count: p + 1 });
    }
    if knots[knots.len() - p - 1..].iter().any(|&k| (k - hi).abs() > eq) {
        return Err(NurbsError::NotClamped { end: "end", count: p + 1 });
    }
    if knots[p + 1] <= lo + eq {
        return Err(NurbsError::EndRepeated { end: "start", count: p + 1 });
    }
    if knots[n_points - 1] >= hi - eq {
        return Err(NurbsError::EndRepeated { end: "end", count: p + 1 });
    }
    let mut i = p + 1;
    while i < n_points {
        let mut j = i;
        while j + 1 < n_points && (knots[j + 1] - knots[i]).abs() <= eq {
            j += 1;
        }
        let mult = j - i + 1;
        if mult > p {
            return Err(NurbsError::Multiplicity { value: knots[i], multiplicity: mult, degree: p });
        }
        i = j + 1;
    }
    Ok(())
}

/// The knot span index `s` with `knots[s] <= u < knots[s + 1]` (the last non-empty span at
/// the end of the range), for `n_points` control points of degree `p`. Values outside the
/// range are clamped to the first or last span.
#[must_use]
pub fn find_span(knots: &[f64], n_points: usize, p: usize, u: f64) -> usize {
    let n = n_points - 1;
    if u >= knots[n + 1] {
        return n;
    }
    if u <= knots[p] {
        return p;
    }
    let (mut low, mut high) = (p, n + 1);
    let mut mid = (low + high) / 2;
    while u < knots[mid] || u >= knots[mid + 1] {
        if u < knots[mid] {
            high = mid;
        } else {
            low = mid;
        }
        mid = (low + high) / 2;
    }
    mid
}
