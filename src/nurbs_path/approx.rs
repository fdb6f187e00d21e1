//! Approximation to a tolerance: a B-spline with far fewer control points than data points,
//! every data point (or every point of a design curve) within a tolerance E of it.
//!
//! Method — least squares with adaptive knot refinement (Piegl & Tiller §9.4.1 for the
//! constrained least-squares fit, refinement in the spirit of their A9.10):
//!
//! 1. start from a clamped knot vector with a few equal spans;
//! 2. fit the control points by least squares with the end points (and optionally the end
//!    tangents) held exactly: the two end rows are fixed, `Σ_k N_i(u_k) N_j(u_k) P_j =
//!    Σ_k N_i(u_k) R_k` for the free ones, a banded symmetric system of bandwidth p;
//! 3. measure the error of every knot span as a true distance (foot points by Newton, not
//!    the parametric difference |C(u_k) − Q_k|, which overstates it);
//! 4. insert a knot into every span whose error exceeds E and go to 2; stop when none does;
//! 5. optionally (`equidistribute`), move the knots so every span carries an equal share of
//!    the error: a span of length h of a degree-p fit errs by about c·h^{p+1}, so with the
//!    measured errors e_i the density ρ_i = e_i^{1/(p+1)} / h_i is integrated and the
//!    fewest spans N with ∫ρ ≤ N·(γE)^{1/(p+1)} (γ = 0.85, a margin) are placed at equal
//!    shares of ∫ρ (de Boor's error equidistribution); kept if the refit holds E, repeated
//!    while it saves spans.
//!
//! For a design curve ([`approximate_curve`]) the parameter is the design curve's arc length
//! (the limit of cumulative chord length, seed 004's parametrisation, as the points become
//! dense), the data are samples of the design curve inside every span, and the error of a
//! span is the larger of (a) the distance from the fitted curve to the design curve, maximised
//! over the span by sampling and golden-section refinement, and (b) the distance from the
//! data samples to the fitted curve — both ways, so neither curve may stray from the other.

#![expect(
    clippy::neg_cmp_op_on_partial_ord,
    reason = "`!(x > 0.0)` is deliberately true for NaN: bad input is rejected, never passed on"
)]

use glam::DVec3;

use super::FitError;
use super::band::{self, BandRow};
use super::fit::{Parametrization, basis_row, check_points, parameters};
use crate::geom::nurbs::MAX_DEGREE;
use crate::geom::{Curve3, NurbsCurve};
use crate::numerics::knots::span_breaks;
use crate::numerics::maximise::max_on_interval;
use crate::numerics::measure::{ArcLengthTable, nearest_on_curve};

/// Options of [`approximate_curve`] and [`approximate_points`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ApproxOptions {
    /// Degree p (default 3). G06.2 takes degree 1 to 3 (order P2 … P4).
    pub degree: usize,
    /// Hold the end tangents of the data as well as the end points (default true): the
    /// curve then leaves and enters along the design direction.
    pub end_tangents: bool,
    /// Length of the initial knot spans (mm, default 20). Refinement halves spans as needed.
    pub initial_span_mm: f64,
    /// Least data samples per knot span (default 12; at least p + 1 keeps the system regular).
    pub samples_per_span: usize,
    /// Largest spacing of data samples along a design curve (mm, default 0.5).
    pub sample_spacing_mm: f64,
    /// Samples per span of the deviation check, before golden-section refinement of the
    /// worst (default 16).
    pub check_samples: usize,
    /// Most control points before giving up (default 20000).
    pub max_control_points: usize,
    /// Knots are multiples of this (mm) when given: a G06.2 program writes knots at the
    /// machine resolution, so the fit is made with the knots the program will carry.
    pub knot_quantum_mm: Option<f64>,
    /// After refinement, redistribute the knots so every span errs about equally
    /// (default true): fewer control points for the same tolerance.
    pub equidistribute: bool,
    /// Keep every knot span equally long (default false): a controller that implies uniform
    /// knots (Sinumerik `BSPLINE` with one `PL`, LinuxCNC `G5.2`) can carry only such a
    /// curve. Refinement then raises the span count for the whole curve (by the h^{p+1} error
    /// model, at least one more span per round) instead of splitting spans; the knot quantum
    /// and equidistribution are not used.
    pub uniform: bool,
}

impl Default for ApproxOptions {
    fn default() -> Self {
        Self {
            degree: 3,
            end_tangents: true,
            initial_span_mm: 20.0,
            samples_per_span: 12,
            sample_spacing_mm: 0.5,
            check_samples: 16,
            max_control_points: 20_000,
            knot_quantum_mm: None,
            equidistribute: true,
            uniform: false,
        }
    }
}

impl ApproxOptions {
    /// Sets the degree.
    #[must_use]
    pub fn with_degree(mut self, degree: usize) -> Self {
        self.degree = degree;
        self
    }
    /// Sets whether end tangents are held.
    #[must_use]
    pub fn with_end_tangents(mut self, on: bool) -> Self {
        self.end_tangents = on;
        self
    }
    /// Sets the knot quantum (mm).
    #[must_use]
    pub fn with_knot_quantum(mut self, quantum_mm: Option<f64>) -> Self {
        self.knot_quantum_mm = quantum_mm;
        self
    }
    /// Sets knot equidistribution.
    #[must_use]
    pub fn with_equidistribution(mut self, on: bool) -> Self {
        self.equidistribute = on;
        self
    }
    /// Sets whether the knot spans stay equal.
    #[must_use]
    pub fn with_uniform_knots(mut self, on: bool) -> Self {
        self.uniform = on;
        self
    }
    /// Sets the initial span length (mm).
    #[must_use]
    pub fn with_initial_span(mut self, mm: f64) -> Self {
        self.initial_span_mm = mm;
        self
    }
}

/// A fitted curve and how well it fits.
#[derive(Clone, Debug, PartialEq)]
pub struct CurveFit {
    /// The B-spline (weights 1), parameter in mm of the design curve's arc length (rounded to
    /// the knot quantum when one was given).
    pub curve: NurbsCurve,
    /// Largest two-sided distance between the fit and the design curve (mm), as measured.
    pub max_deviation_mm: f64,
    /// Refinement rounds made.
    pub iterations: usize,
    /// Arc length of the design curve (mm).
    pub length_mm: f64,
}

fn check_tol(tol_mm: f64) -> Result<(), FitError> {
    if tol_mm.is_finite() && tol_mm > 0.0 { Ok(()) } else { Err(FitError::BadTolerance { tol_mm }) }
}

fn quantize(x: f64, q: Option<f64>) -> f64 {
    match q {
        Some(q) if q > 0.0 => (x / q).round() * q,
        _ => x,
    }
}

/// Clamped knots over `[0, end]` with `spans` equal spans (quantized).
fn uniform_knots(p: usize, end: f64, spans: usize, q: Option<f64>) -> Vec<f64> {
    let mut k = vec![0.0; p + 1];
    for i in 1..spans {
        let v = quantize(end * i as f64 / spans as f64, q);
        if v > k[k.len() - 1] && v < end {
            k.push(v);
        }
    }
    k.extend(std::iter::repeat_n(end, p + 1));
    k
}

/// The clamped knot vector of degree `p` ending at `end` with a knot added inside each span
/// `i` (between breakpoints `w[0] < w[1]`) for which `split(i, w)` gives a value strictly
/// inside it; `None` when no span was split.
fn refine_knots(
    knots: &[f64],
    p: usize,
    end: f64,
    mut split: impl FnMut(usize, [f64; 2]) -> Option<f64>,
) -> Option<Vec<f64>> {
    let bps = span_breaks(knots, p);
    let mut refined: Vec<f64> = knots[..=p].to_vec();
    let mut added = false;
    for (i, w) in bps.windows(2).enumerate() {
        if let Some(mid) = split(i, [w[0], w[1]]).filter(|&m| m > w[0] && m < w[1]) {
            refined.push(mid);
            added = true;
        }
        if i + 2 < bps.len() {
            refined.push(w[1]);
        }
    }
    refined.extend(std::iter::repeat_n(end, p + 1));
    added.then_some(refined)
}

/// Least-squares control points for data `(u, q)` with the end points (and end derivatives
/// `ends`, per unit parameter) held exactly.
fn least_squares(
    p: usize,
    knots: &[f64],
    u: &[f64],
    q: &[DVec3],
    ends: Option<(DVec3, DVec3)>,
) -> Result<Vec<DVec3>, FitError> {
    let n_ctrl = knots.len() - p - 1;
    let last = n_ctrl - 1;
    let mut fixed: Vec<Option<DVec3>> = vec![None; n_ctrl];
    fixed[0] = Some(q[0]);
    fixed[last] = Some(q[q.len() - 1]);
    if let Some((d0, dn)) = ends {
        if n_ctrl < 4 {
            return Err(FitError::TooFewPoints { got: n_ctrl, need: 4, degree: p });
        }
        fixed[1] = Some(q[0] + d0 * (knots[p + 1] - knots[0]) / p as f64);
        fixed[last - 1] = Some(q[q.len() - 1] - dn * (knots[last + p] - knots[last]) / p as f64);
    }
    let lo = fixed.iter().position(Option::is_none);
    let Some(lo) = lo else {
        return Ok(fixed.into_iter().map(|f| f.unwrap_or(DVec3::ZERO)).collect());
    };
    let hi = fixed.iter().rposition(Option::is_none).unwrap_or(lo);
    let m = hi - lo + 1;
    let w = 2 * p + 1;
    // acc[r][c − r + p]: normal-matrix entry (r, c) for unknowns r, c (relative to lo).
    let mut acc = vec![vec![0.0; w]; m];
    let mut rhs = vec![DVec3::ZERO; m];
    for (k, (&uk, &qk)) in u.iter().zip(q.iter()).enumerate() {
        if k == 0 || k + 1 == u.len() {
            continue;
        }
        let row = basis_row(knots, n_ctrl, p, uk);
        let mut r_k = qk;
        for (j, &nj) in row.vals.iter().enumerate() {
            if let Some(pf) = fixed[row.start + j] {
                r_k -= nj * pf;
            }
        }
        for (a, &na) in row.vals.iter().enumerate() {
            let ia = row.start + a;
            if fixed[ia].is_some() || na == 0.0 {
                continue;
            }
            let ra = ia - lo;
            rhs[ra] += na * r_k;
            for (b, &nb) in row.vals.iter().enumerate() {
                let ib = row.start + b;
                if fixed[ib].is_some() {
                    continue;
                }
                let rb = ib - lo;
                acc[ra][rb + p - ra] += na * nb;
            }
        }
    }
    let rows: Vec<BandRow> = acc
        .into_iter()
        .enumerate()
        .map(|(r, vals)| {
            let start = r.saturating_sub(p);
            let skip = start + p - r;
            let take = (m - start).min(w - skip);
            BandRow::new(start, vals[skip..skip + take].to_vec())
        })
        .collect();
    let sol = band::solve(rows, rhs).ok_or(FitError::Singular)?;
    let mut out = Vec::with_capacity(n_ctrl);
    for (i, f) in fixed.iter().enumerate() {
        out.push(match f {
            Some(v) => *v,
            None => sol[i - lo],
        });
    }
    Ok(out)
}

/// Design-curve data of one refinement round: per sample its fit parameter u, design
/// parameter t and point.
struct Samples {
    u: Vec<f64>,
    t: Vec<f64>,
    q: Vec<DVec3>,
}

struct DesignMap<'a> {
    design: &'a dyn Curve3,
    table: ArcLengthTable,
    /// Fit parameter per mm of arc length (1 unless the end knot was rounded).
    scale: f64,
}

impl DesignMap<'_> {
    fn t_of_u(&self, u: f64) -> f64 {
        self.table.t_at(self.design, u / self.scale)
    }
}

fn sample_design(map: &DesignMap<'_>, bps: &[f64], opts: &ApproxOptions) -> Samples {
    let mut s = Samples { u: vec![], t: vec![], q: vec![] };
    let push = |s: &mut Samples, u: f64| {
        let t = map.t_of_u(u);
        s.u.push(u);
        s.t.push(t);
        s.q.push(map.design.point_at(t));
    };
    push(&mut s, bps[0]);
    for w in bps.windows(2) {
        let len = (w[1] - w[0]) / map.scale;
        let n = opts.samples_per_span.max(opts.degree + 1).max((len / opts.sample_spacing_mm).ceil() as usize);
        for i in 1..=n {
            push(&mut s, w[0] + (w[1] - w[0]) * i as f64 / n as f64);
        }
    }
    s
}

/// Two-sided deviation of every knot span of `curve` from the design curve.
fn span_errors(curve: &NurbsCurve, map: &DesignMap<'_>, bps: &[f64], data: &Samples, opts: &ApproxOptions) -> Vec<f64> {
    let (ta, tb) = map.design.range();
    let mut errs = vec![0.0_f64; bps.len() - 1];
    let mut k = 0usize;
    for (i, w) in bps.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        // Indices of the data samples of this span (including its ends).
        while k + 1 < data.u.len() && data.u[k + 1] <= a {
            k += 1;
        }
        let first = k;
        let mut last = k;
        while last + 1 < data.u.len() && data.u[last] < b {
            last += 1;
        }
        // (b) data → fit.
        let mut e = 0.0_f64;
        for j in first..=last {
            let f = nearest_on_curve(curve, data.q[j], data.u[j], a, b);
            e = e.max(f.dist);
        }
        // (a) fit → design, the design foot point guessed by interpolating the samples' t.
        let guess = |u: f64| -> f64 {
            if last == first {
                return data.t[first];
            }
            let idx = data.u[first..=last].partition_point(|&x| x <= u);
            let j = (first + idx).saturating_sub(1).clamp(first, last - 1);
            let (u0, u1) = (data.u[j], data.u[j + 1]);
            if u1 > u0 { data.t[j] + (data.t[j + 1] - data.t[j]) * (u - u0) / (u1 - u0) } else { data.t[j] }
        };
        let mut dev = |u: f64| {
            let x = curve.point_at(u);
            nearest_on_curve(map.design, x, guess(u), ta, tb).dist
        };
        let (worst, _) = max_on_interval(&mut dev, a, b, opts.check_samples, 20);
        errs[i] = e.max(worst);
    }
    errs
}

fn validate_degree(p: usize) -> Result<(), FitError> {
    if p == 0 || p > MAX_DEGREE { Err(FitError::Degree(p)) } else { Ok(()) }
}

/// The error-density shares e_i^{1/(p+1)} of the spans.
fn error_shares(errs: &[f64], p: usize, tol_mm: f64) -> Vec<f64> {
    let ex = 1.0 / (p as f64 + 1.0);
    errs.iter().map(|&e| e.max(crate::numerics::tolerance::ERROR_SHARE_FLOOR_REL * tol_mm).powf(ex)).collect()
}

/// The fewest spans whose equidistributed errors would stay at 0.85·E by the h^{p+1} model,
/// or `None` if that is not fewer than now.
fn predicted_spans(errs: &[f64], p: usize, tol_mm: f64) -> Option<usize> {
    let total: f64 = error_shares(errs, p, tol_mm).iter().sum();
    let unit = (0.85 * tol_mm).powf(1.0 / (p as f64 + 1.0));
    let n = (total / unit).ceil().max(1.0) as usize;
    (n < errs.len()).then_some(n)
}

/// `n` spans placed at equal shares of the error density (see the module notes).
fn equidistributed_knots(bps: &[f64], errs: &[f64], p: usize, n: usize, quantum: Option<f64>) -> Vec<f64> {
    let shares = error_shares(errs, p, errs.iter().copied().fold(0.0, f64::max).max(f64::MIN_POSITIVE));
    let total: f64 = shares.iter().sum();
    let end = bps[bps.len() - 1];
    let mut knots = vec![bps[0]; p + 1];
    let mut acc = 0.0;
    let mut span = 0;
    for k in 1..n {
        let goal = total * k as f64 / n as f64;
        while span < shares.len() && acc + shares[span] < goal {
            acc += shares[span];
            span += 1;
        }
        let span = span.min(shares.len() - 1);
        let frac = if shares[span] > 0.0 { ((goal - acc) / shares[span]).clamp(0.0, 1.0) } else { 0.5 };
        let u = quantize(bps[span] + frac * (bps[span + 1] - bps[span]), quantum);
        if u > knots[knots.len() - 1] && u < end {
            knots.push(u);
        }
    }
    knots.extend(std::iter::repeat_n(end, p + 1));
    knots
}

/// Fits a B-spline to a design curve within `tol_mm` (two-sided distance), parametrised by
/// arc length (mm). The end points are the design curve's, exactly.
///
/// # Errors
/// A bad tolerance or degree, an empty curve, or a tolerance that needs more control points
/// than allowed (or spans shorter than the knot quantum).
pub fn approximate_curve(design: &dyn Curve3, tol_mm: f64, opts: &ApproxOptions) -> Result<CurveFit, FitError> {
    check_tol(tol_mm)?;
    let p = opts.degree;
    validate_degree(p)?;
    let (ta, tb) = design.range();
    if !(ta.is_finite() && tb.is_finite() && tb > ta) {
        return Err(FitError::EmptyCurve);
    }
    let table = ArcLengthTable::new(design, 64);
    let length = table.length();
    if !(length.is_finite() && length > crate::numerics::tolerance::FIT_DUPLICATE_MM) {
        return Err(FitError::EmptyCurve);
    }
    let quantum = if opts.uniform { None } else { opts.knot_quantum_mm };
    let end = quantize(length, quantum);
    if !(end > 0.0) {
        return Err(FitError::EmptyCurve);
    }
    let map = DesignMap { design, table, scale: end / length };
    let ends = |_: &()| -> Option<(DVec3, DVec3)> {
        if !opts.end_tangents {
            return None;
        }
        let d0 = design.derivatives_at(ta)[1];
        let d1 = design.derivatives_at(tb)[1];
        // dC/du = C'(t) / |C'(t)| / scale.
        Some((d0.normalize_or_zero() / map.scale, d1.normalize_or_zero() / map.scale))
    };
    let ends = ends(&());
    let min_spans = if opts.end_tangents { 4usize.saturating_sub(p).max(1) } else { 1 };
    let spans =
        ((length / opts.initial_span_mm.max(crate::numerics::tolerance::MIN_SPAN_MM)).ceil() as usize).max(min_spans);
    let mut knots = uniform_knots(p, end, spans, quantum);
    let fit_with = |knots: &[f64]| -> Result<(NurbsCurve, Vec<f64>), FitError> {
        let bps = span_breaks(knots, p);
        let data = sample_design(&map, &bps, opts);
        let ctrl = least_squares(p, knots, &data.u, &data.q, ends)?;
        let curve = NurbsCurve::try_new(p, knots.to_vec(), &ctrl, None).map_err(FitError::Nurbs)?;
        let errs = span_errors(&curve, &map, &bps, &data, opts);
        Ok((curve, errs))
    };
    let mut iterations = 0;
    let (mut curve, mut errs) = loop {
        iterations += 1;
        let (curve, errs) = fit_with(&knots)?;
        let bad: Vec<usize> = (0..errs.len()).filter(|&i| !(errs[i] <= tol_mm)).collect();
        if bad.is_empty() {
            break (curve, errs);
        }
        let worst = errs.iter().copied().fold(0.0_f64, f64::max);
        if opts.uniform {
            // Equal spans: an error e of spans h scales as h^{p+1}, so the count that brings
            // the worst to 0.85·E, and at least one span more.
            let spans_now = curve.len() - p;
            let grow = (worst / (0.85 * tol_mm)).powf(1.0 / (p as f64 + 1.0));
            let next = if grow.is_finite() { (spans_now as f64 * grow).ceil() as usize } else { 0 };
            let next = next.max(spans_now + 1);
            if next + p > opts.max_control_points {
                return Err(FitError::NotConverged { tol_mm, achieved_mm: worst, control_points: curve.len() });
            }
            knots = uniform_knots(p, end, next, None);
            continue;
        }
        if curve.len() + bad.len() > opts.max_control_points {
            return Err(FitError::NotConverged { tol_mm, achieved_mm: worst, control_points: curve.len() });
        }
        let split = refine_knots(&knots, p, end, |i, w| {
            bad.contains(&i).then(|| quantize(0.5 * (w[0] + w[1]), opts.knot_quantum_mm))
        });
        let Some(split) = split else {
            return Err(FitError::NotConverged { tol_mm, achieved_mm: worst, control_points: curve.len() });
        };
        knots = split;
    };
    if opts.equidistribute && !opts.uniform {
        // At most 10 refits: each round tries the predicted span count, then one more, …,
        // up to one fewer than now; the first that holds E is kept and the next round
        // starts from its errors.
        let mut budget = 10;
        'rounds: while budget > 0 {
            let bps = span_breaks(&knots, p);
            let spans_now = bps.len() - 1;
            let Some(first) = predicted_spans(&errs, p, tol_mm) else {
                break;
            };
            for n in first.max(min_spans)..spans_now {
                if budget == 0 {
                    break 'rounds;
                }
                budget -= 1;
                let trial = equidistributed_knots(&bps, &errs, p, n, opts.knot_quantum_mm);
                if let Ok((c, e)) = fit_with(&trial)
                    && e.iter().all(|&x| x <= tol_mm)
                {
                    knots = trial;
                    curve = c;
                    errs = e;
                    continue 'rounds;
                }
            }
            break;
        }
    }
    let max_deviation_mm = errs.iter().copied().fold(0.0_f64, f64::max);
    Ok(CurveFit { curve, max_deviation_mm, iterations, length_mm: length })
}

/// A B-spline approximating points, and its largest point distance.
#[derive(Clone, Debug, PartialEq)]
pub struct PointsFit {
    /// The B-spline (weights 1), parameter from `parametrization` over [0, chord length].
    pub curve: NurbsCurve,
    /// Largest distance from a data point to the curve (mm).
    pub max_deviation_mm: f64,
    /// Whether refinement ended in interpolation (as many control points as points).
    pub interpolates: bool,
}

/// Approximates `points` within `tol_mm`: every point lies within `tol_mm` of the curve
/// (distance to its foot point), with fewer control points than points wherever the data
/// allow it. The first and last points are interpolated. Knots are inserted at the median
/// parameter of a failing span's points, so every span keeps data; if a span cannot be
/// split further the result is the interpolating curve (error 0).
///
/// # Errors
/// A bad tolerance or degree, too few, repeated or non-finite points.
pub fn approximate_points(
    points: &[DVec3],
    tol_mm: f64,
    parametrization: Parametrization,
    opts: &ApproxOptions,
) -> Result<PointsFit, FitError> {
    check_tol(tol_mm)?;
    let p = opts.degree;
    validate_degree(p)?;
    let need = (p + 1).max(3);
    if points.len() < need {
        return Err(FitError::TooFewPoints { got: points.len(), need, degree: p });
    }
    check_points(points)?;
    let u = parameters(points, parametrization)?;
    let end = u[u.len() - 1];
    let interp = || -> Result<PointsFit, FitError> {
        let o = super::fit::InterpolateOptions::default()
            .with_degree(p)
            .with_parametrization(parametrization)
            .with_end(if opts.end_tangents {
                super::fit::EndCondition::EstimatedTangents
            } else {
                super::fit::EndCondition::Free
            });
        let curve = super::fit::interpolate(points, &o)?;
        Ok(PointsFit { curve, max_deviation_mm: 0.0, interpolates: true })
    };
    let ends = if opts.end_tangents {
        let n = points.len() - 1;
        let t0 = ((2.0 * (u[1] - u[0]) + (u[2] - u[1])) * (points[1] - points[0]) / (u[1] - u[0])
            - (u[1] - u[0]) * (points[2] - points[1]) / (u[2] - u[1]))
            / (u[2] - u[0]);
        let (h1, h2) = (u[n] - u[n - 1], u[n - 1] - u[n - 2]);
        let tn = ((2.0 * h1 + h2) * (points[n] - points[n - 1]) / h1 - h1 * (points[n - 1] - points[n - 2]) / h2)
            / (h1 + h2);
        Some((t0, tn))
    } else {
        None
    };
    let min_ctrl = if opts.end_tangents { 4.max(p + 1) } else { p + 1 };
    let mut knots = uniform_knots(p, end, (min_ctrl - p).max(1), None);
    loop {
        if knots.len() - p > points.len() {
            return interp();
        }
        let Ok(ctrl) = least_squares(p, &knots, &u, points, ends) else {
            return interp();
        };
        let curve = NurbsCurve::try_new(p, knots.clone(), &ctrl, None).map_err(FitError::Nurbs)?;
        let bps = span_breaks(&knots, p);
        let mut worst = vec![0.0_f64; bps.len() - 1];
        for (&uk, &qk) in u.iter().zip(points.iter()) {
            let span = bps.partition_point(|&b| b <= uk).clamp(1, bps.len() - 1) - 1;
            let lo = bps[span.saturating_sub(1)];
            let hi = bps[(span + 2).min(bps.len() - 1)];
            let d = nearest_on_curve(&curve, qk, uk, lo, hi).dist;
            worst[span] = worst[span].max(d);
        }
        let max = worst.iter().copied().fold(0.0_f64, f64::max);
        if max <= tol_mm {
            return Ok(PointsFit { curve, max_deviation_mm: max, interpolates: false });
        }
        // Split each span over the tolerance at the median parameter of its data points.
        let split = refine_knots(&knots, p, end, |i, w| {
            if worst[i] <= tol_mm {
                return None;
            }
            let inside: Vec<f64> = u.iter().copied().filter(|&x| x > w[0] && x < w[1]).collect();
            (inside.len() >= 2).then(|| 0.5 * (inside[(inside.len() - 1) / 2] + inside[inside.len() / 2]))
        });
        let Some(split) = split else {
            return interp();
        };
        knots = split;
    }
}
