//! Differential geometry at one point of a surface: fundamental forms, normal curvature,
//! principal curvatures and directions, geodesic torsion, Weingarten derivatives.
//!
//! Sign convention (the seeds' and the scene format's): the second fundamental form is taken
//! with the *oriented* normal n, `L = r_uu·n, M = r_uv·n, N = r_vv·n`, so the normal
//! curvature `k(t) = II(t, t) / I(t, t)` is **negative where the surface bends away from its
//! normal** — convex toward the cutter (the outside of a sphere with outward normal has
//! k = −1/ρ) — and positive where it is concave toward the cutter (a bore seen from inside).
//!
//! With the shape operator `S = I⁻¹·II` (so that `⟨S x, y⟩ = II(x, y)` and `dn = −S dr`,
//! Weingarten), the geodesic torsion along a unit tangent t is `τ_g(t) = II(t, n × t)`;
//! for `t = cos φ·d_max + sin φ·d_min` (principal directions, `d_min = n × d_max`) this is
//! `τ_g = (k_min − k_max)·sin φ·cos φ` (seed 000, ref. [4]: |τ| = |(k_max − k_min) sin φ cos φ|).

use glam::{DVec2, DVec3};

use super::parametric::SurfaceDerivs;
use crate::numerics::linalg;
use crate::numerics::tolerance;

/// Principal curvatures (1/mm, signed as in the module docs) and unit principal directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Principal {
    /// Larger principal curvature.
    pub k_max: f64,
    /// Smaller principal curvature.
    pub k_min: f64,
    /// Unit tangent direction of `k_max`.
    pub dir_max: DVec3,
    /// Unit tangent direction of `k_min` (`n × dir_max`).
    pub dir_min: DVec3,
}

/// The first fundamental form `(E, F, G, EG − F²)` of `r_u`, `r_v`, or `None` at a singular
/// point of the parametrisation (`|r_u × r_v| ≈ 0`, or no normal there): the test of
/// [`LocalGeometry::try_new`], shared with frames built from first derivatives alone.
#[must_use]
pub(crate) fn first_form_if_regular(du: DVec3, dv: DVec3, normal: DVec3) -> Option<(f64, f64, f64, f64)> {
    let e = du.dot(du);
    let f = du.dot(dv);
    let g = dv.dot(dv);
    let det_i = e * g - f * f;
    (det_i > tolerance::MIN_AREA_ELEMENT * tolerance::MIN_AREA_ELEMENT && normal != DVec3::ZERO)
        .then_some((e, f, g, det_i))
}

/// Fundamental forms at a regular point, from which every local quantity follows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalGeometry {
    /// The derivatives this was built from.
    pub d: SurfaceDerivs,
    /// First fundamental form `E = r_u·r_u`.
    pub e: f64,
    /// `F = r_u·r_v`.
    pub f: f64,
    /// `G = r_v·r_v`.
    pub g: f64,
    /// Second fundamental form `L = r_uu·n`.
    pub l: f64,
    /// `M = r_uv·n`.
    pub m: f64,
    /// `N = r_vv·n`.
    pub n: f64,
    /// `EG − F²` (> 0 at a regular point).
    pub det_i: f64,
}

impl LocalGeometry {
    /// Builds the forms; `None` at a singular point of the parametrisation (`|r_u × r_v| ≈ 0`,
    /// e.g. a sphere pole) where the first fundamental form cannot be inverted.
    #[must_use]
    pub fn try_new(d: SurfaceDerivs) -> Option<Self> {
        let (e, f, g, det_i) = first_form_if_regular(d.du, d.dv, d.normal)?;
        let nrm = d.normal;
        Some(Self { d, e, f, g, l: d.duu.dot(nrm), m: d.duv.dot(nrm), n: d.dvv.dot(nrm), det_i })
    }

    /// Coordinates `(a, b)` of the tangent-plane projection of `t` in the basis `(r_u, r_v)`:
    /// the solution of `I·(a, b) = (t·r_u, t·r_v)`.
    #[must_use]
    pub fn tangent_coords(&self, t: DVec3) -> DVec2 {
        let (tu, tv) = (t.dot(self.d.du), t.dot(self.d.dv));
        DVec2::new(self.g * tu - self.f * tv, self.e * tv - self.f * tu) / self.det_i
    }

    /// `II(x, y)` for tangent coordinates x, y.
    #[must_use]
    pub fn second_form(&self, x: DVec2, y: DVec2) -> f64 {
        self.l * x.x * y.x + self.m * (x.x * y.y + x.y * y.x) + self.n * x.y * y.y
    }

    /// `I(x, y)` for tangent coordinates x, y.
    #[must_use]
    pub fn first_form(&self, x: DVec2, y: DVec2) -> f64 {
        self.e * x.x * y.x + self.f * (x.x * y.y + x.y * y.x) + self.g * x.y * y.y
    }

    /// Normal curvature `k(t) = II(t, t)/I(t, t)` in the direction of the tangent t
    /// (1/mm; only t's tangential part matters).
    #[must_use]
    pub fn normal_curvature(&self, t: DVec3) -> f64 {
        // Tangent coordinates up to the common factor 1/(EG − F²), which cancels in the ratio.
        let (tu, tv) = (t.dot(self.d.du), t.dot(self.d.dv));
        let c = DVec2::new(self.g * tu - self.f * tv, self.e * tv - self.f * tu);
        self.second_form(c, c) / self.first_form(c, c)
    }

    /// Whether the offset surface at distance `r` (mm) on the normal side is regular here:
    /// `1 − k·r > 0` for the normal curvature k of every direction, i.e. the form `I − r·II`
    /// is positive definite. Cheaper than [`Self::principal_curvatures`] (no square root).
    #[must_use]
    pub fn offset_is_regular(&self, r: f64) -> bool {
        let a = self.e - r * self.l;
        let b = self.f - r * self.m;
        let c = self.g - r * self.n;
        a > 0.0 && a * c - b * b > 0.0
    }

    /// Geodesic torsion `τ_g(t) = II(t, n × t) / I(t, t)` along the tangent t (1/mm).
    #[must_use]
    pub fn geodesic_torsion(&self, t: DVec3) -> f64 {
        let c = self.tangent_coords(t);
        let w = self.tangent_coords(self.d.normal.cross(t));
        self.second_form(c, w) / self.first_form(c, c)
    }

    /// Mean curvature `H = (k_max + k_min)/2` (1/mm).
    #[must_use]
    pub fn mean_curvature(&self) -> f64 {
        (self.e * self.n + self.g * self.l - 2.0 * self.f * self.m) / (2.0 * self.det_i)
    }

    /// Gaussian curvature `K = k_max·k_min` (1/mm²).
    #[must_use]
    pub fn gaussian_curvature(&self) -> f64 {
        (self.l * self.n - self.m * self.m) / self.det_i
    }

    /// The shape operator in the orthonormal tangent frame `e1 = r_u/|r_u|`, `e2 = n × e1`:
    /// the symmetric matrix `[[a, b], [b, c]]` with `a = II(e1, e1)`, `b = II(e1, e2)`,
    /// `c = II(e2, e2)`, and the frame.
    fn shape_matrix(&self) -> (f64, f64, f64, DVec3, DVec3) {
        let e1 = self.d.du / self.e.sqrt();
        let e2 = self.d.normal.cross(e1);
        let c1 = DVec2::new(1.0 / self.e.sqrt(), 0.0);
        let c2 = self.tangent_coords(e2);
        (self.second_form(c1, c1), self.second_form(c1, c2), self.second_form(c2, c2), e1, e2)
    }

    /// Principal curvatures only: `(k_max, k_min)`, the eigenvalues of the shape operator
    /// `(a + c)/2 ± √(((a − c)/2)² + b²)` in an orthonormal frame. The discriminant is a sum
    /// of squares, so umbilics (spheres) come out exact instead of √(rounding) apart.
    #[must_use]
    pub fn principal_curvatures(&self) -> (f64, f64) {
        let (a, b, c, _, _) = self.shape_matrix();
        let mean = 0.5 * (a + c);
        let half = 0.5 * (a - c);
        let disc = half.hypot(b);
        (mean + disc, mean - disc)
    }

    /// Principal curvatures and directions. At an umbilic (all directions principal) the
    /// directions are `r_u` normalised and `n × r_u`.
    #[must_use]
    pub fn principal(&self) -> Principal {
        let (a, b, c, e1, e2) = self.shape_matrix();
        let mean = 0.5 * (a + c);
        let half = 0.5 * (a - c);
        let disc = half.hypot(b);
        // Rotation taking e1 to the k_max direction: tan 2θ = 2b / (a − c).
        let theta = 0.5 * b.atan2(half);
        let dir_max = theta.cos() * e1 + theta.sin() * e2;
        let dir_min = self.d.normal.cross(dir_max);
        Principal { k_max: mean + disc, k_min: mean - disc, dir_max, dir_min }
    }

    /// Derivatives of the unit normal, `(n_u, n_v)`, by the Weingarten equations
    /// `n_u = ((FM − GL) r_u + (FL − EM) r_v)/(EG − F²)`,
    /// `n_v = ((FN − GM) r_u + (FM − EN) r_v)/(EG − F²)`.
    #[must_use]
    pub fn normal_derivatives(&self) -> (DVec3, DVec3) {
        let (e, f, g, l, m, n) = (self.e, self.f, self.g, self.l, self.m, self.n);
        let nu = ((f * m - g * l) * self.d.du + (f * l - e * m) * self.d.dv) / self.det_i;
        let nv = ((f * n - g * m) * self.d.du + (f * m - e * n) * self.d.dv) / self.det_i;
        (nu, nv)
    }

    /// Solves for the parameter increments whose tangent `r_u δu + r_v δv` equals the
    /// tangential part of `t` (mm → parameter units). Same as [`Self::tangent_coords`].
    #[must_use]
    pub fn param_step(&self, t: DVec3) -> DVec2 {
        self.tangent_coords(t)
    }
}

/// Solves `(r_u δu + r_v δv)·a = α, (r_u δu + r_v δv)·b = β` for `(δu, δv)`.
#[must_use]
pub(crate) fn solve_tangent(d: &SurfaceDerivs, a: DVec3, alpha: f64, b: DVec3, beta: f64) -> Option<DVec2> {
    linalg::solve2(d.du.dot(a), d.dv.dot(a), d.du.dot(b), d.dv.dot(b), DVec2::new(alpha, beta))
}
