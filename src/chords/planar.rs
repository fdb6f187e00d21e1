//! Seed 003 on planar non-circular curves: the paper's geometric construction of
//! equal-error nodes on the parabola, the test curves (hyperbola, ellipse, any parametric
//! curve), and the two classical alternatives it is compared with.
//!
//! - **Equal-error** ([`super::equal_error_chords`]): every chord deviates by exactly d.
//! - **Equal-interval**: nodes at a constant parameter step (constant Δx on a graph
//!   y = f(x); constant Δt on a parametric curve; constant Δs on the crease).
//! - **Equal-step**: nodes at a constant chord length L (the last chord shorter).
//!
//! Seed 003 sizes the last two for the smallest radius of curvature ρ_min: the chord of a
//! circle of radius ρ_min with sagitta d, `L = 2√(2ρ_min·d − d²)`, as the step (equal-step)
//! and, converted with the speed |C'| at that point, as the parameter step (equal-interval)
//! — [`Sizing::MinRadius`]. Because that sizing is only a local argument, the table also
//! gives the widest uniform spacing that really keeps every chord within d —
//! [`Sizing::Widest`].
//!
//! **The paper's construction** (§2, for y = a·x², a > 0): around the current node
//! a = (x_a, y_a) draw the tolerance circle of radius d; the common tangent PT of that circle
//! and the curve touches the curve at T; the chord through a parallel to PT meets the curve
//! again at the next node b. PT is at distance d from a, so the curve's farthest point from
//! the chord line is T, at exactly d. For the parabola this reads
//! `a(x_T − x_a)² = d·√(1 + 4a²x_T²)` (the distance from a to the tangent at T), and since
//! the chord ab has the slope 2a·x_T of that tangent, `x_b = 2x_T − x_a` (the paper's
//! eq. 10 with y_a = a·x_a²). [`parabola_paper_nodes`] solves this directly, independent
//! of the general search. (The printed eq. 8 and its program are garbled in the OCR'd copy;
//! this is the same construction derived afresh.)

use glam::{DVec2, DVec3};

use super::deviation::{DeviationOptions, chord_deviation};
use super::{ChordError, ChordOptions, equal_error_chords_with};
use crate::geom::Curve3;
use crate::geom::Parabola;

/// The rectangular hyperbola x·y = k (k > 0) in z = 0, parametrised by x over `[x0, x1]`
/// (0 < x0 < x1). Its radius of curvature `(x² + y²)^{3/2}/(2k)` is smallest, √(2k), at
/// the vertex x = y = √k.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hyperbola {
    /// k (mm²).
    pub k: f64,
    /// First x (mm), > 0.
    pub x0: f64,
    /// Last x (mm).
    pub x1: f64,
}

impl Curve3 for Hyperbola {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let x = s.clamp(self.x0, self.x1);
        let k = self.k;
        [DVec3::new(x, k / x, 0.0), DVec3::new(1.0, -k / (x * x), 0.0), DVec3::new(0.0, 2.0 * k / (x * x * x), 0.0)]
    }
    fn range(&self) -> (f64, f64) {
        (self.x0, self.x1)
    }
}

/// The ellipse (a·cos t, b·sin t) in z = 0 for t in `[t0, t1]` (rad). With a > b its
/// radius of curvature runs from b²/a (at t = 0, π) to a²/b (at t = ±π/2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipse {
    /// Semi-axis along x (mm).
    pub a: f64,
    /// Semi-axis along y (mm).
    pub b: f64,
    /// First parameter (rad).
    pub t0: f64,
    /// Last parameter (rad).
    pub t1: f64,
}

impl Curve3 for Ellipse {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let (sn, cs) = s.clamp(self.t0, self.t1).sin_cos();
        let (a, b) = (self.a, self.b);
        [DVec3::new(a * cs, b * sn, 0.0), DVec3::new(-a * sn, b * cs, 0.0), DVec3::new(-a * cs, -b * sn, 0.0)]
    }
    fn range(&self) -> (f64, f64) {
        (self.t0, self.t1)
    }
}

/// Any plane curve t ↦ (x(t), y(t)) given as a function (in z = 0), e.g. one typed in the
/// app. Derivatives by central differences with step `h` (clamped to the range).
pub struct FnCurve {
    f: Box<dyn Fn(f64) -> DVec2 + Send + Sync>,
    range: (f64, f64),
    h: f64,
}

impl std::fmt::Debug for FnCurve {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("FnCurve").field("range", &self.range).finish_non_exhaustive()
    }
}

impl FnCurve {
    /// The curve `f` over `range`; derivatives use the step 1e-5 of the range width.
    #[must_use]
    pub fn new(f: impl Fn(f64) -> DVec2 + Send + Sync + 'static, range: (f64, f64)) -> Self {
        Self { f: Box::new(f), range, h: crate::numerics::tolerance::FD_STEP_REL * (range.1 - range.0).abs() }
    }
}

impl Curve3 for FnCurve {
    fn derivatives_at(&self, s: f64) -> [DVec3; 3] {
        let (lo, hi) = self.range;
        let s = s.clamp(lo, hi);
        let h = self.h;
        let m = s.clamp(lo + h, hi - h);
        let p = |t: f64| (self.f)(t).extend(0.0);
        let (a, b, c) = (p(m - h), p(m), p(m + h));
        let d2 = (a - 2.0 * b + c) / (h * h);
        let d1 = (c - a) / (2.0 * h) + d2 * (s - m);
        [p(s), d1, d2]
    }
    fn range(&self) -> (f64, f64) {
        self.range
    }
}

/// Seed 003's construction on the parabola y = a·x² (module docs): the x of every node
/// from `x_start` to `x_end` (a > 0, 0 ≤ x_start < x_end), each chord deviating by exactly
/// d, the last by at most d.
///
/// # Errors
/// [`ChordError::BadTolerance`] for d ≤ 0; [`ChordError::EmptyCurve`] for an empty range or
/// a ≤ 0.
pub fn parabola_paper_nodes(a: f64, x_start: f64, x_end: f64, d: f64) -> Result<Vec<f64>, ChordError> {
    if !(d > 0.0 && d.is_finite()) {
        return Err(ChordError::BadTolerance { tol_mm: d });
    }
    if !(a > 0.0 && x_start >= 0.0 && x_end > x_start && x_end.is_finite()) {
        return Err(ChordError::EmptyCurve { start: x_start, end: x_end });
    }
    // g(x_T) = a(x_T − x_a)² − d·√(1 + 4a²x_T²): negative at x_a, positive far on.
    let g = |xa: f64, xt: f64| a * (xt - xa) * (xt - xa) - d * (1.0 + 4.0 * a * a * xt * xt).sqrt();
    let mut nodes = vec![x_start];
    let mut xa = x_start;
    while xa < x_end {
        let mut hi = xa + (d / a).sqrt();
        while g(xa, hi) < 0.0 {
            hi = xa + 2.0 * (hi - xa);
        }
        let mut lo = xa;
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if g(xa, mid) < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
            if hi - lo <= crate::numerics::tolerance::BISECTION_REL * hi.abs().max(1.0) {
                break;
            }
        }
        let xb = 2.0 * (0.5 * (lo + hi)) - xa;
        xa = if xb >= x_end { x_end } else { xb };
        nodes.push(xa);
    }
    Ok(nodes)
}

/// Deviation of every chord between consecutive `params` (mm).
#[must_use]
pub fn chord_errors(curve: &dyn Curve3, params: &[f64], opts: &DeviationOptions) -> Vec<f64> {
    params.windows(2).map(|w| chord_deviation(curve, w[0], w[1], opts).max_mm).collect()
}

/// The smallest radius of curvature of the curve and where (sampled, then refined).
#[must_use]
pub fn min_radius(curve: &dyn Curve3) -> (f64, f64) {
    let (lo, hi) = curve.range();
    let n = 4000;
    let h = (hi - lo) / f64::from(n);
    let mut best = (lo, curve.curvature_at(lo));
    for i in 1..=n {
        let s = lo + h * f64::from(i);
        let k = curve.curvature_at(s);
        if k > best.1 {
            best = (s, k);
        }
    }
    let f = |s: f64| -> Result<f64, std::convert::Infallible> { Ok(curve.curvature_at(s)) };
    let (a, b) = ((best.0 - h).max(lo), (best.0 + h).min(hi));
    let Ok((s, k, _)) =
        crate::numerics::maximise::brent_max(f, a, b, crate::numerics::tolerance::PARAM_SEARCH_REL * (hi - lo), best);
    if k > best.1 {
        best = (s, k);
    }
    (best.0, if best.1 > 0.0 { 1.0 / best.1 } else { f64::INFINITY })
}

/// Nodes at the constant parameter step `step` from the start; the last node is the end
/// (so the last interval may be shorter).
#[must_use]
pub fn equal_interval_nodes(curve: &dyn Curve3, step: f64) -> Vec<f64> {
    let (lo, hi) = curve.range();
    let n = ((hi - lo) / step).ceil().max(1.0) as usize;
    let mut v: Vec<f64> = (0..n).map(|i| lo + step * i as f64).collect();
    v.push(hi);
    v
}

/// Nodes at the constant chord length `chord_mm`: each node is the first point past the
/// previous one at that distance from it; the last node is the end (its chord shorter).
///
/// # Errors
/// [`ChordError::BadTolerance`] for a chord length that is not positive,
/// [`ChordError::TooManyNodes`] past `max_nodes`.
pub fn equal_step_nodes(curve: &dyn Curve3, chord_mm: f64, max_nodes: usize) -> Result<Vec<f64>, ChordError> {
    if !(chord_mm > 0.0 && chord_mm.is_finite()) {
        return Err(ChordError::BadTolerance { tol_mm: chord_mm });
    }
    let (lo, hi) = curve.range();
    let mut nodes = vec![lo];
    let mut s = lo;
    while s < hi {
        if nodes.len() >= max_nodes {
            return Err(ChordError::TooManyNodes { tol_mm: chord_mm, max_nodes, s, start: lo, end: hi });
        }
        let p = curve.point_at(s);
        let dist = |t: f64| (curve.point_at(t) - p).length() - chord_mm;
        // March in steps of a quarter of the chord (as a parameter step) until the distance
        // reaches L, then bisect: the first crossing, not just any.
        let speed = curve.derivatives_at(s)[1].length();
        let dt = if speed > 0.0 { 0.25 * chord_mm / speed } else { (hi - lo) / 64.0 };
        let mut a = s;
        let mut b = (s + dt).min(hi);
        while dist(b) < 0.0 && b < hi {
            a = b;
            b = (b + dt).min(hi);
        }
        if dist(b) < 0.0 {
            nodes.push(hi);
            break;
        }
        for _ in 0..100 {
            let m = 0.5 * (a + b);
            if dist(m) < 0.0 {
                a = m;
            } else {
                b = m;
            }
        }
        s = b;
        nodes.push(s);
    }
    Ok(nodes)
}

/// How the two classical spacings are sized.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sizing {
    /// From the smallest radius of curvature (seed 003): L = 2√(2ρ_min·d − d²).
    MinRadius,
    /// The widest uniform spacing whose every chord is within d (searched).
    Widest,
}

/// The spacings compared by seed 003.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Spacing {
    /// Every chord deviates by d.
    EqualError,
    /// Constant parameter step.
    EqualInterval(Sizing),
    /// Constant chord length.
    EqualStep(Sizing),
}

impl Spacing {
    /// A label for tables.
    #[must_use]
    pub fn label(self) -> &'static str {
        match self {
            Self::EqualError => "equal-error",
            Self::EqualInterval(Sizing::MinRadius) => "equal-interval, sized by ρ_min",
            Self::EqualInterval(Sizing::Widest) => "equal-interval, widest within d",
            Self::EqualStep(Sizing::MinRadius) => "equal-step, sized by ρ_min",
            Self::EqualStep(Sizing::Widest) => "equal-step, widest within d",
        }
    }

    /// Every spacing, in table order.
    pub const ALL: [Self; 5] = [
        Self::EqualError,
        Self::EqualInterval(Sizing::MinRadius),
        Self::EqualInterval(Sizing::Widest),
        Self::EqualStep(Sizing::MinRadius),
        Self::EqualStep(Sizing::Widest),
    ];
}

/// One row of the seed-003 comparison.
#[derive(Clone, Debug, PartialEq)]
pub struct SpacingRow {
    /// Which spacing.
    pub spacing: Spacing,
    /// Node parameters.
    pub params: Vec<f64>,
    /// Every chord's deviation (mm).
    pub errors_mm: Vec<f64>,
    /// The uniform step used (parameter step or chord length in mm; 0 for equal-error).
    pub step: f64,
}

impl SpacingRow {
    /// The largest chord deviation (mm).
    #[must_use]
    pub fn worst_mm(&self) -> f64 {
        self.errors_mm.iter().copied().fold(0.0, f64::max)
    }
}

/// Nodes of one spacing for tolerance d.
///
/// # Errors
/// [`ChordError`] from the equal-error search or a node count past `opts.max_nodes`.
pub fn spacing_nodes(
    curve: &dyn Curve3,
    d: f64,
    spacing: Spacing,
    opts: &ChordOptions,
) -> Result<SpacingRow, ChordError> {
    if !(d > 0.0 && d.is_finite()) {
        return Err(ChordError::BadTolerance { tol_mm: d });
    }
    let dev = DeviationOptions { floor_mm: opts.deviation_floor_rel * d, ..opts.deviation };
    let (lo, hi) = curve.range();
    // Length of the curve (a 256-chord polyline; enough to cap a step).
    let length: f64 = equal_interval_nodes(curve, (hi - lo) / 256.0)
        .windows(2)
        .map(|w| (curve.point_at(w[1]) - curve.point_at(w[0])).length())
        .sum();
    let min_radius_chord = || {
        let (s, rho) = min_radius(curve);
        let l = if rho.is_finite() && rho > 0.5 * d { 2.0 * (2.0 * rho * d - d * d).sqrt() } else { 2.0 * d };
        (s, l.min(length.max(2.0 * d)))
    };
    let guard = |n: f64| {
        if n > opts.max_nodes as f64 {
            Err(ChordError::TooManyNodes { tol_mm: d, max_nodes: opts.max_nodes, s: lo, start: lo, end: hi })
        } else {
            Ok(())
        }
    };
    let (params, step) = match spacing {
        Spacing::EqualError => (equal_error_chords_with(curve, d, opts)?.params, 0.0),
        Spacing::EqualInterval(Sizing::MinRadius) => {
            let (s, l) = min_radius_chord();
            let speed = curve.derivatives_at(s)[1].length();
            let step = if speed > 0.0 { l / speed } else { hi - lo };
            guard((hi - lo) / step)?;
            (equal_interval_nodes(curve, step), step)
        }
        Spacing::EqualStep(Sizing::MinRadius) => {
            let (_, l) = min_radius_chord();
            (equal_step_nodes(curve, l, opts.max_nodes)?, l)
        }
        Spacing::EqualInterval(Sizing::Widest) => {
            // The fewest equal parts of the range with every chord within d.
            let worst = |n: usize| -> f64 {
                let p = equal_interval_nodes(curve, (hi - lo) / n as f64);
                chord_errors(curve, &p, &dev).into_iter().fold(0.0, f64::max)
            };
            let mut n = 1usize;
            let mut w = worst(n);
            while w > d {
                // Chord errors scale as 1/n²: jump close, then step.
                let next = ((n as f64) * (w / d).sqrt()).ceil() as usize;
                n = next.max(n + 1);
                guard(n as f64)?;
                w = worst(n);
            }
            while n > 1 && worst(n - 1) <= d {
                n -= 1;
            }
            let step = (hi - lo) / n as f64;
            (equal_interval_nodes(curve, step), step)
        }
        Spacing::EqualStep(Sizing::Widest) => {
            // Bisection on L between a length that keeps every chord within d and one that
            // does not.
            let worst = |l: f64| -> Result<f64, ChordError> {
                let p = equal_step_nodes(curve, l, opts.max_nodes)?;
                Ok(chord_errors(curve, &p, &dev).into_iter().fold(0.0, f64::max))
            };
            let (_, l0) = min_radius_chord();
            let mut ok = l0;
            while worst(ok)? > d {
                ok *= 0.5;
                guard((hi - lo) / ok)?;
            }
            let mut bad = ok * 2.0;
            while worst(bad)? <= d && bad < 2.0 * length {
                ok = bad;
                bad *= 2.0;
            }
            for _ in 0..40 {
                let m = 0.5 * (ok + bad);
                if worst(m)? <= d {
                    ok = m;
                } else {
                    bad = m;
                }
            }
            (equal_step_nodes(curve, ok, opts.max_nodes)?, ok)
        }
    };
    let errors_mm = chord_errors(curve, &params, &dev);
    Ok(SpacingRow { spacing, params, errors_mm, step })
}

/// The seed-003 parabola y = a·x² with a = 0.025 /mm (vertex radius 20 mm) for x from 0 to
/// 60 mm — the x > 0 half of the project's parabola profile.
#[must_use]
pub fn seed003_parabola() -> Parabola {
    Parabola { a: 0.025, x0: 0.0, x1: 60.0, z: 0.0 }
}

/// The hyperbola x·y = 400 mm² for x from 5 to 80 mm (vertex radius √800 ≈ 28.3 mm at
/// (20, 20)).
#[must_use]
pub fn seed003_hyperbola() -> Hyperbola {
    Hyperbola { k: 400.0, x0: 5.0, x1: 80.0 }
}

/// A quarter of the ellipse with semi-axes 60 and 30 mm, from (60, 0) to (0, 30) (radius of
/// curvature 15 to 120 mm).
#[must_use]
pub fn seed003_ellipse() -> Ellipse {
    Ellipse { a: 60.0, b: 30.0, t0: 0.0, t1: std::f64::consts::FRAC_PI_2 }
}
