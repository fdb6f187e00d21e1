//! Tolerance-driven arc fitting: the design curve as a chain of G02/G03 arcs (in G17, G18
//! or G19, helical where the normal axis moves in proportion to the angle) and G01 lines,
//! each piece as long as the tolerance allows — the "line and arc" program of seed 004.
//!
//! Greedy, from the start: for a candidate piece from A = C(t_a) to B = C(t_b) the
//! candidates are the segment AB and, in each principal plane, the arc through the plane
//! projections of A, M = C((t_a + t_b)/2) and B with the normal coordinate linear in the
//! angle (a helix when it changes). A candidate's deviation is the largest distance from the
//! design curve on `[t_a, t_b]` to it (sampled, the worst sample refined by golden section);
//! the best of the four is kept if within the tolerance. The piece is lengthened by doubling
//! while a candidate fits, then the longest fitting length is bracketed by bisection.
//! Distances to a helix are measured to the helix point at the same polar angle, an upper
//! bound of the true distance, so the check errs on the safe side.

#![expect(
    clippy::neg_cmp_op_on_partial_ord,
    reason = "`!(x > 0.0)` is deliberately true for NaN: bad input is rejected, never passed on"
)]

use glam::DVec3;
use thiserror::Error;

use super::path::{ArcMove, LineMove, Plane};
use crate::geom::Curve3;
use crate::numerics::maximise::max_on_interval;
use crate::numerics::measure::{ArcLengthTable, distance_to_segment};
use crate::numerics::tolerance;

/// Options of [`fit_arcs`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcFitOptions {
    /// Allow helical arcs (default true); otherwise an arc must keep its normal coordinate.
    pub helical: bool,
    /// Largest angle of one arc (deg, default 180): keeps every arc unambiguous for readers
    /// that convert to the radius format.
    pub max_sweep_deg: f64,
    /// Samples of the design curve per candidate, before refinement (default 16).
    pub check_samples: usize,
    /// Bisection steps bracketing the longest piece (default 10: within 0.1 % of it).
    pub bisections: usize,
    /// Most pieces before giving up (default 1 000 000).
    pub max_pieces: usize,
}

impl Default for ArcFitOptions {
    fn default() -> Self {
        Self { helical: true, max_sweep_deg: 180.0, check_samples: 16, bisections: 10, max_pieces: 1_000_000 }
    }
}

impl ArcFitOptions {
    /// Sets whether helical arcs are allowed.
    #[must_use]
    pub fn with_helical(mut self, on: bool) -> Self {
        self.helical = on;
        self
    }
}

/// Why arcs could not be fitted.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum ArcFitError {
    /// Bad tolerance.
    #[error("the arc-fitting tolerance must be a positive length in mm, got {0}")]
    BadTolerance(f64),
    /// Empty curve.
    #[error("the design curve has no length")]
    EmptyCurve,
    /// Too many pieces.
    #[error("more than {0} arcs and lines would be needed; raise the tolerance")]
    TooManyPieces(usize),
    /// No piece fits, however short.
    #[error(
        "no line or arc fits the design curve near parameter {t}: the curve is not smooth there (a corner or a cusp)"
    )]
    Stuck {
        /// Where.
        t: f64,
    },
}

/// A straight or circular piece.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Piece {
    /// G01.
    Line(LineMove),
    /// G02/G03.
    Arc(ArcMove),
}

impl Piece {
    /// End point (mm).
    #[must_use]
    pub fn end(&self) -> DVec3 {
        match self {
            Self::Line(l) => l.end,
            Self::Arc(a) => a.end,
        }
    }
}

/// A fitted piece with the design-curve parameters it covers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FittedPiece {
    /// Geometry.
    pub piece: Piece,
    /// Design parameter at the start.
    pub t0: f64,
    /// Design parameter at the end.
    pub t1: f64,
    /// Deviation measured while fitting (mm).
    pub deviation_mm: f64,
}

/// The arc through the plane projections of a, m, b, or `None` if they are (nearly)
/// collinear in that plane or the arc is too flat, too long or not allowed to be helical.
#[must_use]
pub fn arc_through(a: DVec3, m: DVec3, b: DVec3, plane: Plane, helical: bool, max_sweep: f64) -> Option<ArcMove> {
    let (aa, ab, an) = plane.split(a);
    let (ma, mb, _) = plane.split(m);
    let (ba, bb, bn) = plane.split(b);
    if !helical && (bn - an).abs() > tolerance::FIT_DUPLICATE_MM {
        return None;
    }
    // Relative to a.
    let (x1, y1) = (ma - aa, mb - ab);
    let (x2, y2) = (ba - aa, bb - ab);
    let d = 2.0 * (x1 * y2 - y1 * x2);
    let chord = x2.hypot(y2);
    let l1 = x1.hypot(y1);
    if !(chord > 0.0 && l1 > 0.0) {
        return None;
    }
    // Bulge: twice the triangle area over the squared chord ~ sagitta / chord.
    if !(d.abs() > 2.0 * tolerance::ARC_MIN_BULGE * chord * chord) {
        return None;
    }
    let s1 = x1 * x1 + y1 * y1;
    let s2 = x2 * x2 + y2 * y2;
    let ux = (y2 * s1 - y1 * s2) / d;
    let uy = (x1 * s2 - x2 * s1) / d;
    let arc = ArcMove { start: a, end: b, center: plane.join(aa + ux, ab + uy, an), plane, ccw: d > 0.0 };
    if arc.sweep().abs() > max_sweep {
        return None;
    }
    Some(arc)
}

/// Distance from x to the arc's point at x's polar angle (clamped to the arc's sweep): the
/// exact distance for a planar arc, an upper bound for a helix.
#[must_use]
pub fn distance_to_arc(arc: &ArcMove, x: DVec3) -> f64 {
    let (ca, cb, _) = arc.plane.split(arc.center);
    let (sa, sb, _) = arc.plane.split(arc.start);
    let (xa, xb, _) = arc.plane.split(x);
    let th_s = (sb - cb).atan2(sa - ca);
    let phi = (xb - cb).atan2(xa - ca);
    let sweep = arc.sweep();
    let tau_full = std::f64::consts::TAU;
    let delta = if sweep > 0.0 { (phi - th_s).rem_euclid(tau_full) } else { (th_s - phi).rem_euclid(tau_full) };
    let s = sweep.abs();
    let tau = if delta <= s {
        delta / s
    } else if delta - s < tau_full - delta {
        1.0
    } else {
        0.0
    };
    (arc.point_at(tau) - x).length()
}

/// Fits lines and arcs to `design` within `tol_mm`.
///
/// # Errors
/// [`ArcFitError`] for a bad tolerance, an empty curve, too many pieces, or a corner.
pub fn fit_arcs(design: &dyn Curve3, tol_mm: f64, opts: &ArcFitOptions) -> Result<Vec<FittedPiece>, ArcFitError> {
    if !(tol_mm.is_finite() && tol_mm > 0.0) {
        return Err(ArcFitError::BadTolerance(tol_mm));
    }
    let (ta, tb) = design.range();
    if !(tb > ta) {
        return Err(ArcFitError::EmptyCurve);
    }
    let table = ArcLengthTable::new(design, 64);
    let total = table.length();
    if !(total > tolerance::FIT_DUPLICATE_MM) {
        return Err(ArcFitError::EmptyCurve);
    }
    let max_sweep = opts.max_sweep_deg.to_radians();
    let n = opts.check_samples.max(2);
    let candidate = |t0: f64, t1: f64| -> (Option<Piece>, f64) {
        let a = design.point_at(t0);
        let b = design.point_at(t1);
        let m = design.point_at(0.5 * (t0 + t1));
        // The design samples are shared by the four candidates.
        let h = (t1 - t0) / n as f64;
        let xs: Vec<DVec3> = (0..=n).map(|i| design.point_at(if i == n { t1 } else { t0 + h * i as f64 })).collect();
        let dist = |piece: &Piece, x: DVec3| match piece {
            Piece::Line(l) => distance_to_segment(x, l.start, l.end),
            Piece::Arc(c) => distance_to_arc(c, x),
        };
        let mut options = vec![Piece::Line(LineMove { start: a, end: b })];
        for plane in Plane::ALL {
            if let Some(arc) = arc_through(a, m, b, plane, opts.helical, max_sweep) {
                options.push(Piece::Arc(arc));
            }
        }
        let mut best: Option<(Piece, f64, usize)> = None;
        for piece in options {
            let (worst_i, worst) = xs
                .iter()
                .enumerate()
                .map(|(i, &x)| (i, dist(&piece, x)))
                .fold((0, 0.0_f64), |acc, v| if v.1 > acc.1 { v } else { acc });
            if best.as_ref().is_none_or(|b| worst < b.1) {
                best = Some((piece, worst, worst_i));
            }
        }
        let Some((piece, sampled, i)) = best else {
            return (None, f64::INFINITY);
        };
        if sampled > tol_mm {
            // Refinement only raises the maximum.
            return (Some(piece), sampled);
        }
        // Refine the best candidate's worst sample by golden section between its neighbours.
        let lo = t0 + h * i.saturating_sub(1) as f64;
        let hi = (t0 + h * (i + 1) as f64).min(t1);
        let mut f = |t: f64| dist(&piece, design.point_at(t));
        let (refined, _) = max_on_interval(&mut f, lo, hi, 2, 10);
        (Some(piece), sampled.max(refined))
    };
    let mut pieces: Vec<FittedPiece> = Vec::new();
    let mut s0 = 0.0;
    let mut t0 = ta;
    // First trial length: the chord of the osculating circle with sagitta tol, ×4 for arcs.
    let kappa = design.curvature_at(ta);
    let mut trial = if kappa > 0.0 { 4.0 * (8.0 * tol_mm / kappa).sqrt() } else { total };
    while t0 < tb {
        if pieces.len() >= opts.max_pieces {
            return Err(ArcFitError::TooManyPieces(opts.max_pieces));
        }
        let remaining = total - s0;
        let mut ok: Option<(f64, f64, Piece, f64)> = None; // (len, t1, piece, dev)
        let mut fail_len = f64::INFINITY;
        let mut len = trial.min(remaining).max(crate::numerics::tolerance::ARC_MIN_TRIAL_MM);
        // Grow while it fits (or shrink until it does).
        loop {
            let t1 = if len >= remaining { tb } else { table.t_at(design, s0 + len) };
            let (piece, dev) = candidate(t0, t1);
            match piece {
                Some(p) if dev <= tol_mm => {
                    ok = Some((len, t1, p, dev));
                    if len >= remaining || fail_len.is_finite() {
                        break;
                    }
                    len = (2.0 * len).min(remaining);
                }
                _ => {
                    fail_len = len;
                    if ok.is_some() {
                        break;
                    }
                    len *= 0.5;
                    if len < crate::numerics::tolerance::ARC_MIN_PIECE_REL * total.max(1.0) {
                        return Err(ArcFitError::Stuck { t: t0 });
                    }
                }
            }
        }
        let Some((mut lo, mut t_lo, mut p_lo, mut d_lo)) = ok else {
            return Err(ArcFitError::Stuck { t: t0 });
        };
        if fail_len.is_finite() && lo < remaining {
            let mut hi = fail_len;
            for _ in 0..opts.bisections {
                let mid = 0.5 * (lo + hi);
                let t1 = table.t_at(design, s0 + mid);
                match candidate(t0, t1) {
                    (Some(p), dev) if dev <= tol_mm => {
                        lo = mid;
                        t_lo = t1;
                        p_lo = p;
                        d_lo = dev;
                    }
                    _ => hi = mid,
                }
            }
        }
        pieces.push(FittedPiece { piece: p_lo, t0, t1: t_lo, deviation_mm: d_lo });
        trial = lo;
        s0 += lo;
        t0 = t_lo;
        if lo >= remaining {
            break;
        }
    }
    Ok(pieces)
}
