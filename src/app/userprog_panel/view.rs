//! The user program's path in 3D (egui shapes through the orbit camera's projection,
//! thinned to what the screen can show: consecutive points closer than a pixel within one
//! colour are merged, so a 180 000-block program draws as a few tens of thousands of
//! segments) and its machined stock as a picture coloured by the tool that cut each ray last,
//! both with a red cross at each crash the simulation found (the one picked circled).

use eframe::egui;
use glam::Vec3;

use super::ColourBy;
use crate::jobs::user_program::{CrashRow, Finished, ReadSummary};
use crate::render::OrbitCamera;
use crate::simulate::NO_TOOL;
use crate::simulate::canon::NO_SLOT;

/// Tool colours by slot, cycling.
const PALETTE: [egui::Color32; 8] = [
    egui::Color32::from_rgb(90, 160, 230),
    egui::Color32::from_rgb(255, 150, 50),
    egui::Color32::from_rgb(90, 200, 110),
    egui::Color32::from_rgb(230, 80, 80),
    egui::Color32::from_rgb(180, 130, 220),
    egui::Color32::from_rgb(200, 160, 110),
    egui::Color32::from_rgb(240, 140, 200),
    egui::Color32::from_rgb(200, 200, 90),
];

/// The colour of a tool slot.
#[must_use]
pub fn tool_colour(slot: usize) -> egui::Color32 {
    PALETTE[slot % PALETTE.len()]
}

/// Most path points drawn (about as many segments): past it the path is thinned evenly.
pub const MAX_DRAWN: usize = 40_000;

const RAPID: egui::Color32 = egui::Color32::from_rgb(120, 120, 120);
/// The colour of a crash's mark.
pub const CRASH: egui::Color32 = egui::Color32::from_rgb(255, 40, 40);

/// The crashes marked in a view: the list and the one picked (index in it).
#[derive(Clone, Copy, Debug, Default)]
pub struct CrashMarks<'a> {
    /// The crashes (their places, mm).
    pub list: &'a [CrashRow],
    /// The crash picked in the list, circled.
    pub selected: Option<usize>,
}

/// A crash's mark at `at` (screen): a red cross with a dark outline (it shows over a red
/// path too), circled in white when picked.
fn crash_mark(shapes: &mut Vec<egui::Shape>, at: egui::Pos2, picked: bool) {
    let h = if picked { 7.0 } else { 4.5 };
    for (w, c) in [(4.0, egui::Color32::from_black_alpha(200)), (2.0, CRASH)] {
        shapes
            .push(egui::Shape::line_segment([at + egui::vec2(-h, -h), at + egui::vec2(h, h)], egui::Stroke::new(w, c)));
        shapes
            .push(egui::Shape::line_segment([at + egui::vec2(-h, h), at + egui::vec2(h, -h)], egui::Stroke::new(w, c)));
    }
    if picked {
        shapes.push(egui::Shape::circle_stroke(at, 11.0, egui::Stroke::new(2.5, egui::Color32::WHITE)));
    }
}
const UNMEASURED: egui::Color32 = egui::Color32::from_rgb(95, 105, 115);
const OVER: egui::Color32 = egui::Color32::from_rgb(255, 0, 220);

/// Green → yellow → red over t ∈ [0, 1].
fn ramp(t: f32) -> egui::Color32 {
    let t = t.clamp(0.0, 1.0);
    let (r, g) = if t < 0.5 { (2.0 * t, 1.0) } else { (1.0, 2.0 - 2.0 * t) };
    egui::Color32::from_rgb((40.0 + 215.0 * r) as u8, (60.0 + 180.0 * g) as u8, 60)
}

/// Blue → cyan → yellow over t ∈ [0, 1] (feeds).
fn feed_ramp(t: f32) -> egui::Color32 {
    let t = t.clamp(0.0, 1.0);
    egui::Color32::from_rgb((40.0 + 215.0 * t) as u8, (90.0 + 150.0 * t.sqrt()) as u8, (230.0 * (1.0 - t) + 40.0) as u8)
}

/// The colour of a block.
fn block_colour(
    s: &ReadSummary,
    b: usize,
    by: ColourBy,
    tol: f64,
    feed_range: (f32, f32),
    achieved: Option<&[f32]>,
) -> egui::Color32 {
    let kind = s.block_kind.get(b).copied().unwrap_or(0);
    match by {
        ColourBy::Kind => match kind {
            0 => RAPID,
            1 => egui::Color32::from_rgb(110, 180, 255),
            2 => egui::Color32::from_rgb(110, 220, 130),
            _ => egui::Color32::from_rgb(255, 170, 70),
        },
        ColourBy::Feed => {
            if kind == 0 {
                return RAPID;
            }
            let f = s.block_feed.get(b).copied().unwrap_or(0.0);
            let (lo, hi) = feed_range;
            feed_ramp(if hi > lo { (f - lo) / (hi - lo) } else { 0.5 })
        }
        ColourBy::Tool => {
            let slot = s.block_slot.get(b).copied().unwrap_or(NO_SLOT);
            if kind == 0 || slot == NO_SLOT { RAPID } else { tool_colour(usize::from(slot)) }
        }
        ColourBy::Achieved => {
            if kind == 0 {
                return RAPID;
            }
            let f = achieved.and_then(|a| a.get(b)).copied().unwrap_or(f32::NAN);
            let p = s.block_feed.get(b).copied().unwrap_or(0.0);
            if f.is_finite() && p > 0.0 { ramp(1.0 - f / p) } else { UNMEASURED }
        }
        ColourBy::Error => {
            let e = s.block_error.get(b).copied().unwrap_or(f32::NAN);
            if !e.is_finite() {
                if kind == 0 { RAPID } else { UNMEASURED }
            } else if f64::from(e) > tol {
                OVER
            } else {
                ramp((f64::from(e) / tol) as f32)
            }
        }
    }
}

/// What the cached shapes were made for.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Key {
    rect: egui::Rect,
    camera: OrbitCamera,
    serial: u64,
    moving: bool,
}

/// The path view: camera, cached shapes and projected points (for picking).
#[derive(Default)]
pub struct PathView {
    camera: OrbitCamera,
    origin: Vec3,
    fitted: bool,
    serial: u64,
    key: Option<Key>,
    shapes: Vec<egui::Shape>,
    segments: usize,
    /// Crash marks drawn inside the view in the last build.
    marks: usize,
    /// Projected points kept for picking: (screen position, block).
    picks: Vec<(egui::Pos2, u32)>,
    /// Each block's colour, for the serial they were made for.
    colours: (u64, Vec<egui::Color32>),
    map_texture: Option<(usize, egui::TextureHandle)>,
}

impl PathView {
    /// Frame the path again at the next draw.
    pub fn refit(&mut self) {
        self.fitted = false;
        self.invalidate();
    }

    /// Draw the shapes again (colours, selection, slider changed).
    pub fn invalidate(&mut self) {
        self.serial += 1;
        self.key = None;
    }

    /// Segments drawn in the last frame (after thinning).
    #[must_use]
    pub fn drawn_segments(&self) -> usize {
        self.segments
    }

    /// Crash marks drawn inside the path view in the last frame.
    #[must_use]
    pub fn drawn_crash_marks(&self) -> usize {
        self.marks
    }

    /// Frames the box `b` (mm: min x, y, z, max x, y, z) at the next draw: the whole path's,
    /// known from its first piece.
    pub fn fit_box(&mut self, b: [f32; 6]) {
        let (lo, hi) = (Vec3::new(b[0], b[1], b[2]), Vec3::new(b[3], b[4], b[5]));
        if lo.is_finite() && hi.is_finite() && lo.cmple(hi).all() {
            self.origin = 0.5 * (lo + hi);
            self.camera.fit(Vec3::ZERO, (0.5 * (hi - lo).length()).max(1.0));
            self.fitted = true;
        } else {
            self.fitted = false;
        }
        self.invalidate();
    }

    fn fit(&mut self, s: &ReadSummary) {
        let mut lo = Vec3::splat(f32::INFINITY);
        let mut hi = Vec3::splat(f32::NEG_INFINITY);
        for p in s.points.chunks_exact(3) {
            let v = Vec3::new(p[0], p[1], p[2]);
            if v.is_finite() {
                lo = lo.min(v);
                hi = hi.max(v);
            }
        }
        if lo.x > hi.x {
            return;
        }
        self.origin = 0.5 * (lo + hi);
        self.camera.fit(Vec3::ZERO, (0.5 * (hi - lo).length()).max(1.0));
        self.fitted = true;
    }

    /// Draws the path in `rect`; returns the block clicked, if any.
    #[allow(clippy::too_many_arguments, reason = "the view's inputs, all read-only")]
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        rect: egui::Rect,
        s: &ReadSummary,
        by: ColourBy,
        tol: f64,
        selected: Option<usize>,
        shown: Option<usize>,
        achieved: Option<&[f32]>,
        crashes: CrashMarks<'_>,
    ) -> Option<usize> {
        if !self.fitted {
            self.fit(s);
        }
        let resp = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        if resp.dragged_by(egui::PointerButton::Primary) {
            let d = resp.drag_delta();
            self.camera.orbit(d.x, d.y);
        }
        if resp.dragged_by(egui::PointerButton::Secondary) || resp.dragged_by(egui::PointerButton::Middle) {
            let d = resp.drag_delta();
            self.camera.pan(d.x, d.y, rect.height());
        }
        if resp.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll.abs() > 0.0 {
                self.camera.zoom((scroll * 0.003).exp());
            }
        }
        let painter = ui.painter_at(rect);
        painter.rect_filled(rect, 0.0, egui::Color32::from_gray(22));
        // While the view turns, a coarser path (a quarter of the points); the whole when it rests.
        let moving = resp.dragged() || ui.input(|i| i.smooth_scroll_delta.y.abs() > 0.0);
        let key = Key { rect, camera: self.camera, serial: self.serial, moving };
        if self.key != Some(key) {
            let max = if moving { MAX_DRAWN / 4 } else { MAX_DRAWN };
            self.build(rect, s, by, tol, selected, shown, max, achieved, crashes);
            self.key = Some(key);
        }
        if moving {
            ui.ctx().request_repaint();
        }
        painter.extend(self.shapes.iter().cloned());
        self.legend(&painter, rect, s, by, tol, crashes.list.len());
        let clicked = resp.clicked().then(|| resp.interact_pointer_pos()).flatten();
        clicked.and_then(|at| {
            self.picks
                .iter()
                .map(|(p, b)| (p.distance_sq(at), *b))
                .filter(|(d, _)| *d < 100.0)
                .min_by(|a, b| a.0.total_cmp(&b.0))
                .map(|(_, b)| b as usize)
        })
    }

    #[allow(clippy::too_many_arguments, reason = "the view's inputs, all read-only")]
    fn build(
        &mut self,
        rect: egui::Rect,
        s: &ReadSummary,
        by: ColourBy,
        tol: f64,
        selected: Option<usize>,
        shown: Option<usize>,
        max_points: usize,
        achieved: Option<&[f32]>,
        crashes: CrashMarks<'_>,
    ) {
        self.shapes.clear();
        self.picks.clear();
        self.segments = 0;
        let aspect = rect.width() / rect.height().max(1.0);
        let to_screen = |p: Vec3| -> Option<egui::Pos2> {
            let ndc = self.camera.project(aspect, p - self.origin)?;
            Some(egui::pos2(
                rect.center().x + 0.5 * ndc.x * rect.width(),
                rect.center().y - 0.5 * ndc.y * rect.height(),
            ))
        };
        let feeds: Vec<f32> = s
            .block_feed
            .iter()
            .zip(&s.block_kind)
            .filter(|(f, k)| **k != 0 && f.is_finite() && **f > 0.0)
            .map(|(f, _)| *f)
            .collect();
        let feed_range = (
            feeds.iter().copied().fold(f32::INFINITY, f32::min),
            feeds.iter().copied().fold(f32::NEG_INFINITY, f32::max),
        );
        // The stock block's edges.
        let b = s.stock_mm;
        let corner = |i: usize| {
            Vec3::new(
                if i & 1 == 0 { b[0] } else { b[3] } as f32,
                if i & 2 == 0 { b[1] } else { b[4] } as f32,
                if i & 4 == 0 { b[2] } else { b[5] } as f32,
            )
        };
        for (i, j) in [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)] {
            if let (Some(p), Some(q)) = (to_screen(corner(i)), to_screen(corner(j))) {
                self.shapes
                    .push(egui::Shape::line_segment([p, q], egui::Stroke::new(1.0, egui::Color32::from_gray(70))));
            }
        }
        if self.colours.0 != self.serial || self.colours.1.len() != s.block_kind.len() {
            let colours = (0..s.block_kind.len()).map(|b| block_colour(s, b, by, tol, feed_range, achieved)).collect();
            self.colours = (self.serial, colours);
        }
        let colours = &self.colours.1;
        let colour_of = |b: usize| colours.get(b).copied().unwrap_or(RAPID);
        let limit = shown.unwrap_or(usize::MAX);
        // At most MAX_DRAWN points: past it every `stride`-th point of a run is kept (its
        // first and last always), besides merging points within a pixel.
        let stride = (s.point_block.len() / max_points.max(1) + 1).max(1);
        let mut since = 0usize;
        let mut run: Vec<egui::Pos2> = Vec::new();
        let mut run_colour = egui::Color32::TRANSPARENT;
        let mut last: Option<egui::Pos2> = None;
        let mut sel_pts: Vec<egui::Pos2> = Vec::new();
        let flush =
            |run: &mut Vec<egui::Pos2>, colour: egui::Color32, shapes: &mut Vec<egui::Shape>, segs: &mut usize| {
                if run.len() >= 2 {
                    *segs += run.len() - 1;
                    shapes.push(egui::Shape::line(std::mem::take(run), egui::Stroke::new(1.2, colour)));
                }
                run.clear();
            };
        let mut marker = None;
        let n_points = s.point_block.len();
        for (k, p) in s.points.chunks_exact(3).enumerate() {
            let b = s.point_block.get(k).copied().unwrap_or(0) as usize;
            if b >= limit {
                break;
            }
            let colour = colour_of(b);
            let change = colour != run_colour;
            let next_block = s.point_block.get(k + 1).map(|nb| *nb as usize);
            let is_end = next_block.is_none_or(|nb| nb >= limit || colour_of(nb) != colour);
            let is_selected = Some(b) == selected || next_block == selected;
            since += 1;
            // Points between kept ones are not even projected (the thinning's saving).
            if !(change || is_end || is_selected || since.is_multiple_of(stride) || k + 1 == n_points) {
                continue;
            }
            let Some(q) = to_screen(Vec3::new(p[0], p[1], p[2])) else {
                last = None;
                continue;
            };
            marker = Some(q);
            if Some(b) == selected {
                if sel_pts.is_empty()
                    && let Some(l) = last
                {
                    sel_pts.push(l);
                }
                sel_pts.push(q);
            }
            if change {
                let prev = run.last().copied();
                flush(&mut run, run_colour, &mut self.shapes, &mut self.segments);
                run_colour = colour;
                if let Some(pv) = prev.or(last) {
                    run.push(pv);
                }
                run.push(q);
            } else if is_end || run.last().is_none_or(|l| l.distance_sq(q) >= 1.0) {
                run.push(q);
            }
            last = Some(q);
            self.picks.push((q, u32::try_from(b).unwrap_or(u32::MAX)));
        }
        flush(&mut run, run_colour, &mut self.shapes, &mut self.segments);
        if sel_pts.len() == 1 {
            self.shapes.push(egui::Shape::circle_stroke(sel_pts[0], 6.0, egui::Stroke::new(2.0, egui::Color32::WHITE)));
        } else if sel_pts.len() >= 2 {
            self.shapes.push(egui::Shape::line(sel_pts, egui::Stroke::new(3.5, egui::Color32::WHITE)));
        }
        if shown.is_some()
            && let Some(m) = marker
        {
            self.shapes.push(egui::Shape::circle_filled(m, 5.0, egui::Color32::WHITE));
        }
        // The crashes over the path, the picked one last (on top).
        let at = |c: &CrashRow| to_screen(c.at_mm.as_vec3()).filter(|q| q.is_finite());
        self.marks = 0;
        for (k, c) in crashes.list.iter().enumerate() {
            if Some(k) != crashes.selected
                && let Some(q) = at(c)
            {
                crash_mark(&mut self.shapes, q, false);
                self.marks += usize::from(rect.contains(q));
            }
        }
        if let Some(q) = crashes.selected.and_then(|k| crashes.list.get(k)).and_then(at) {
            crash_mark(&mut self.shapes, q, true);
            self.marks += usize::from(rect.contains(q));
        }
    }

    fn legend(
        &self,
        painter: &egui::Painter,
        rect: egui::Rect,
        s: &ReadSummary,
        by: ColourBy,
        tol: f64,
        crashes: usize,
    ) {
        let x = rect.left() + 10.0;
        let mut y = rect.top() + 8.0;
        let entry = |y: &mut f32, c: egui::Color32, t: String| super::super::widgets::legend_entry(painter, x, y, c, t);
        match by {
            ColourBy::Kind => {
                entry(&mut y, RAPID, "rapid (G0)".to_owned());
                entry(&mut y, egui::Color32::from_rgb(110, 180, 255), "line (G1)".to_owned());
                entry(&mut y, egui::Color32::from_rgb(110, 220, 130), "arc (G2/G3)".to_owned());
                entry(&mut y, egui::Color32::from_rgb(255, 170, 70), "spline".to_owned());
            }
            ColourBy::Feed => {
                entry(&mut y, feed_ramp(0.0), "lowest feed".to_owned());
                entry(&mut y, feed_ramp(1.0), "highest feed".to_owned());
                entry(&mut y, RAPID, "rapid".to_owned());
            }
            ColourBy::Tool => {
                for (k, t) in s.tools.iter().enumerate().take(10) {
                    let name = if t.number < 0 { "default".to_owned() } else { format!("T{}", t.number) };
                    entry(&mut y, tool_colour(k), format!("{name}: {}", t.cutter));
                }
            }
            ColourBy::Achieved => {
                entry(&mut y, ramp(0.0), "at the programmed feed".to_owned());
                entry(&mut y, ramp(0.5), "half of it, on average over the block".to_owned());
                entry(&mut y, ramp(1.0), "near rest".to_owned());
                entry(&mut y, UNMEASURED, "not timed: Time on a machine → Time it".to_owned());
                entry(&mut y, RAPID, "rapid".to_owned());
            }
            ColourBy::Error => {
                entry(&mut y, ramp(0.0), "nonlinear error 0".to_owned());
                entry(&mut y, ramp(1.0), format!("… up to E = {tol} mm"));
                entry(&mut y, OVER, "over E".to_owned());
                entry(&mut y, UNMEASURED, "not measured (no rotary motion)".to_owned());
            }
        }
        if crashes > 0 {
            entry(&mut y, CRASH, format!("crash (red cross): {crashes} listed under Crashes"));
        }
        painter.text(
            egui::pos2(rect.right() - 10.0, rect.bottom() - 8.0),
            egui::Align2::RIGHT_BOTTOM,
            format!("{} segments drawn · drag to turn, right-drag to pan, scroll to zoom, click a move", self.segments),
            egui::FontId::proportional(12.0),
            egui::Color32::from_gray(170),
        );
    }

    /// The machined stock, top view: each ray in its last tool's colour, shaded by height.
    pub fn map(&mut self, ui: &mut egui::Ui, rect: egui::Rect, f: &Finished, selected_crash: Option<usize>) {
        let g = f.map.grid;
        let serial = f.map.top_mm.len() ^ (f.map.top_mm.first().map_or(0, |z| z.to_bits() as usize));
        if self.map_texture.as_ref().is_none_or(|(s, _)| *s != serial) {
            let (lo, hi) =
                f.map.top_mm.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), z| (a.min(*z), b.max(*z)));
            let mut pixels = Vec::with_capacity(g.len());
            for row in 0..g.ny {
                let j = g.ny - 1 - row;
                for i in 0..g.nx {
                    let k = j * g.nx + i;
                    let t = f.tool_map.get(k).copied().unwrap_or(NO_TOOL);
                    let shade = if hi > lo { ((f.map.top_mm[k] - lo) / (hi - lo)) as f32 } else { 1.0 };
                    let base = if t == NO_TOOL { egui::Color32::from_gray(200) } else { tool_colour(usize::from(t)) };
                    let k = 0.35 + 0.65 * shade;
                    pixels.push(egui::Color32::from_rgb(
                        (f32::from(base.r()) * k) as u8,
                        (f32::from(base.g()) * k) as u8,
                        (f32::from(base.b()) * k) as u8,
                    ));
                }
            }
            let image =
                egui::ColorImage { size: [g.nx, g.ny], source_size: egui::vec2(g.nx as f32, g.ny as f32), pixels };
            let tex = ui.ctx().load_texture("userprog-stock", image, egui::TextureOptions::NEAREST);
            self.map_texture = Some((serial, tex));
        }
        if let Some((_, tex)) = &self.map_texture {
            let aspect = g.nx as f32 / g.ny.max(1) as f32;
            let (w, h) = if aspect >= 1.0 {
                (rect.width(), rect.width() / aspect)
            } else {
                (rect.height() * aspect, rect.height())
            };
            let r = egui::Rect::from_min_size(rect.min, egui::vec2(w, h));
            ui.painter().image(
                tex.id(),
                r,
                egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0)),
                egui::Color32::WHITE,
            );
            ui.painter().text(
                egui::pos2(r.left() + 6.0, r.bottom() + 4.0),
                egui::Align2::LEFT_TOP,
                format!("stock, top view: colour = last tool, shade = height ({} × {} rays)", g.nx, g.ny),
                egui::FontId::proportional(12.0),
                egui::Color32::from_gray(190),
            );
            // The crashes where they are seen from above (x right, y up).
            let (sx, sy) = (g.nx as f64 * g.pitch_mm, g.ny as f64 * g.pitch_mm);
            if sx > 0.0 && sy > 0.0 {
                let to_screen = |c: &CrashRow| {
                    let u = ((c.at_mm.x - g.x0_mm) / sx) as f32;
                    let v = 1.0 - ((c.at_mm.y - g.y0_mm) / sy) as f32;
                    let q = egui::pos2(r.left() + u * r.width(), r.top() + v * r.height());
                    q.is_finite().then_some(q)
                };
                let mut shapes = Vec::new();
                for (k, c) in f.crashes.iter().enumerate() {
                    if Some(k) != selected_crash
                        && let Some(q) = to_screen(c)
                    {
                        crash_mark(&mut shapes, q, false);
                    }
                }
                if let Some(q) = selected_crash.and_then(|k| f.crashes.get(k)).and_then(to_screen) {
                    crash_mark(&mut shapes, q, true);
                }
                ui.painter().with_clip_rect(rect).extend(shapes);
            }
        }
    }
}
