//! The panel's 3D view (GPU view 2): the design path, the G06.2 curve as read back from its
//! program with its control polygon, control points and knots, the real-time interpolated
//! points coloured by feed fluctuation, and a program drawn over the design (G01 / G02-G03
//! written here, or a loaded file) with its worst deviation marked.
//!
//! Layers are rebuilt only when what they show changes (tracked by the work's generation
//! numbers); the dots and markers are sized in screen points, so they are rebuilt when the
//! zoom changes by more than a step.

use crate::app::overlay::{
    ViewButton, axis_triad, no_gpu, orbit_and_pan, paint_view, scale_bar, view_buttons, zoom_factor,
};
use eframe::egui;
use eframe::egui_wgpu::RenderState;
use glam::{DVec3, Vec3, Vec4};

use super::work::{Loaded, Realtime, Work};
use crate::gcode::path::sample_params;
use crate::gcode::{Deviation, PathBlock, Segment, Toolpath};
use crate::geom::{Curve3, NurbsCurve};
use crate::render::geometry::{Origin, bounds, polyline};
use crate::render::{Layer, LineSegment, OrbitCamera, Renderer3d, SphereInstance, ViewId};

/// Floor (mm) of a length the view divides by or takes the logarithm of (a feed per period,
/// millimetres per point), so a zero never reaches the division.
const MIN_LENGTH_MM: f64 = 1e-9;
/// A colour bar's last tick may pass its upper end by this (in the bar's unit) from the
/// rounding of the tick steps.
const TICK_SLACK: f64 = 1e-9;

/// GPU view id of this panel (0 is the crease view, 1 the 5-axis view).
pub const VIEW_ID: ViewId = 2;

const BACKGROUND: [f32; 4] = [0.075, 0.08, 0.095, 1.0];
pub(super) const DESIGN_COLOR: egui::Color32 = egui::Color32::from_rgb(205, 205, 210);
pub(super) const CURVE_COLOR: egui::Color32 = egui::Color32::from_rgb(240, 95, 225);
pub(super) const POLYGON_COLOR: egui::Color32 = egui::Color32::from_rgb(190, 85, 180);
pub(super) const KNOT_COLOR: egui::Color32 = egui::Color32::from_rgb(250, 250, 250);
pub(super) const LINES_COLOR: egui::Color32 = egui::Color32::from_rgb(80, 220, 210);
pub(super) const ARCS_COLOR: egui::Color32 = egui::Color32::from_rgb(165, 135, 255);
pub(super) const LOADED_COLOR: egui::Color32 = egui::Color32::from_rgb(250, 230, 60);
pub(super) const RAPID_COLOR: egui::Color32 = egui::Color32::from_rgb(120, 120, 130);
pub(super) const WORST_COLOR: egui::Color32 = egui::Color32::from_rgb(255, 70, 60);

/// Decades of the fluctuation colour scale: |Δf/f| from 1e-14 (rounding level) to 1e-3.
pub(super) const FLUCT_DECADES: (f64, f64) = (-14.0, -3.0);

/// Turbo colour map (Mikhailov 2019, polynomial fit), t in 0..1, starting a little above
/// its darkest blue so the low end shows on the dark background.
pub(super) fn turbo(t: f64) -> egui::Color32 {
    let t = 0.08 + 0.92 * t.clamp(0.0, 1.0);
    let r = 0.135_721_38
        + t * (4.615_392_6 + t * (-42.660_322_58 + t * (132.131_082_34 + t * (-152.942_393_96 + t * 59.286_379_43))));
    let g = 0.091_402_61
        + t * (2.194_188_39 + t * (4.842_966_58 + t * (-14.185_033_33 + t * (4.277_298_57 + t * 2.829_566_04))));
    let b = 0.106_673_3
        + t * (12.641_946_08 + t * (-60.582_048_36 + t * (110.362_767_71 + t * (-89.903_109_12 + t * 27.348_249_73))));
    let c = |x: f64| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    egui::Color32::from_rgb(c(r), c(g), c(b))
}

/// Position of a relative feed fluctuation on the colour scale (0..1, log of |Δf/f|).
pub(super) fn fluct_t(fluct: f64) -> f64 {
    let (lo, hi) = FLUCT_DECADES;
    let a = fluct.abs();
    if !(a > 0.0) {
        return 0.0;
    }
    ((a.log10() - lo) / (hi - lo)).clamp(0.0, 1.0)
}

/// Depth bias of the G06.2 curve over the design path it lies within E of (normalised
/// depth; see `LineSegment::depth_bias`).
const CURVE_BIAS: f32 = 2e-6;
/// Depth bias of the selected program: drawn over the curves and the interpolated points
/// (about a dot's radius at any zoom).
const OVERLAY_BIAS: f32 = 6e-5;

fn with_bias(mut lines: Vec<LineSegment>, bias: f32) -> Vec<LineSegment> {
    for l in &mut lines {
        *l = l.with_depth_bias(bias);
    }
    lines
}

fn rgba(c: egui::Color32, a: f32) -> [f32; 4] {
    [f32::from(c.r()) / 255.0, f32::from(c.g()) / 255.0, f32::from(c.b()) / 255.0, a]
}

/// Which layers are drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Show {
    /// The design path.
    pub design: bool,
    /// The G06.2 curve.
    pub curve: bool,
    /// Its control polygon and control points.
    pub polygon: bool,
    /// Its knots.
    pub knots: bool,
    /// The real-time interpolated points.
    pub points: bool,
    /// The selected program (G01, G02/G03 or a loaded file).
    pub program: bool,
}

impl Default for Show {
    fn default() -> Self {
        Self { design: true, curve: true, polygon: true, knots: true, points: true, program: true }
    }
}

/// The program drawn over the design.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Overlay {
    /// None (the G06.2 program is the curve itself).
    None,
    /// Row `i` of the comparison (0 G01, 1 G02/G03).
    Row(usize),
    /// The loaded file.
    Loaded,
}

/// What the view draws this frame.
pub struct Drawn<'a> {
    /// The panel's results.
    pub work: &'a Work,
    /// The program drawn over the design.
    pub overlay: Overlay,
    /// Translation from the ball centre to the programmed point (mm).
    pub offset: DVec3,
    /// The work's state for the corner (`(ok, text)`).
    pub status: (bool, String),
}

/// What the layers were built from (generations and settings), to rebuild only on change.
#[derive(Clone, Debug, PartialEq)]
struct Built {
    design: u64,
    offset: [u64; 3],
    curve: u64,
    realtime: u64,
    overlay: Overlay,
    overlay_gen: u64,
    deviation_gen: u64,
    show: Show,
    /// Zoom step (dots are sized in points).
    zoom_step: i32,
}

/// Counts shown in the legend.
#[derive(Clone, Debug, Default)]
struct LegendInfo {
    control_points: usize,
    degree: usize,
    knots: usize,
    dots_every: usize,
    periods: usize,
    overlay: Option<(String, egui::Color32)>,
}

/// State of the 3D view.
pub struct NurbsView {
    camera: OrbitCamera,
    origin: Origin,
    radius: f64,
    /// Design generation the camera was last fitted to.
    fitted_for: Option<u64>,
    built: Option<Built>,
    legend: LegendInfo,
    /// Worst-deviation marker (world) and its label.
    worst: Option<(DVec3, String)>,
    /// That deviation (mm).
    worst_mm: f64,
    /// Where that marker was drawn last frame (points), for tests and tools.
    pub worst_on_screen: Option<egui::Pos2>,
    /// Layers shown.
    pub show: Show,
    /// Points of the design path (local), to find what lies under the pointer.
    pick: Vec<Vec3>,
}

impl Default for NurbsView {
    fn default() -> Self {
        Self {
            camera: OrbitCamera::default(),
            origin: Origin::default(),
            radius: 100.0,
            fitted_for: None,
            built: None,
            legend: LegendInfo::default(),
            worst: None,
            worst_mm: 0.0,
            worst_on_screen: None,
            show: Show::default(),
            pick: Vec::new(),
        }
    }
}

/// Points along a program's segment for drawing: lines by their ends, arcs every ~3°,
/// G06.2 curves 24 per knot span.
fn segment_points(seg: &Segment) -> Vec<DVec3> {
    let c = seg.curve();
    match seg {
        Segment::Line(l) => vec![l.start, l.end],
        Segment::Arc(a) => {
            let n = ((a.length() / DRAW_CHORD_MM).ceil() as usize).clamp(4, 20_000);
            let (t0, t1) = c.range();
            (0..=n).map(|i| c.point_at(t0 + (t1 - t0) * i as f64 / n as f64)).collect()
        }
        Segment::Nurbs(_) => {
            // The span ends (distinct knots), as the reader's sampling uses them.
            curve_points(c, &sample_params(seg, 1))
        }
    }
}

/// Drawn chords are at most this long (mm): on a 20 mm radius they stray 0.25 µm from the
/// curve, invisible at the µm zoom where deviations of the programs are looked at.
const DRAW_CHORD_MM: f64 = 0.2;

/// Points of a curve between consecutive `breaks` (knot span ends), spans cut into chords
/// of at most [`DRAW_CHORD_MM`] (by an 8-chord estimate of each span's length).
fn curve_points(c: &dyn Curve3, breaks: &[f64]) -> Vec<DVec3> {
    let mut pts = Vec::new();
    for w in breaks.windows(2) {
        let est: f64 = (0..8)
            .map(|i| {
                let t = |k: f64| w[0] + (w[1] - w[0]) * k / 8.0;
                (c.point_at(t(f64::from(i) + 1.0)) - c.point_at(t(f64::from(i)))).length()
            })
            .sum();
        let n = ((est / DRAW_CHORD_MM).ceil() as usize).clamp(4, 20_000);
        pts.extend((0..n).map(|i| c.point_at(w[0] + (w[1] - w[0]) * i as f64 / n as f64)));
    }
    if let Some(&last) = breaks.last() {
        pts.push(c.point_at(last));
    }
    pts
}

/// The distinct knot values inside a curve's range (the span ends).
fn span_breaks(c: &NurbsCurve) -> Vec<f64> {
    let p = c.degree();
    let k = c.knots();
    let mut out: Vec<f64> = Vec::new();
    for &x in &k[p..k.len() - p] {
        if out.last().is_none_or(|&l| x > l) {
            out.push(x);
        }
    }
    out
}

impl NurbsView {
    fn fit(&mut self) {
        self.camera.fit(Vec3::ZERO, self.radius as f32);
    }

    /// The point to zoom about for a pointer at `p`: the nearest drawn path point within 40
    /// points on screen, else the point of the target's plane under the pointer (local).
    fn anchor_under(&self, p: egui::Pos2, rect: egui::Rect) -> Vec3 {
        let clip = self.camera.clip_from_world(rect.width() / rect.height().max(1.0));
        let to_screen = |q: Vec3| {
            let c = clip * Vec4::from((q, 1.0));
            (c.w > 0.0).then(|| {
                egui::pos2(
                    rect.center().x + c.x / c.w * rect.width() * 0.5,
                    rect.center().y - c.y / c.w * rect.height() * 0.5,
                )
            })
        };
        // Nearest point of the design polyline on screen (chords 0.25 mm long).
        let mut best = (40.0f32 * 40.0, None);
        let screen: Vec<Option<egui::Pos2>> = self.pick.iter().map(|q| to_screen(*q)).collect();
        for i in 1..self.pick.len() {
            let (Some(a), Some(b)) = (screen[i - 1], screen[i]) else { continue };
            let ab = b - a;
            let t = if ab.length_sq() > 0.0 { ((p - a).dot(ab) / ab.length_sq()).clamp(0.0, 1.0) } else { 0.0 };
            let d2 = (a + ab * t - p).length_sq();
            if d2 < best.0 {
                best = (d2, Some(self.pick[i - 1].lerp(self.pick[i], t)));
            }
        }
        best.1.unwrap_or_else(|| {
            let d = p - rect.center();
            let mm = self.camera.mm_per_point(rect.height());
            let forward = (self.camera.target - self.camera.eye()).normalize();
            let right = forward.cross(Vec3::Z).normalize_or_zero();
            let up = right.cross(forward);
            self.camera.target + (right * d.x - up * d.y) * mm
        })
    }

    /// Millimetres per point at the target's depth.
    fn mm_per_point(&self, h: f32) -> f64 {
        f64::from(self.camera.mm_per_point(h))
    }

    #[expect(clippy::too_many_lines, reason = "one pass over the layers keeps their order and keys in one place")]
    fn rebuild(&mut self, rs: &RenderState, work: &Work, overlay: Overlay, offset: DVec3, h: f32) {
        let Some(design) = work.design.ok() else {
            Renderer3d::with(rs, |r| r.clear_view(VIEW_ID));
            self.built = None;
            return;
        };
        // Origin and framing follow the design.
        if self.fitted_for != Some(work.design.generation) {
            let pts = design.samples(1.0);
            let (c, r) = bounds(pts.iter().map(|p| *p + offset)).unwrap_or((DVec3::ZERO, 100.0));
            self.origin = Origin(c);
            self.radius = r.max(1.0);
            let (lo, hi) =
                pts.iter().fold((DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)), |(lo, hi), p| {
                    (lo.min(*p), hi.max(*p))
                });
            let ext = hi - lo;
            // A planar design in a horizontal plane is best seen from above.
            if ext.z < 0.05 * ext.x.max(ext.y) {
                self.camera.pitch = 1.25;
                self.camera.yaw = -std::f32::consts::FRAC_PI_2;
            } else {
                let d = OrbitCamera::default();
                self.camera.pitch = d.pitch;
                self.camera.yaw = d.yaw;
            }
            self.fit();
            self.fitted_for = Some(work.design.generation);
            self.built = None;
        }
        let mm_pt = self.mm_per_point(h);
        let zoom_step = (mm_pt.max(MIN_LENGTH_MM).ln() / 1.2f64.ln()).floor() as i32;
        let (overlay_gen, deviation_gen) = match overlay {
            Overlay::None => (0, 0),
            Overlay::Row(i) => (work.rows[i].generation, 0),
            Overlay::Loaded => (work.loaded.as_ref().map_or(0, |l| l.generation), work.loaded_deviation.generation),
        };
        let key = Built {
            design: work.design.generation,
            offset: [offset.x.to_bits(), offset.y.to_bits(), offset.z.to_bits()],
            curve: work.rows[2].generation,
            realtime: work.realtime.generation,
            overlay,
            overlay_gen,
            deviation_gen,
            show: self.show,
            zoom_step,
        };
        if self.built.as_ref() == Some(&key) {
            return;
        }
        // Millimetres per point at the target's depth, rounded to the zoom step: sizes below
        // are in points.
        let pt = 1.2f64.powi(zoom_step) * 1.1;
        let o = self.origin;
        let mut legend = LegendInfo::default();
        let mut spheres = Vec::new();
        let mut polygon_lines = Vec::new();
        let mut curve_lines = Vec::new();
        let mut design_lines = Vec::new();
        let mut overlay_lines = Vec::new();
        self.worst = None;

        let pts: Vec<DVec3> = design.samples(0.25).into_iter().map(|p| p + offset).collect();
        self.pick = pts.iter().map(|p| o.local_vec(*p)).collect();
        if self.show.design {
            design_lines = polyline(pts, o, 1.6, rgba(DESIGN_COLOR, 1.0));
        }
        let curve = work.row(2).and_then(|r| r.program.read_back_curves().next());
        if let Some(c) = curve {
            legend.control_points = c.len();
            legend.degree = c.degree();
            let breaks = span_breaks(c);
            legend.knots = breaks.len();
            if self.show.curve {
                let pts = curve_points(c, &breaks);
                curve_lines = with_bias(polyline(pts, o, 2.6, rgba(CURVE_COLOR, 1.0)), CURVE_BIAS);
            }
            if self.show.polygon {
                let cps: Vec<DVec3> = (0..c.len()).map(|i| c.control_point(i)).collect();
                polygon_lines = polyline(cps.iter().copied(), o, 1.3, rgba(POLYGON_COLOR, 0.9));
                for p in cps {
                    spheres.push(SphereInstance {
                        center: o.local(p),
                        radius: (4.0 * pt) as f32,
                        color: rgba(CURVE_COLOR, 1.0),
                    });
                }
            }
            if self.show.knots {
                for u in breaks {
                    spheres.push(SphereInstance {
                        center: o.local(c.point_at(u)),
                        radius: (3.6 * pt) as f32,
                        color: rgba(KNOT_COLOR, 1.0),
                    });
                }
            }
        }
        if let (true, Some(rt)) = (self.show.points, work.realtime.ok()) {
            let (dots, every) = realtime_dots(rt, 11.0 * pt, (2.4 * pt) as f32, o);
            legend.dots_every = every;
            legend.periods = rt.run.samples.len();
            spheres.extend(dots);
        }
        if self.show.program {
            let drawn: Option<(&Toolpath, String, egui::Color32, Option<&Deviation>)> = match overlay {
                Overlay::None => None,
                Overlay::Row(i) => work.row(i).map(|r| {
                    let color = if i == 0 { LINES_COLOR } else { ARCS_COLOR };
                    let name = format!("{} program ({} blocks)", r.kind.label(), r.path_blocks);
                    (&r.program.parsed.toolpath, name, color, Some(&r.program.deviation))
                }),
                Overlay::Loaded => match &work.loaded {
                    Some(Loaded { parsed: Ok(p), name, .. }) => {
                        Some((&p.toolpath, name.clone(), LOADED_COLOR, work.loaded_deviation.ok()))
                    }
                    _ => None,
                },
            };
            if let Some((path, name, color, dev)) = drawn {
                legend.overlay = Some((name, color));
                for b in &path.blocks {
                    let rapid = b.motion == crate::gcode::Motion::Rapid;
                    let (c, w) = if rapid { (rgba(RAPID_COLOR, 0.8), 1.0) } else { (rgba(color, 1.0), 2.4) };
                    overlay_lines.extend(with_bias(polyline(segment_points(&b.segment), o, w, c), OVERLAY_BIAS));
                }
                // Block ends mark where the program's moves meet.
                let cuts: Vec<&PathBlock> = path.cuts().collect();
                if cuts.len() <= 5000 {
                    for b in &cuts {
                        spheres.push(SphereInstance {
                            center: o.local(b.segment.end()),
                            radius: (2.2 * pt) as f32,
                            color: rgba(color, 1.0),
                        });
                    }
                }
                if let Some(d) = dev {
                    let (p, what) = if d.program_to_design_mm >= d.design_to_program_mm {
                        (d.program_point, format!("line {}", d.program_line))
                    } else {
                        (d.design_point, format!("design s = {:.1} mm", d.design_s_mm))
                    };
                    self.worst_mm = d.max_mm();
                    self.worst = Some((p, format!("max deviation {} ({what})", super::super::fmt_len(d.max_mm()))));
                    spheres.push(SphereInstance {
                        center: o.local(p),
                        radius: (5.0 * pt) as f32,
                        color: rgba(WORST_COLOR, 1.0),
                    });
                }
            }
        }
        Renderer3d::with(rs, |r| {
            r.set_spheres(VIEW_ID, Layer::Markers, &spheres);
            r.set_lines(VIEW_ID, Layer::StaticLines, &polygon_lines, 0);
            r.set_lines(VIEW_ID, Layer::PathLines, &curve_lines, 0);
            r.set_lines(VIEW_ID, Layer::ExactLines, &design_lines, 0);
            r.set_lines(VIEW_ID, Layer::DynamicLines, &overlay_lines, 0);
        });
        self.legend = legend;
        self.built = Some(key);
    }

    /// Draws the view into `rect`.
    pub fn ui(&mut self, ui: &mut egui::Ui, rect: egui::Rect, rs: Option<&RenderState>, what: Drawn<'_>) {
        let Drawn { work, overlay, offset, status } = what;
        let response = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        let Some(rs) = rs else {
            no_gpu(ui.painter(), rect);
            return;
        };
        orbit_and_pan(&mut self.camera, ui, &response, rect);
        let factor = zoom_factor(ui, &response);
        if (factor - 1.0).abs() > f32::EPSILON {
            let anchor = response.hover_pos().map(|p| self.anchor_under(p, rect));
            let before = self.camera.distance;
            self.camera.zoom(factor);
            if let Some(a) = anchor {
                // Scale the camera about the anchor: it stays under the pointer, so a
                // deviation of a few µm can be inspected where it is.
                let k = self.camera.distance / before;
                self.camera.target = a + (self.camera.target - a) * k;
            }
        }
        if response.double_clicked() {
            self.fit();
        }
        self.rebuild(rs, work, overlay, offset, rect.height());

        let clip = paint_view(ui, rect, &self.camera, VIEW_ID, BACKGROUND, false);
        self.overlays(ui, rect, work, clip, Some(status));
    }

    fn overlays(
        &mut self,
        ui: &mut egui::Ui,
        rect: egui::Rect,
        work: &Work,
        clip: glam::Mat4,
        status: Option<(bool, String)>,
    ) {
        let painter = ui.painter_at(rect);
        let font = egui::FontId::proportional(13.0);
        let text_color = egui::Color32::from_gray(225);
        // Legend, top left.
        let x = rect.left() + 10.0;
        let mut y = rect.top() + 8.0;
        let mut entry = |color: egui::Color32, text: String, dot: bool| {
            let r = egui::Rect::from_min_size(egui::pos2(x, y + 3.0), egui::vec2(12.0, 10.0));
            if dot {
                painter.circle_filled(r.center(), 4.5, color);
            } else {
                painter.rect_filled(egui::Rect::from_center_size(r.center(), egui::vec2(14.0, 3.0)), 1.0, color);
            }
            painter.text(egui::pos2(x + 20.0, y), egui::Align2::LEFT_TOP, text, font.clone(), text_color);
            y += 18.0;
        };
        let l = &self.legend;
        if work.design.ok().is_some() {
            if self.show.design {
                let len = work.design.ok().map_or(0.0, |d| d.length_mm);
                entry(DESIGN_COLOR, format!("design path ({len:.1} mm)"), false);
            }
            if l.control_points > 0 {
                if self.show.curve {
                    entry(CURVE_COLOR, format!("G06.2 curve, degree {} (order P{})", l.degree, l.degree + 1), false);
                }
                if self.show.polygon {
                    entry(POLYGON_COLOR, format!("control polygon, {} control points", l.control_points), true);
                }
                if self.show.knots {
                    entry(KNOT_COLOR, format!("knots: {} span ends", l.knots), true);
                }
            }
            if self.show.points && l.periods > 0 {
                let every = if l.dots_every > 1 {
                    format!(" (a dot per {}; zoom in for all)", l.dots_every)
                } else {
                    String::new()
                };
                entry(turbo(0.75), format!("interpolated points: {} periods{every}", l.periods), true);
            }
            if let Some((name, color)) = &l.overlay {
                entry(*color, name.clone(), false);
            }
        }
        // Worst deviation label next to its marker.
        self.worst_on_screen = None;
        if let Some((p, label)) = &self.worst {
            let q = clip * Vec4::from((self.origin.local_vec(*p), 1.0));
            if q.w > 0.0 {
                let ndc = q.truncate() / q.w;
                let s = egui::pos2(
                    rect.center().x + ndc.x * rect.width() * 0.5,
                    rect.center().y - ndc.y * rect.height() * 0.5,
                );
                if rect.contains(s) {
                    self.worst_on_screen = Some(s);
                    let galley = painter.layout_no_wrap(label.clone(), font.clone(), WORST_COLOR);
                    // Right of the marker, or left of it near the right edge; inside the view.
                    let mut at = s + egui::vec2(12.0, -12.0 - galley.size().y);
                    if at.x + galley.size().x > rect.right() - 6.0 {
                        at.x = s.x - 12.0 - galley.size().x;
                    }
                    at.y = at.y.max(rect.top() + 4.0);
                    let bg = egui::Rect::from_min_size(at - egui::vec2(3.0, 2.0), galley.size() + egui::vec2(6.0, 4.0));
                    painter.rect_filled(bg, 3.0, egui::Color32::from_black_alpha(170));
                    painter
                        .line_segment([s, at + egui::vec2(0.0, galley.size().y)], egui::Stroke::new(1.0, WORST_COLOR));
                    painter.galley(at, galley, WORST_COLOR);
                }
            }
        }
        // Colour scale of the fluctuation, bottom left above the axes.
        if self.show.points && l.periods > 0 {
            fluct_legend(&painter, egui::pos2(rect.right() - 256.0, rect.bottom() - 66.0), 240.0, &font);
        }
        axis_triad(&painter, rect.left_bottom() + egui::vec2(40.0, -40.0), 26.0, &self.camera, &font);
        scale_bar(&painter, rect.right_bottom() + egui::vec2(-20.0, -22.0), self.mm_per_point(rect.height()), &font);
        // Status, top right; fit / reset under it.
        if let Some((ok, text)) = status {
            let color = if ok { egui::Color32::from_gray(210) } else { egui::Color32::from_rgb(255, 120, 110) };
            let galley = painter.layout(text, font, color, (rect.width() * 0.45).max(120.0));
            let at = egui::pos2(rect.right() - 10.0 - galley.size().x, rect.top() + 8.0);
            painter.galley(at, galley, color);
        }
        let buttons = egui::Rect::from_min_size(rect.right_top() + egui::vec2(-140.0, 30.0), egui::vec2(130.0, 24.0));
        match view_buttons(ui, buttons, "Frame the design path (double-click)") {
            Some(ViewButton::Reset) => {
                self.camera = OrbitCamera::default();
                self.fitted_for = None;
            }
            Some(ViewButton::Fit) => self.fit(),
            None => {}
        }
        if let Some((p, _)) = &self.worst {
            let at = egui::Rect::from_min_size(rect.right_top() + egui::vec2(-200.0, 56.0), egui::vec2(190.0, 24.0));
            let mut child = ui.new_child(
                egui::UiBuilder::new().max_rect(at).layout(egui::Layout::right_to_left(egui::Align::Center)),
            );
            if child
                .small_button("zoom to max deviation")
                .on_hover_text("Centre the largest deviation and zoom until it spans a tenth of the view")
                .clicked()
            {
                self.camera.target = self.origin.local_vec(*p);
                let height_mm = (10.0 * self.worst_mm).max(0.005) as f32;
                self.camera.distance = (height_mm / (2.0 * (self.camera.fov_y * 0.5).tan())).max(0.05);
            }
        }
    }
}

/// Dots of the real-time run, at most one per `spacing_mm` along the path: each shown dot
/// stands for a run of consecutive periods and takes the largest |fluctuation| among them,
/// so the colour never hides a peak. Returns the dots and the periods per dot.
fn realtime_dots(rt: &Realtime, spacing_mm: f64, radius: f32, o: Origin) -> (Vec<SphereInstance>, usize) {
    let samples = &rt.run.samples;
    let every = ((spacing_mm / rt.feed_per_period_mm.max(MIN_LENGTH_MM)).ceil() as usize).max(1);
    let every = every.max(samples.len().div_ceil(20_000));
    let mut dots = Vec::with_capacity(samples.len() / every + 1);
    for chunk in samples.chunks(every) {
        let worst = chunk.iter().filter(|s| !s.last).map(|s| s.fluctuation.abs()).fold(0.0, f64::max);
        if let Some(s) = chunk.last() {
            dots.push(SphereInstance { center: o.local(s.point), radius, color: rgba(turbo(fluct_t(worst)), 1.0) });
        }
    }
    (dots, every)
}

/// The colour bar of |Δf/f| (log), with decade labels.
pub(super) fn fluct_legend(painter: &egui::Painter, left_bottom: egui::Pos2, width: f32, font: &egui::FontId) {
    let (lo, hi) = FLUCT_DECADES;
    let h = 10.0;
    let top = left_bottom.y - h;
    let steps = 64;
    for i in 0..steps {
        let t0 = i as f32 / steps as f32;
        let t1 = (i + 1) as f32 / steps as f32;
        let r = egui::Rect::from_min_max(
            egui::pos2(left_bottom.x + t0 * width, top),
            egui::pos2(left_bottom.x + t1 * width + 0.5, left_bottom.y),
        );
        painter.rect_filled(r, 0.0, turbo(f64::from(t0 + t1) * 0.5));
    }
    let small = egui::FontId::proportional(11.0);
    let mut d = lo;
    while d <= hi + TICK_SLACK {
        let x = left_bottom.x + ((d - lo) / (hi - lo)) as f32 * width;
        painter.line_segment(
            [egui::pos2(x, left_bottom.y), egui::pos2(x, left_bottom.y + 3.0)],
            egui::Stroke::new(1.0, egui::Color32::GRAY),
        );
        painter.text(
            egui::pos2(x, left_bottom.y + 3.0),
            egui::Align2::CENTER_TOP,
            format!("1e{d:.0}"),
            small.clone(),
            egui::Color32::from_gray(200),
        );
        d += 2.0;
    }
    painter.text(
        egui::pos2(left_bottom.x, top - 2.0),
        egui::Align2::LEFT_BOTTOM,
        "feed fluctuation |Δf/f| per period (log)",
        font.clone(),
        egui::Color32::from_gray(225),
    );
}
