//! A NURBS surface in power form: one polynomial patch per knot-span pair, evaluated by
//! Horner's rule for the point and first derivatives.

use glam::{DVec2, DVec3, DVec4};

use super::MAX_ORDER;

/// Most homogeneous coefficients a surface's power form holds (32 bytes each: 2 MB, and
/// 1.5 MB more for the copy without weights of a net whose weights are all 1).
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
pub(super) struct PowerPatches {
    /// Per knot-span index s − p in u.
    spans_u: Vec<Span>,
    /// The same in v.
    spans_v: Vec<Span>,
    /// `(p + 1)(q + 1)` coefficients per span pair, pair `(iu, iv)` at
    /// `(iu·spans_v.len() + iv)·(p + 1)(q + 1)`, coefficient `a_mn` at `m·(q + 1) + n`.
    coeffs: Vec<DVec4>,
    /// The same without the weight when every weight is 1 (a polynomial surface: w ≡ 1, so
    /// the point and its derivatives are the sums themselves, no quotient rule).
    plain: Option<Vec<DVec3>>,
}

/// One knot span of a power form: `[start, start + width)`, the patch's variable
/// `(u − start)/width`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Span {
    /// Its first knot u0.
    start: f64,
    /// Its width Δu; 0 for an empty span (never looked up).
    width: f64,
}

/// A patch's sum by Horner's rule and its derivatives in the patch's variables x and y.
#[derive(Clone, Copy, Debug)]
struct HornerSums<T> {
    /// A.
    value: T,
    /// ∂A/∂x.
    d_x: T,
    /// ∂A/∂y.
    d_y: T,
}

/// Horner's rule on one patch of [`PowerPatches`] (orders `ou` × `ov`): the sum and its
/// derivatives in x and y.
#[inline(always)]
fn horner_tangents<T>(patch: &[T], ou: usize, ov: usize, x: f64, y: f64) -> HornerSums<T>
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
    HornerSums { value: a00, d_x: a10, d_y: a01 }
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
    pub(super) fn new(degree: [usize; 2], knots: [&[f64]; 2], n: [usize; 2], control: &[DVec4]) -> Option<Self> {
        let [p, q] = degree;
        let (cu, cv) = (n[0] - p, n[1] - q);
        let per = (p + 1) * (q + 1);
        if cu.checked_mul(cv)?.checked_mul(per)? > MAX_POWER_COEFFICIENTS {
            return None;
        }
        let spans = |k: &[f64], deg: usize, count: usize| -> Vec<Span> {
            (0..count).map(|i| Span { start: k[deg + i], width: k[deg + i + 1] - k[deg + i] }).collect()
        };
        let (spans_u, spans_v) = (spans(knots[0], p, cu), spans(knots[1], q, cv));
        let mut coeffs = vec![DVec4::ZERO; cu * cv * per];
        for (iu, span_u) in spans_u.iter().enumerate() {
            if !(span_u.width > 0.0) {
                continue;
            }
            let bu = span_power_basis(knots[0], p + iu, p);
            for (iv, span_v) in spans_v.iter().enumerate() {
                if !(span_v.width > 0.0) {
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

    /// r, r_u and r_v at `uv` on the patch of knot spans `span` (each span index less the
    /// degree, as [`super::find_span`] − p), whose orders are `ou` × `ov` (p + 1, q + 1).
    #[inline(always)]
    pub(super) fn tangents(&self, span: [usize; 2], ou: usize, ov: usize, uv: DVec2) -> (DVec3, DVec3, DVec3) {
        let [su, sv] = span;
        let (span_u, span_v) = (self.spans_u[su], self.spans_v[sv]);
        let (du, dv) = (span_u.width, span_v.width);
        let (x, y) = ((uv.x - span_u.start) / du, (uv.y - span_v.start) / dv);
        let at = (su * self.spans_v.len() + sv) * ou * ov;
        if let Some(plain) = &self.plain {
            let a = horner_tangents(&plain[at..][..ou * ov], ou, ov, x, y);
            return (a.value, a.d_x / du, a.d_y / dv);
        }
        let a = horner_tangents(&self.coeffs[at..][..ou * ov], ou, ov, x, y);
        let (a10, a01) = (a.d_x / du, a.d_y / dv);
        let w = a.value.w;
        let s = a.value.truncate() / w;
        (s, (a10.truncate() - a10.w * s) / w, (a01.truncate() - a01.w * s) / w)
    }

    /// Whether the patches are the polynomial ones (every weight 1: no quotient rule).
    #[cfg(test)]
    pub(super) fn is_polynomial(&self) -> bool {
        self.plain.is_some()
    }
}
