//! Global interpolation: a B-spline (a NURBS with all weights 1) of degree p through given
//! points Q_0 … Q_n, as seed 004 does for its parabola: parameters for the points, a knot
//! vector from them, then the control points from one banded linear system.
//!
//! **Parameters** ū_k (all scaled to run from 0 to the total chord length L, so knots are in
//! mm and a chord-length curve has |C'| ≈ 1):
//! - uniform: ū_k = k·L/n;
//! - cumulative chord length: ū_k = Σ_{i≤k} |Q_i − Q_{i−1}| (seed 004's choice);
//! - centripetal: ū_k ∝ Σ_{i≤k} |Q_i − Q_{i−1}|^½ (Lee 1989), better at sharp turns.
//!
//! **End conditions**:
//! - free: n + 1 control points, one equation per point;
//! - end tangents (seed 004: "the two end tangent vectors give the supplementary
//!   equations"): n + 3 control points; besides C(ū_k) = Q_k, the derivative rows
//!   `P_1 − P_0 = (u_{p+1} − u_0)/p · D_0` and `P_{N} − P_{N−1} = (u_{N+p} − u_N)/p · D_n`
//!   (N = n + 2), from `C'(u_0) = p/(u_{p+1} − u_1)·(P_1 − P_0)` on a clamped knot vector.
//!   Given tangents are directions; their length is set to the local chord speed
//!   |Q_1 − Q_0|/(ū_1 − ū_0) (1 for chord length). Estimated tangents are the derivative of
//!   the parabola through the first (last) three points (Bessel's end condition).
//!
//! **Knots** (clamped: p + 1 equal knots at each end):
//! - averaging (Piegl & Tiller, *The NURBS Book*, eq. 9.8 free, 9.22 with end derivatives):
//!   free `u_{j+p} = (1/p)·Σ_{i=j}^{j+p−1} ū_i`, j = 1 … n − p; with end tangents
//!   `u_{j+p+1} = (1/p)·Σ_{i=j}^{j+p−1} ū_i`, j = 0 … n − p + 1. Every knot span then holds
//!   a parameter, so the system is regular (Schoenberg–Whitney);
//! - at the parameters (the classic cubic spline, and what seed 004 writes): interior knots
//!   are ū_1 … ū_{n−1}. It fits the count only for a cubic with end tangents (or degree 1
//!   free).

use glam::DVec3;

use super::FitError;
use super::band::{self, BandRow};
use crate::geom::NurbsCurve;
use crate::geom::nurbs::{MAX_DEGREE, basis_derivatives, find_span};
use crate::numerics::tolerance;

/// How points are given parameter values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Parametrization {
    /// Equally spaced.
    Uniform,
    /// Cumulative chord length (seed 004).
    ChordLength,
    /// Cumulative square root of chord length.
    Centripetal,
}

impl Parametrization {
    /// Name used on the command line and in tables.
    #[must_use]
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Uniform => "uniform",
            Self::ChordLength => "chord",
            Self::Centripetal => "centripetal",
        }
    }
}

/// Conditions at the two ends of an interpolating curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EndCondition {
    /// No end derivative: n + 1 control points.
    Free,
    /// End tangents from the parabola through the first and last three points.
    EstimatedTangents,
    /// End tangent directions (need not be unit; must not be zero).
    Tangents {
        /// Direction at the first point.
        start: DVec3,
        /// Direction at the last point.
        end: DVec3,
    },
}

/// How the knot vector is built from the parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum KnotRule {
    /// Averaging of p consecutive parameters (always regular).
    Averaging,
    /// Interior knots at the parameters (cubic with end tangents, or degree 1 free).
    AtParameters,
}

/// Options of [`interpolate`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InterpolateOptions {
    /// Degree p (default 3, as in seed 004), 1 … [`MAX_DEGREE`].
    pub degree: usize,
    /// Parametrisation (default cumulative chord length).
    pub parametrization: Parametrization,
    /// End condition (default estimated end tangents).
    pub end: EndCondition,
    /// Knot rule (default averaging).
    pub knots: KnotRule,
}

impl Default for InterpolateOptions {
    fn default() -> Self {
        Self {
            degree: 3,
            parametrization: Parametrization::ChordLength,
            end: EndCondition::EstimatedTangents,
            knots: KnotRule::Averaging,
        }
    }
}

impl InterpolateOptions {
    /// Sets the degree.
    #[must_use]
    pub fn with_degree(mut self, degree: usize) -> Self {
        self.degree = degree;
        self
    }
    /// Sets the parametrisation.
    #[must_use]
    pub fn with_parametrization(mut self, p: Parametrization) -> Self {
        self.parametrization = p;
        self
    }
    /// Sets the end condition.
    #[must_use]
    pub fn with_end(mut self, end: EndCondition) -> Self {
        self.end = end;
        self
    }
    /// Sets the knot rule.
    #[must_use]
    pub fn with_knots(mut self, knots: KnotRule) -> Self {
        self.knots = knots;
        self
    }
}

/// Checks that points are finite and consecutive ones distinct.
pub(crate) fn check_points(points: &[DVec3]) -> Result<(), FitError> {
    if let Some(index) = points.iter().position(|p| !p.is_finite()) {
        return Err(FitError::NotFinite { index });
    }
    for (i, w) in points.windows(2).enumerate() {
        if (w[1] - w[0]).length() <= tolerance::FIT_DUPLICATE_MM {
            return Err(FitError::DuplicatePoint { index: i + 1 });
        }
    }
    Ok(())
}

/// Parameters ū_0 = 0 < … < ū_n = L (L: total chord length, mm) of the points.
///
/// # Errors
/// Fewer than 2 points, non-finite or repeated consecutive points.
pub fn parameters(points: &[DVec3], kind: Parametrization) -> Result<Vec<f64>, FitError> {
    if points.len() < 2 {
        return Err(FitError::TooFewPoints { got: points.len(), need: 2, degree: 1 });
    }
    check_points(points)?;
    let chords: Vec<f64> = points.windows(2).map(|w| (w[1] - w[0]).length()).collect();
    let total: f64 = chords.iter().sum();
    let steps: Vec<f64> = match kind {
        Parametrization::Uniform => vec![1.0; chords.len()],
        Parametrization::ChordLength => chords,
        Parametrization::Centripetal => chords.iter().map(|c| c.sqrt()).collect(),
    };
    let sum: f64 = steps.iter().sum();
    let mut u = Vec::with_capacity(points.len());
    let mut acc = 0.0;
    u.push(0.0);
    for s in &steps {
        acc += s;
        u.push(acc / sum * total);
    }
    let last = u.len() - 1;
    u[last] = total;
    Ok(u)
}

/// Clamped knot vector by averaging for `n_ctrl` control points of degree p over the
/// parameters `u` (Piegl & Tiller 9.8 when `n_ctrl = u.len()`, 9.22 when `n_ctrl = u.len() + 2`).
#[must_use]
pub fn averaged_knots(u: &[f64], degree: usize, n_ctrl: usize) -> Vec<f64> {
    let p = degree;
    let (a, b) = (u[0], u[u.len() - 1]);
    let mut knots = vec![a; p + 1];
    let interior = n_ctrl - p - 1;
    // With n_ctrl = m + 1 + e (e extra end equations), average p consecutive parameters
    // starting at j + 1 − e/2·… : for e = 0 start at j = 1, for e = 2 start at j = 0.
    let first = if n_ctrl == u.len() { 1 } else { 0 };
    for j in 0..interior {
        let s: f64 = u[first + j..first + j + p].iter().sum();
        knots.push(s / p as f64);
    }
    knots.extend(std::iter::repeat_n(b, p + 1));
    knots
}

/// The B-spline basis functions at `t` as a matrix row (`start` = first non-zero column).
pub(crate) fn basis_row(knots: &[f64], n_ctrl: usize, p: usize, t: f64) -> BandRow {
    let span = find_span(knots, n_ctrl, p, t);
    let ders = basis_derivatives(knots, span, p, t);
    BandRow::new(span - p, ders[0][..=p].to_vec())
}

fn bessel_tangent(q: [DVec3; 3], u: [f64; 3]) -> DVec3 {
    let (h1, h2) = (u[1] - u[0], u[2] - u[1]);
    let d1 = (q[1] - q[0]) / h1;
    let d2 = (q[2] - q[1]) / h2;
    ((2.0 * h1 + h2) * d1 - h1 * d2) / (h1 + h2)
}

/// End derivative vectors (per unit parameter) for the end condition, or `None` for free ends.
fn end_derivatives(points: &[DVec3], u: &[f64], end: EndCondition) -> Result<Option<(DVec3, DVec3)>, FitError> {
    let n = points.len() - 1;
    match end {
        EndCondition::Free => Ok(None),
        EndCondition::EstimatedTangents => {
            if n == 1 {
                let d = (points[1] - points[0]) / (u[1] - u[0]);
                return Ok(Some((d, d)));
            }
            let d0 = bessel_tangent([points[0], points[1], points[2]], [u[0], u[1], u[2]]);
            // At the far end the same formula with the order reversed, negated.
            let dn = -bessel_tangent([points[n], points[n - 1], points[n - 2]], [-u[n], -u[n - 1], -u[n - 2]]);
            Ok(Some((d0, dn)))
        }
        EndCondition::Tangents { start, end } => {
            let t0 = start.normalize_or_zero();
            let t1 = end.normalize_or_zero();
            if !t0.is_finite() || t0 == DVec3::ZERO {
                return Err(FitError::ZeroTangent { end: "start" });
            }
            if !t1.is_finite() || t1 == DVec3::ZERO {
                return Err(FitError::ZeroTangent { end: "end" });
            }
            let v0 = (points[1] - points[0]).length() / (u[1] - u[0]);
            let v1 = (points[n] - points[n - 1]).length() / (u[n] - u[n - 1]);
            Ok(Some((t0 * v0, t1 * v1)))
        }
    }
}

/// Interpolates `points` with a degree-p B-spline (weights 1).
///
/// # Errors
/// Too few points for the degree, repeated or non-finite points, zero end tangents, a knot
/// rule that does not fit the degree and end condition, or a singular system.
pub fn interpolate(points: &[DVec3], opts: &InterpolateOptions) -> Result<NurbsCurve, FitError> {
    let p = opts.degree;
    if p == 0 || p > MAX_DEGREE {
        return Err(FitError::Degree(p));
    }
    let with_tangents = opts.end != EndCondition::Free;
    // Free ends need n + 1 ≥ p + 1 points; end tangents n + 3 ≥ p + 1 and at least 2 points.
    let need = if with_tangents { p.saturating_sub(1).max(2) } else { p + 1 };
    if points.len() < need {
        return Err(FitError::TooFewPoints { got: points.len(), need, degree: p });
    }
    let u = parameters(points, opts.parametrization)?;
    let n = points.len() - 1;
    let ends = end_derivatives(points, &u, opts.end)?;
    let n_ctrl = if ends.is_some() { n + 3 } else { n + 1 };
    let knots = match opts.knots {
        KnotRule::Averaging => averaged_knots(&u, p, n_ctrl),
        KnotRule::AtParameters => {
            if n_ctrl - p - 1 != n - 1 {
                return Err(FitError::KnotRule { degree: p, tangents: with_tangents });
            }
            let mut k = vec![u[0]; p + 1];
            k.extend_from_slice(&u[1..n]);
            k.extend(std::iter::repeat_n(u[n], p + 1));
            k
        }
    };
    let mut rows = Vec::with_capacity(n_ctrl);
    let mut rhs = Vec::with_capacity(n_ctrl);
    match ends {
        None => {
            for (k, q) in points.iter().enumerate() {
                rows.push(basis_row(&knots, n_ctrl, p, u[k]));
                rhs.push(*q);
            }
        }
        Some((d0, dn)) => {
            let m = knots.len() - 1;
            rows.push(BandRow::new(0, vec![1.0]));
            rhs.push(points[0]);
            rows.push(BandRow::new(0, vec![-1.0, 1.0]));
            rhs.push(d0 * (knots[p + 1] - knots[0]) / p as f64);
            for k in 1..n {
                rows.push(basis_row(&knots, n_ctrl, p, u[k]));
                rhs.push(points[k]);
            }
            rows.push(BandRow::new(n_ctrl - 2, vec![-1.0, 1.0]));
            rhs.push(dn * (knots[m] - knots[n_ctrl - 1]) / p as f64);
            rows.push(BandRow::new(n_ctrl - 1, vec![1.0]));
            rhs.push(points[n]);
        }
    }
    let ctrl = band::solve(rows, rhs).ok_or(FitError::Singular)?;
    NurbsCurve::try_new(p, knots, &ctrl, None).map_err(FitError::Nurbs)
}
