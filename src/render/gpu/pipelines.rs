//! The render pipelines of the 3D views, created once per device, and the unit sphere the
//! sphere layers instance.

use eframe::egui_wgpu::wgpu;
use wgpu::util::DeviceExt;

use super::targets::{COLOR_FORMAT, DEPTH_FORMAT};
use crate::render::geometry::{LineSegment, MeshVertex, SphereInstance, icosphere};

/// The pipelines of the 3D views and their bind group layouts.
pub(super) struct Pipelines {
    /// Layout of a view's frame uniforms.
    pub(super) frame_layout: wgpu::BindGroupLayout,
    /// Layout of a view's image, read by the composite.
    pub(super) composite_layout: wgpu::BindGroupLayout,
    /// The scene pass's pipelines.
    pub(super) scene: ScenePipelines,
    /// Copies a view's image into egui's pass.
    pub(super) composite: wgpu::RenderPipeline,
}

/// The pipelines of a view's scene pass, one per kind of layer.
pub(super) struct ScenePipelines {
    /// Opaque meshes.
    pub(super) mesh_opaque: wgpu::RenderPipeline,
    /// Translucent meshes (no depth write).
    pub(super) mesh_translucent: wgpu::RenderPipeline,
    /// Opaque spheres.
    pub(super) sphere_opaque: wgpu::RenderPipeline,
    /// Translucent spheres (no depth write).
    pub(super) sphere_translucent: wgpu::RenderPipeline,
    /// Lines.
    pub(super) lines: wgpu::RenderPipeline,
}

impl Pipelines {
    /// The pipelines drawing into a view's targets at `sample_count` samples, the composite
    /// into egui's target of `target_format`.
    pub(super) fn new(device: &wgpu::Device, target_format: wgpu::TextureFormat, sample_count: u32) -> Self {
        let scene_shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("interpolab scene shader"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../shaders/scene.wgsl").into()),
        });
        let composite_shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("interpolab composite shader"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../shaders/composite.wgsl").into()),
        });
        let frame_layout = crate::render::uniform_layout(
            device,
            "interpolab frame uniforms layout",
            wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
        );
        // The composite reads the view's image texel by texel (`textureLoad`): no sampler.
        let composite_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("interpolab composite layout"),
            entries: &[crate::render::fragment_texture_entry(0)],
        });
        let scene_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("interpolab scene pipeline layout"),
            bind_group_layouts: &[Some(&frame_layout)],
            immediate_size: 0,
        });
        let composite_pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("interpolab composite pipeline layout"),
            bind_group_layouts: &[Some(&composite_layout)],
            immediate_size: 0,
        });
        let scene = ScenePipelines::new(device, &scene_layout, &scene_shader, sample_count);
        let composite = composite_pipeline(device, &composite_pl, &composite_shader, target_format);
        Self { frame_layout, composite_layout, scene, composite }
    }
}

impl ScenePipelines {
    /// The scene pass's pipelines in `layout` from `shader` at `sample_count` samples.
    fn new(
        device: &wgpu::Device,
        layout: &wgpu::PipelineLayout,
        shader: &wgpu::ShaderModule,
        sample_count: u32,
    ) -> Self {
        let mesh_attrs = wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x4];
        let mesh_buffer = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<MeshVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &mesh_attrs,
        };
        let unit_attrs = wgpu::vertex_attr_array![0 => Float32x3];
        let unit_buffer = wgpu::VertexBufferLayout {
            array_stride: 12,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &unit_attrs,
        };
        let sphere_attrs = wgpu::vertex_attr_array![1 => Float32x4, 2 => Float32x4];
        let sphere_buffer = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<SphereInstance>() as u64,
            step_mode: wgpu::VertexStepMode::Instance,
            attributes: &sphere_attrs,
        };
        let line_attrs = wgpu::vertex_attr_array![0 => Float32x4, 1 => Float32x4, 2 => Float32x4];
        // Per vertex, not per instance: each segment is stored once per corner of its quad (see
        // `set_lines`), and the whole layer is one non-instanced draw.
        let line_buffer = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<LineSegment>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &line_attrs,
        };

        let multisample = wgpu::MultisampleState { count: sample_count, mask: !0, alpha_to_coverage_enabled: false };
        let depth = |write: bool| {
            Some(wgpu::DepthStencilState {
                format: DEPTH_FORMAT,
                depth_write_enabled: Some(write),
                depth_compare: Some(wgpu::CompareFunction::LessEqual),
                stencil: wgpu::StencilState::default(),
                bias: wgpu::DepthBiasState::default(),
            })
        };
        let target = |blend: Option<wgpu::BlendState>| {
            [Some(wgpu::ColorTargetState { format: COLOR_FORMAT, blend, write_mask: wgpu::ColorWrites::ALL })]
        };
        let opaque_target = target(None);
        let blended_target = target(Some(wgpu::BlendState::ALPHA_BLENDING));
        let pipeline = |label: &str,
                        vs: &str,
                        fs: &str,
                        buffers: &[Option<wgpu::VertexBufferLayout<'_>>],
                        targets: &[Option<wgpu::ColorTargetState>],
                        depth_write: bool| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module: shader,
                    entry_point: Some(vs),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    buffers,
                },
                primitive: wgpu::PrimitiveState {
                    topology: wgpu::PrimitiveTopology::TriangleList,
                    cull_mode: None,
                    ..Default::default()
                },
                depth_stencil: depth(depth_write),
                multisample,
                fragment: Some(wgpu::FragmentState {
                    module: shader,
                    entry_point: Some(fs),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    targets,
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        let mesh_opaque = pipeline(
            "interpolab mesh (opaque)",
            "vs_mesh",
            "fs_shaded",
            &[Some(mesh_buffer.clone())],
            &opaque_target,
            true,
        );
        let mesh_translucent = pipeline(
            "interpolab mesh (translucent)",
            "vs_mesh",
            "fs_shaded",
            &[Some(mesh_buffer)],
            &blended_target,
            false,
        );
        let sphere_opaque = pipeline(
            "interpolab spheres (opaque)",
            "vs_sphere",
            "fs_sphere",
            &[Some(unit_buffer.clone()), Some(sphere_buffer.clone())],
            &opaque_target,
            true,
        );
        let sphere_translucent = pipeline(
            "interpolab spheres (translucent)",
            "vs_sphere",
            "fs_sphere",
            &[Some(unit_buffer), Some(sphere_buffer)],
            &blended_target,
            false,
        );
        let lines = pipeline("interpolab lines", "vs_line", "fs_line", &[Some(line_buffer)], &blended_target, true);
        Self { mesh_opaque, mesh_translucent, sphere_opaque, sphere_translucent, lines }
    }
}

/// The pipeline that copies a view's image (`layout`, `shader`) into egui's target of
/// `target_format` (linear or display values as the format wants).
fn composite_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    shader: &wgpu::ShaderModule,
    target_format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("interpolab composite"),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: shader,
            entry_point: Some("vs_fullscreen"),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            buffers: &[],
        },
        primitive: wgpu::PrimitiveState::default(),
        depth_stencil: None,
        multisample: wgpu::MultisampleState::default(),
        fragment: Some(wgpu::FragmentState {
            module: shader,
            entry_point: Some(if target_format.is_srgb() { "fs_linear" } else { "fs_display" }),
            compilation_options: wgpu::PipelineCompilationOptions::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: target_format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        multiview_mask: None,
        cache: None,
    })
}

/// The unit sphere (an icosphere) the sphere layers draw once per instance.
pub(super) struct UnitSphere {
    /// Its vertices.
    pub(super) vertices: wgpu::Buffer,
    /// Its triangles' indices.
    pub(super) indices: wgpu::Buffer,
    /// Indices.
    pub(super) index_count: u32,
}

impl UnitSphere {
    /// The unit sphere's buffers on `device`.
    pub(super) fn new(device: &wgpu::Device) -> Self {
        let (unit, indices) = icosphere(2);
        let sphere_vertices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("interpolab unit sphere vertices"),
            contents: bytemuck::cast_slice(&unit),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let sphere_indices = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("interpolab unit sphere indices"),
            contents: bytemuck::cast_slice(&indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        Self { vertices: sphere_vertices, indices: sphere_indices, index_count: indices.len() as u32 }
    }
}
