//! The numerics floor: helpers every paper module may use, importing nothing above
//! [`crate::geom`] (and mostly not even that). A paper module imports another paper only where
//! it builds on that paper's method (5-axis steps along a crease), never for a helper; the
//! helpers live here.
//!
//! Also part of the floor, kept at their old paths: [`crate::tolerance`] (every named small
//! number) and [`crate::limits`] (caps on input sizes and loops), and [`crate::linalg`].
//!
//! - [`format`]: number text (shortest round-trip decimals, fixed decimals).

pub mod format;
