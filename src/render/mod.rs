//! GPU drawing of 3D views (feature `app`): surfaces, offset surfaces, iso-parameter lines,
//! paths, ball cutters and overlays, rendered off-screen with depth and 4× MSAA and composited
//! into egui through a paint callback.
//!
//! - [`geometry`]: CPU-side vertex types (`#[repr(C)]`, `bytemuck::Pod`, padded as WGSL wants)
//!   and builders from core types — the one place where f64 becomes f32, relative to a
//!   per-scene origin so f32 keeps sub-micrometre resolution near the part;
//! - [`camera`]: an orbit camera with z up;
//! - [`gpu`]: pipelines, per-view layer buffers and targets, the egui-wgpu callback;
//! - [`flat_fill`]: large opaque rectangles of the UI filled by a flat-colour pipeline
//!   instead of egui's textured, blending one (cheap on CPU rasterisers);
//! - [`egui_pass`]: egui's remaining shapes (text, small rectangles, lines, circles) drawn
//!   from egui's own tessellation by a pipeline whose fragment shader has no branches.
//!
//! Nothing here computes geometry of the part: it only draws what the core produced.

pub mod camera;
pub mod egui_pass;
pub mod flat_fill;
pub mod geometry;
pub mod gpu;

pub use camera::OrbitCamera;
pub use geometry::{LineSegment, Mesh, MeshVertex, SphereInstance};
pub use gpu::{Layer, Renderer3d, ViewCallback, ViewId};
