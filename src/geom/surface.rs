//! The surface types of the scene format and the trait they share.
//!
//! Every surface gives its point, first and second partial derivatives and oriented unit
//! normal at a parameter pair, and its parameter domain. Parametrisations (scene format,
//! `interpolab-scene/1`), with `(e1, e2, a)` the surface's [`Frame`]:
//!
//! | type | r(u, v) | normal |
//! |---|---|---|
//! | plane | o + u·e1 + v·e2, e2 = n × e1 | n (given) |
//! | cylinder | o + ρ(cos u·e1 + sin u·e2) + v·a | ±(cos u·e1 + sin u·e2) |
//! | sphere | c + ρ(cos v cos u·e1 + cos v sin u·e2 + sin v·a) | ±(r − c)/ρ |
//! | torus | c + (R0 + r0 cos v)(cos u·e1 + sin u·e2) + r0 sin v·a | ±(cos v(cos u·e1 + sin u·e2) + sin v·a) |
//! | nurbs | Σ w_ij P_ij N_i(u) N_j(v) / Σ w_ij N_i(u) N_j(v) | ±r_u × r_v / \|r_u × r_v\| |
//!
//! For every analytic type r_u × r_v points outward (away from the axis or centre), so
//! "outward" is the orientation of the parametrisation and "inward" its reverse.

use glam::{DVec2, DVec3};

use super::domain::{Domain, ParamRange, ParamUnit};
use super::frame::Frame;
use super::nurbs::NurbsSurface;
use super::parametric::{FirstOrder, ParametricSurface, SurfaceDerivs};

/// A plane `r = o + u·e1 + v·e2`, `e2 = n × e1`, normal `n`; u, v in mm.
#[derive(Clone, Debug, PartialEq)]
pub struct Plane {
    /// A point of the plane, at (u, v) = (0, 0) (mm).
    pub origin: DVec3,
    /// `e1 = u_axis`, `e2 = n × e1`, `a = n`.
    pub frame: Frame,
    /// Parameter domain (mm).
    pub domain: Domain,
}

impl Plane {
    /// A plane through `origin` with unit `normal` and in-plane `u_axis`; `u`, `v` ranges in mm.
    #[must_use]
    pub fn new(origin: DVec3, normal: DVec3, u_axis: DVec3, u: [f64; 2], v: [f64; 2]) -> Self {
        Self {
            origin,
            frame: Frame::from_axis(normal, Some(u_axis)),
            domain: Domain {
                u: ParamRange::new(u[0], u[1], ParamUnit::Length),
                v: ParamRange::new(v[0], v[1], ParamUnit::Length),
            },
        }
    }
}

impl ParametricSurface for Plane {
    fn point_at(&self, uv: DVec2) -> DVec3 {
        self.origin + uv.x * self.frame.e1 + uv.y * self.frame.e2
    }
    fn derivatives_at(&self, uv: DVec2) -> SurfaceDerivs {
        SurfaceDerivs {
            point: self.point_at(uv),
            du: self.frame.e1,
            dv: self.frame.e2,
            duu: DVec3::ZERO,
            duv: DVec3::ZERO,
            dvv: DVec3::ZERO,
            normal: self.frame.a,
        }
    }
    fn domain(&self) -> Domain {
        self.domain
    }
}

/// A circular cylinder `r = o + ρ(cos u·e1 + sin u·e2) + v·a`; u angle, v mm along the axis.
#[derive(Clone, Debug, PartialEq)]
pub struct Cylinder {
    /// A point on the axis, at v = 0 (mm).
    pub origin: DVec3,
    /// Axis frame.
    pub frame: Frame,
    /// Radius ρ (mm).
    pub radius: f64,
    /// +1 for an outward normal (cutter outside), −1 inward (cutter inside the bore).
    pub sign: f64,
    /// Parameter domain (u rad, v mm).
    pub domain: Domain,
}

impl ParametricSurface for Cylinder {
    fn point_at(&self, uv: DVec2) -> DVec3 {
        let (s, c) = uv.x.sin_cos();
        self.origin + self.radius * (c * self.frame.e1 + s * self.frame.e2) + uv.y * self.frame.a
    }
    fn derivatives_at(&self, uv: DVec2) -> SurfaceDerivs {
        let (s, c) = uv.x.sin_cos();
        let radial = c * self.frame.e1 + s * self.frame.e2;
        let tangential = -s * self.frame.e1 + c * self.frame.e2;
        SurfaceDerivs {
            point: self.origin + self.radius * radial + uv.y * self.frame.a,
            du: self.radius * tangential,
            dv: self.frame.a,
            duu: -self.radius * radial,
            duv: DVec3::ZERO,
            dvv: DVec3::ZERO,
            normal: self.sign * radial,
        }
    }
    fn domain(&self) -> Domain {
        self.domain
    }
}

/// A sphere `r = c + ρ(cos v cos u·e1 + cos v sin u·e2 + sin v·a)`; u longitude, v latitude.
#[derive(Clone, Debug, PartialEq)]
pub struct Sphere {
    /// Centre (mm).
    pub center: DVec3,
    /// Polar axis frame.
    pub frame: Frame,
    /// Radius ρ (mm).
    pub radius: f64,
    /// +1 outward, −1 inward.
    pub sign: f64,
    /// Parameter domain (rad).
    pub domain: Domain,
}

impl ParametricSurface for Sphere {
    fn point_at(&self, uv: DVec2) -> DVec3 {
        let (su, cu) = uv.x.sin_cos();
        let (sv, cv) = uv.y.sin_cos();
        self.center + self.radius * (cv * (cu * self.frame.e1 + su * self.frame.e2) + sv * self.frame.a)
    }
    fn derivatives_at(&self, uv: DVec2) -> SurfaceDerivs {
        let (su, cu) = uv.x.sin_cos();
        let (sv, cv) = uv.y.sin_cos();
        let radial = cu * self.frame.e1 + su * self.frame.e2;
        let tangential = -su * self.frame.e1 + cu * self.frame.e2;
        let dir = cv * radial + sv * self.frame.a;
        let rho = self.radius;
        SurfaceDerivs {
            point: self.center + rho * dir,
            du: rho * cv * tangential,
            dv: rho * (-sv * radial + cv * self.frame.a),
            duu: -rho * cv * radial,
            duv: -rho * sv * tangential,
            dvv: -rho * dir,
            normal: self.sign * dir,
        }
    }
    fn domain(&self) -> Domain {
        self.domain
    }
}

/// A ring torus `r = c + (R0 + r0 cos v)(cos u·e1 + sin u·e2) + r0 sin v·a`.
#[derive(Clone, Debug, PartialEq)]
pub struct Torus {
    /// Centre (mm).
    pub center: DVec3,
    /// Axis frame.
    pub frame: Frame,
    /// Distance R0 from the axis to the tube's centre circle (mm).
    pub major_radius: f64,
    /// Tube radius r0 (mm).
    pub minor_radius: f64,
    /// +1 outward (away from the tube's centre circle), −1 inward.
    pub sign: f64,
    /// Parameter domain (rad).
    pub domain: Domain,
}

impl ParametricSurface for Torus {
    fn point_at(&self, uv: DVec2) -> DVec3 {
        let (su, cu) = uv.x.sin_cos();
        let (sv, cv) = uv.y.sin_cos();
        let w = self.major_radius + self.minor_radius * cv;
        self.center + w * (cu * self.frame.e1 + su * self.frame.e2) + self.minor_radius * sv * self.frame.a
    }
    fn derivatives_at(&self, uv: DVec2) -> SurfaceDerivs {
        let (su, cu) = uv.x.sin_cos();
        let (sv, cv) = uv.y.sin_cos();
        let radial = cu * self.frame.e1 + su * self.frame.e2;
        let tangential = -su * self.frame.e1 + cu * self.frame.e2;
        let a = self.frame.a;
        let r0 = self.minor_radius;
        let w = self.major_radius + r0 * cv;
        SurfaceDerivs {
            point: self.center + w * radial + r0 * sv * a,
            du: w * tangential,
            dv: r0 * (-sv * radial + cv * a),
            duu: -w * radial,
            duv: -r0 * sv * tangential,
            dvv: -r0 * (cv * radial + sv * a),
            normal: self.sign * (cv * radial + sv * a),
        }
    }
    fn domain(&self) -> Domain {
        self.domain
    }
}

/// Any surface of the scene format. An enum rather than a trait object so the interpolator's
/// inner loop dispatches with a jump table and no allocation.
#[derive(Clone, Debug, PartialEq)]
pub enum Surface {
    /// See [`Plane`].
    Plane(Plane),
    /// See [`Cylinder`].
    Cylinder(Cylinder),
    /// See [`Sphere`].
    Sphere(Sphere),
    /// See [`Torus`].
    Torus(Torus),
    /// See [`NurbsSurface`].
    Nurbs(NurbsSurface),
}

impl Surface {
    /// The scene-format type name (`"plane"`, `"cylinder"`, …).
    #[must_use]
    pub fn type_name(&self) -> &'static str {
        match self {
            Self::Plane(_) => "plane",
            Self::Cylinder(_) => "cylinder",
            Self::Sphere(_) => "sphere",
            Self::Torus(_) => "torus",
            Self::Nurbs(_) => "nurbs",
        }
    }
}

impl ParametricSurface for Surface {
    #[inline]
    fn point_at(&self, uv: DVec2) -> DVec3 {
        match self {
            Self::Plane(s) => s.point_at(uv),
            Self::Cylinder(s) => s.point_at(uv),
            Self::Sphere(s) => s.point_at(uv),
            Self::Torus(s) => s.point_at(uv),
            Self::Nurbs(s) => s.point_at(uv),
        }
    }
    #[inline]
    fn derivatives_at(&self, uv: DVec2) -> SurfaceDerivs {
        match self {
            Self::Plane(s) => s.derivatives_at(uv),
            Self::Cylinder(s) => s.derivatives_at(uv),
            Self::Sphere(s) => s.derivatives_at(uv),
            Self::Torus(s) => s.derivatives_at(uv),
            Self::Nurbs(s) => s.derivatives_at(uv),
        }
    }
    #[inline]
    fn tangents_at(&self, uv: DVec2) -> (DVec3, DVec3, DVec3) {
        match self {
            Self::Plane(s) => s.tangents_at(uv),
            Self::Cylinder(s) => s.tangents_at(uv),
            Self::Sphere(s) => s.tangents_at(uv),
            Self::Torus(s) => s.tangents_at(uv),
            Self::Nurbs(s) => s.tangents_at(uv),
        }
    }
    #[inline]
    fn first_order_at(&self, uv: DVec2) -> FirstOrder {
        match self {
            Self::Nurbs(s) => s.first_order_at(uv),
            _ => self.derivatives_at(uv).into(),
        }
    }
    #[inline]
    fn tangents_fast_at(&self, uv: DVec2) -> (DVec3, DVec3, DVec3) {
        match self {
            Self::Nurbs(s) => s.tangents_fast_at(uv),
            _ => self.tangents_at(uv),
        }
    }
    #[inline]
    fn domain(&self) -> Domain {
        match self {
            Self::Plane(s) => s.domain(),
            Self::Cylinder(s) => s.domain(),
            Self::Sphere(s) => s.domain(),
            Self::Torus(s) => s.domain(),
            Self::Nurbs(s) => s.domain(),
        }
    }
}
