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
//!
//! Rooms: [`NurbsError`] (what a definition may break), the knot vector's rules and span
//! search ([`validate_knots`], [`find_span`]), the basis functions ([`basis_functions`],
//! [`basis_derivatives`]), [`NurbsCurve`], [`NurbsSurface`] by the standard algorithms, and
//! the surface's power form (polynomial patches for fast first derivatives, at most
//! [`MAX_POWER_COEFFICIENTS`] coefficients).

mod basis;
mod curve;
mod error;
mod knots;
mod power;
mod surface;
#[cfg(test)]
mod tests;

pub use basis::{basis_derivatives, basis_functions};
pub use curve::NurbsCurve;
pub use error::NurbsError;
pub use knots::{find_span, validate_knots};
pub use power::MAX_POWER_COEFFICIENTS;
pub use surface::NurbsSurface;

/// Highest supported degree. Basis tables live on the stack in fixed arrays of this order.
pub const MAX_DEGREE: usize = 9;
const MAX_ORDER: usize = MAX_DEGREE + 1;
