//! The numerics floor: helpers every paper module may use, importing nothing above
//! [`crate::geom`] (and mostly not even that). A paper module imports another paper only where
//! it builds on that paper's method (5-axis steps along a crease), never for a helper; the
//! helpers live here.
//!
//! Also part of the floor, kept at their old paths: [`crate::tolerance`] (every named small
//! number) and [`crate::limits`] (caps on input sizes and loops), and [`crate::linalg`].
//!
//! - [`mod@format`]: number text (shortest round-trip decimals, fixed decimals);
//! - [`measure`]: distances to segments and curves (foot points), arc-length tables;
//! - [`knots`]: span breaks (distinct knots) of a clamped knot vector;
//! - [`maximise`]: the largest value of a 1-D function on an interval;
//! - [`roots`]: bracketing and root finders for "the next parameter where g(s) = E";
//! - [`planefit`]: the best-fit plane of points (covariance, Jacobi eigen-solver);
//! - [`units`]: conversions between the file's units and the core's;
//! - [`sign`]: the one sign convention of machining error (overcut positive).

pub mod format;
pub mod knots;
pub mod maximise;
pub mod measure;
pub mod planefit;
pub mod roots;
pub mod sign;
pub mod units;
