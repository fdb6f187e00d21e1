//! A tensor-product NURBS surface, evaluated by the standard algorithm (and its power form
//! where only the first derivatives are wanted to rounding).

use glam::{DVec2, DVec3, DVec4};

use super::basis::{basis_derivatives_sized, basis_functions_of};
use super::power::PowerPatches;
use super::{MAX_ORDER, NurbsError, find_span, validate_knots};
use crate::geom::domain::{Domain, ParamRange, ParamUnit};
use crate::geom::parametric::{FirstOrder, ParametricSurface, SurfaceDerivs};
use crate::numerics::tolerance;

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
    /// would take more than [`MAX_POWER_COEFFICIENTS`](super::MAX_POWER_COEFFICIENTS).
    power: Option<PowerPatches>,
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

    /// The power form, if the net has one.
    #[cfg(test)]
    pub(super) fn power_form(&self) -> Option<&PowerPatches> {
        self.power.as_ref()
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

    fn first_order_at(&self, uv: DVec2) -> FirstOrder {
        let (point, du, dv) = self.tangents_at(uv);
        FirstOrder { point, du, dv, normal: self.normal_of(du, dv) }
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
        power.tangents([su, sv], ou, ov, uv)
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
        let normal = self.normal_of(su_, sv_);
        SurfaceDerivs { point: s, du: su_, dv: sv_, duu: suu, duv: suv, dvv: svv, normal }
    }

    /// The oriented unit normal from r_u and r_v (zero where they are parallel).
    #[inline(always)]
    fn normal_of(&self, du: DVec3, dv: DVec3) -> DVec3 {
        let cross = du.cross(dv);
        let len = cross.length();
        if len > tolerance::MIN_AREA_ELEMENT { self.sign * cross / len } else { DVec3::ZERO }
    }
}
