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

use eframe::egui_wgpu::wgpu;

/// A bind group layout of one uniform buffer at binding 0, seen by `visibility`'s stages (the
/// per-frame uniforms of the 3D views, the egui pass's screen size).
pub(crate) fn uniform_layout(
    device: &wgpu::Device,
    label: &str,
    visibility: wgpu::ShaderStages,
) -> wgpu::BindGroupLayout {
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some(label),
        entries: &[wgpu::BindGroupLayoutEntry {
            binding: 0,
            visibility,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        }],
    })
}

/// A layout entry for a filterable 2D colour texture read by the fragment stage at `binding`.
pub(crate) fn fragment_texture_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: true },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}
pub use geometry::{LineSegment, Mesh, MeshVertex, SphereInstance};
pub use gpu::{Layer, Renderer3d, ViewCallback, ViewId};
