//! egui's own shapes — text, rectangles, lines, circles — drawn through a pipeline of ours
//! whose fragment shader does the least it can, instead of egui-wgpu's.
//!
//! egui-wgpu's fragment shader carries two branches (dithering, "predictable texture
//! filtering") that a CPU rasteriser (SwiftShader: headless Chromium, browsers without a GPU)
//! pays for even when they are not taken: measured in raw WebGL2 pages at 1400×900, a
//! full-window covering by egui's shader costs ~67 ms, a texture-sampling one without the
//! branches ~16 ms, a flat one nothing over the clear (docs/speed.md, rounds 5–7).
//!
//! [`replace_frame`] runs at the end of the app's frame (after `flat_fill`): in every painted
//! layer, each *run* — consecutive shapes in one clip rectangle that egui would draw with its
//! font atlas ([`eligible`]) — is tessellated here with epaint's own [`Tessellator`] (the same
//! pixels per point, tessellation options, atlas size and prepared discs as egui's, so the
//! triangles are egui's) and replaced by one paint callback ([`RunCallback`]) drawing that
//! mesh with `shaders/egui_pass.wgsl`: vertex colour × the atlas's sample, premultiplied alpha
//! blended exactly as egui-wgpu blends ([`replace_runs`] does it for one layer). The picture
//! is the same; the order of everything is kept (each run's callback takes its first shape's
//! place, the rest of the run becomes `Noop`).
//!
//! Left to egui: shapes with another texture, callbacks (3D views, flat fills) and `Vec`s
//! holding them, shapes transformed after tessellation, layers with a transform, and — for a
//! whole frame — every shape while the atlas egui-wgpu holds on the GPU may not be the one the
//! text was laid out in ([`AtlasGuard`]). Beyond [`MAX_EGUI_PASS_VERTICES`] a frame's further
//! runs go to egui as the meshes tessellated here (the same triangles, egui's shader).
//!
//! Nothing changes before [`EguiPass::install`] ran (no GPU: the headless tests) or when turned
//! off for measuring (`?hide=eguipass`).

use std::ops::Range;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use eframe::egui::{self, epaint};
use eframe::egui_wgpu::{self, CallbackResources, CallbackTrait, RenderState, ScreenDescriptor, wgpu};
use epaint::{ClippedShape, Shape, Tessellator, Vertex};

/// Most vertices drawn by this pass in one frame (20 bytes each: 10 MiB of vertex buffer);
/// further runs are drawn by egui. The app's tabs draw 7 000–41 000 (counted headless at
/// 1400×900; the crease tab the most, its plot's series).
pub const MAX_EGUI_PASS_VERTICES: usize = 1 << 19;

/// How deep a `Shape::Vec` is looked into to decide whether all of it can be drawn here;
/// deeper nesting stays egui's.
const MAX_VEC_DEPTH: usize = 4;

/// Initial GPU buffer sizes (vertices, indices); they grow by doubling, never shrink.
const INITIAL_VERTICES: u64 = 16 * 1024;
const INITIAL_INDICES: u64 = 48 * 1024;

/// egui's atlas is cleared (and its texture recreated at the same size) when it is fuller than
/// this at the start of a frame (epaint's `Fonts::begin_pass`, 0.8); above it the pass stands
/// aside, as a cleared atlas is not told apart from a grown one by its size.
const ATLAS_CLEAR_FILL_RATIO: f32 = 0.75;

/// Whether the pipelines are installed (a GPU render state exists).
static INSTALLED: AtomicBool = AtomicBool::new(false);

/// Measuring only (`app::ablate`, web `?hide=eguipass`): leave every shape to egui.
static DISABLED: AtomicBool = AtomicBool::new(false);

/// Number of the last frame this pass drew (its callbacks carry it; the meshes pending upload
/// are that frame's).
static FRAME_SERIAL: AtomicU64 = AtomicU64::new(0);

/// Frames left to egui whole because its atlas may have been replaced (for `?hide=area`'s log).
static FRAMES_LEFT: AtomicU64 = AtomicU64::new(0);

/// How many frames this pass drew and how many it left to egui whole because the atlas may
/// have been replaced (since the start; measuring aid, logged by `app::ablate::log_area`).
#[must_use]
pub fn frame_counts() -> (u64, u64) {
    (FRAME_SERIAL.load(Ordering::Relaxed), FRAMES_LEFT.load(Ordering::Relaxed))
}

/// Turns the pass off (`true`) for measuring the difference on the same build.
pub fn set_disabled(disabled: bool) {
    DISABLED.store(disabled, Ordering::Relaxed);
}

// ------------------------------------------------------------------------------------------
// Runs: pure logic over one layer's shapes.

/// Whether egui would draw `shape` with its font atlas and nothing else: no callback, no other
/// texture, no transform after tessellation (the pass draws the tessellated mesh as it is).
#[must_use]
pub fn eligible(cs: &ClippedShape) -> bool {
    cs.transform_after_tessellation == epaint::emath::TSTransform::IDENTITY && shape_eligible(&cs.shape, 0)
}

fn shape_eligible(shape: &Shape, depth: usize) -> bool {
    match shape {
        Shape::Callback(_) => false,
        Shape::Vec(parts) => depth < MAX_VEC_DEPTH && parts.iter().all(|s| shape_eligible(s, depth + 1)),
        other => other.texture_id() == egui::TextureId::default(),
    }
}

/// The runs of `shapes`: maximal ranges of consecutive [`eligible`] shapes with the same clip
/// rectangle, in order. Shapes in between (callbacks, other textures) are in no run.
#[must_use]
pub fn runs(shapes: &[ClippedShape]) -> Vec<Range<usize>> {
    let mut out: Vec<Range<usize>> = Vec::new();
    let mut start: Option<usize> = None;
    for (i, cs) in shapes.iter().enumerate() {
        if let Some(s) = start
            && !(eligible(cs) && shapes[s].clip_rect == cs.clip_rect)
        {
            out.push(s..i);
            start = None;
        }
        if start.is_none() && eligible(cs) {
            start = Some(i);
        }
    }
    if let Some(s) = start {
        out.push(s..shapes.len());
    }
    out
}

/// One run's mesh in the frame's buffers.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RunDraw {
    /// Its indices in the frame's index buffer (they already point at the frame's vertices).
    pub indices: Range<u32>,
}

/// The meshes of one frame's runs, one after another.
#[derive(Default)]
pub struct FrameMeshes {
    /// Every run's vertices (positions in points).
    pub vertices: Vec<Vertex>,
    /// Every run's indices, offset to point into `vertices`.
    pub indices: Vec<u32>,
}

/// Tessellates each run of one layer's `shapes` and replaces it: its first shape by the shape
/// `make` returns for its [`RunDraw`] (a paint callback), the others by `Noop`. A run whose
/// mesh would take the frame past `max_vertices` becomes that mesh as a `Shape::Mesh` instead
/// (egui draws the same triangles); a run that tessellates to nothing (all culled) becomes
/// `Noop`s.
/// Returns how many runs were replaced by `make`'s shapes.
pub fn replace_runs(
    shapes: &mut [ClippedShape],
    tessellator: &mut Tessellator,
    frame: &mut FrameMeshes,
    max_vertices: usize,
    make: &mut dyn FnMut(&RunDraw, egui::Rect) -> Shape,
) -> usize {
    let mut replaced = 0;
    let mut primitives = Vec::new();
    for run in runs(shapes) {
        let clip = shapes[run.start].clip_rect;
        primitives.clear();
        for cs in &mut shapes[run.clone()] {
            let shape = std::mem::replace(&mut cs.shape, Shape::Noop);
            let owned = ClippedShape {
                clip_rect: cs.clip_rect,
                shape,
                transform_after_tessellation: cs.transform_after_tessellation,
            };
            tessellator.tessellate_clipped_shape(owned, &mut primitives);
        }
        // A run shares one clip rectangle and texture: egui makes one mesh of it (none if all
        // of it was culled; the shapes, now `Noop`, drew nothing then either).
        let mut mesh = epaint::Mesh::default();
        for p in primitives.drain(..) {
            if let epaint::Primitive::Mesh(m) = p.primitive {
                mesh.append(m);
            }
        }
        if mesh.is_empty() {
            continue;
        }
        let first = run.start;
        let fits = frame.vertices.len() + mesh.vertices.len() <= max_vertices
            && u32::try_from(frame.indices.len() + mesh.indices.len()).is_ok();
        if !fits {
            shapes[first].shape = Shape::Mesh(mesh.into());
            continue;
        }
        let base = frame.vertices.len() as u32;
        let start = frame.indices.len() as u32;
        frame.vertices.extend_from_slice(&mesh.vertices);
        frame.indices.extend(mesh.indices.iter().map(|i| i + base));
        let draw = RunDraw { indices: start..frame.indices.len() as u32 };
        shapes[first].shape = make(&draw, clip);
        replaced += 1;
    }
    replaced
}

// ------------------------------------------------------------------------------------------
// The tessellator egui would use, and the guard on the atlas.

/// What egui's own tessellation depends on, besides the shapes.
#[derive(Clone, Copy, PartialEq)]
struct TessellatorKey {
    pixels_per_point: f32,
    options: epaint::TessellationOptions,
    atlas_size: [usize; 2],
    text_options: epaint::text::TextOptions,
}

/// The tessellator, made again when its key changes (its prepared discs need an atlas).
struct CachedTessellator {
    key: TessellatorKey,
    tessellator: Tessellator,
}

/// A tessellator set up as egui's own (`egui::Context::tessellate`): same pixels per point,
/// options, font atlas size and prepared discs. The discs' places in the atlas are those of a
/// fresh atlas of the same width (epaint allocates them first, in a fixed order, on every new
/// atlas); their texture coordinates are normalised by the current size, as epaint does.
#[must_use]
pub fn egui_tessellator(ctx: &egui::Context) -> Tessellator {
    let key = tessellator_key(ctx);
    make_tessellator(key)
}

fn tessellator_key(ctx: &egui::Context) -> TessellatorKey {
    let (atlas_size, text_options) = ctx.fonts(|f| (f.font_image_size(), *f.options()));
    TessellatorKey {
        pixels_per_point: ctx.pixels_per_point(),
        options: ctx.tessellation_options(|o| *o),
        atlas_size,
        text_options,
    }
}

/// Height epaint gives a new font atlas (`GlyphAtlas::new`); the discs fit in it.
const NEW_ATLAS_HEIGHT: usize = 32;

fn make_tessellator(key: TessellatorKey) -> Tessellator {
    let [w, h] = key.atlas_size;
    let fresh = epaint::TextureAtlas::new([w.max(1024), NEW_ATLAS_HEIGHT], key.text_options);
    let fresh_size = fresh.size();
    let mut discs = fresh.prepared_discs();
    let (inv_w, inv_h) = (1.0 / w.max(1) as f32, 1.0 / h.max(1) as f32);
    for d in &mut discs {
        // Back to texels (exact: small integers), then normalised as epaint does for `[w, h]`.
        let texel = |u: f32, size: usize| (u * size as f32).round();
        d.uv = egui::Rect::from_min_max(
            egui::pos2(texel(d.uv.min.x, fresh_size[0]) * inv_w, texel(d.uv.min.y, fresh_size[1]) * inv_h),
            egui::pos2(texel(d.uv.max.x, fresh_size[0]) * inv_w, texel(d.uv.max.y, fresh_size[1]) * inv_h),
        );
    }
    Tessellator::new(key.pixels_per_point, key.options, key.atlas_size, discs)
}

/// What the pass remembers of the last frame's atlas, to notice a cleared one: epaint clears
/// its atlas at the start of a frame when it is fuller than 0.8, or when its options change,
/// and egui-wgpu then makes a new texture, possibly of the same size. A fill ratio lower than
/// last frame's, other options, or a last ratio near the clearing point make the pass leave
/// that frame to egui.
#[derive(Clone, Copy, PartialEq)]
pub struct AtlasGuard {
    fill_ratio: f32,
    text_options: epaint::text::TextOptions,
}

impl AtlasGuard {
    /// Whether this frame's atlas (`now`) is surely the one of the last frame (`last`), grown
    /// at most by glyphs added since (which egui-wgpu writes into the same texture).
    #[must_use]
    pub fn same_atlas(last: Option<Self>, now: Self) -> bool {
        last.is_some_and(|l| {
            l.text_options == now.text_options
                && now.fill_ratio >= l.fill_ratio
                && l.fill_ratio <= ATLAS_CLEAR_FILL_RATIO
        })
    }
}

/// State kept from frame to frame on the app's side.
struct HookState {
    tessellator: Option<CachedTessellator>,
    last_atlas: Option<AtlasGuard>,
}

static HOOK: Mutex<HookState> = Mutex::new(HookState { tessellator: None, last_atlas: None });

// ------------------------------------------------------------------------------------------
// The hook and the GPU side.

/// Replaces the frame's runs of egui shapes by callbacks drawing them with this pass (see the
/// module's text). Call at the end of the app's frame, after the flat fills; does nothing
/// before [`EguiPass::install`], without a render state, or when turned off for measuring.
pub fn replace_frame(ctx: &egui::Context, rs: Option<&RenderState>) {
    let Some(rs) = rs else { return };
    if !INSTALLED.load(Ordering::Relaxed) || DISABLED.load(Ordering::Relaxed) {
        return;
    }
    let Ok(mut hook) = HOOK.lock() else { return };
    let now = ctx.fonts(|f| AtlasGuard { fill_ratio: f.font_atlas_fill_ratio(), text_options: *f.options() });
    let last = hook.last_atlas.replace(now);
    // The atlas egui-wgpu holds now, and its size against the one the text was laid out in.
    let atlas = rs.renderer.read().texture(&egui::TextureId::default()).and_then(|t| t.texture.clone());
    let key = tessellator_key(ctx);
    let Some(atlas) = atlas
        .filter(|a| AtlasGuard::same_atlas(last, now) && [a.width() as usize, a.height() as usize] == key.atlas_size)
    else {
        FRAMES_LEFT.fetch_add(1, Ordering::Relaxed);
        return;
    };
    let cached = match hook.tessellator.take() {
        Some(c) if c.key == key => c,
        _ => CachedTessellator { key, tessellator: make_tessellator(key) },
    };
    let mut tessellator = cached.tessellator;

    let serial = FRAME_SERIAL.fetch_add(1, Ordering::Relaxed) + 1;
    let mut frame = FrameMeshes::default();
    let mut make = |draw: &RunDraw, clip: egui::Rect| {
        Shape::Callback(egui_wgpu::Callback::new_paint_callback(
            clip,
            RunCallback { serial, indices: draw.indices.clone() },
        ))
    };
    let layers: Vec<egui::LayerId> = ctx.memory(|m| m.layer_ids().collect());
    let layers: Vec<egui::LayerId> =
        layers.into_iter().filter(|id| ctx.layer_transform_to_global(*id).is_none()).collect();
    ctx.graphics_mut(|g| {
        let mut shapes: Vec<ClippedShape> = Vec::new();
        for id in layers {
            let Some(list) = g.get_mut(id) else { continue };
            let n = list.next_idx().0;
            shapes.clear();
            for i in 0..n {
                list.mutate_shape(egui::layers::ShapeIdx(i), |cs| {
                    shapes.push(std::mem::replace(
                        cs,
                        ClippedShape {
                            clip_rect: cs.clip_rect,
                            shape: Shape::Noop,
                            transform_after_tessellation: cs.transform_after_tessellation,
                        },
                    ));
                });
            }
            replace_runs(&mut shapes, &mut tessellator, &mut frame, MAX_EGUI_PASS_VERTICES, &mut make);
            for (i, cs) in shapes.drain(..).enumerate() {
                list.mutate_shape(egui::layers::ShapeIdx(i), |slot| *slot = cs);
            }
        }
    });
    hook.tessellator = Some(CachedTessellator { key, tessellator });
    drop(hook);
    if let Some(pass) = rs.renderer.write().callback_resources.get_mut::<EguiPass>() {
        pass.pending = Some(PendingFrame { serial, meshes: frame, atlas });
    }
}

/// A frame's meshes waiting for the first of its callbacks to upload them.
struct PendingFrame {
    serial: u64,
    meshes: FrameMeshes,
    atlas: wgpu::Texture,
}

/// Screen size uniform (matches `Locals` in egui_pass.wgsl).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
struct Locals {
    screen_size_pt: [f32; 2],
    pad: [f32; 2],
}

/// The pass's pipelines and buffers, in egui-wgpu's callback resources.
pub struct EguiPass {
    pipeline: wgpu::RenderPipeline,
    locals: wgpu::Buffer,
    locals_now: Locals,
    locals_group: wgpu::BindGroup,
    atlas_layout: wgpu::BindGroupLayout,
    sampler: wgpu::Sampler,
    /// The atlas texture bound, and its bind group.
    atlas: Option<(wgpu::Texture, wgpu::BindGroup)>,
    vertices: wgpu::Buffer,
    vertex_capacity: u64,
    indices: wgpu::Buffer,
    index_capacity: u64,
    /// The frame whose meshes are in the buffers.
    uploaded: u64,
    pending: Option<PendingFrame>,
}

fn vertex_buffer(device: &wgpu::Device, count: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("interpolab egui pass vertices"),
        size: count * std::mem::size_of::<Vertex>() as u64,
        usage: wgpu::BufferUsages::VERTEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

fn index_buffer(device: &wgpu::Device, count: u64) -> wgpu::Buffer {
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("interpolab egui pass indices"),
        size: count * 4,
        usage: wgpu::BufferUsages::INDEX | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

impl EguiPass {
    /// Creates the pipelines (for the render state's target format, with egui-wgpu's blending)
    /// in egui-wgpu's callback resources and turns [`replace_frame`] on.
    pub fn install(rs: &RenderState) {
        let device = &rs.device;
        let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("interpolab egui pass shader"),
            source: wgpu::ShaderSource::Wgsl(include_str!("shaders/egui_pass.wgsl").into()),
        });
        let locals_layout =
            super::uniform_layout(device, "interpolab egui pass locals layout", wgpu::ShaderStages::VERTEX);
        let atlas_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("interpolab egui pass atlas layout"),
            entries: &[
                super::fragment_texture_entry(0),
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
            ],
        });
        let locals_now = Locals { screen_size_pt: [1.0, 1.0], pad: [0.0; 2] };
        let locals = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("interpolab egui pass locals"),
            size: std::mem::size_of::<Locals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        rs.queue.write_buffer(&locals, 0, bytemuck::bytes_of(&locals_now));
        let locals_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("interpolab egui pass locals"),
            layout: &locals_layout,
            entries: &[wgpu::BindGroupEntry { binding: 0, resource: locals.as_entire_binding() }],
        });
        let srgb = rs.target_format.is_srgb();
        let pipeline = |label: &str, layouts: &[Option<&wgpu::BindGroupLayout>], fragment: &str| {
            let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: layouts,
                immediate_size: 0,
            });
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&layout),
                vertex: wgpu::VertexState {
                    module: &module,
                    entry_point: Some("vs_main"),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    // epaint's `Vertex`: position (points), texture coordinates, colour (u32).
                    buffers: &[Some(wgpu::VertexBufferLayout {
                        array_stride: std::mem::size_of::<Vertex>() as u64,
                        step_mode: wgpu::VertexStepMode::Vertex,
                        attributes: &wgpu::vertex_attr_array![0 => Float32x2, 1 => Float32x2, 2 => Uint32],
                    })],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: None,
                multisample: wgpu::MultisampleState::default(),
                fragment: Some(wgpu::FragmentState {
                    module: &module,
                    entry_point: Some(fragment),
                    compilation_options: wgpu::PipelineCompilationOptions::default(),
                    targets: &[Some(wgpu::ColorTargetState {
                        format: rs.target_format,
                        // egui-wgpu's blending: premultiplied colour; alpha accumulates.
                        blend: Some(wgpu::BlendState {
                            color: wgpu::BlendComponent {
                                src_factor: wgpu::BlendFactor::One,
                                dst_factor: wgpu::BlendFactor::OneMinusSrcAlpha,
                                operation: wgpu::BlendOperation::Add,
                            },
                            alpha: wgpu::BlendComponent {
                                src_factor: wgpu::BlendFactor::OneMinusDstAlpha,
                                dst_factor: wgpu::BlendFactor::One,
                                operation: wgpu::BlendOperation::Add,
                            },
                        }),
                        write_mask: wgpu::ColorWrites::ALL,
                    })],
                }),
                multiview_mask: None,
                cache: None,
            })
        };
        // As egui-wgpu: the gamma-space shader for a plain target (the web), the decoding one
        // for an sRGB target.
        let pipeline = pipeline(
            "interpolab egui pass",
            &[Some(&locals_layout), Some(&atlas_layout)],
            if srgb { "fs_main_linear_framebuffer" } else { "fs_main_gamma_framebuffer" },
        );
        // egui's sampler for its font atlas (`TextureOptions::LINEAR`).
        let sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("interpolab egui pass atlas sampler"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            ..Default::default()
        });
        let pass = Self {
            pipeline,
            locals,
            locals_now,
            locals_group,
            atlas_layout,
            sampler,
            atlas: None,
            vertices: vertex_buffer(device, INITIAL_VERTICES),
            vertex_capacity: INITIAL_VERTICES,
            indices: index_buffer(device, INITIAL_INDICES),
            index_capacity: INITIAL_INDICES,
            uploaded: 0,
            pending: None,
        };
        rs.renderer.write().callback_resources.insert(pass);
        INSTALLED.store(true, Ordering::Relaxed);
    }

    /// Uploads the pending frame `serial` (once, by its first callback): grows the buffers if
    /// needed, rebinds the atlas if egui-wgpu made a new texture, updates the screen size.
    fn upload(&mut self, serial: u64, device: &wgpu::Device, queue: &wgpu::Queue, screen: &ScreenDescriptor) {
        let ppp = screen.pixels_per_point;
        let locals = Locals {
            screen_size_pt: [screen.size_in_pixels[0] as f32 / ppp, screen.size_in_pixels[1] as f32 / ppp],
            pad: [0.0; 2],
        };
        if locals != self.locals_now {
            queue.write_buffer(&self.locals, 0, bytemuck::bytes_of(&locals));
            self.locals_now = locals;
        }
        if self.uploaded == serial {
            return;
        }
        let Some(frame) = self.pending.take_if(|p| p.serial == serial) else { return };
        if self.atlas.as_ref().is_none_or(|(t, _)| *t != frame.atlas) {
            let view = frame.atlas.create_view(&wgpu::TextureViewDescriptor::default());
            let group = device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("interpolab egui pass atlas"),
                layout: &self.atlas_layout,
                entries: &[
                    wgpu::BindGroupEntry { binding: 0, resource: wgpu::BindingResource::TextureView(&view) },
                    wgpu::BindGroupEntry { binding: 1, resource: wgpu::BindingResource::Sampler(&self.sampler) },
                ],
            });
            self.atlas = Some((frame.atlas, group));
        }
        let (nv, ni) = (frame.meshes.vertices.len() as u64, frame.meshes.indices.len() as u64);
        if nv > self.vertex_capacity {
            self.vertex_capacity = nv.next_power_of_two();
            self.vertices = vertex_buffer(device, self.vertex_capacity);
        }
        if ni > self.index_capacity {
            self.index_capacity = ni.next_power_of_two();
            self.indices = index_buffer(device, self.index_capacity);
        }
        if nv > 0 {
            queue.write_buffer(&self.vertices, 0, bytemuck::cast_slice(&frame.meshes.vertices));
        }
        if ni > 0 {
            queue.write_buffer(&self.indices, 0, bytemuck::cast_slice(&frame.meshes.indices));
        }
        self.uploaded = serial;
    }
}

/// One run of egui shapes: its indices in the frame's buffers.
#[derive(Clone, Debug)]
pub struct RunCallback {
    /// The frame the indices belong to.
    serial: u64,
    indices: Range<u32>,
}

impl CallbackTrait for RunCallback {
    fn prepare(
        &self,
        device: &wgpu::Device,
        queue: &wgpu::Queue,
        screen: &ScreenDescriptor,
        _encoder: &mut wgpu::CommandEncoder,
        resources: &mut CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        if let Some(pass) = resources.get_mut::<EguiPass>() {
            pass.upload(self.serial, device, queue, screen);
        }
        Vec::new()
    }

    fn paint(
        &self,
        info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &CallbackResources,
    ) {
        let Some(p) = resources.get::<EguiPass>() else { return };
        if p.uploaded != self.serial || self.indices.is_empty() {
            return;
        }
        // egui-wgpu set the viewport to the callback's rectangle; the mesh is in screen points.
        let [w, h] = info.screen_size_px;
        pass.set_viewport(0.0, 0.0, w as f32, h as f32, 0.0, 1.0);
        let Some((_, atlas)) = &p.atlas else { return };
        pass.set_pipeline(&p.pipeline);
        pass.set_bind_group(0, &p.locals_group, &[]);
        pass.set_bind_group(1, atlas, &[]);
        pass.set_vertex_buffer(0, p.vertices.slice(..));
        pass.set_index_buffer(p.indices.slice(..), wgpu::IndexFormat::Uint32);
        pass.draw_indexed(self.indices.clone(), 0, 0..1);
    }
}

#[cfg(test)]
mod tests;
