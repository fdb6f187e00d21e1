//! Rational B-splines (NURBS): basis functions with derivatives, curves and tensor-product
//! surfaces, evaluated by the standard algorithms (knot-span search, the triangular table of
//! basis functions and their derivatives, then the rational quotient rule) — never by finite
//! differences.
//!
//! A NURBS is stored in homogeneous form `Pw = (w·x, w·y, w·z, w)`. With `A(u)` the
//! B-spline combination of the first three coordinates and `w(u)` that of the fourth,
//! `C = A / w` and the quotient rule gives
//!
//! - `C' = (A' − w'·C) / w`
//! - `C'' = (A'' − 2w'·C' − w''·C) / w`
//!
//! and for surfaces, with subscripts for partial derivatives,
//! `S_uv = (A_uv − w_u·S_v − w_v·S_u − w_uv·S) / w`.

use glam::{DVec2, DVec3, DVec4};
use thiserror::Error;

use super::domain::{Domain, ParamRange, ParamUnit};
use super::parametric::{ParametricSurface, SurfaceDerivs};
use crate::numerics::tolerance;

/// Highest supported degree. Basis tables live on the stack in fixed arrays of this order.
pub const MAX_DEGREE: usize = 9;
const MAX_ORDER: usize = MAX_DEGREE + 1;

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

/// Basis functions `N_{span−p+j, p}` and their first and second derivatives at `u`:
/// `ders[k][j]` is the k-th derivative, `j = 0..=p`. Derivatives above the degree are zero.
#[must_use]
pub fn basis_derivatives(knots: &[f64], span: usize, p: usize, u: f64) -> [[f64; MAX_ORDER]; 3] {
    // The common degrees with p a constant, so the loops unroll and the unused parts of the
    // tables vanish; the arithmetic (and so every bit of the result) is the same.
    match p {
        1 => basis_derivatives_of(knots, span, 1, u),
        2 => basis_derivatives_of(knots, span, 2, u),
        3 => basis_derivatives_of(knots, span, 3, u),
        _ => basis_derivatives_of(knots, span, p, u),
    }
}

/// The basis functions `N_{span−p+j, p}(u)`, `j = 0..=p`: the first row of
/// [`basis_derivatives`], by the same arithmetic (the same bits) without the derivatives.
#[must_use]
pub fn basis_functions(knots: &[f64], span: usize, p: usize, u: f64) -> [f64; MAX_ORDER] {
    match p {
        1 => basis_functions_of(knots, span, 1, u),
        2 => basis_functions_of(knots, span, 2, u),
        3 => basis_functions_of(knots, span, 3, u),
        _ => basis_functions_of(knots, span, p, u),
    }
}

#[inline(always)]
fn basis_functions_of(knots: &[f64], span: usize, p: usize, u: f64) -> [f64; MAX_ORDER] {
    let mut n = [0.0; MAX_ORDER];
    let mut left = [0.0; MAX_ORDER];
    let mut right = [0.0; MAX_ORDER];
    n[0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            // As in `basis_derivatives_of`: n[r] holds ndu[r][j − 1], the divisor ndu[j][r].
            let temp = n[r] / (right[r + 1] + left[j - r]);
            n[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        n[j] = saved;
    }
    n
}

#[inline(always)]
fn basis_derivatives_of(knots: &[f64], span: usize, p: usize, u: f64) -> [[f64; MAX_ORDER]; 3] {
    basis_derivatives_sized::<MAX_ORDER, 2>(knots, span, p, u)
}

/// [`basis_derivatives_of`] in tables of order `O` (> p; the exact p + 1 for the common
/// degrees, so no unused table is cleared) up to the derivative order `D` (≤ 2; the rows
/// above it stay zero), by the same arithmetic: the values it computes have the same bits.
#[inline(always)]
fn basis_derivatives_sized<const O: usize, const D: usize>(
    knots: &[f64],
    span: usize,
    p: usize,
    u: f64,
) -> [[f64; O]; 3] {
    let mut ndu = [[0.0; O]; O];
    let mut left = [0.0; O];
    let mut right = [0.0; O];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            // Lower triangle: knot differences; upper: basis functions.
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    let mut ders = [[0.0; O]; 3];
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    let nd = p.min(D);
    let mut a = [[0.0; 3]; 2];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0][0] = 1.0;
        for k in 1..=nd {
            let mut d = 0.0;
            let pk = p - k;
            // rk = r − k may be negative; keep it signed.
            let rk = r as isize - k as isize;
            if rk >= 0 {
                a[s2][0] = a[s1][0] / ndu[pk + 1][rk as usize];
                d = a[s2][0] * ndu[rk as usize][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if r as isize - 1 <= pk as isize { k - 1 } else { p - r };
            let mut j = j1;
            while j <= j2 {
                let idx = (rk + j as isize) as usize;
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                d += a[s2][j] * ndu[idx][pk];
                j += 1;
            }
            if r <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut factor = p as f64;
    for (k, row) in ders.iter_mut().enumerate().take(nd + 1).skip(1) {
        for v in row.iter_mut().take(p + 1) {
            *v *= factor;
        }
        factor *= (p - k) as f64;
    }
    ders
}

/// A NURBS curve of any degree up to [`MAX_DEGREE`] in 3D (mm).
#[derive(Clone, Debug, PartialEq)]
pub struct NurbsCurve {
    degree: usize,
    knots: Vec<f64>,
    /// Homogeneous control points (w·P, w).
    control: Vec<DVec4>,
}

impl NurbsCurve {
    /// A curve from its degree, clamped knot vector, control points (mm) and optional
    /// weights (all 1 when `None`).
    ///
    /// # Errors
    /// [`NurbsError`] naming the first broken rule.
    pub fn try_new(
        degree: usize,
        knots: Vec<f64>,
        points: &[DVec3],
        weights: Option<&[f64]>,
    ) -> Result<Self, NurbsError> {
        validate_knots(&knots, points.len(), degree)?;
        if let Some(w) = weights {
            if w.len() != points.len() {
                return Err(NurbsError::WeightShape);
            }
            if let Some((index, &value)) = w.iter().enumerate().find(|(_, w)| !(w.is_finite() && **w > 0.0)) {
                return Err(NurbsError::Weight { index, value });
            }
        }
        let control = points
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let w = weights.map_or(1.0, |w| w[i]);
                (*p * w).extend(w)
            })
            .collect();
        Ok(Self { degree, knots, control })
    }

    /// The degree p.
    #[must_use]
    pub fn degree(&self) -> usize {
        self.degree
    }
    /// The knot vector.
    #[must_use]
    pub fn knots(&self) -> &[f64] {
        &self.knots
    }
    /// Number of control points.
    #[must_use]
    pub fn len(&self) -> usize {
        self.control.len()
    }
    /// Never true: a valid curve has at least degree + 1 control points.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.control.is_empty()
    }
    /// Control point `i` in mm (Euclidean, not homogeneous).
    #[must_use]
    pub fn control_point(&self, i: usize) -> DVec3 {
        self.control[i].truncate() / self.control[i].w
    }
    /// Weight of control point `i`.
    #[must_use]
    pub fn weight(&self, i: usize) -> f64 {
        self.control[i].w
    }
    /// Parameter range `[knots[p], knots[n+1]]`.
    #[must_use]
    pub fn range(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.control.len()])
    }

    /// C(u) (mm).
    #[must_use]
    pub fn point_at(&self, u: f64) -> DVec3 {
        self.derivatives_at(u)[0]
    }

    /// `[C, C', C'']` at u (mm, mm per unit u, mm per unit u²).
    #[must_use]
    pub fn derivatives_at(&self, u: f64) -> [DVec3; 3] {
        let p = self.degree;
        let span = find_span(&self.knots, self.control.len(), p, u);
        let n = basis_derivatives(&self.knots, span, p, u);
        let mut aw = [DVec4::ZERO; 3];
        for j in 0..=p {
            let cp = self.control[span - p + j];
            for (k, acc) in aw.iter_mut().enumerate() {
                *acc += n[k][j] * cp;
            }
        }
        let w = aw[0].w;
        let c0 = aw[0].truncate() / w;
        let c1 = (aw[1].truncate() - aw[1].w * c0) / w;
        let c2 = (aw[2].truncate() - 2.0 * aw[1].w * c1 - aw[2].w * c0) / w;
        [c0, c1, c2]
    }
}

/// A tensor-product NURBS surface. `points[i][j]`: i runs along u, j along v.
#[derive(Clone, Debug, PartialEq)]
pub struct NurbsSurface {
    degree: [usize; 2],
    knots_u: Vec<f64>,
    knots_v: Vec<f64>,
    n_u: usize,
    n_v: usize,
    /// Homogeneous control net, row-major: index `i * n_v + j`.
    control: Vec<DVec4>,
    /// −1 when the normal is reversed (`flip_normal`), else +1.
    sign: f64,
    /// The net in power form on every span pair ([`PowerPatches`]); `None` when that
    /// would take more than [`MAX_POWER_COEFFICIENTS`].
    power: Option<PowerPatches>,
}

/// Most homogeneous coefficients a surface's power form (`PowerPatches`) holds (32 bytes each: 2 MB, and 1.5 MB
/// more for the copy without weights of a net whose weights are all 1).
pub const MAX_POWER_COEFFICIENTS: usize = 1 << 16;

/// A tensor-product NURBS in power form, one polynomial patch per knot-span pair: on span
/// `[u0, u0 + Δu) × [v0, v0 + Δv)`, with `s = (u − u0)/Δu` and `t = (v − v0)/Δv`, the
/// homogeneous surface is `A(s, t) = Σ_m Σ_n a_mn s^m t^n`. Each basis function restricted to
/// one span is a polynomial of degree p; its coefficients in s follow from the Cox–de Boor
/// recursion carried out on polynomials (each step multiplies by a linear factor in s), and
/// `a_mn = Σ_i Σ_j c_im d_jn Pw_ij` with c, d those coefficients in u and v. Evaluated by
/// Horner's rule: the same values as the standard algorithm to rounding (not the same bits),
/// at a fraction of the work — for callers whose answer does not hang on the last bits.
#[derive(Clone, Debug, PartialEq)]
struct PowerPatches {
    /// Per knot-span index s − p in u: (u0, Δu); Δu = 0 for an empty span (never looked up).
    spans_u: Vec<(f64, f64)>,
    /// The same in v.
    spans_v: Vec<(f64, f64)>,
    /// `(p + 1)(q + 1)` coefficients per span pair, pair `(iu, iv)` at
    /// `(iu·spans_v.len() + iv)·(p + 1)(q + 1)`, coefficient `a_mn` at `m·(q + 1) + n`.
    coeffs: Vec<DVec4>,
    /// The same without the weight when every weight is 1 (a polynomial surface: w ≡ 1, so
    /// the point and its derivatives are the sums themselves, no quotient rule).
    plain: Option<Vec<DVec3>>,
}

/// Horner's rule on one patch of [`PowerPatches`] (orders `ou` × `ov`): the sum and its
/// derivatives in x and y, `(A, ∂A/∂x, ∂A/∂y)`.
#[inline(always)]
fn horner_tangents<T>(patch: &[T], ou: usize, ov: usize, x: f64, y: f64) -> (T, T, T)
where
    T: Copy + Default + std::ops::Add<Output = T> + std::ops::Mul<f64, Output = T>,
{
    // Along each row m in y (value and derivative), then in x.
    let (mut a00, mut a10, mut a01) = (T::default(), T::default(), T::default());
    for m in (0..ou).rev() {
        let row = &patch[m * ov..][..ov];
        let (mut b, mut db) = (row[ov - 1], T::default());
        for &c in row[..ov - 1].iter().rev() {
            db = db * y + b;
            b = b * y + c;
        }
        a10 = a10 * x + a00;
        a00 = a00 * x + b;
        a01 = a01 * x + db;
    }
    (a00, a10, a01)
}

/// Power-form coefficients of the p + 1 basis functions that are non-zero on knot span s
/// (`N_{s−p+j}`, j = 0..=p) in `x = (u − knots[s])/(knots[s+1] − knots[s])`: `c[j][m]` is
/// the coefficient of x^m. The span must be non-empty.
fn span_power_basis(knots: &[f64], s: usize, p: usize) -> [[f64; MAX_ORDER]; MAX_ORDER] {
    let (u0, du) = (knots[s], knots[s + 1] - knots[s]);
    // n[j] holds N_{s−k+j, k} at level k (j = 0..=k); at level 0 only N_{s,0} = 1.
    let mut n = [[0.0; MAX_ORDER]; MAX_ORDER];
    n[0][0] = 1.0;
    for k in 1..=p {
        let mut next = [[0.0; MAX_ORDER]; MAX_ORDER];
        for (j, out) in next.iter_mut().enumerate().take(k + 1) {
            // i = s − k + j; N_{i,k} = (u − u_i)/(u_{i+k} − u_i)·N_{i,k−1}
            //                        + (u_{i+k+1} − u)/(u_{i+k+1} − u_{i+1})·N_{i+1,k−1},
            // N_{i,k−1} = n[j − 1] (zero for j = 0), N_{i+1,k−1} = n[j] (zero for j = k).
            let i = s + j - k;
            if j >= 1 {
                let den = knots[i + k] - knots[i];
                if den > 0.0 {
                    // (u − u_i)/den = (u0 − u_i)/den + (du/den)·x.
                    let (c0, c1) = ((u0 - knots[i]) / den, du / den);
                    for m in 0..k {
                        out[m] += c0 * n[j - 1][m];
                        out[m + 1] += c1 * n[j - 1][m];
                    }
                }
            }
            if j < k {
                let den = knots[i + k + 1] - knots[i + 1];
                if den > 0.0 {
                    let (c0, c1) = ((knots[i + k + 1] - u0) / den, -du / den);
                    for m in 0..k {
                        out[m] += c0 * n[j][m];
                        out[m + 1] += c1 * n[j][m];
                    }
                }
            }
        }
        n = next;
    }
    n
}

impl PowerPatches {
    /// The patches of a net (row-major `n_u × n_v`, homogeneous) of degrees (p, q), or
    /// `None` beyond [`MAX_POWER_COEFFICIENTS`].
    fn new(degree: [usize; 2], knots: [&[f64]; 2], n: [usize; 2], control: &[DVec4]) -> Option<Self> {
        let [p, q] = degree;
        let (cu, cv) = (n[0] - p, n[1] - q);
        let per = (p + 1) * (q + 1);
        if cu.checked_mul(cv)?.checked_mul(per)? > MAX_POWER_COEFFICIENTS {
            return None;
        }
        let spans = |k: &[f64], deg: usize, count: usize| -> Vec<(f64, f64)> {
            (0..count).map(|i| (k[deg + i], k[deg + i + 1] - k[deg + i])).collect()
        };
        let (spans_u, spans_v) = (spans(knots[0], p, cu), spans(knots[1], q, cv));
        let mut coeffs = vec![DVec4::ZERO; cu * cv * per];
        for (iu, &(_, du)) in spans_u.iter().enumerate() {
            if !(du > 0.0) {
                continue;
            }
            let bu = span_power_basis(knots[0], p + iu, p);
            for (iv, &(_, dv)) in spans_v.iter().enumerate() {
                if !(dv > 0.0) {
                    continue;
                }
                let bv = span_power_basis(knots[1], q + iv, q);
                let patch = &mut coeffs[(iu * cv + iv) * per..][..per];
                for i in 0..=p {
                    for j in 0..=q {
                        let pw = control[(iu + i) * n[1] + iv + j];
                        for m in 0..=p {
                            for l in 0..=q {
                                patch[m * (q + 1) + l] += (bu[i][m] * bv[j][l]) * pw;
                            }
                        }
                    }
                }
            }
        }
        // Exactly 1, not nearly: only then is w ≡ 1 and the quotient rule the identity.
        #[expect(clippy::float_cmp, reason = "a weight of exactly 1 is what makes the surface polynomial")]
        let unit = control.iter().all(|c| c.w == 1.0);
        let plain = unit.then(|| coeffs.iter().map(|c| c.truncate()).collect());
        Some(Self { spans_u, spans_v, coeffs, plain })
    }
}

impl NurbsSurface {
    /// A surface from degrees `[p, q]`, clamped knot vectors, the control net
    /// (`points[i][j]`, i along u) and optional weights of the same shape.
    ///
    /// # Errors
    /// [`NurbsError`] naming the first broken rule.
    pub fn try_new(
        degree: [usize; 2],
        knots_u: Vec<f64>,
        knots_v: Vec<f64>,
        points: &[Vec<DVec3>],
        weights: Option<&[Vec<f64>]>,
        flip_normal: bool,
    ) -> Result<Self, NurbsError> {
        let n_u = points.len();
        let n_v = points.first().map_or(0, Vec::len);
        if let Some((row, r)) = points.iter().enumerate().find(|(_, r)| r.len() != n_v) {
            return Err(NurbsError::Ragged { row, got: r.len(), expected: n_v });
        }
        validate_knots(&knots_u, n_u, degree[0])?;
        validate_knots(&knots_v, n_v, degree[1])?;
        if let Some(w) = weights {
            if w.len() != n_u || w.iter().any(|r| r.len() != n_v) {
                return Err(NurbsError::WeightShape);
            }
            for (index, &value) in w.iter().flatten().enumerate() {
                if !(value.is_finite() && value > 0.0) {
                    return Err(NurbsError::Weight { index, value });
                }
            }
        }
        let mut control = Vec::with_capacity(n_u * n_v);
        for (i, row) in points.iter().enumerate() {
            for (j, p) in row.iter().enumerate() {
                let w = weights.map_or(1.0, |w| w[i][j]);
                control.push((*p * w).extend(w));
            }
        }
        let power = PowerPatches::new(degree, [&knots_u, &knots_v], [n_u, n_v], &control);
        Ok(Self { degree, knots_u, knots_v, n_u, n_v, control, sign: if flip_normal { -1.0 } else { 1.0 }, power })
    }

    /// Degrees `[p, q]`.
    #[must_use]
    pub fn degree(&self) -> [usize; 2] {
        self.degree
    }
    /// Knot vector in u.
    #[must_use]
    pub fn knots_u(&self) -> &[f64] {
        &self.knots_u
    }
    /// Knot vector in v.
    #[must_use]
    pub fn knots_v(&self) -> &[f64] {
        &self.knots_v
    }
    /// Control net size `(n_u, n_v)`.
    #[must_use]
    pub fn net_size(&self) -> (usize, usize) {
        (self.n_u, self.n_v)
    }
    /// Control point `(i, j)` (mm).
    #[must_use]
    pub fn control_point(&self, i: usize, j: usize) -> DVec3 {
        let c = self.control[i * self.n_v + j];
        c.truncate() / c.w
    }
    /// Weight of control point `(i, j)`.
    #[must_use]
    pub fn weight(&self, i: usize, j: usize) -> f64 {
        self.control[i * self.n_v + j].w
    }
    /// Whether the normal is reversed relative to r_u × r_v.
    #[must_use]
    pub fn flipped(&self) -> bool {
        self.sign < 0.0
    }
}

impl ParametricSurface for NurbsSurface {
    fn point_at(&self, uv: DVec2) -> DVec3 {
        match self.degree {
            [3, 3] => self.point_of(uv, 3, 3),
            [2, 2] => self.point_of(uv, 2, 2),
            [2, 1] => self.point_of(uv, 2, 1),
            [1, 2] => self.point_of(uv, 1, 2),
            [p, q] => self.point_of(uv, p, q),
        }
    }

    fn derivatives_at(&self, uv: DVec2) -> SurfaceDerivs {
        // The common degrees with constants, so the sums unroll (the same arithmetic).
        match self.degree {
            [3, 3] => self.derivatives_of::<4, 4>(uv, 3, 3),
            [2, 2] => self.derivatives_of::<3, 3>(uv, 2, 2),
            [2, 1] => self.derivatives_of::<3, 2>(uv, 2, 1),
            [1, 2] => self.derivatives_of::<2, 3>(uv, 1, 2),
            [p, q] => self.derivatives_of::<MAX_ORDER, MAX_ORDER>(uv, p, q),
        }
    }

    fn tangents_at(&self, uv: DVec2) -> (DVec3, DVec3, DVec3) {
        match self.degree {
            [3, 3] => self.tangents_of::<4, 4>(uv, 3, 3),
            [2, 2] => self.tangents_of::<3, 3>(uv, 2, 2),
            [2, 1] => self.tangents_of::<3, 2>(uv, 2, 1),
            [1, 2] => self.tangents_of::<2, 3>(uv, 1, 2),
            [p, q] => self.tangents_of::<MAX_ORDER, MAX_ORDER>(uv, p, q),
        }
    }

    fn tangents_fast_at(&self, uv: DVec2) -> (DVec3, DVec3, DVec3) {
        match self.degree {
            [3, 3] => self.tangents_fast_of::<4, 4>(uv),
            [2, 2] => self.tangents_fast_of::<3, 3>(uv),
            [2, 1] => self.tangents_fast_of::<3, 2>(uv),
            [1, 2] => self.tangents_fast_of::<2, 3>(uv),
            _ => self.tangents_fast_of::<0, 0>(uv),
        }
    }

    fn domain(&self) -> Domain {
        let [p, q] = self.degree;
        Domain {
            u: ParamRange::new(self.knots_u[p], self.knots_u[self.n_u], ParamUnit::Knot),
            v: ParamRange::new(self.knots_v[q], self.knots_v[self.n_v], ParamUnit::Knot),
        }
    }
}

impl NurbsSurface {
    /// r(u, v) of degrees (p, q): the point of [`Self::derivatives_of`], by the same
    /// arithmetic (the same bits), without the derivatives.
    #[inline(always)]
    fn point_of(&self, uv: DVec2, p: usize, q: usize) -> DVec3 {
        let su = find_span(&self.knots_u, self.n_u, p, uv.x);
        let sv = find_span(&self.knots_v, self.n_v, q, uv.y);
        let nu = basis_functions_of(&self.knots_u, su, p, uv.x);
        let nv = basis_functions_of(&self.knots_v, sv, q, uv.y);
        let mut a00 = DVec4::ZERO;
        for i in 0..=p {
            let row = (su - p + i) * self.n_v + (sv - q);
            let mut t0 = DVec4::ZERO;
            for j in 0..=q {
                t0 += nv[j] * self.control[row + j];
            }
            a00 += nu[i] * t0;
        }
        a00.truncate() / a00.w
    }

    /// r, r_u and r_v of degrees (p, q): those of [`Self::derivatives_of`], by the same
    /// arithmetic (the same bits), without the second derivatives.
    #[inline(always)]
    fn tangents_of<const OU: usize, const OV: usize>(&self, uv: DVec2, p: usize, q: usize) -> (DVec3, DVec3, DVec3) {
        let su = find_span(&self.knots_u, self.n_u, p, uv.x);
        let sv = find_span(&self.knots_v, self.n_v, q, uv.y);
        let nu = basis_derivatives_sized::<OU, 1>(&self.knots_u, su, p, uv.x);
        let nv = basis_derivatives_sized::<OV, 1>(&self.knots_v, sv, q, uv.y);
        let (mut a00, mut a10, mut a01) = (DVec4::ZERO, DVec4::ZERO, DVec4::ZERO);
        for i in 0..=p {
            let row = (su - p + i) * self.n_v + (sv - q);
            let (mut t0, mut t1) = (DVec4::ZERO, DVec4::ZERO);
            for j in 0..=q {
                let cp = self.control[row + j];
                t0 += nv[0][j] * cp;
                t1 += nv[1][j] * cp;
            }
            a00 += nu[0][i] * t0;
            a10 += nu[1][i] * t0;
            a01 += nu[0][i] * t1;
        }
        let w = a00.w;
        let s = a00.truncate() / w;
        (s, (a10.truncate() - a10.w * s) / w, (a01.truncate() - a01.w * s) / w)
    }

    /// r, r_u and r_v from the power form ([`PowerPatches`]; the standard algorithm where
    /// there is none): the same values to rounding. `OU`, `OV`: the orders p + 1, q + 1 as
    /// constants, or 0 for any degree.
    #[inline(always)]
    fn tangents_fast_of<const OU: usize, const OV: usize>(&self, uv: DVec2) -> (DVec3, DVec3, DVec3) {
        let Some(power) = &self.power else {
            return self.tangents_at(uv);
        };
        let [p, q] = self.degree;
        let (ou, ov) = if OU == 0 { (p + 1, q + 1) } else { (OU, OV) };
        let su = find_span(&self.knots_u, self.n_u, p, uv.x) - p;
        let sv = find_span(&self.knots_v, self.n_v, q, uv.y) - q;
        let ((u0, du), (v0, dv)) = (power.spans_u[su], power.spans_v[sv]);
        let (x, y) = ((uv.x - u0) / du, (uv.y - v0) / dv);
        let at = (su * power.spans_v.len() + sv) * ou * ov;
        if let Some(plain) = &power.plain {
            let (a00, a10, a01) = horner_tangents(&plain[at..][..ou * ov], ou, ov, x, y);
            return (a00, a10 / du, a01 / dv);
        }
        let (a00, a10, a01) = horner_tangents(&power.coeffs[at..][..ou * ov], ou, ov, x, y);
        let (a10, a01) = (a10 / du, a01 / dv);
        let w = a00.w;
        let s = a00.truncate() / w;
        (s, (a10.truncate() - a10.w * s) / w, (a01.truncate() - a01.w * s) / w)
    }

    #[inline(always)]
    fn derivatives_of<const OU: usize, const OV: usize>(&self, uv: DVec2, p: usize, q: usize) -> SurfaceDerivs {
        let su = find_span(&self.knots_u, self.n_u, p, uv.x);
        let sv = find_span(&self.knots_v, self.n_v, q, uv.y);
        let nu = basis_derivatives_sized::<OU, 2>(&self.knots_u, su, p, uv.x);
        let nv = basis_derivatives_sized::<OV, 2>(&self.knots_v, sv, q, uv.y);
        // Homogeneous sums A^(k,l) = Σ_i Σ_j N_i^(k) N_j^(l) Pw_ij.
        let (mut a00, mut a10, mut a01) = (DVec4::ZERO, DVec4::ZERO, DVec4::ZERO);
        let (mut a20, mut a11, mut a02) = (DVec4::ZERO, DVec4::ZERO, DVec4::ZERO);
        for i in 0..=p {
            let row = (su - p + i) * self.n_v + (sv - q);
            let (mut t0, mut t1, mut t2) = (DVec4::ZERO, DVec4::ZERO, DVec4::ZERO);
            for j in 0..=q {
                let cp = self.control[row + j];
                t0 += nv[0][j] * cp;
                t1 += nv[1][j] * cp;
                t2 += nv[2][j] * cp;
            }
            a00 += nu[0][i] * t0;
            a10 += nu[1][i] * t0;
            a20 += nu[2][i] * t0;
            a01 += nu[0][i] * t1;
            a11 += nu[1][i] * t1;
            a02 += nu[0][i] * t2;
        }
        let w = a00.w;
        let s = a00.truncate() / w;
        let su_ = (a10.truncate() - a10.w * s) / w;
        let sv_ = (a01.truncate() - a01.w * s) / w;
        let suu = (a20.truncate() - 2.0 * a10.w * su_ - a20.w * s) / w;
        let suv = (a11.truncate() - a10.w * sv_ - a01.w * su_ - a11.w * s) / w;
        let svv = (a02.truncate() - 2.0 * a01.w * sv_ - a02.w * s) / w;
        let cross = su_.cross(sv_);
        let len = cross.length();
        let normal = if len > tolerance::MIN_AREA_ELEMENT { self.sign * cross / len } else { DVec3::ZERO };
        SurfaceDerivs { point: s, du: su_, dv: sv_, duu: suu, duv: suv, dvv: svv, normal }
    }
}

#[cfg(test)]
mod tangents_tests {
    use super::*;

    /// `tangents_at` gives exactly (every bit) the point and first derivatives of
    /// `derivatives_at`, for rational surfaces of the specialised and the general degrees.
    #[test]
    fn tangents_are_the_first_derivatives_bit_for_bit() {
        for degree in [[3, 3], [2, 2], [2, 1], [1, 2], [3, 2], [4, 1]] {
            let (n_u, n_v) = (degree[0] + 3, degree[1] + 2);
            let clamped = |p: usize, n: usize| {
                let mut k = vec![0.0; p + 1];
                for i in 1..n - p {
                    k.push(i as f64 / (n - p) as f64 + 0.01 * (i * i) as f64);
                }
                let last = k.last().copied().unwrap_or(0.0) + 0.5;
                k.extend(std::iter::repeat_n(last, p + 1));
                k
            };
            let (points, weights) = wavy_net(n_u, n_v);
            let s = NurbsSurface::try_new(
                degree,
                clamped(degree[0], n_u),
                clamped(degree[1], n_v),
                &points,
                Some(&weights),
                false,
            )
            .unwrap_or_else(|e| panic!("{degree:?}: {e}"));
            let dom = s.domain();
            let mut compared = 0;
            for i in 0..=20 {
                for j in 0..=20 {
                    let uv = DVec2::new(
                        dom.u.min + dom.u.width() * f64::from(i) / 20.0,
                        dom.v.min + dom.v.width() * f64::from(j) / 20.0,
                    );
                    let d = s.derivatives_at(uv);
                    let (p, du, dv) = s.tangents_at(uv);
                    assert!(p == d.point && du == d.du && dv == d.dv, "{degree:?} at {uv}");
                    assert!(d.du.length() > 0.0 && d.dv.length() > 0.0, "{degree:?} at {uv}: degenerate");
                    compared += 1;
                }
            }
            assert_eq!(compared, 441);
        }
    }

    /// A clamped knot vector for n points of degree p with uneven interior spacing, one
    /// interior knot doubled when `doubled` (and p ≥ 2).
    /// An n_u × n_v net of a wavy sheet and uneven weights (1 … 1.9), for the tests below.
    fn wavy_net(n_u: usize, n_v: usize) -> (Vec<Vec<DVec3>>, Vec<Vec<f64>>) {
        let points = (0..n_u)
            .map(|i| {
                (0..n_v)
                    .map(|j| {
                        let (x, y) = (i as f64, j as f64);
                        DVec3::new(10.0 * x, 7.0 * y + x, (0.7 * x + 1.3 * y).sin() * 3.0)
                    })
                    .collect()
            })
            .collect();
        let weights = (0..n_u).map(|i| (0..n_v).map(|j| 1.0 + 0.3 * ((i * 3 + j) % 4) as f64).collect()).collect();
        (points, weights)
    }

    fn uneven_knots(p: usize, n: usize, doubled: bool) -> Vec<f64> {
        let mut k = vec![0.0; p + 1];
        let mut i = 1;
        while k.len() < n {
            let x = i as f64 / (n - p) as f64 + 0.01 * (i * i) as f64;
            k.push(x);
            if doubled && p >= 2 && i == 1 && k.len() < n {
                k.push(x);
            }
            i += 1;
        }
        let last = k.last().copied().unwrap_or(0.0) + 0.5;
        k.extend(std::iter::repeat_n(last, p + 1));
        k
    }

    /// The power form gives the point and first derivatives of the standard algorithm to
    /// rounding (1e-12 relative to the net's size), on every span (a doubled knot included),
    /// at the ends and outside the domain (both extrapolate the end spans' polynomials),
    /// for rational nets of the specialised and general degrees.
    #[test]
    fn power_form_tangents_agree_with_the_standard_algorithm() {
        let cases = [([3, 3], true), ([2, 2], false), ([2, 1], true), ([1, 2], false), ([3, 2], true), ([5, 4], true)];
        for ((degree, doubled), rational) in cases.into_iter().flat_map(|c| [(c, true), (c, false)]) {
            let (n_u, n_v) = (degree[0] + 5, degree[1] + 4);
            let (points, weights) = wavy_net(n_u, n_v);
            let s = NurbsSurface::try_new(
                degree,
                uneven_knots(degree[0], n_u, doubled),
                uneven_knots(degree[1], n_v, doubled),
                &points,
                rational.then_some(weights.as_slice()),
                false,
            )
            .unwrap_or_else(|e| panic!("{degree:?}: {e}"));
            let power = s.power.as_ref().unwrap_or_else(|| panic!("{degree:?}: no power form"));
            // Unit weights take the polynomial path.
            assert_eq!(power.plain.is_some(), !rational, "{degree:?}");
            let dom = s.domain();
            let mut worst = 0.0f64;
            for i in -2..=62 {
                for j in -2..=62 {
                    let uv = DVec2::new(
                        dom.u.min + dom.u.width() * f64::from(i) / 60.0,
                        dom.v.min + dom.v.width() * f64::from(j) / 60.0,
                    );
                    let (p, du, dv) = s.tangents_at(uv);
                    let (fp, fdu, fdv) = s.tangents_fast_at(uv);
                    let scale = p.length().max(du.length()).max(dv.length()).max(1.0);
                    let err = (fp - p).length().max((fdu - du).length()).max((fdv - dv).length()) / scale;
                    worst = worst.max(err);
                }
            }
            assert!(worst < 1e-12, "{degree:?} (rational {rational}): relative difference {worst:e}");
        }
    }

    /// A net whose power form would exceed [`MAX_POWER_COEFFICIENTS`] keeps none and
    /// evaluates by the standard algorithm (the same bits).
    #[test]
    fn a_net_too_large_for_the_power_form_falls_back() {
        let (p, n) = (9, 40);
        let points: Vec<Vec<DVec3>> =
            (0..n).map(|i| (0..n).map(|j| DVec3::new(i as f64, j as f64, ((i * j) % 7) as f64)).collect()).collect();
        let s =
            NurbsSurface::try_new([p, p], uneven_knots(p, n, false), uneven_knots(p, n, false), &points, None, false)
                .unwrap_or_else(|e| panic!("{e}"));
        assert!((n - p) * (n - p) * (p + 1) * (p + 1) > MAX_POWER_COEFFICIENTS);
        assert!(s.power.is_none());
        let uv = DVec2::new(0.37, 0.61);
        assert_eq!(s.tangents_fast_at(uv), s.tangents_at(uv));
    }
}
