//! Measuring curves against curves: the nearest point of a curve to a point (foot point),
//! arc-length tables, and the largest value of a deviation function over an interval.
//!
//! These are the yardsticks of fitting and of G-code checks: a fit or a program is "within
//! E" when every point of it lies within E of the design curve and every point of the design
//! curve lies within E of it (a two-sided, Hausdorff-style distance).

#![expect(
    clippy::neg_cmp_op_on_partial_ord,
    reason = "`!(x > 0.0)` is deliberately true for NaN: bad input is rejected, never passed on"
)]

use glam::DVec3;

use crate::geom::Curve3;
use crate::numerics::tolerance;

/// The nearest point of a curve to a given point, found by [`nearest_on_curve`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveFoot {
    /// Curve parameter of the foot point.
    pub t: f64,
    /// The foot point (mm).
    pub point: DVec3,
    /// Distance from the given point to the foot point (mm).
    pub dist: f64,
}

/// The point of `curve` nearest to `x` within the parameter window `[lo, hi]`, by Newton's
/// method on the foot-point condition `g(t) = (C(t) − x)·C'(t) = 0` from `guess`, with
/// `g' = |C'|² + (C − x)·C''`. Where `g' ≤ 0` (x beyond the centre of curvature) it falls
/// back to the gradient step `−g/|C'|²`; every step is clamped to the window and accepted
/// only if it brings the point closer (otherwise halved). Both window ends are compared too,
/// so a point past the end of an open curve gets the end point.
///
/// The guess must be in the right valley: callers pass the parameter of the nearest of a
/// set of samples, or the previous foot point when marching along a path.
#[must_use]
pub fn nearest_on_curve(curve: &dyn Curve3, x: DVec3, guess: f64, lo: f64, hi: f64) -> CurveFoot {
    let (lo, hi) = if lo <= hi { (lo, hi) } else { (hi, lo) };
    let mut t = guess.clamp(lo, hi);
    let [mut c, mut d1, mut d2] = curve.derivatives_at(t);
    let mut dist2 = (c - x).length_squared();
    for _ in 0..40 {
        let w = c - x;
        let g = w.dot(d1);
        let speed2 = d1.length_squared();
        if !(speed2 > 0.0) {
            break;
        }
        let gp = speed2 + w.dot(d2);
        let mut step = if gp > 0.0 { -g / gp } else { -g / speed2 };
        let mut moved = false;
        for _ in 0..30 {
            let tn = (t + step).clamp(lo, hi);
            if tn.to_bits() == t.to_bits() {
                break;
            }
            let [cn, d1n, d2n] = curve.derivatives_at(tn);
            let dn = (cn - x).length_squared();
            if dn <= dist2 {
                let shift = (cn - c).length();
                t = tn;
                c = cn;
                d1 = d1n;
                d2 = d2n;
                dist2 = dn;
                moved = shift > tolerance::CURVE_PROJECT_MM;
                break;
            }
            step *= 0.5;
        }
        if !moved {
            break;
        }
    }
    let mut best = CurveFoot { t, point: c, dist: dist2.sqrt() };
    for end in [lo, hi] {
        let p = curve.point_at(end);
        let d = (p - x).length();
        if d < best.dist {
            best = CurveFoot { t: end, point: p, dist: d };
        }
    }
    best
}

/// Distance from `x` to the segment `[a, b]` (mm); a zero-length segment is its point.
#[must_use]
pub fn distance_to_segment(x: DVec3, a: DVec3, b: DVec3) -> f64 {
    let ab = b - a;
    let l2 = ab.length_squared();
    let t = if l2 > 0.0 { ((x - a).dot(ab) / l2).clamp(0.0, 1.0) } else { 0.0 };
    (a + t * ab - x).length()
}

/// Five-point Gauss–Legendre nodes and weights on [−1, 1].
const GAUSS5: [(f64, f64); 5] = [
    (0.0, 0.568_888_888_888_888_9),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_5),
    (-0.906_179_845_938_664, 0.236_926_885_056_189_1),
    (0.906_179_845_938_664, 0.236_926_885_056_189_1),
];

fn gauss_length(curve: &dyn Curve3, a: f64, b: f64) -> f64 {
    let (m, r) = (0.5 * (a + b), 0.5 * (b - a));
    GAUSS5.iter().map(|&(x, w)| w * curve.derivatives_at(m + r * x)[1].length()).sum::<f64>() * r
}

/// Rounding noise of a cell's length comparison, in units of the machine epsilon times the
/// lengths compared (five Gauss terms each for three sums).
const ARC_NOISE_ULPS: f64 = 64.0;

/// Arc length s(t) = ∫|C'| dt of a curve, tabulated on an adaptive grid of its parameter
/// (five-point Gauss–Legendre per cell, cells halved until the two halves agree with the
/// whole to [`tolerance::ARC_LENGTH_REL`] of the total), and its inverse t(s).
#[derive(Clone, Debug, PartialEq)]
pub struct ArcLengthTable {
    t: Vec<f64>,
    s: Vec<f64>,
    /// Parametric speed |C'| at the nodes: ds/dt, for a Hermite first guess of t(s).
    v: Vec<f64>,
}

impl ArcLengthTable {
    /// Tabulates `curve` starting from `cells` equal cells (at least 1).
    #[must_use]
    pub fn new(curve: &dyn Curve3, cells: usize) -> Self {
        let (a, b) = curve.range();
        let cells = cells.max(1);
        let h = (b - a) / cells as f64;
        let coarse: Vec<f64> = (0..cells)
            .map(|i| gauss_length(curve, a + h * i as f64, if i + 1 == cells { b } else { a + h * (i + 1) as f64 }))
            .collect();
        let total: f64 = coarse.iter().sum();
        let eps = tolerance::ARC_LENGTH_REL * total.max(f64::MIN_POSITIVE) / cells as f64;
        let mut t = vec![a];
        let mut s = vec![0.0];
        for (i, &whole) in coarse.iter().enumerate() {
            let (c0, c1) = (a + h * i as f64, if i + 1 == cells { b } else { a + h * (i + 1) as f64 });
            Self::refine(curve, c0, c1, whole, eps, 0, &mut t, &mut s);
        }
        let v = t.iter().map(|&x| curve.derivatives_at(x)[1].length()).collect();
        Self { t, s, v }
    }

    #[expect(clippy::too_many_arguments, reason = "recursive helper carrying the table being built")]
    fn refine(
        curve: &dyn Curve3,
        a: f64,
        b: f64,
        whole: f64,
        eps: f64,
        depth: u32,
        t: &mut Vec<f64>,
        s: &mut Vec<f64>,
    ) {
        let m = 0.5 * (a + b);
        let (l, r) = (gauss_length(curve, a, m), gauss_length(curve, m, b));
        // Beside the relative tolerance, a difference within the rounding of the sums
        // themselves is agreement (a nanometre-long curve never meets 1e-8 of its length
        // otherwise), and the table stops growing at its node budget: the work is bounded by
        // the budget whatever the curve.
        let noise = ARC_NOISE_ULPS * f64::EPSILON * (l.abs() + r.abs() + whole.abs());
        if depth >= 30
            || (l + r - whole).abs() <= eps.max(noise)
            || t.len() >= crate::numerics::limits::MAX_ARC_TABLE_NODES
        {
            let base = s[s.len() - 1];
            t.push(m);
            s.push(base + l);
            t.push(b);
            s.push(base + l + r);
        } else {
            Self::refine(curve, a, m, l, 0.5 * eps, depth + 1, t, s);
            Self::refine(curve, m, b, r, 0.5 * eps, depth + 1, t, s);
        }
    }

    /// Total length (mm).
    #[must_use]
    pub fn length(&self) -> f64 {
        self.s[self.s.len() - 1]
    }

    /// Arc length from the start to parameter `t` (clamped to the range).
    #[must_use]
    pub fn s_at(&self, curve: &dyn Curve3, t: f64) -> f64 {
        let t = t.clamp(self.t[0], self.t[self.t.len() - 1]);
        let i = match self.t.binary_search_by(|x| x.total_cmp(&t)) {
            Ok(i) => return self.s[i],
            Err(i) => i.saturating_sub(1).min(self.t.len() - 2),
        };
        self.s[i] + gauss_length(curve, self.t[i], t)
    }

    /// The parameter at arc length `s` (clamped to `[0, length]`): a cubic Hermite guess of
    /// t(s) inside the table cell (slopes dt/ds = 1/|C'| at its ends, error O(h⁴)), then
    /// Newton steps `t += (s − s(t)) / |C'(t)|` until the step is below
    /// [`tolerance::CURVE_PROJECT_MM`] (usually one).
    #[must_use]
    pub fn t_at(&self, curve: &dyn Curve3, s: f64) -> f64 {
        let s = s.clamp(0.0, self.length());
        let i = match self.s.binary_search_by(|x| x.total_cmp(&s)) {
            Ok(i) => return self.t[i],
            Err(i) => i.saturating_sub(1).min(self.s.len() - 2),
        };
        let (t0, t1, s0, s1) = (self.t[i], self.t[i + 1], self.s[i], self.s[i + 1]);
        let h = s1 - s0;
        let mut t = if h > 0.0 {
            let x = (s - s0) / h;
            let (x2, x3) = (x * x, x * x * x);
            let (m0, m1) = if self.v[i] > 0.0 && self.v[i + 1] > 0.0 {
                (h / self.v[i], h / self.v[i + 1])
            } else {
                (t1 - t0, t1 - t0)
            };
            ((2.0 * x3 - 3.0 * x2 + 1.0) * t0 + (x3 - 2.0 * x2 + x) * m0 + (-2.0 * x3 + 3.0 * x2) * t1 + (x3 - x2) * m1)
                .clamp(t0, t1)
        } else {
            t0
        };
        for _ in 0..8 {
            let err = s - (s0 + gauss_length(curve, t0, t));
            let speed = curve.derivatives_at(t)[1].length();
            if !(speed > 0.0) {
                break;
            }
            let tn = (t + err / speed).clamp(t0, t1);
            let moved = (tn - t).abs() * speed;
            t = tn;
            if moved <= tolerance::CURVE_PROJECT_MM {
                break;
            }
        }
        t
    }

    /// The tabulated parameters (grid of the table).
    #[must_use]
    pub fn params(&self) -> &[f64] {
        &self.t
    }
}

/// A curve translated by a constant vector: the ball tip of a 3-axis ball end mill is the
/// cutter centre moved by −R·ẑ.
#[derive(Clone, Copy)]
pub struct Translated<'a> {
    /// The curve moved.
    pub inner: &'a dyn Curve3,
    /// The translation (mm).
    pub offset: DVec3,
}

impl Curve3 for Translated<'_> {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let [c, d1, d2] = self.inner.derivatives_at(s);
        [c + self.offset, d1, d2]
    }
    fn range(&self) -> (f64, f64) {
        self.inner.range()
    }
}
