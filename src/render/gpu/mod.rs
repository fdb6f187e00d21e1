//! GPU resources and the egui-wgpu paint callback of the 3D views.
//!
//! One [`Renderer3d`] lives in egui-wgpu's `callback_resources`: the pipelines (created
//! once), a unit icosphere, and per view ([`ViewId`]) its layer buffers, uniforms and
//! off-screen targets. The app uploads layers when its data changes
//! ([`Renderer3d::set_mesh`], [`Renderer3d::set_lines`], [`Renderer3d::set_spheres`]); each
//! frame a [`ViewCallback`] carries only the camera and size. In `prepare` the view is drawn
//! off-screen (depth, 4× MSAA where the adapter supports it) and resolved; in `paint` the
//! resolved image is copied into egui's pass. A missing resource is logged once and the view
//! skipped — never a panic in the browser.
//!
//! Files, one concern each: `pipelines.rs` (the pipelines and the unit sphere, created once),
//! `upload.rs` (layer buffers that send only what changed), `targets.rs` (a view's off-screen
//! targets), `draw.rs` (a view's scene pass), [`marks`] (measuring aids: layers left out,
//! performance marks, the one log line of a missing resource).

use std::collections::BTreeMap;

use eframe::egui_wgpu::{self, CallbackResources, CallbackTrait, RenderState, ScreenDescriptor, wgpu};

use super::geometry::{LineSegment, Mesh, MeshVertex, SphereInstance};
use draw::Drawn;
use marks::{log_missing_once, mark};
use pipelines::{Pipelines, UnitSphere};
use targets::{COLOR_FORMAT, DEPTH_FORMAT, Targets};
use upload::{GpuArray, LINE_CORNERS, MeshBuffers, per_corner};

mod draw;
pub mod marks;
mod pipelines;
mod targets;
mod upload;

/// Identifies one 3D view (each view keeps its own layers and targets).
pub type ViewId = u32;

/// The layers of a view, drawn in this order (translucent ones last).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Layer {
    /// Shaded surfaces (opaque).
    Surfaces,
    /// Opaque spheres: markers, the cutter at the playback position.
    Markers,
    /// Lines that change with the scene (iso-lines, the exact crease).
    StaticLines,
    /// The computed path (grows while computing).
    PathLines,
    /// The exact crease (grows with the path; drawn over it).
    ExactLines,
    /// Lines that change every frame (normals at the playback position, axes).
    DynamicLines,
    /// Translucent offset surfaces.
    Offsets,
    /// Translucent spheres: ball cutters along the path.
    Cutters,
}

#[derive(Default)]
struct ViewGpu {
    meshes: BTreeMap<Layer, MeshBuffers>,
    lines: BTreeMap<Layer, GpuArray>,
    spheres: BTreeMap<Layer, GpuArray>,
    uniforms: Option<(wgpu::Buffer, wgpu::BindGroup)>,
    targets: Option<Targets>,
    /// Counts the changes of the view's layers.
    version: u64,
    /// What the image in `targets` shows: the layers' version and the frame's uniforms and
    /// background. The same again (a frame where only the UI around the view changed) reuses
    /// the image instead of drawing the scene again — on a CPU rasteriser the view's pass is
    /// most of a frame.
    drawn: Option<Drawn>,
}

/// Device-level resources of all 3D views.
pub struct Renderer3d {
    device: wgpu::Device,
    queue: wgpu::Queue,
    sample_count: u32,
    pipelines: Pipelines,
    sphere: UnitSphere,
    views: BTreeMap<ViewId, ViewGpu>,
    /// Scratch of [`Renderer3d::set_lines`]: the segments repeated per corner.
    line_corners: Vec<LineSegment>,
}

impl Renderer3d {
    /// Creates the pipelines and stores the renderer in egui-wgpu's callback resources.
    pub fn install(rs: &RenderState) {
        let renderer = Self::new(rs);
        rs.renderer.write().callback_resources.insert(renderer);
    }

    /// Runs `f` on the installed renderer (no-op if it is missing).
    pub fn with<R>(rs: &RenderState, f: impl FnOnce(&mut Self) -> R) -> Option<R> {
        let mut guard = rs.renderer.write();
        let r = guard.callback_resources.get_mut::<Self>();
        if r.is_none() {
            log_missing_once("renderer not installed");
        }
        r.map(f)
    }

    fn new(rs: &RenderState) -> Self {
        let device = rs.device.clone();
        let queue = rs.queue.clone();
        let supports =
            |f: wgpu::TextureFormat| rs.adapter.get_texture_format_features(f).flags.sample_count_supported(4);
        // A CPU rasteriser (SwiftShader, llvmpipe: browsers without a GPU, headless tests)
        // pays for every sample: 4× MSAA made each 3D view cost about four times the
        // fragment work and a resolve pass per frame there. Lines and shading stay readable
        // without it; GPUs keep 4×.
        let software = is_software(&rs.adapter.get_info());
        let sample_count = if !software && supports(COLOR_FORMAT) && supports(DEPTH_FORMAT) { 4 } else { 1 };
        log::info!(
            "3D views: {sample_count}× MSAA, target {:?}, adapter {:?} ({:?})",
            rs.target_format,
            rs.adapter.get_info().name,
            rs.adapter.get_info().device_type
        );
        let pipelines = Pipelines::new(&device, rs.target_format, sample_count);
        let sphere = UnitSphere::new(&device);
        Self { device, queue, sample_count, pipelines, sphere, views: BTreeMap::new(), line_corners: Vec::new() }
    }

    /// MSAA samples used (4, or 1 where the adapter cannot).
    #[must_use]
    pub fn sample_count(&self) -> u32 {
        self.sample_count
    }

    /// Replaces a mesh layer of a view.
    pub fn set_mesh(&mut self, view: ViewId, layer: Layer, mesh: &Mesh) {
        let (device, queue) = (&self.device, &self.queue);
        let v = self.views.entry(view).or_default();
        let vb = bytemuck::cast_slice::<MeshVertex, u8>(&mesh.vertices);
        let ib = bytemuck::cast_slice::<u32, u8>(&mesh.indices);
        let m = v.meshes.entry(layer).or_insert_with(|| MeshBuffers {
            vertices: GpuArray::with_capacity(device, "interpolab mesh vertices", wgpu::BufferUsages::VERTEX, vb.len()),
            indices: GpuArray::with_capacity(device, "interpolab mesh indices", wgpu::BufferUsages::INDEX, ib.len()),
        });
        let changed = m.vertices.write(device, queue, vb, mesh.vertices.len() as u32, 0)
            | m.indices.write(device, queue, ib, mesh.indices.len() as u32, 0);
        if changed {
            v.version += 1;
            let sent = m.vertices.sent_bytes + m.indices.sent_bytes;
            mark(|| format!("3d upload view {view} {layer:?} mesh {} B, sent {sent} B", vb.len() + ib.len()));
        }
    }

    /// Replaces a line layer; the first `unchanged` segments are known to be on the GPU
    /// already (pass 0 when unsure).
    ///
    /// Each segment is written `LINE_CORNERS` times, once per vertex of its quad, and drawn
    /// without instancing: SwiftShader (the browsers' CPU rasteriser) runs an instanced draw as
    /// one draw per instance, so a layer of a few thousand segments cost some 100 ms per scene
    /// pass; as plain vertices it is one draw (docs/speed.md, "Frames on SwiftShader").
    pub fn set_lines(&mut self, view: ViewId, layer: Layer, lines: &[LineSegment], unchanged: usize) {
        let per_segment = LINE_CORNERS * std::mem::size_of::<LineSegment>();
        let v = self.views.entry(view).or_default();
        // Only the segments after the unchanged ones are repeated per corner, compared and
        // sent: a path that grows piece by piece does not copy what it already drew (a
        // 180 000-segment path is 52 MB of corners).
        let held = v.lines.get(&layer).map_or(0, |a| a.held_bytes() / per_segment);
        let unchanged = unchanged.min(lines.len()).min(held);
        let mut corners = std::mem::take(&mut self.line_corners);
        per_corner(&lines[unchanged..], &mut corners);
        let tail = bytemuck::cast_slice::<LineSegment, u8>(&corners);
        let count = (lines.len() * LINE_CORNERS) as u32;
        let device = &self.device;
        let array = v.lines.entry(layer).or_insert_with(|| {
            GpuArray::with_capacity(device, "interpolab instances", wgpu::BufferUsages::VERTEX, tail.len())
        });
        if array.write_tail(device, &self.queue, unchanged * per_segment, tail, count) {
            v.version += 1;
            let sent = array.sent_bytes;
            mark(|| format!("3d upload view {view} {layer:?} lines {} B, sent {sent} B", lines.len() * per_segment));
        }
        // A big scratch is not kept (it would double the memory of a long path).
        if corners.capacity() <= 1 << 16 {
            self.line_corners = corners;
        }
    }

    /// Replaces a sphere layer.
    pub fn set_spheres(&mut self, view: ViewId, layer: Layer, spheres: &[SphereInstance]) {
        let bytes = bytemuck::cast_slice::<SphereInstance, u8>(spheres);
        let v = self.views.entry(view).or_default();
        if Self::write_instances(&self.device, &self.queue, v.spheres.entry(layer), bytes, spheres.len() as u32, 0) {
            v.version += 1;
            let sent = v.spheres.get(&layer).map_or(0, |a| a.sent_bytes);
            mark(|| {
                format!("3d upload view {view} {layer:?} spheres {} ({} B), sent {sent} B", spheres.len(), bytes.len())
            });
        }
    }

    fn write_instances(
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        entry: std::collections::btree_map::Entry<'_, Layer, GpuArray>,
        bytes: &[u8],
        count: u32,
        prefix: u64,
    ) -> bool {
        // A new buffer holds nothing yet, so all of it is written.
        let prefix = if matches!(entry, std::collections::btree_map::Entry::Vacant(_)) { 0 } else { prefix };
        entry
            .or_insert_with(|| {
                GpuArray::with_capacity(device, "interpolab instances", wgpu::BufferUsages::VERTEX, bytes.len())
            })
            .write(device, queue, bytes, count, prefix)
    }

    /// Drops everything of a view.
    pub fn clear_view(&mut self, view: ViewId) {
        self.views.remove(&view);
    }

    fn ensure_targets(&mut self, view: ViewId, size: [u32; 2]) {
        let device = &self.device;
        let v = self.views.entry(view).or_default();
        if v.targets.as_ref().is_some_and(|t| t.size == size) {
            return;
        }
        v.targets = Some(Targets::new(device, size, self.sample_count, &self.pipelines.composite_layout));
        mark(|| format!("3d targets view {view} {}x{}", size[0], size[1]));
        v.drawn = None;
    }
}

/// Per-frame data of one view's paint callback (small and `Copy`).
#[derive(Clone, Copy, Debug)]
pub struct ViewCallback {
    /// Which view.
    pub view: ViewId,
    /// `clip_from_local` (column-major).
    pub clip_from_local: [[f32; 4]; 4],
    /// Eye position (local mm).
    pub eye: [f32; 3],
    /// Size of the view in physical pixels.
    pub size_px: [u32; 2],
    /// Clear colour (display RGBA).
    pub background: [f32; 4],
    /// Hide the side of surfaces their normal points away from (the material side).
    pub hide_back_faces: bool,
}

impl CallbackTrait for ViewCallback {
    fn prepare(
        &self,
        _device: &wgpu::Device,
        _queue: &wgpu::Queue,
        _screen: &ScreenDescriptor,
        encoder: &mut wgpu::CommandEncoder,
        resources: &mut CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        if self.size_px[0] == 0 || self.size_px[1] == 0 {
            return Vec::new();
        }
        match resources.get_mut::<Renderer3d>() {
            Some(r) => r.draw_view(self, encoder),
            None => log_missing_once("renderer not installed"),
        }
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &CallbackResources,
    ) {
        let Some(r) = resources.get::<Renderer3d>() else {
            return;
        };
        let Some(t) = r.views.get(&self.view).and_then(|v| v.targets.as_ref()) else {
            return;
        };
        if t.size != self.size_px {
            return;
        }
        pass.set_pipeline(&r.pipelines.composite);
        pass.set_bind_group(0, &t.composite, &[]);
        pass.draw(0..3, 0..1);
    }
}

/// Whether an adapter rasterises on the CPU (wgpu's own guess, or SwiftShader / llvmpipe
/// in its name: WebGL reports the renderer string only through an extension).
#[must_use]
pub fn is_software(info: &wgpu::AdapterInfo) -> bool {
    let name = info.name.to_ascii_lowercase();
    info.device_type == wgpu::DeviceType::Cpu
        || ["swiftshader", "llvmpipe", "software"].iter().any(|s| name.contains(s))
}

/// Wraps a view callback for egui's painter.
#[must_use]
pub fn paint_callback(rect: egui::Rect, cb: ViewCallback) -> egui::PaintCallback {
    egui_wgpu::Callback::new_paint_callback(rect, cb)
}

use eframe::egui;
