//! What every surface gives: its point, partial derivatives to second order and oriented
//! normal at a parameter pair ([`SurfaceDerivs`]), and its domain ([`ParametricSurface`]).
//!
//! A file of its own below both [`super::surface`] (the analytic types and the `Surface`
//! enum) and [`super::nurbs`] (the NURBS surface): the enum holds a NURBS surface and the
//! NURBS surface implements the trait, so with the trait in `surface.rs` the two files
//! imported each other.

use glam::{DVec2, DVec3};

use super::domain::Domain;

/// Point, partial derivatives up to second order and oriented unit normal of a surface at
/// one parameter pair. Lengths in mm; derivatives in mm per internal parameter unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceDerivs {
    /// r(u, v).
    pub point: DVec3,
    /// ∂r/∂u.
    pub du: DVec3,
    /// ∂r/∂v.
    pub dv: DVec3,
    /// ∂²r/∂u².
    pub duu: DVec3,
    /// ∂²r/∂u∂v.
    pub duv: DVec3,
    /// ∂²r/∂v².
    pub dvv: DVec3,
    /// Oriented unit normal (the cutter's side). Zero where the parametrisation is singular
    /// and the surface type has no closed form for it.
    pub normal: DVec3,
}

/// Point, first partial derivatives and oriented unit normal at one parameter pair: a
/// [`SurfaceDerivs`] without the second derivatives ([`ParametricSurface::first_order_at`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FirstOrder {
    /// r(u, v) (mm).
    pub point: DVec3,
    /// ∂r/∂u (mm per internal unit).
    pub du: DVec3,
    /// ∂r/∂v (mm per internal unit).
    pub dv: DVec3,
    /// Oriented unit normal, zero where [`SurfaceDerivs::normal`] is.
    pub normal: DVec3,
}

impl From<SurfaceDerivs> for FirstOrder {
    fn from(d: SurfaceDerivs) -> Self {
        Self { point: d.point, du: d.du, dv: d.dv, normal: d.normal }
    }
}

/// A parametric surface with derivatives and an oriented normal.
pub trait ParametricSurface {
    /// r(u, v) in mm; `uv` in internal units.
    fn point_at(&self, uv: DVec2) -> DVec3;
    /// Point, derivatives to second order and oriented normal at `uv`.
    fn derivatives_at(&self, uv: DVec2) -> SurfaceDerivs;
    /// Point and first derivatives `(r, r_u, r_v)` at `uv` (mm, mm per internal unit), the
    /// same values as [`Self::derivatives_at`]'s; surfaces where the second derivatives cost
    /// extra work (NURBS) skip it.
    fn tangents_at(&self, uv: DVec2) -> (DVec3, DVec3, DVec3) {
        let d = self.derivatives_at(uv);
        (d.point, d.du, d.dv)
    }
    /// Point, first derivatives and normal at `uv`, the same values as
    /// [`Self::derivatives_at`]'s to the last bit; surfaces where the second derivatives cost
    /// extra work (NURBS) skip it. For callers that place a cutter on the surface and need
    /// no curvature.
    fn first_order_at(&self, uv: DVec2) -> FirstOrder {
        self.derivatives_at(uv).into()
    }
    /// [`Self::tangents_at`] to rounding, not necessarily to the last bit: a NURBS evaluates
    /// its power form ([`super::nurbs`]), several times faster. For callers whose answer
    /// does not hang on the last bits (the certified gouge check's bounds).
    fn tangents_fast_at(&self, uv: DVec2) -> (DVec3, DVec3, DVec3) {
        self.tangents_at(uv)
    }
    /// The parameter domain (internal units).
    fn domain(&self) -> Domain;
}
