//! The numerics floor: helpers every paper module may use, importing nothing above
//! [`crate::geom`] (and mostly not even that). A paper module imports another paper only where
//! it builds on that paper's method (5-axis steps along a crease), never for a helper; the
//! helpers live here.
//!
//! Three of them sit below [`crate::geom`] (which uses them) and import nothing outside this
//! directory: [`tolerance`] (every named small number), [`limits`] (caps on input sizes and
//! loops) and [`linalg`] (small solves). `scripts/modgraph.py` therefore counts each file here
//! as a module of its own.
//!
//! - [`tolerance`]: the named tolerances, one per kind of quantity;
//! - [`limits`]: size caps on what is read and how much work one request may ask for;
//! - [`linalg`]: small dense linear solves (2×2, 3×3, 4×4) without allocation;
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
pub mod limits;
pub mod linalg;
pub mod maximise;
pub mod measure;
pub mod planefit;
pub mod roots;
pub mod sign;
pub mod tolerance;
pub mod units;
