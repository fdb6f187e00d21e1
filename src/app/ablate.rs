//! Frame ablation for measuring where a frame's drawing time goes (`e2e/frame-profile.mjs`):
//! the page address's `hide=` list leaves parts of every frame out, one at a time, so the
//! frame time with and without each part can be compared on the same build. Web only: the
//! browser entry point (`app::web`) reads the address once at start; natively nothing is ever
//! hidden. Not a user feature: a page with a part hidden is incomplete on purpose.
//!
//! `?hide=NAME[,NAME…]`, names (unknown ones are ignored):
//! - structural (the part is not laid out): `side` (the side panel), `top` (the top bar),
//!   `tabs` (the row of tab buttons), `bottom` (the crease tab's plots panel: playback bar,
//!   summary and plot), `plot` (only the crease tab's plot widget), `plotdata` (the crease
//!   plot's series: frame, grid and axes stay), `grid` (the crease plot's grid);
//! - by kind of shape, removed after the frame was laid out (the layout is unchanged):
//!   `view3d` (the 3D views' paint callbacks: their composite pass), `text` (all text),
//!   `rects` (filled or outlined rectangles: buttons, frames, plot backgrounds, slider
//!   rails), `lines` (paths and line segments: plot lines, grids, separators, the axis triad),
//!   `meshes` (egui meshes: the slider handles' circles are not meshes, glyphs are not either);
//! - inside the 3D views' scene pass (`render::gpu`): `scene3d` (no scene pass once a view
//!   holds an image: it shows a stale image, but its composite still runs), `surfaces`
//!   (the shaded surfaces), `offsets` (the translucent offset surfaces), `lines3d` (every line
//!   layer), `spheres` (markers and cutters);
//! - in egui's look: `feathering` (no anti-aliasing fringe on shapes: fewer triangles, jagged
//!   edges), `rounding` (square corners on every widget: fewer triangles);
//! - `area` hides nothing: it logs to the browser console (as a warning: release builds keep
//!   only warnings), every 30 frames, the area (in
//!   points², clipped, from each shape's bounding rectangle) the frame's shapes cover, by kind
//!   of shape — an upper bound of the pixels egui's shader fills (text is counted by its
//!   bounding box, not its glyphs; counted before the flat fills and `render::egui_pass` take
//!   theirs), and how many frames `render::egui_pass` drew and how many it left to egui whole;
//! - `flatfill` leaves out an optimisation instead of a part: the large opaque rectangles
//!   are drawn by egui's shader again, not by `render::flat_fill`'s flat-colour pipeline;
//! - `eguipass` likewise: egui's text, rectangles, lines and circles are drawn by egui-wgpu's
//!   own pipeline again, not by `render::egui_pass`'s;
//! - `marks` hides nothing: the 3D renderer leaves a `performance.mark` for every scene pass
//!   (view, size, spheres, line vertices, mesh indices) and every layer upload (bytes), so a
//!   trace of a long frame says what it drew and sent (`frame-profile.mjs --trace`).

use std::sync::atomic::{AtomicU32, Ordering};

use eframe::egui;

/// A part of the frame that can be left out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum Part {
    /// The side panel (the tab's controls).
    Side = 1,
    /// The top bar (scene, presets, help).
    Top = 1 << 1,
    /// The row of tab buttons over the view.
    Tabs = 1 << 2,
    /// The crease tab's bottom panel (playback bar, summary, plot).
    Bottom = 1 << 3,
    /// The crease tab's plot widget (egui_plot).
    Plot = 1 << 4,
    /// The 3D views' paint callbacks.
    View3d = 1 << 5,
    /// All text shapes.
    Text = 1 << 6,
    /// All rectangle shapes.
    Rects = 1 << 7,
    /// All paths and line segments.
    Lines = 1 << 8,
    /// All mesh shapes.
    Meshes = 1 << 9,
    /// The 3D views' scene pass once they hold an image.
    Scene3d = 1 << 10,
    /// The 3D views' shaded surfaces.
    Surfaces = 1 << 11,
    /// The 3D views' translucent offset surfaces.
    Offsets = 1 << 12,
    /// The 3D views' line layers.
    Lines3d = 1 << 13,
    /// The 3D views' spheres (markers, cutters).
    Spheres = 1 << 14,
    /// egui's feathering (anti-aliasing fringe of shapes).
    Feathering = 1 << 15,
    /// The widgets' rounded corners.
    Rounding = 1 << 16,
    /// The crease plot's series (lines).
    PlotData = 1 << 17,
    /// The crease plot's grid.
    Grid = 1 << 18,
    /// Log the covered area by kind of shape (hides nothing).
    Area = 1 << 19,
    /// Leave the large opaque rectangles to egui's shader (`render::flat_fill` off).
    FlatFill = 1 << 20,
    /// Leave egui's shapes to egui-wgpu's pipeline (`render::egui_pass` off).
    EguiPass = 1 << 21,
    /// Leave performance marks of the 3D views' scene passes and uploads (hides nothing).
    Marks = 1 << 22,
}

/// The names in the address, in [`Part`]'s order.
const NAMES: [(&str, Part); 23] = [
    ("side", Part::Side),
    ("top", Part::Top),
    ("tabs", Part::Tabs),
    ("bottom", Part::Bottom),
    ("plot", Part::Plot),
    ("view3d", Part::View3d),
    ("text", Part::Text),
    ("rects", Part::Rects),
    ("lines", Part::Lines),
    ("meshes", Part::Meshes),
    ("scene3d", Part::Scene3d),
    ("surfaces", Part::Surfaces),
    ("offsets", Part::Offsets),
    ("lines3d", Part::Lines3d),
    ("spheres", Part::Spheres),
    ("feathering", Part::Feathering),
    ("rounding", Part::Rounding),
    ("plotdata", Part::PlotData),
    ("grid", Part::Grid),
    ("area", Part::Area),
    ("flatfill", Part::FlatFill),
    ("eguipass", Part::EguiPass),
    ("marks", Part::Marks),
];

static HIDDEN: AtomicU32 = AtomicU32::new(0);

/// The parts a query string (`?a=b&hide=side,plot`) hides, as a bit set.
#[must_use]
pub fn parse(query: &str) -> u32 {
    let q = query.strip_prefix('?').unwrap_or(query);
    q.split('&')
        .filter_map(|kv| kv.strip_prefix("hide="))
        .flat_map(|list| list.split([',', '+', ' ']))
        .filter_map(|name| NAMES.iter().find(|(n, _)| *n == name).map(|(_, p)| *p as u32))
        .fold(0, |acc, bit| acc | bit)
}

/// Sets the hidden parts for the rest of the session (the browser entry point, once),
/// including the 3D views' layers (`render::gpu::marks::set_skipped_layers`).
pub fn set(bits: u32) {
    use crate::render::gpu::Layer;
    use crate::render::gpu::marks::{SKIP_SCENE_PASS, set_skipped_layers};
    HIDDEN.store(bits, Ordering::Relaxed);
    let has = |p: Part| bits & p as u32 != 0;
    let layer = |l: Layer| 1u32 << l as u32;
    let mut layers = 0;
    if has(Part::Scene3d) {
        layers |= SKIP_SCENE_PASS;
    }
    if has(Part::Surfaces) {
        layers |= layer(Layer::Surfaces);
    }
    if has(Part::Offsets) {
        layers |= layer(Layer::Offsets);
    }
    if has(Part::Lines3d) {
        layers |=
            layer(Layer::StaticLines) | layer(Layer::PathLines) | layer(Layer::ExactLines) | layer(Layer::DynamicLines);
    }
    if has(Part::Spheres) {
        layers |= layer(Layer::Markers) | layer(Layer::Cutters);
    }
    set_skipped_layers(layers);
    crate::render::flat_fill::set_disabled(has(Part::FlatFill));
    crate::render::egui_pass::set_disabled(has(Part::EguiPass));
    crate::render::gpu::marks::set_marks(has(Part::Marks));
}

/// Whether `part` is left out of every frame.
#[must_use]
pub fn hidden(part: Part) -> bool {
    HIDDEN.load(Ordering::Relaxed) & part as u32 != 0
}

/// Applies the hidden parts of egui's look (`feathering`, `rounding`) to `ctx` (once, after
/// the app's own style).
pub fn restyle(ctx: &egui::Context) {
    if hidden(Part::Feathering) {
        ctx.tessellation_options_mut(|o| o.feathering = false);
    }
    if hidden(Part::Rounding) {
        ctx.style_mut_of(egui::Theme::Dark, |s| {
            let w = &mut s.visuals.widgets;
            for v in [&mut w.noninteractive, &mut w.inactive, &mut w.hovered, &mut w.active, &mut w.open] {
                v.corner_radius = egui::CornerRadius::ZERO;
            }
            s.visuals.window_corner_radius = egui::CornerRadius::ZERO;
            s.visuals.menu_corner_radius = egui::CornerRadius::ZERO;
        });
    }
}

/// How often [`log_area`] logs (app frames).
const AREA_LOG_EVERY_FRAMES: u64 = 30;

/// Logs the area the frame's shapes cover by kind (every `AREA_LOG_EVERY_FRAMES`th frame,
/// when `area` is asked).
pub fn log_area(ctx: &egui::Context, frame: u64) {
    if !hidden(Part::Area) || !frame.is_multiple_of(AREA_LOG_EVERY_FRAMES) {
        return;
    }
    let mut area = [0.0f64; 7];
    let names = ["rect", "text", "path/segment", "mesh", "callback", "circle", "other"];
    let mut count = [0usize; 7];
    let layers: Vec<egui::LayerId> = ctx.memory(|m| m.layer_ids().collect());
    ctx.graphics(|g| {
        for id in layers {
            let Some(list) = g.get(id) else { continue };
            for cs in list.all_entries() {
                let k = match &cs.shape {
                    egui::Shape::Rect(_) => 0,
                    egui::Shape::Text(_) => 1,
                    egui::Shape::Path(_) | egui::Shape::LineSegment { .. } => 2,
                    egui::Shape::Mesh(_) => 3,
                    egui::Shape::Callback(_) => 4,
                    egui::Shape::Circle(_) => 5,
                    egui::Shape::Noop => continue,
                    _ => 6,
                };
                let r = cs.shape.visual_bounding_rect().intersect(cs.clip_rect);
                if r.is_positive() {
                    area[k] += f64::from(r.area());
                    count[k] += 1;
                }
            }
        }
    });
    let text: Vec<String> =
        (0..7).map(|k| format!("{}: {} shapes, {:.0} kpt²", names[k], count[k], area[k] / 1e3)).collect();
    let (drawn, left) = crate::render::egui_pass::frame_counts();
    log::warn!(
        "frame area by kind of shape: {}; egui_pass since the start: {drawn} frames drawn, {left} left to egui",
        text.join("; ")
    );
}

/// Removes the hidden kinds of shape from everything painted so far this frame (called at the
/// end of the app's frame). Does nothing when no kind of shape is hidden.
pub fn strip_shapes(ctx: &egui::Context) {
    let kinds = Part::View3d as u32 | Part::Text as u32 | Part::Rects as u32 | Part::Lines as u32 | Part::Meshes as u32;
    let bits = HIDDEN.load(Ordering::Relaxed);
    if bits & kinds == 0 {
        return;
    }
    let drop = move |shape: &egui::Shape| match shape {
        egui::Shape::Callback(_) => bits & Part::View3d as u32 != 0,
        egui::Shape::Text(_) => bits & Part::Text as u32 != 0,
        egui::Shape::Rect(_) => bits & Part::Rects as u32 != 0,
        egui::Shape::Path(_) | egui::Shape::LineSegment { .. } => bits & Part::Lines as u32 != 0,
        egui::Shape::Mesh(_) => bits & Part::Meshes as u32 != 0,
        _ => false,
    };
    crate::render::flat_fill::mutate_painted_shapes(ctx, |cs| {
        if drop(&cs.shape) {
            cs.shape = egui::Shape::Noop;
        }
    });
}

#[cfg(test)]
mod tests {
    use super::{Part, parse};

    #[test]
    fn the_address_names_the_parts_to_hide() {
        assert_eq!(parse("?hide=side,plot"), Part::Side as u32 | Part::Plot as u32);
        assert_eq!(parse("?x=1&hide=text&hide=view3d"), Part::Text as u32 | Part::View3d as u32);
        assert_eq!(parse("?hide=nothing,side"), Part::Side as u32, "unknown names are ignored");
        assert_eq!(parse("?hide=eguipass,flatfill"), Part::EguiPass as u32 | Part::FlatFill as u32);
        assert_eq!(parse("?probe=floor"), 0);
        assert_eq!(parse(""), 0);
    }
}
