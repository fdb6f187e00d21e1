//! Large opaque rectangles of the UI (plot backgrounds, framed tables) drawn by a flat-colour
//! pipeline of our own instead of egui's.
//!
//! egui-wgpu draws every shape with one pipeline: it samples a texture and blends, for every
//! pixel, whatever the shape's alpha. On a CPU rasteriser (SwiftShader: headless Chromium,
//! browsers without a GPU) that costs about 53 ns per pixel, some 67 ms per covering of a
//! 1400×900 window (docs/speed.md, "Frames on SwiftShader"), while a flat colour without
//! texture or blending costs next to nothing over the clear. [`flatten`] runs at the end of
//! the app's frame: each opaque, untextured, unrotated, sharp rectangle of at least
//! [`MIN_FLAT_FILL_AREA_PT2`] becomes a paint callback ([`FillCallback`]) filling its
//! rectangle with one colour, followed by the same rectangle without fill for its outline
//! (drawn by egui as before). The picture is the same but for the anti-aliased fringe of the
//! fill's edge (now a sharp pixel edge) and corners rounded by at most
//! [`MAX_FLAT_FILL_RADIUS_PT`] (now square under the rounded outline).
//!
//! One pipeline per colour (the colour is a constant of its shader), created the first time a
//! frame asks for it; at most [`MAX_FLAT_FILL_COLOURS`] colours are admitted, further ones
//! stay egui's. Nothing changes until [`FlatFills::install`] ran (no GPU: egui draws all).

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

use eframe::egui;
use eframe::egui_wgpu::{self, CallbackResources, CallbackTrait, RenderState, ScreenDescriptor, wgpu};

/// Smallest rectangle worth a callback of its own (points², after clipping): each callback
/// switches egui's pipeline away and back, so small fills stay egui's.
pub const MIN_FLAT_FILL_AREA_PT2: f32 = 4000.0;

/// Largest corner radius (points) a rectangle may have to be filled flat: its corners become
/// square (a fraction of a pixel's difference under a 1-point outline at this radius).
pub const MAX_FLAT_FILL_RADIUS_PT: f32 = 3.0;

/// How many colours get a pipeline (the UI uses two or three).
pub const MAX_FLAT_FILL_COLOURS: usize = 16;

/// Whether the pipelines are installed (a GPU render state exists).
static INSTALLED: AtomicBool = AtomicBool::new(false);

/// Measuring only (`app::ablate`, web `?hide=flatfill`): leave every fill to egui.
static DISABLED: AtomicBool = AtomicBool::new(false);

/// The colours admitted so far (each has, or will get in `prepare`, a pipeline).
static ADMITTED: Mutex<Vec<egui::Color32>> = Mutex::new(Vec::new());

/// Turns the flat fills off (`true`) for measuring the difference on the same build.
pub fn set_disabled(disabled: bool) {
    DISABLED.store(disabled, Ordering::Relaxed);
}

/// The flat-colour pipelines, in egui-wgpu's callback resources.
pub struct FlatFills {
    device: wgpu::Device,
    target_format: wgpu::TextureFormat,
    layout: wgpu::PipelineLayout,
    pipelines: Vec<(egui::Color32, wgpu::RenderPipeline)>,
}

impl FlatFills {
    /// Stores the (still empty) pipeline cache in egui-wgpu's callback resources and turns
    /// [`flatten`] on.
    pub fn install(rs: &RenderState) {
        let layout = rs.device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("interpolab flat fill pipeline layout"),
            bind_group_layouts: &[],
            immediate_size: 0,
        });
        let fills = Self { device: rs.device.clone(), target_format: rs.target_format, layout, pipelines: Vec::new() };
        rs.renderer.write().callback_resources.insert(fills);
        INSTALLED.store(true, Ordering::Relaxed);
    }

    fn pipeline(&self, colour: egui::Color32) -> Option<&wgpu::RenderPipeline> {
        self.pipelines.iter().find(|(c, _)| *c == colour).map(|(_, p)| p)
    }

    fn ensure(&mut self, colour: egui::Color32) {
        if self.pipeline(colour).is_some() || self.pipelines.len() >= MAX_FLAT_FILL_COLOURS {
            return;
        }
        let rgb = shader_rgb(colour, self.target_format.is_srgb());
        let source = include_str!("shaders/flat_fill.wgsl")
            .replace("FILL_RGB", &format!("{:.6}, {:.6}, {:.6}", rgb[0], rgb[1], rgb[2]));
        let module = self.device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("interpolab flat fill shader"),
            source: wgpu::ShaderSource::Wgsl(source.into()),
        });
        let pipeline = self.device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
            label: Some("interpolab flat fill"),
            layout: Some(&self.layout),
            vertex: wgpu::VertexState {
                module: &module,
                entry_point: Some("vs_fullscreen"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                buffers: &[],
            },
            primitive: wgpu::PrimitiveState::default(),
            depth_stencil: None,
            multisample: wgpu::MultisampleState::default(),
            fragment: Some(wgpu::FragmentState {
                module: &module,
                entry_point: Some("fs_flat"),
                compilation_options: wgpu::PipelineCompilationOptions::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: self.target_format,
                    blend: None,
                    write_mask: wgpu::ColorWrites::ALL,
                })],
            }),
            multiview_mask: None,
            cache: None,
        });
        self.pipelines.push((colour, pipeline));
    }
}

/// The colour a flat-fill shader writes (0–1 per channel): egui's colours are gamma-encoded;
/// an sRGB target (native) wants linear values (the hardware encodes on write), a plain one
/// (the web) the encoded values themselves — as egui's own shader does.
#[must_use]
pub fn shader_rgb(colour: egui::Color32, srgb_target: bool) -> [f32; 3] {
    if srgb_target {
        let l = egui::Rgba::from(colour);
        [l.r(), l.g(), l.b()]
    } else {
        let g = colour.to_normalized_gamma_f32();
        [g[0], g[1], g[2]]
    }
}

/// One flat fill: the callback's rectangle in one opaque colour.
#[derive(Clone, Copy, Debug)]
pub struct FillCallback {
    /// The fill colour (opaque).
    pub colour: egui::Color32,
}

impl CallbackTrait for FillCallback {
    fn prepare(
        &self,
        _device: &wgpu::Device,
        _queue: &wgpu::Queue,
        _screen: &ScreenDescriptor,
        _encoder: &mut wgpu::CommandEncoder,
        resources: &mut CallbackResources,
    ) -> Vec<wgpu::CommandBuffer> {
        if let Some(f) = resources.get_mut::<FlatFills>() {
            f.ensure(self.colour);
        }
        Vec::new()
    }

    fn paint(
        &self,
        _info: egui::PaintCallbackInfo,
        pass: &mut wgpu::RenderPass<'static>,
        resources: &CallbackResources,
    ) {
        if let Some(p) = resources.get::<FlatFills>().and_then(|f| f.pipeline(self.colour)) {
            pass.set_pipeline(p);
            pass.draw(0..3, 0..1);
        }
    }
}

/// Whether `colour` may be filled flat (admits it if there is room for its pipeline).
fn admit(colour: egui::Color32) -> bool {
    let Ok(mut admitted) = ADMITTED.lock() else {
        return false;
    };
    if admitted.contains(&colour) {
        return true;
    }
    if admitted.len() >= MAX_FLAT_FILL_COLOURS {
        return false;
    }
    admitted.push(colour);
    true
}

/// The largest of a rectangle's four corner radii (points).
fn largest_radius(c: egui::CornerRadius) -> f32 {
    f32::from(c.nw.max(c.ne).max(c.sw).max(c.se))
}

/// The shape that replaces `rect` (seen through `clip`), if it qualifies for a flat fill: the
/// fill as a callback, then the outline alone.
#[must_use]
pub fn flat_replacement(rect: &egui::epaint::RectShape, clip: egui::Rect) -> Option<egui::Shape> {
    let qualifies = rect.fill.is_opaque()
        && rect.brush.is_none()
        && rect.blur_width == 0.0
        && rect.angle == 0.0
        && largest_radius(rect.corner_radius) <= MAX_FLAT_FILL_RADIUS_PT
        && rect.rect.intersect(clip).is_positive()
        && rect.rect.intersect(clip).area() >= MIN_FLAT_FILL_AREA_PT2;
    if !qualifies || !admit(rect.fill) {
        return None;
    }
    let fill =
        egui::Shape::Callback(egui_wgpu::Callback::new_paint_callback(rect.rect, FillCallback { colour: rect.fill }));
    if rect.stroke.is_empty() {
        return Some(fill);
    }
    let mut outline = rect.clone();
    outline.fill = egui::Color32::TRANSPARENT;
    Some(egui::Shape::Vec(vec![fill, egui::Shape::Rect(outline)]))
}

/// Replaces the frame's large opaque rectangles by flat fills (see the module's text). Call
/// at the end of the app's frame; does nothing before [`FlatFills::install`] or when turned
/// off for measuring.
pub fn flatten(ctx: &egui::Context) {
    if !INSTALLED.load(Ordering::Relaxed) || DISABLED.load(Ordering::Relaxed) {
        return;
    }
    mutate_painted_shapes(ctx, |cs| {
        if let egui::Shape::Rect(r) = &cs.shape
            && let Some(s) = flat_replacement(r, cs.clip_rect)
        {
            cs.shape = s;
        }
    });
}

/// Calls `f` on every shape painted so far this frame, in every layer, to change it in place
/// (the flat fills here, the ablation switches of `app::ablate`).
pub fn mutate_painted_shapes(ctx: &egui::Context, mut f: impl FnMut(&mut egui::epaint::ClippedShape)) {
    let layers: Vec<egui::LayerId> = ctx.memory(|m| m.layer_ids().collect());
    ctx.graphics_mut(|g| {
        for id in layers {
            let Some(list) = g.get_mut(id) else { continue };
            for i in 0..list.next_idx().0 {
                list.mutate_shape(egui::layers::ShapeIdx(i), &mut f);
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::{MIN_FLAT_FILL_AREA_PT2, flat_replacement, shader_rgb};
    use eframe::egui::{self, Color32, CornerRadius, Rect, Shape, Stroke, StrokeKind, epaint::RectShape, pos2};

    fn rect(w: f32, h: f32, fill: Color32, radius: u8, stroke: Stroke) -> RectShape {
        RectShape::new(
            Rect::from_min_size(pos2(10.0, 20.0), egui::vec2(w, h)),
            CornerRadius::same(radius),
            fill,
            stroke,
            StrokeKind::Inside,
        )
    }
    const EVERYWHERE: Rect = Rect::EVERYTHING;

    #[test]
    fn a_large_opaque_rectangle_becomes_a_fill_and_its_outline() {
        let stroke = Stroke::new(1.0, Color32::from_gray(60));
        let r = rect(300.0, 200.0, Color32::from_gray(10), 2, stroke);
        let Some(Shape::Vec(parts)) = flat_replacement(&r, EVERYWHERE) else { panic!("not replaced") };
        assert_eq!(parts.len(), 2);
        let Shape::Callback(cb) = &parts[0] else { panic!("the fill comes first, as a callback") };
        assert_eq!(cb.rect, r.rect, "the fill covers the rectangle");
        let Shape::Rect(outline) = &parts[1] else { panic!("then the outline") };
        assert_eq!(outline.fill, Color32::TRANSPARENT);
        assert_eq!((outline.rect, outline.stroke, outline.corner_radius), (r.rect, r.stroke, r.corner_radius));
        let bare = rect(300.0, 200.0, Color32::from_gray(10), 0, Stroke::NONE);
        assert!(matches!(flat_replacement(&bare, EVERYWHERE), Some(Shape::Callback(_))), "no outline to keep");
    }

    #[test]
    fn translucent_small_rounded_or_clipped_away_rectangles_stay_egui_s() {
        let opaque = Color32::from_gray(10);
        assert!(
            flat_replacement(&rect(300.0, 200.0, Color32::from_black_alpha(200), 0, Stroke::NONE), EVERYWHERE)
                .is_none()
        );
        assert!(
            flat_replacement(&rect(300.0, 200.0, Color32::from_additive_luminance(5), 0, Stroke::NONE), EVERYWHERE)
                .is_none()
        );
        assert!(flat_replacement(&rect(300.0, 200.0, opaque, 8, Stroke::NONE), EVERYWHERE).is_none());
        let side = (MIN_FLAT_FILL_AREA_PT2.sqrt() * 0.9).floor();
        assert!(flat_replacement(&rect(side, side, opaque, 0, Stroke::NONE), EVERYWHERE).is_none());
        let mut blurred = rect(300.0, 200.0, opaque, 0, Stroke::NONE);
        blurred.blur_width = 4.0;
        assert!(flat_replacement(&blurred, EVERYWHERE).is_none());
        // Large, but only a sliver of it is visible.
        let sliver = Rect::from_min_size(pos2(10.0, 20.0), egui::vec2(300.0, 5.0));
        assert!(flat_replacement(&rect(300.0, 200.0, opaque, 0, Stroke::NONE), sliver).is_none());
    }

    #[test]
    fn the_shader_colour_is_encoded_for_its_target() {
        let c = Color32::from_rgb(10, 128, 255);
        let plain = shader_rgb(c, false);
        for (got, byte) in plain.iter().zip([10u8, 128, 255]) {
            assert!((got - f32::from(byte) / 255.0).abs() < 1e-6, "{got} for {byte}");
        }
        // sRGB decoding (IEC 61966-2-1) of 128/255: ((0.50196 + 0.055) / 1.055)^2.4 = 0.21586.
        let linear = shader_rgb(c, true);
        assert!((linear[1] - 0.215_86).abs() < 1e-3, "{}", linear[1]);
        assert!(linear[0] < plain[0] && (linear[2] - 1.0).abs() < 1e-6);
    }
}
