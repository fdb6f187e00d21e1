//! A view's scene pass: its layers drawn off-screen in order (translucent ones last), or
//! the image it holds kept when nothing it shows changed.

use std::sync::atomic::Ordering;

use eframe::egui_wgpu::wgpu;

use super::marks::{SKIP_SCENE_PASS, SKIPPED, mark, skipped};
use super::{Layer, Renderer3d, ViewCallback};

/// Uniforms of one view (matches `Frame` in scene.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub(super) struct FrameUniforms {
    /// Clip space from local (column-major).
    clip_from_local: [[f32; 4]; 4],
    /// Eye position (local mm, w = 1).
    eye: [f32; 4],
    /// Width, height (pixels), hide back faces (1 or 0), unused.
    viewport: [f32; 4],
}

/// What a view's image shows: the layers' version, the frame's uniforms and the background.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Drawn {
    /// The view's layers' version.
    version: u64,
    /// The frame's uniforms.
    uniforms: FrameUniforms,
    /// The clear colour.
    background: [f32; 4],
}

impl Renderer3d {
    /// Draws the view of `cb` into its targets with `encoder`, unless its image already
    /// shows the same layers, uniforms and background.
    pub(super) fn draw_view(&mut self, cb: &ViewCallback, encoder: &mut wgpu::CommandEncoder) {
        self.ensure_targets(cb.view, cb.size_px);
        let uniforms = FrameUniforms {
            clip_from_local: cb.clip_from_local,
            eye: [cb.eye[0], cb.eye[1], cb.eye[2], 1.0],
            viewport: [cb.size_px[0] as f32, cb.size_px[1] as f32, if cb.hide_back_faces { 1.0 } else { 0.0 }, 0.0],
        };
        let (device, queue, layout) = (&self.device, &self.queue, &self.pipelines.frame_layout);
        let Some(v) = self.views.get_mut(&cb.view) else {
            return;
        };
        let drawn = Some(Drawn { version: v.version, uniforms, background: cb.background });
        if v.drawn == drawn || (SKIPPED.load(Ordering::Relaxed) & SKIP_SCENE_PASS != 0 && v.drawn.is_some()) {
            return;
        }
        v.drawn = drawn;
        mark(|| {
            let spheres: u32 = v.spheres.values().map(|s| s.count).sum();
            let line_vertices: u32 = v.lines.values().map(|l| l.count).sum();
            let mesh_indices: u32 = v.meshes.values().map(|m| m.indices.count).sum();
            format!(
                "3d scene pass view {} {}x{}: spheres {spheres}, line vertices {line_vertices}, mesh indices {mesh_indices}",
                cb.view, cb.size_px[0], cb.size_px[1]
            )
        });
        let (ubuf, ubind) = v.uniforms.get_or_insert_with(|| {
            let buffer = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("interpolab frame uniforms"),
                size: std::mem::size_of::<FrameUniforms>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            });
            let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("interpolab frame bind group"),
                layout,
                entries: &[wgpu::BindGroupEntry { binding: 0, resource: buffer.as_entire_binding() }],
            });
            (buffer, bind)
        });
        queue.write_buffer(ubuf, 0, bytemuck::bytes_of(&uniforms));
        let Some(t) = v.targets.as_ref() else { return };
        let (view, resolve) = match &t.msaa {
            Some(m) => (m, Some(&t.resolved)),
            None => (&t.resolved, None),
        };
        let [r, g, b, a] = cb.background;
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("interpolab view pass"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view,
                depth_slice: None,
                resolve_target: resolve,
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color { r: r.into(), g: g.into(), b: b.into(), a: a.into() }),
                    store: wgpu::StoreOp::Store,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &t.depth,
                depth_ops: Some(wgpu::Operations { load: wgpu::LoadOp::Clear(1.0), store: wgpu::StoreOp::Discard }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        pass.set_bind_group(0, &*ubind, &[]);
        let draw_mesh = |pass: &mut wgpu::RenderPass<'_>, pipeline: &wgpu::RenderPipeline, layer: Layer| {
            if let Some(m) = v.meshes.get(&layer).filter(|m| m.indices.count > 0 && !skipped(layer)) {
                pass.set_pipeline(pipeline);
                pass.set_vertex_buffer(0, m.vertices.buffer.slice(..));
                pass.set_index_buffer(m.indices.buffer.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..m.indices.count, 0, 0..1);
            }
        };
        let draw_spheres = |pass: &mut wgpu::RenderPass<'_>, pipeline: &wgpu::RenderPipeline, layer: Layer| {
            if let Some(s) = v.spheres.get(&layer).filter(|s| s.count > 0 && !skipped(layer)) {
                pass.set_pipeline(pipeline);
                pass.set_vertex_buffer(0, self.sphere.vertices.slice(..));
                pass.set_vertex_buffer(1, s.buffer.slice(..));
                pass.set_index_buffer(self.sphere.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..self.sphere.index_count, 0, 0..s.count);
            }
        };
        draw_mesh(&mut pass, &self.pipelines.scene.mesh_opaque, Layer::Surfaces);
        draw_spheres(&mut pass, &self.pipelines.scene.sphere_opaque, Layer::Markers);
        for layer in [Layer::StaticLines, Layer::PathLines, Layer::ExactLines, Layer::DynamicLines] {
            if let Some(l) = v.lines.get(&layer).filter(|l| l.count > 0 && !skipped(layer)) {
                pass.set_pipeline(&self.pipelines.scene.lines);
                pass.set_vertex_buffer(0, l.buffer.slice(..));
                pass.draw(0..l.count, 0..1);
            }
        }
        draw_mesh(&mut pass, &self.pipelines.scene.mesh_translucent, Layer::Offsets);
        draw_spheres(&mut pass, &self.pipelines.scene.sphere_translucent, Layer::Cutters);
    }
}
