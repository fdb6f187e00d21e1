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

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, AtomicU32, Ordering};

use eframe::egui_wgpu::{self, CallbackResources, CallbackTrait, RenderState, ScreenDescriptor, wgpu};
use wgpu::util::DeviceExt;

use super::geometry::{LineSegment, Mesh, MeshVertex, SphereInstance, icosphere};

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

/// Measuring only (`app::ablate`, web `?hide=`): the layers left out of every scene pass, one
/// bit per [`Layer`] in declaration order, and bit 31 to skip the scene pass altogether (the
/// view then shows the image it holds). Zero in normal use.
static SKIPPED: AtomicU32 = AtomicU32::new(0);

/// The bit of `SKIPPED` that skips the whole scene pass.
pub const SKIP_SCENE_PASS: u32 = 1 << 31;

/// Sets the layers (bit `1 << layer as u32`) left out of every scene pass, for measuring.
pub fn set_skipped_layers(bits: u32) {
    SKIPPED.store(bits, Ordering::Relaxed);
}

/// Measuring only (`app::ablate`, web `?hide=marks`): whether the renderer leaves a
/// `performance.mark` in the page for each scene pass and each layer upload, so a Chromium
/// trace (`e2e/frame-profile.mjs --trace`) tells what a long frame held. Off in normal use.
static MARKS: AtomicBool = AtomicBool::new(false);

/// Turns the performance marks of scene passes and uploads on or off, for measuring.
pub fn set_marks(on: bool) {
    MARKS.store(on, Ordering::Relaxed);
}

/// Leaves `text()` as a performance mark in the page when marks are on (web only).
fn mark(text: impl FnOnce() -> String) {
    if !MARKS.load(Ordering::Relaxed) {
        return;
    }
    let text = text();
    #[cfg(target_arch = "wasm32")]
    if let Some(p) = web_sys::window().and_then(|w| w.performance()) {
        // A failed mark only loses a measuring aid.
        let _ = p.mark(&text);
    }
    #[cfg(not(target_arch = "wasm32"))]
    log::debug!("{text}");
}

fn skipped(layer: Layer) -> bool {
    SKIPPED.load(Ordering::Relaxed) & (1 << layer as u32) != 0
}

const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth24Plus;

/// Uniforms of one view (matches `Frame` in scene.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct FrameUniforms {
    clip_from_local: [[f32; 4]; 4],
    eye: [f32; 4],
    viewport: [f32; 4],
}

/// A growable GPU buffer of `count` elements.
struct GpuArray {
    buffer: wgpu::Buffer,
    capacity_bytes: u64,
    count: u32,
    label: &'static str,
    usage: wgpu::BufferUsages,
    /// The bytes the buffer holds (its first `shadow.len()` bytes), kept on the CPU so a
    /// write sends only the range that differs: the same data again (a layer rebuilt with
    /// nothing changed, the unchanged index buffer of a mesh whose heights changed) sends
    /// nothing and leaves the view's image valid.
    shadow: Vec<u8>,
    /// Bytes sent by the last write that changed something (for `?hide=marks`).
    sent_bytes: usize,
}

/// Bytes compared at a time when looking for the first or last difference (a slice
/// comparison per chunk, then byte by byte inside the chunk that differs).
const DIFF_CHUNK_BYTES: usize = 256;

/// The first index below `min(a.len(), b.len())` where `a` and `b` differ.
fn first_difference(a: &[u8], b: &[u8]) -> Option<usize> {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let chunk = a.chunks(DIFF_CHUNK_BYTES).zip(b.chunks(DIFF_CHUNK_BYTES)).position(|(x, y)| x != y)?;
    let from = chunk * DIFF_CHUNK_BYTES;
    a[from..].iter().zip(&b[from..]).position(|(x, y)| x != y).map(|i| from + i)
}

/// The last index below `min(a.len(), b.len())` where `a` and `b` differ.
fn last_difference(a: &[u8], b: &[u8]) -> Option<usize> {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let chunk = a.rchunks(DIFF_CHUNK_BYTES).zip(b.rchunks(DIFF_CHUNK_BYTES)).position(|(x, y)| x != y)?;
    let to = n - chunk * DIFF_CHUNK_BYTES;
    let from = to.saturating_sub(DIFF_CHUNK_BYTES);
    a[from..to].iter().zip(&b[from..to]).rposition(|(x, y)| x != y).map(|i| from + i)
}

/// The byte range of `new` to send to a buffer holding `old` so that it holds `new`, the
/// first `known_same` bytes being known equal (rounded to whole 4-byte words, as
/// `write_buffer` wants); `None` if nothing differs.
fn changed_range(old: &[u8], new: &[u8], known_same: usize) -> Option<std::ops::Range<usize>> {
    let skip = known_same.min(old.len()).min(new.len());
    let common = old.len().min(new.len());
    let first = first_difference(&old[skip..common], &new[skip..common]).map(|i| skip + i);
    let last = last_difference(&old[skip..common], &new[skip..common]).map(|i| skip + i);
    let grown = new.len() > common;
    let (start, end) = match (first, last) {
        (Some(f), _) if grown => (f, new.len()),
        (Some(f), Some(l)) => (f, l + 1),
        _ if grown => (common, new.len()),
        _ => return None,
    };
    let start = start & !3;
    let end = end.next_multiple_of(4).min(new.len());
    Some(start..end)
}

impl GpuArray {
    /// An empty array with room for `capacity_bytes` (at least 64).
    fn with_capacity(
        device: &wgpu::Device,
        label: &'static str,
        usage: wgpu::BufferUsages,
        capacity_bytes: usize,
    ) -> Self {
        let size = (capacity_bytes as u64).max(64).next_multiple_of(4);
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size,
            usage: usage | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        Self { buffer, capacity_bytes: size, count: 0, label, usage, shadow: Vec::new(), sent_bytes: 0 }
    }

    /// Writes `bytes` (all `count` elements), sending only the range that differs from what
    /// the buffer holds; the first `unchanged_prefix_bytes` are known to be the same (the
    /// path grows by appending) and are not compared. Returns whether the contents changed
    /// (false: the same data again, nothing sent).
    fn write(
        &mut self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        bytes: &[u8],
        count: u32,
        unchanged_prefix_bytes: u64,
    ) -> bool {
        self.sent_bytes = 0;
        if bytes.len() as u64 > self.capacity_bytes {
            *self = Self::with_capacity(device, self.label, self.usage, bytes.len() * 3 / 2);
            queue.write_buffer(&self.buffer, 0, bytes);
            self.shadow.extend_from_slice(bytes);
            self.sent_bytes = bytes.len();
            self.count = count;
            return true;
        }
        let known_same = usize::try_from(unchanged_prefix_bytes).unwrap_or(usize::MAX);
        let range = changed_range(&self.shadow, bytes, known_same);
        if range.is_none() && count == self.count {
            return false;
        }
        self.shadow.resize(bytes.len(), 0);
        self.sent_bytes = range.as_ref().map_or(0, std::ops::Range::len);
        if let Some(r) = range.filter(|r| !r.is_empty()) {
            // write_buffer needs a multiple of 4 bytes; vertex data always is.
            queue.write_buffer(&self.buffer, r.start as u64, &bytes[r.clone()]);
            self.shadow[r.clone()].copy_from_slice(&bytes[r]);
        }
        self.count = count;
        true
    }
}

struct MeshBuffers {
    vertices: GpuArray,
    indices: GpuArray,
}

/// Off-screen targets of one view at one size.
struct Targets {
    size: [u32; 2],
    msaa: Option<wgpu::TextureView>,
    depth: wgpu::TextureView,
    resolved: wgpu::TextureView,
    composite: wgpu::BindGroup,
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
    drawn: Option<(u64, FrameUniforms, [f32; 4])>,
}

/// Device-level resources of all 3D views.
pub struct Renderer3d {
    device: wgpu::Device,
    queue: wgpu::Queue,
    sample_count: u32,
    frame_layout: wgpu::BindGroupLayout,
    composite_layout: wgpu::BindGroupLayout,
    mesh_opaque: wgpu::RenderPipeline,
    mesh_translucent: wgpu::RenderPipeline,
    sphere_opaque: wgpu::RenderPipeline,
    sphere_translucent: wgpu::RenderPipeline,
    lines: wgpu::RenderPipeline,
    composite: wgpu::RenderPipeline,
    sphere_vertices: wgpu::Buffer,
    sphere_indices: wgpu::Buffer,
    sphere_index_count: u32,
    views: BTreeMap<ViewId, ViewGpu>,
    /// Scratch of [`Renderer3d::set_lines`]: the segments repeated per corner.
    line_corners: Vec<LineSegment>,
}

/// Vertices of a line segment's quad (two triangles; `vs_line` in scene.wgsl).
const LINE_CORNERS: usize = 6;

/// The vertex data of a line layer: each segment once per corner of its quad, in order, so
/// vertex `i` belongs to segment `i / LINE_CORNERS` and is its corner `i % LINE_CORNERS`.
fn per_corner(lines: &[LineSegment], out: &mut Vec<LineSegment>) {
    out.clear();
    out.extend(lines.iter().flat_map(|l| std::iter::repeat_n(*l, LINE_CORNERS)));
}

static MISSING_LOGGED: AtomicBool = AtomicBool::new(false);

fn log_missing_once(what: &str) {
    if !MISSING_LOGGED.swap(true, Ordering::Relaxed) {
        log::error!("3D view skipped: {what}");
    }
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

        let scene_shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("interpolab scene shader"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shaders/scene.wgsl").into()),
        });
        let composite_shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("interpolab composite shader"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shaders/composite.wgsl").into()),
        });
        let frame_layout = super::uniform_layout(
            &device,
            "interpolab frame uniforms layout",
            wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
        );
        // The composite reads the view's image texel by texel (`textureLoad`): no sampler.
        let composite_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("interpolab composite layout"),
            entries: &[super::fragment_texture_entry(0)],
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
                layout: Some(&scene_layout),
                vertex: wgpu::VertexState {
                    module: &scene_shader,
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
                    module: &scene_shader,
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

        let composite = device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("interpolab composite"),
            layout: Some(&composite_pl),
            vertex: wgpu::VertexState {
                module: &composite_shader,
                entry_point: Some("vs_fullscreen"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &composite_shader,
                entry_point: Some(if rs.target_format.is_srgb() { "fs_linear" } else { "fs_display" }),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: rs.target_format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });

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

        Self {
            device,
            queue,
            sample_count,
            frame_layout,
            composite_layout,
            mesh_opaque,
            mesh_translucent,
            sphere_opaque,
            sphere_translucent,
            lines,
            composite,
            sphere_vertices,
            sphere_indices,
            sphere_index_count: indices.len() as u32,
            views: BTreeMap::new(),
            line_corners: Vec::new(),
        }
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
        let mut corners = std::mem::take(&mut self.line_corners);
        per_corner(lines, &mut corners);
        let bytes = bytemuck::cast_slice::<LineSegment, u8>(&corners);
        let prefix = (unchanged.min(lines.len()) * LINE_CORNERS * std::mem::size_of::<LineSegment>()) as u64;
        let v = self.views.entry(view).or_default();
        if Self::write_instances(&self.device, &self.queue, v.lines.entry(layer), bytes, corners.len() as u32, prefix) {
            v.version += 1;
            let sent = v.lines.get(&layer).map_or(0, |a| a.sent_bytes);
            mark(|| format!("3d upload view {view} {layer:?} lines {} B, sent {sent} B", bytes.len()));
        }
        self.line_corners = corners;
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
        let extent = wgpu::Extent3d { width: size[0], height: size[1], depth_or_array_layers: 1 };
        let texture = |label: &str, format, samples, usage| {
            device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: extent,
                    mip_level_count: 1,
                    sample_count: samples,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage,
                    view_formats: &[],
                })
                .create_view(&wgpu::TextureViewDescriptor::default())
        };
        let resolved = texture(
            "interpolab view image",
            COLOR_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let msaa = (self.sample_count > 1).then(|| {
            texture(
                "interpolab view MSAA colour",
                COLOR_FORMAT,
                self.sample_count,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
        });
        let depth =
            texture("interpolab view depth", DEPTH_FORMAT, self.sample_count, wgpu::TextureUsages::RENDER_ATTACHMENT);
        let composite = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("interpolab composite bind group"),
            layout: &self.composite_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&resolved) }],
        });
        v.targets = Some(Targets { size, msaa, depth, resolved, composite });
        mark(|| format!("3d targets view {view} {}x{}", size[0], size[1]));
        v.drawn = None;
    }

    fn draw_view(&mut self, cb: &ViewCallback, encoder: &mut wgpu::CommandEncoder) {
        self.ensure_targets(cb.view, cb.size_px);
        let uniforms = FrameUniforms {
            clip_from_local: cb.clip_from_local,
            eye: [cb.eye[0], cb.eye[1], cb.eye[2], 1.0],
            viewport: [cb.size_px[0] as f32, cb.size_px[1] as f32, if cb.hide_back_faces { 1.0 } else { 0.0 }, 0.0],
        };
        let (device, queue, layout) = (&self.device, &self.queue, &self.frame_layout);
        let Some(v) = self.views.get_mut(&cb.view) else {
            return;
        };
        let drawn = Some((v.version, uniforms, cb.background));
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
                pass.set_vertex_buffer(0, self.sphere_vertices.slice(..));
                pass.set_vertex_buffer(1, s.buffer.slice(..));
                pass.set_index_buffer(self.sphere_indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..self.sphere_index_count, 0, 0..s.count);
            }
        };
        draw_mesh(&mut pass, &self.mesh_opaque, Layer::Surfaces);
        draw_spheres(&mut pass, &self.sphere_opaque, Layer::Markers);
        for layer in [Layer::StaticLines, Layer::PathLines, Layer::ExactLines, Layer::DynamicLines] {
            if let Some(l) = v.lines.get(&layer).filter(|l| l.count > 0 && !skipped(layer)) {
                pass.set_pipeline(&self.lines);
                pass.set_vertex_buffer(0, l.buffer.slice(..));
                pass.draw(0..l.count, 0..1);
            }
        }
        draw_mesh(&mut pass, &self.mesh_translucent, Layer::Offsets);
        draw_spheres(&mut pass, &self.sphere_translucent, Layer::Cutters);
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
        pass.set_pipeline(&r.composite);
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

#[cfg(test)]
mod tests {
    use super::{LINE_CORNERS, LineSegment, changed_range, per_corner};

    /// A small deterministic generator (xorshift) for the byte patterns below.
    fn bytes(seed: &mut u64, n: usize) -> Vec<u8> {
        (0..n)
            .map(|_| {
                *seed ^= *seed << 13;
                *seed ^= *seed >> 7;
                *seed ^= *seed << 17;
                (*seed >> 56) as u8
            })
            .collect()
    }

    #[test]
    fn the_changed_range_makes_the_old_contents_the_new_and_starts_at_the_first_difference() {
        let mut seed = 0x9E37_79B9_7F4A_7C15;
        for case in 0..400 {
            let n_old = 4 * (case % 7) * (1 + case % 300);
            let old = bytes(&mut seed, n_old);
            let mut new = old.clone();
            // Grow, shrink or keep the length, then change a few bytes (or none).
            let n_new = match case % 3 {
                0 => n_old + 4 * (case % 5),
                1 => n_old - 4 * (case % 5).min(n_old / 4),
                _ => n_old,
            };
            new.resize(n_new, 0);
            let tail = bytes(&mut seed, n_new.saturating_sub(n_old));
            new[n_old.min(n_new)..].copy_from_slice(&tail);
            let changes = case % 4;
            for k in 0..changes {
                if n_new > 0 {
                    let at = (case * 7919 + k * 104_729) % n_new;
                    new[at] = new[at].wrapping_add(1);
                }
            }
            let first = (0..n_old.min(n_new)).find(|&i| old[i] != new[i]).or((n_new > n_old).then_some(n_old));
            let last = (0..n_old.min(n_new)).rev().find(|&i| old[i] != new[i]);
            match changed_range(&old, &new, 0) {
                None => assert_eq!(first, None, "case {case}: a difference was missed"),
                Some(r) => {
                    let f = first.expect("a range only where something differs");
                    assert_eq!(r.start, f & !3, "case {case}: starts at the first difference's word");
                    assert_eq!(r.start % 4, 0, "case {case}");
                    assert!(r.end % 4 == 0 && r.end <= n_new, "case {case}: {r:?} of {n_new}");
                    if n_new <= n_old {
                        assert_eq!(r.end, (last.expect("a last difference") + 1).next_multiple_of(4), "case {case}");
                    }
                    // Applying the range to the old contents gives the new ones.
                    let mut held = old.clone();
                    held.resize(n_new, 0);
                    held[r.clone()].copy_from_slice(&new[r]);
                    assert_eq!(held, new, "case {case}");
                }
            }
        }
    }

    #[test]
    fn a_known_same_prefix_is_not_compared() {
        let old = vec![1u8; 64];
        let mut new = old.clone();
        new[8] = 9; // inside the prefix said to be the same: not looked at
        new[40] = 9;
        assert_eq!(changed_range(&old, &new, 16), Some(40..44));
        assert_eq!(changed_range(&old, &old, 0), None);
        let mut longer = old.clone();
        longer.extend_from_slice(&[7; 8]);
        assert_eq!(changed_range(&old, &longer, 0), Some(64..72), "only the appended tail");
        assert_eq!(changed_range(&old, &old[..32], 0), None, "a shorter prefix sends nothing");
    }

    #[test]
    fn each_line_vertex_carries_its_segment() {
        let lines: Vec<LineSegment> = (0..5u8)
            .map(|i| LineSegment::new([f32::from(i), 0.0, 0.0], [0.0, f32::from(i), 1.0], 1.0 + f32::from(i), [1.0; 4]))
            .collect();
        let mut out = vec![LineSegment::default(); 3];
        per_corner(&lines, &mut out);
        assert_eq!(out.len(), lines.len() * LINE_CORNERS, "the scratch is cleared first");
        for (i, v) in out.iter().enumerate() {
            assert_eq!(*v, lines[i / LINE_CORNERS], "vertex {i}");
        }
    }
}
