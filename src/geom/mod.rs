//! Geometry of the part: parametric surfaces with derivatives, NURBS, differential
//! geometry and foot-point projection.
//!
//! Glossary used throughout the core:
//! - *surface* S(u, v): a part face, parametrised over a rectangular [`Domain`];
//! - *normal rule*: every surface has an oriented unit normal n; the cutter is on the side n
//!   points to;
//! - *offset surface*: S(u, v) + R'·n(u, v), where a ball of radius R' touching S has its
//!   centre;
//! - *contact point* (CC point) q: where the ball touches a surface; *cutter centre*
//!   (CL point for a ball end mill) p = q + R'·n.
//!
//! Internal units: mm for lengths, radians for angular parameters, knot units for NURBS.
//! Degrees appear only at the edges (scene files, UI), converted by [`ParamUnit`].

mod curve;
pub mod cutter;
mod diffgeo;
mod domain;
mod frame;
pub mod nurbs;
mod parabola;
mod parametric;
mod project;
mod ray;
mod surface;

pub use curve::{Curve3, HermitePath};
pub use cutter::{BodySpec, Cutter, CutterError, CutterKind, Taper};
pub use diffgeo::{LocalGeometry, Principal};
pub(crate) use diffgeo::{first_form_if_regular, solve_tangent};
pub use domain::{Domain, ParamRange, ParamUnit};
pub use frame::{Frame, any_perpendicular};
pub use nurbs::{NurbsCurve, NurbsError, NurbsSurface};
pub use parabola::Parabola;
pub use parametric::{FirstOrder, ParametricSurface, SurfaceDerivs};
pub use project::{Foot, ProjectOptions, project_point, project_point_from, project_point_global};
pub use ray::{RAY_GRID_MAX, RAY_NEWTON_STEPS, RayHit, ray_hit};
pub use surface::{Cylinder, Plane, Sphere, Surface, Torus};
