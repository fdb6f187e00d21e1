//! The user program's path in 3D and its machined stock as a picture coloured by the tool that
//! cut each ray last, both with a red cross at each crash the simulation found (the one picked
//! circled).
//!
//! The path is drawn by the 3D views' GPU line renderer (`render::gpu`): its segments are
//! uploaded when the path, its colours, the selection or the blocks shown change — only those
//! after the part that stayed the same, so a path read piece by piece sends each piece once —
//! and the camera is a uniform, so turning and zooming project nothing on the CPU. A program
//! of more than [`MAX_UPLOADED`] points is thinned evenly, the same whatever the view. The
//! crash marks, the marker of the last block shown, the legend and the help are egui shapes
//! over the image, their few points projected with the same camera; a click projects the
//! points once to find the move nearest to it.

use eframe::egui;
use eframe::egui_wgpu::RenderState;
use glam::Vec3;

use super::ColourBy;
use crate::app::overlay::{camera_controls, no_gpu, paint_view};
use crate::jobs::user_program::{CrashRow, Finished, ReadSummary};
use crate::render::{Layer, LineSegment, OrbitCamera, Renderer3d, ViewId};
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

/// This view's GPU id.
pub const VIEW_ID: ViewId = 5;
/// The view's background (egui's grey 22).
const BACKGROUND: [f32; 4] = [22.0 / 255.0, 22.0 / 255.0, 22.0 / 255.0, 1.0];

/// Most path segments uploaded (about): past it the path is thinned evenly, whatever the view.
pub const MAX_UPLOADED: usize = 50_000;
/// Farthest a merged point may be from the segment drawn for it, as a share of the radius of
/// the path's box: about 1/30 of a pixel when the whole path fills a view 800 pixels high.
const SIMPLIFY: f32 = 1e-4;

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

/// What the uploaded lines were made for: the view's serial ([`PathView::invalidate`]) and
/// the pixels per point their widths were scaled by.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Uploaded {
    serial: u64,
    ppp: u32,
}

/// The path view: camera, the path's segments as handed to the GPU (to upload only what
/// follows the part unchanged), and what the overlays drawn over the image need.
#[derive(Default)]
pub struct PathView {
    camera: OrbitCamera,
    origin: Vec3,
    /// Radius of the sphere framed (mm), for a double click's fit.
    radius: f32,
    fitted: bool,
    serial: u64,
    uploaded: Option<Uploaded>,
    /// The path's segments on the GPU (local to `origin`).
    path: Vec<LineSegment>,
    /// The last point drawn (the marker at the last block shown).
    last_point: Option<Vec3>,
    /// The selected block's point when it has no segment of its own (circled).
    selected_point: Option<Vec3>,
    /// Crash marks drawn inside the view in the last frame.
    marks: usize,
    map_texture: Option<(usize, egui::TextureHandle)>,
}

/// An egui colour as the renderer's display RGBA in 0…1.
fn rgba(c: egui::Color32) -> [f32; 4] {
    let [r, g, b, a] = c.to_srgba_unmultiplied();
    [f32::from(r) / 255.0, f32::from(g) / 255.0, f32::from(b) / 255.0, f32::from(a) / 255.0]
}

/// The lowest and highest programmed feed of the moves that cut (mm/min).
fn feed_range(s: &ReadSummary) -> (f32, f32) {
    s.block_feed
        .iter()
        .zip(&s.block_kind)
        .filter(|(f, k)| **k != 0 && f.is_finite() && **f > 0.0)
        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), (f, _)| (lo.min(*f), hi.max(*f)))
}

/// Point `k` of the path (mm; not finite where the reader left a gap).
fn point(s: &ReadSummary, k: usize) -> Vec3 {
    s.points.get(3 * k..3 * k + 3).map_or(Vec3::NAN, |p| Vec3::new(p[0], p[1], p[2]))
}

/// Points merged into one segment at the most (bounds the work of [`Simplifier::offer`]).
const RUN_WINDOW: usize = 32;

/// Distance from `p` to the segment `a`–`b` (mm).
fn distance_to_segment(p: Vec3, a: Vec3, b: Vec3) -> f32 {
    let ab = b - a;
    let len2 = ab.length_squared();
    let t = if len2 > 0.0 { ((p - a).dot(ab) / len2).clamp(0.0, 1.0) } else { 0.0 };
    p.distance(a + t * ab)
}

/// Merges consecutive points of one colour into one segment while every point merged stays
/// within `tolerance` of it (at most [`RUN_WINDOW`] of them): the segments only depend on the
/// points before, so a path that grows keeps the segments it had.
struct Simplifier {
    tolerance: f32,
    origin: Vec3,
    width_px: f32,
    /// The last point kept.
    anchor: Option<Vec3>,
    /// The points after it not kept yet (the last one the tentative end) and their colour.
    pending: Vec<Vec3>,
    colour: egui::Color32,
    out: Vec<LineSegment>,
}

impl Simplifier {
    fn segment(&mut self, a: Vec3, b: Vec3, c: egui::Color32) {
        let o = self.origin;
        self.out.push(LineSegment::new((a - o).to_array(), (b - o).to_array(), self.width_px, rgba(c)));
    }

    /// Ends the current segment at the tentative end (kept).
    fn settle(&mut self) {
        if let (Some(a), Some(&t)) = (self.anchor, self.pending.last()) {
            self.segment(a, t, self.colour);
            self.anchor = Some(t);
        }
        self.pending.clear();
    }

    /// Whether the segment from the anchor to `p` passes within the tolerance of every point
    /// pending.
    fn covers(&self, p: Vec3) -> bool {
        let Some(a) = self.anchor else { return false };
        self.pending.len() < RUN_WINDOW && self.pending.iter().all(|q| distance_to_segment(*q, a, p) <= self.tolerance)
    }

    /// The next point, in colour `c`; `keep`: it must be a point of the drawing (a run's end
    /// or start).
    fn offer(&mut self, p: Vec3, c: egui::Color32, keep: bool) {
        if c != self.colour {
            // A colour change: the last run ends at its last point, the new one starts there.
            self.settle();
            self.colour = c;
        } else if !self.covers(p) {
            self.settle();
        }
        if self.anchor.is_none() {
            self.anchor = Some(p);
            return;
        }
        self.pending.push(p);
        if keep {
            self.settle();
        }
    }

    /// Breaks the path (a gap): what is pending is drawn up to its last point.
    fn gap(&mut self) {
        self.settle();
        self.anchor = None;
    }
}

/// The path's segments, point to point in order, each in the colour of its end point's block
/// (`colour`), as far as the blocks below `limit`; a point that is not finite breaks the path.
/// Consecutive points of one colour are merged while the segment stays within `tolerance`
/// (mm) of every point it replaces, each run's ends and every colour change kept. Past
/// `max_segments` segments, every `stride`-th point of a run is kept besides its ends and
/// merged likewise. Nothing depends on the view. The segments are local to `origin`; returns
/// them and the last point drawn (mm).
fn path_segments(
    s: &ReadSummary,
    origin: Vec3,
    limit: usize,
    max_segments: usize,
    tolerance: f32,
    colour: impl Fn(usize) -> egui::Color32,
    width_px: f32,
) -> (Vec<LineSegment>, Option<Vec3>) {
    let n = s.point_block.len().min(s.points.len() / 3);
    let mut stride = 1;
    loop {
        let mut m = Simplifier {
            tolerance,
            origin,
            width_px,
            anchor: None,
            pending: Vec::with_capacity(RUN_WINDOW),
            colour: egui::Color32::TRANSPARENT,
            out: Vec::new(),
        };
        let mut last = None;
        for k in 0..n {
            let b = s.point_block[k] as usize;
            if b >= limit {
                break;
            }
            let p = point(s, k);
            if !p.is_finite() {
                m.gap();
                continue;
            }
            let c = colour(b);
            let next = s.point_block.get(k + 1).map(|nb| *nb as usize);
            let is_end = next.is_none_or(|nb| nb >= limit || colour(nb) != c || !point(s, k + 1).is_finite());
            if stride > 1 && !is_end && c == m.colour && m.anchor.is_some() && !k.is_multiple_of(stride) {
                continue;
            }
            m.offer(p, c, is_end);
            last = Some(p);
        }
        m.settle();
        if m.out.len() <= max_segments || stride > 1 {
            return (m.out, last);
        }
        stride = m.out.len() / max_segments.max(1) + 1;
    }
}

/// The first index where `a` and `b` differ (the shorter one's length if one begins the other).
fn common_prefix(a: &[LineSegment], b: &[LineSegment]) -> usize {
    a.iter().zip(b).position(|(x, y)| x != y).unwrap_or(a.len().min(b.len()))
}

impl PathView {
    /// Frame the path again at the next draw.
    pub fn refit(&mut self) {
        self.fitted = false;
        self.invalidate();
    }

    /// Upload the lines again (path, colours, selection, slider changed).
    pub fn invalidate(&mut self) {
        self.serial += 1;
    }

    /// Segments of the path handed to the GPU in the last upload (after thinning).
    #[must_use]
    pub fn drawn_segments(&self) -> usize {
        self.path.len()
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
            self.frame(lo, hi);
        } else {
            self.fitted = false;
        }
        self.invalidate();
    }

    fn frame(&mut self, lo: Vec3, hi: Vec3) {
        self.origin = 0.5 * (lo + hi);
        self.radius = (0.5 * (hi - lo).length()).max(1.0);
        self.camera.fit(Vec3::ZERO, self.radius);
        self.fitted = true;
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
        if lo.x <= hi.x {
            self.frame(lo, hi);
        }
    }

    /// Draws the path in `rect` with the GPU line renderer of `rs` (a message without one);
    /// returns the block clicked, if any.
    #[allow(clippy::too_many_arguments, reason = "the view's inputs, all read-only")]
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        rect: egui::Rect,
        rs: Option<&RenderState>,
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
        let limit = shown.unwrap_or(usize::MAX);
        let clicked = resp.clicked().then(|| resp.interact_pointer_pos()).flatten();
        let picked = clicked.and_then(|at| self.pick(s, rect, limit, at));
        camera_controls(&mut self.camera, ui, &resp, rect, self.radius);
        let ppp = ui.ctx().pixels_per_point();
        let key = Uploaded { serial: self.serial, ppp: ppp.to_bits() };
        if self.uploaded != Some(key) {
            self.upload(rs, s, by, tol, selected, limit, achieved, ppp);
            self.uploaded = Some(key);
        }
        // Without a GPU the path is still made (and counted) and the marks placed over the
        // message, so what the view would show is known.
        match rs {
            Some(_) => {
                paint_view(ui, rect, &self.camera, VIEW_ID, BACKGROUND, false);
            }
            None => no_gpu(ui.painter(), rect),
        }
        self.overlays(ui, rect, shown.is_some(), crashes);
        self.legend(&ui.painter_at(rect), rect, s, by, tol, crashes.list.len());
        picked
    }

    /// Where a point of the path's space (mm) appears in `rect`, if in front of the eye.
    fn to_screen(&self, rect: egui::Rect, p: Vec3) -> Option<egui::Pos2> {
        let ndc = self.camera.project(rect.width() / rect.height().max(1.0), p - self.origin)?;
        let q = egui::pos2(rect.center().x + 0.5 * ndc.x * rect.width(), rect.center().y - 0.5 * ndc.y * rect.height());
        q.is_finite().then_some(q)
    }

    /// The block of the point shown nearest to a click at `at` (within 10 points): every point
    /// below the slider's `limit` projected once, on the CPU.
    fn pick(&self, s: &ReadSummary, rect: egui::Rect, limit: usize, at: egui::Pos2) -> Option<usize> {
        let clip = self.camera.clip_from_world(rect.width() / rect.height().max(1.0));
        let mut best: Option<(f32, usize)> = None;
        for (k, b) in s.point_block.iter().enumerate() {
            let b = *b as usize;
            if b >= limit {
                break;
            }
            let q = clip * (point(s, k) - self.origin).extend(1.0);
            if !(q.w > 0.0) {
                continue;
            }
            let screen = egui::pos2(
                rect.center().x + 0.5 * q.x / q.w * rect.width(),
                rect.center().y - 0.5 * q.y / q.w * rect.height(),
            );
            let d = screen.distance_sq(at);
            if d < 100.0 && best.is_none_or(|(bd, _)| d < bd) {
                best = Some((d, b));
            }
        }
        best.map(|(_, b)| b)
    }

    /// Makes and, with a GPU, uploads the stock's edges, the path (only what follows the part
    /// unchanged) and the selected block's highlight.
    #[allow(clippy::too_many_arguments, reason = "the view's inputs, all read-only")]
    fn upload(
        &mut self,
        rs: Option<&RenderState>,
        s: &ReadSummary,
        by: ColourBy,
        tol: f64,
        selected: Option<usize>,
        limit: usize,
        achieved: Option<&[f32]>,
        ppp: f32,
    ) {
        let o = self.origin;
        let local = |p: Vec3| (p - o).to_array();
        // The stock block's edges.
        let b = s.stock_mm;
        let corner = |i: usize| {
            Vec3::new(
                if i & 1 == 0 { b[0] } else { b[3] } as f32,
                if i & 2 == 0 { b[1] } else { b[4] } as f32,
                if i & 4 == 0 { b[2] } else { b[5] } as f32,
            )
        };
        let edge = rgba(egui::Color32::from_gray(70));
        let stock: Vec<LineSegment> =
            [(0, 1), (2, 3), (4, 5), (6, 7), (0, 2), (1, 3), (4, 6), (5, 7), (0, 4), (1, 5), (2, 6), (3, 7)]
                .into_iter()
                .map(|(i, j)| (corner(i), corner(j)))
                .filter(|(p, q)| p.is_finite() && q.is_finite())
                .map(|(p, q)| LineSegment::new(local(p), local(q), ppp, edge))
                .collect();
        // Each block's colour once, then the path in them.
        let feeds = feed_range(s);
        let colours: Vec<egui::Color32> =
            (0..s.block_kind.len()).map(|b| block_colour(s, b, by, tol, feeds, achieved)).collect();
        let colour = |b: usize| colours.get(b).copied().unwrap_or(RAPID);
        let tolerance = self.radius * SIMPLIFY;
        let (path, last) = path_segments(s, o, limit, MAX_UPLOADED, tolerance, colour, 1.2 * ppp);
        self.last_point = last;
        let unchanged = common_prefix(&self.path, &path);
        self.path = path;
        // The selected block in white over the path: its moves from the point before it.
        let mut highlight = Vec::new();
        self.selected_point = None;
        if let Some(sel) = selected.filter(|b| *b < limit) {
            let white = rgba(egui::Color32::WHITE);
            for (k, _) in s.point_block.iter().enumerate().filter(|(_, b)| **b as usize == sel) {
                let p = point(s, k);
                let before = k.checked_sub(1).map(|j| point(s, j)).filter(|q| q.is_finite());
                match before {
                    Some(q) if p.is_finite() => {
                        highlight.push(LineSegment::new(local(q), local(p), 3.5 * ppp, white).with_depth_bias(0.003))
                    }
                    _ if p.is_finite() && self.selected_point.is_none() => self.selected_point = Some(p),
                    _ => {}
                }
            }
            if !highlight.is_empty() {
                self.selected_point = None;
            }
        }
        if let Some(rs) = rs {
            Renderer3d::with(rs, |r| {
                r.set_lines(VIEW_ID, Layer::StaticLines, &stock, 0);
                r.set_lines(VIEW_ID, Layer::PathLines, &self.path, unchanged);
                r.set_lines(VIEW_ID, Layer::DynamicLines, &highlight, 0);
            });
        }
    }

    /// What is drawn over the GPU image, projected with the same camera: the marker at the last
    /// point shown (with the slider), the selected block when it is a single point, and the
    /// crashes (the picked one last, on top).
    fn overlays(&mut self, ui: &egui::Ui, rect: egui::Rect, slider: bool, crashes: CrashMarks<'_>) {
        let mut shapes = Vec::new();
        if let Some(q) = self.selected_point.and_then(|p| self.to_screen(rect, p)) {
            shapes.push(egui::Shape::circle_stroke(q, 6.0, egui::Stroke::new(2.0, egui::Color32::WHITE)));
        }
        if slider && let Some(q) = self.last_point.and_then(|p| self.to_screen(rect, p)) {
            shapes.push(egui::Shape::circle_filled(q, 5.0, egui::Color32::WHITE));
        }
        let at = |c: &CrashRow| self.to_screen(rect, c.at_mm.as_vec3());
        let mut marks = 0;
        for (k, c) in crashes.list.iter().enumerate() {
            if Some(k) != crashes.selected
                && let Some(q) = at(c)
            {
                crash_mark(&mut shapes, q, false);
                marks += usize::from(rect.contains(q));
            }
        }
        if let Some(q) = crashes.selected.and_then(|k| crashes.list.get(k)).and_then(at) {
            crash_mark(&mut shapes, q, true);
            marks += usize::from(rect.contains(q));
        }
        self.marks = marks;
        ui.painter_at(rect).extend(shapes);
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
            format!(
                "{} segments drawn · drag to turn, right-drag to pan, scroll to zoom, click a move",
                self.path.len()
            ),
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A raster like the browser test's: rows of 200 points 0.25 mm apart over a wavy floor,
    /// one block per point; blocks from `tool_change` on in another colour, and a gap (a point
    /// that is not finite) at 1 234.
    fn raster(points: usize) -> ReadSummary {
        let mut s = ReadSummary::default();
        for k in 0..points {
            let (row, i) = (k / 200, k % 200);
            let x = if row % 2 == 0 { i } else { 199 - i } as f32 * 0.25;
            let y = row as f32 * 0.25;
            let z = if k == 1234 { f32::NAN } else { -1.0 - 0.8 * (x / 9.0).sin() * (y / 7.0).cos() };
            s.points.extend([x, y, z]);
            s.point_block.push(k as u32);
        }
        s
    }

    fn colour_at(tool_change: usize) -> impl Fn(usize) -> egui::Color32 {
        move |b| if b < tool_change { RAPID } else { CRASH }
    }

    fn ends(l: &LineSegment) -> (Vec3, Vec3) {
        (Vec3::from_array(l.a), Vec3::from_array(l.b))
    }

    #[test]
    fn every_point_stays_within_the_tolerance_of_a_segment_of_its_colour() {
        let s = raster(6000);
        let tol = 0.004;
        let colour = colour_at(3100);
        let (path, last) = path_segments(&s, Vec3::ZERO, usize::MAX, 50_000, tol, &colour, 1.0);
        assert!(path.len() < 6000 / 3, "{} segments for 6000 points: little merged", path.len());
        assert_eq!(last, Some(point(&s, 5999)), "the last point is drawn");
        for k in (0..6000).filter(|k| *k != 1234) {
            let p = point(&s, k);
            let c = rgba(colour(k));
            let d = path
                .iter()
                .filter(|l| l.color == c)
                .map(|l| {
                    let (a, b) = ends(l);
                    distance_to_segment(p, a, b)
                })
                .fold(f32::INFINITY, f32::min);
            assert!(d <= tol * 1.001, "point {k} is {d} mm from the path drawn");
        }
        // Each segment is in the colour of its end, and the path is broken at the gap.
        let gap = (point(&s, 1233), point(&s, 1235));
        assert!(path.iter().all(|l| ends(l) != gap && ends(l) != (gap.1, gap.0)));
        let first_red = path.iter().position(|l| l.color == rgba(CRASH)).expect("a red run");
        assert_eq!(ends(&path[first_red]).0, point(&s, 3099), "the red run starts where the last one ends");
        assert_eq!(ends(&path[first_red - 1]).1, point(&s, 3099));
    }

    #[test]
    fn a_path_that_grows_keeps_its_segments_but_the_last() {
        let colour = colour_at(usize::MAX);
        let (part, _) = path_segments(&raster(2500), Vec3::ZERO, usize::MAX, 50_000, 0.004, &colour, 1.0);
        let (whole, _) = path_segments(&raster(5000), Vec3::ZERO, usize::MAX, 50_000, 0.004, &colour, 1.0);
        assert!(common_prefix(&part, &whole) + 1 >= part.len(), "{} of {}", common_prefix(&part, &whole), part.len());
    }

    #[test]
    fn past_the_cap_the_path_is_thinned_keeping_the_ends_and_the_slider_s_limit() {
        let s = raster(20_000);
        let colour = colour_at(9000);
        let (all, _) = path_segments(&s, Vec3::ZERO, usize::MAX, 50_000, 0.0, &colour, 1.0);
        let (capped, last) = path_segments(&s, Vec3::ZERO, usize::MAX, 2000, 0.0, &colour, 1.0);
        assert!(all.len() > 10_000 && capped.len() <= 2 * 2000, "{} → {} segments", all.len(), capped.len());
        assert_eq!(last, Some(point(&s, 19_999)));
        let first_red = capped.iter().position(|l| l.color == rgba(CRASH)).expect("a red run");
        assert_eq!(ends(&capped[first_red]).0, point(&s, 8999), "the colour change is kept");
        assert_eq!(ends(&capped[first_red - 1]).1, point(&s, 8999));
        let (shown, last) = path_segments(&s, Vec3::ZERO, 700, 50_000, 0.0, &colour, 1.0);
        assert_eq!(last, Some(point(&s, 699)), "the last block shown ends the path");
        assert_eq!(shown.len(), 699, "without tolerance only exactly collinear points merge");
    }
}
