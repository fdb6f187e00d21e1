//! The five-axis 3D view (GPU view 1): the part's surfaces (translucent, so a gouge inside
//! shows), the design path of the ball centre and of the tool tip, thin tool axes along it,
//! the programmed chords between blocks with the tool axis at every block, and the swept
//! tool-tip (or ball-centre) curves coloured by the ball's signed error. Layers are rebuilt
//! only when what they show changes; interaction as in the crease view.

use crate::app::overlay::{axis_triad, camera_controls, fit_buttons, no_gpu, paint_view, scale_bar};
use eframe::egui;
use eframe::egui_wgpu::RenderState;
use glam::{DVec3, Vec3};

use super::work::{Design, Plan, Shape};
use crate::app::widgets::SURFACE_COLORS;
use crate::render::geometry::{Origin, bounds, iso_lines, polyline, tessellate};
use crate::render::{Layer, LineSegment, Mesh, MeshVertex, OrbitCamera, Renderer3d, SphereInstance, ViewId};

/// Lines drawn on a surface are lifted off it by this fraction of the scene's radius, so the
/// depth test does not hide them in the surface's own triangles.
const LINE_LIFT_REL: f64 = 1e-3;
/// A largest deviation (mm) at or below this is not exaggerated: the factor is 1.
const MIN_EXAGGERATED_DEV_MM: f64 = 1e-12;
/// A point whose clip-space w is at or below this lies at or behind the eye: not drawn.
const MIN_CLIP_W: f32 = 1e-6;

/// The GPU view id of the five-axis view (the crease view uses 0, the NURBS view 2).
pub const VIEW_ID: ViewId = 1;

const BACKGROUND: [f32; 4] = [0.075, 0.08, 0.095, 1.0];
/// Design path of the ball centre.
pub const DESIGN_CENTRE: egui::Color32 = egui::Color32::from_rgb(235, 235, 235);
/// Design path of the tool tip.
pub const DESIGN_TIP: egui::Color32 = egui::Color32::from_rgb(140, 150, 165);
/// Programmed chords.
pub const CHORD: egui::Color32 = egui::Color32::from_rgb(250, 210, 80);
/// Tool axes at the blocks.
pub const AXIS: egui::Color32 = egui::Color32::from_rgb(120, 200, 255);
/// Thin tool axes along the design path.
pub const AXIS_THIN: egui::Color32 = egui::Color32::from_rgb(90, 110, 140);
/// Stock left (δ = −E) … exact (0) … overcut (δ = +E); beyond ±E.
pub const STOCK: egui::Color32 = egui::Color32::from_rgb(60, 120, 255);
/// Exact (δ = 0).
pub const EXACT: egui::Color32 = egui::Color32::from_rgb(215, 215, 215);
/// Overcut δ = +E.
pub const OVERCUT: egui::Color32 = egui::Color32::from_rgb(245, 60, 50);
/// Overcut beyond E.
pub const OVERCUT_BEYOND: egui::Color32 = egui::Color32::from_rgb(255, 40, 230);
/// Stock beyond E.
pub const STOCK_BEYOND: egui::Color32 = egui::Color32::from_rgb(20, 235, 255);

/// Which swept curve is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Swept {
    /// The tool tip (the programmed point).
    Tip,
    /// The ball centre.
    Centre,
    /// Both.
    Both,
}

/// Display options of the view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Display {
    /// Draw the part's surfaces.
    pub surfaces: bool,
    /// Draw thin tool axes along the design path.
    pub thin_axes: bool,
    /// Which swept curve.
    pub swept: Swept,
    /// Exaggeration of the swept curves' distance from the programmed chords.
    pub magnify: f64,
    /// Choose the exaggeration so the largest distance shows as 3 % of the view.
    pub auto_magnify: bool,
}

impl Default for Display {
    fn default() -> Self {
        Self { surfaces: true, thin_axes: true, swept: Swept::Tip, magnify: 1.0, auto_magnify: true }
    }
}

fn rgba(c: egui::Color32, a: f32) -> [f32; 4] {
    [f32::from(c.r()) / 255.0, f32::from(c.g()) / 255.0, f32::from(c.b()) / 255.0, a]
}

fn mix(a: egui::Color32, b: egui::Color32, t: f32) -> egui::Color32 {
    let t = t.clamp(0.0, 1.0);
    let m = |x: u8, y: u8| (f32::from(x) + (f32::from(y) - f32::from(x)) * t).round() as u8;
    egui::Color32::from_rgb(m(a.r(), b.r()), m(a.g(), b.g()), m(a.b(), b.b()))
}

/// The colour of a signed error δ on the scale ±`scale_mm`.
pub fn error_color(delta_mm: f64, scale_mm: f64) -> egui::Color32 {
    if !delta_mm.is_finite() || scale_mm <= 0.0 {
        return EXACT;
    }
    let x = delta_mm / scale_mm;
    // Past ±E by more than the search's acceptance slack: the "beyond" colours.
    if x > 1.0 + crate::numerics::tolerance::STEP_WINDOW_REL {
        OVERCUT_BEYOND
    } else if x < -1.0 - crate::numerics::tolerance::STEP_WINDOW_REL {
        STOCK_BEYOND
    } else if x >= 0.0 {
        mix(EXACT, OVERCUT, x as f32)
    } else {
        mix(EXACT, STOCK, (-x) as f32)
    }
}

/// State of the five-axis 3D view.
pub struct FiveAxisView {
    camera: OrbitCamera,
    origin: Origin,
    radius: f64,
    static_for: Option<((super::work::Source, u64, crate::fiveaxis::ToolAxisRule), bool, bool)>,
    plan_for: Option<(u64, usize, usize, Swept, u64)>,
    dynamic_for: Option<(u64, Option<usize>, usize, u64)>,
    fit_requested: bool,
    /// The design whose first complete plan the camera was fitted to (the swept tool may
    /// leave the design's bounds far, as in Example 1 before steps are inserted).
    fitted_plan: Option<(super::work::Source, u64, crate::fiveaxis::ToolAxisRule)>,
}

impl Default for FiveAxisView {
    fn default() -> Self {
        Self {
            camera: OrbitCamera::default(),
            origin: Origin::default(),
            radius: 50.0,
            static_for: None,
            plan_for: None,
            dynamic_for: None,
            fit_requested: true,
            fitted_plan: None,
        }
    }
}

/// The cylinder of Example 1 (radius, height of the contact circle) around the arc.
fn cylinder_mesh(origin: Origin, radius: f64, z: f64, color: [f32; 4]) -> Mesh {
    let (n_a, n_z) = (96usize, 2usize);
    let (a0, a1) = (40f64.to_radians(), 140f64.to_radians());
    let (z0, z1) = (z - 12.0, z + 12.0);
    let mut mesh = Mesh::default();
    for i in 0..=n_a {
        let a = a0 + (a1 - a0) * i as f64 / n_a as f64;
        let n = DVec3::new(a.cos(), a.sin(), 0.0);
        for j in 0..=n_z {
            let zz = z0 + (z1 - z0) * j as f64 / n_z as f64;
            mesh.vertices.push(MeshVertex {
                position: origin.local(DVec3::new(radius * a.cos(), radius * a.sin(), zz)),
                normal: [n.x as f32, n.y as f32, 0.0],
                color,
            });
        }
    }
    let row = (n_z + 1) as u32;
    for i in 0..n_a as u32 {
        for j in 0..n_z as u32 {
            let (a, b, c, d) = (i * row + j, (i + 1) * row + j, (i + 1) * row + j + 1, i * row + j + 1);
            mesh.indices.extend_from_slice(&[a, b, c, a, c, d]);
        }
    }
    mesh
}

/// A planar profile extruded along Z by ±`half_height` mm, normals toward the tool.
fn extrusion_mesh(origin: Origin, profile: &[(DVec3, DVec3)], half_height: f64, color: [f32; 4]) -> Mesh {
    let mut mesh = Mesh::default();
    for (p, n) in profile {
        for dz in [-half_height, half_height] {
            mesh.vertices.push(MeshVertex {
                position: origin.local(*p + DVec3::Z * dz),
                normal: [n.x as f32, n.y as f32, n.z as f32],
                color,
            });
        }
    }
    for i in 0..profile.len().saturating_sub(1) as u32 {
        let (a, b, c, d) = (2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1);
        // Counter-clockwise seen from the tool side.
        mesh.indices.extend_from_slice(&[a, c, b, a, d, c]);
    }
    mesh
}

impl FiveAxisView {
    /// Frames the design at the next frame.
    pub fn request_fit(&mut self) {
        self.fit_requested = true;
    }

    fn rebuild_static(&mut self, rs: &RenderState, design: &Design, display: &Display) {
        let key = (design.key, display.surfaces, display.thin_axes);
        if self.static_for.as_ref() == Some(&key) {
            return;
        }
        let geometry_changed = self.static_for.as_ref().is_none_or(|k| k.0 != design.key);
        let r = design.path.ball_radius_mm();
        let pts = design.samples.iter().flat_map(|l| [l.centre, l.tip, l.tip + 3.0 * r * l.axis]);
        let (center, radius) = bounds(pts).unwrap_or((DVec3::ZERO, 50.0));
        if geometry_changed {
            let source_changed = self.static_for.as_ref().is_none_or(|k| k.0.0 != design.key.0);
            self.origin = Origin(center);
            self.radius = radius.max(5.0);
            self.plan_for = None;
            self.dynamic_for = None;
            if source_changed {
                // Profiles lie in a plane z = const: look at them from above; a crease from
                // the crease view's angle.
                self.camera = OrbitCamera::default();
                if !matches!(design.shape, Shape::Crease(_)) {
                    // From above and outside: toward the tool side of the profile's start.
                    let n = design.samples.first().map_or(DVec3::Y, |l| l.normals[0]);
                    self.camera.pitch = 1.0;
                    self.camera.yaw = (n.y.atan2(n.x) - 0.35) as f32;
                }
                self.fit_requested = true;
                self.fitted_plan = None;
            }
        }
        let mut mesh = Mesh::default();
        let mut lines = Vec::new();
        if display.surfaces {
            match &design.shape {
                Shape::Crease(job) => {
                    for (i, s) in job.surfaces.iter().enumerate() {
                        let c = SURFACE_COLORS[i];
                        mesh.extend(&tessellate(s, self.origin, 64, 0.0, rgba(c, 0.28)));
                        let lift = LINE_LIFT_REL * self.radius;
                        lines.extend(iso_lines(s, self.origin, 10, 80, lift, 1.0, rgba(c.gamma_multiply(0.55), 1.0)));
                    }
                }
                Shape::Cylinder { radius_mm, z_mm } => {
                    mesh.extend(&cylinder_mesh(self.origin, *radius_mm, *z_mm, rgba(SURFACE_COLORS[0], 0.3)));
                    // Generators every 5° and the contact circle, for depth.
                    let c = rgba(SURFACE_COLORS[0].gamma_multiply(0.7), 1.0);
                    for k in 8..=28 {
                        let a = f64::from(k * 5).to_radians();
                        let p = DVec3::new(radius_mm * a.cos(), radius_mm * a.sin(), *z_mm);
                        lines.extend(polyline([p - 12.0 * DVec3::Z, p + 12.0 * DVec3::Z], self.origin, 1.0, c));
                    }
                    let circle = (0..=200).map(|i| {
                        let a = (40.0 + 100.0 * f64::from(i) / 200.0f64).to_radians();
                        DVec3::new(radius_mm * a.cos(), radius_mm * a.sin(), *z_mm)
                    });
                    lines.extend(polyline(circle, self.origin, 1.0, c));
                }
                Shape::Extrusion(profile) => {
                    mesh.extend(&extrusion_mesh(self.origin, profile, 10.0, rgba(SURFACE_COLORS[0], 0.3)));
                    let c = rgba(SURFACE_COLORS[0].gamma_multiply(0.7), 1.0);
                    for dz in [-10.0, 0.0, 10.0] {
                        lines.extend(polyline(profile.iter().map(|(p, _)| *p + DVec3::Z * dz), self.origin, 1.0, c));
                    }
                }
            }
        }
        let centres = design.samples.iter().map(|l| l.centre);
        lines.extend(polyline(centres, self.origin, 1.6, rgba(DESIGN_CENTRE, 0.9)));
        let tips = design.samples.iter().map(|l| l.tip);
        lines.extend(polyline(tips, self.origin, 1.4, rgba(DESIGN_TIP, 0.9)));
        if display.thin_axes {
            let every = (design.samples.len() / 16).max(1);
            for l in design.samples.iter().step_by(every) {
                lines.push(LineSegment::new(
                    self.origin.local(l.tip),
                    self.origin.local(l.tip + 2.0 * r * l.axis),
                    1.0,
                    rgba(AXIS_THIN, 0.8),
                ));
            }
        }
        Renderer3d::with(rs, |r| {
            r.set_mesh(VIEW_ID, Layer::Offsets, &mesh);
            r.set_mesh(VIEW_ID, Layer::Surfaces, &Mesh::default());
            r.set_lines(VIEW_ID, Layer::StaticLines, &lines, 0);
        });
        self.static_for = Some(key);
    }

    fn drawn(&self, swept: DVec3, chord: DVec3, magnify: f64) -> [f32; 3] {
        self.origin.local(chord + (swept - chord) * magnify)
    }

    fn rebuild_plan(&mut self, rs: &RenderState, plan: &Plan, display: &Display, scale_mm: f64) {
        let key = (plan.serial, plan.nodes.len(), plan.segs.len(), display.swept, (display.magnify * 1e6) as u64);
        if self.plan_for == Some(key) {
            return;
        }
        let r = plan.design.path.ball_radius_mm();
        if plan.shown_complete() && self.fitted_plan != Some(plan.design.key) {
            self.fitted_plan = Some(plan.design.key);
            let swept = plan.segs.iter().flat_map(|sg| sg.samples.iter().flat_map(|x| [x.tip, x.centre]));
            let design = plan.design.samples.iter().flat_map(|l| [l.centre, l.tip, l.tip + 3.0 * r * l.axis]);
            if let Some((c, radius)) = bounds(swept.chain(design)) {
                self.camera.target = self.origin.local_vec(c);
                self.camera.fit(self.origin.local_vec(c), radius.max(5.0) as f32);
                self.radius = self.radius.max(radius);
                self.fit_requested = false;
            }
        }
        let mut chords = Vec::new();
        let mut swept = Vec::new();
        let mut dots = Vec::new();
        let dot = (0.012 * self.radius).clamp(0.05, 1.5) as f32;
        for n in &plan.nodes {
            let l = &n.block.location;
            chords.push(LineSegment::new(
                self.origin.local(l.tip),
                self.origin.local(l.tip + 3.0 * r * l.axis),
                2.2,
                rgba(AXIS, 1.0),
            ));
            dots.push(SphereInstance { center: self.origin.local(l.tip), radius: dot, color: rgba(CHORD, 1.0) });
        }
        for w in plan.nodes.windows(2) {
            let (a, b) = (&w[0].block.location, &w[1].block.location);
            chords.push(LineSegment::new(self.origin.local(a.tip), self.origin.local(b.tip), 2.0, rgba(CHORD, 1.0)));
            if display.swept != Swept::Tip {
                chords.push(LineSegment::new(
                    self.origin.local(a.centre),
                    self.origin.local(b.centre),
                    1.4,
                    rgba(CHORD, 0.6),
                ));
            }
        }
        // At most ~8000 swept pieces: with many segments every k-th sample (ends kept).
        let total: usize = plan.segs.iter().map(|sg| sg.samples.len().saturating_sub(1)).sum();
        let stride = total.div_ceil(8000).max(1);
        for seg in &plan.segs {
            let last = seg.samples.len().saturating_sub(1);
            let picked: Vec<_> = seg
                .samples
                .iter()
                .enumerate()
                .filter(|(i, _)| i % stride == 0 || *i == last)
                .map(|(_, x)| *x)
                .collect();
            for w in picked.windows(2) {
                let color = rgba(error_color(0.5 * (w[0].delta_mm + w[1].delta_mm), scale_mm), 1.0);
                // The tip's curve unless only the centre's is asked for, and the other way round.
                let curves = [
                    (Swept::Centre, [(w[0].tip, w[0].tip_chord), (w[1].tip, w[1].tip_chord)]),
                    (Swept::Tip, [(w[0].centre, w[0].centre_chord), (w[1].centre, w[1].centre_chord)]),
                ];
                for (unless, [(p0, c0), (p1, c1)]) in curves {
                    if display.swept != unless {
                        let (a, b) = (self.drawn(p0, c0, display.magnify), self.drawn(p1, c1, display.magnify));
                        swept.push(LineSegment::new(a, b, 3.2, color));
                    }
                }
            }
        }
        Renderer3d::with(rs, |g| {
            g.set_lines(VIEW_ID, Layer::PathLines, &chords, 0);
            g.set_lines(VIEW_ID, Layer::ExactLines, &swept, 0);
            g.set_spheres(VIEW_ID, Layer::Markers, &dots);
        });
        self.plan_for = Some(key);
    }

    fn rebuild_dynamic(&mut self, rs: &RenderState, plan: &Plan, selected: Option<usize>, display: &Display) {
        let key = (plan.serial, selected, plan.segs.len(), (display.magnify * 1e6) as u64);
        if self.dynamic_for == Some(key) {
            return;
        }
        let mut balls = Vec::new();
        let mut lines = Vec::new();
        let r = plan.design.path.ball_radius_mm();
        if let Some(k) = selected
            && let (Some(w), Some(seg)) = (plan.nodes.get(k..k + 2), plan.segs.get(k))
        {
            let tau = w[1].report.map_or(0.5, |rep| rep.at_tau);
            let pose = plan.inputs.machine.pose_from_joints(&w[0].block.joints.lerp(&w[1].block.joints, tau));
            let centre = pose.tip_in_workpiece + r * pose.axis_in_workpiece;
            balls.push(SphereInstance {
                center: self.origin.local(centre),
                radius: r as f32,
                color: [0.95, 0.95, 0.98, 0.35],
            });
            // The tool's shank along the swept axis, and the highlighted segment.
            lines.push(LineSegment::new(
                self.origin.local(centre),
                self.origin.local(centre + 2.5 * r * pose.axis_in_workpiece),
                4.0,
                [0.8, 0.82, 0.86, 0.6],
            ));
            for s in seg.samples.windows(2) {
                lines.push(LineSegment::new(
                    self.drawn(s[0].tip, s[0].tip_chord, display.magnify),
                    self.drawn(s[1].tip, s[1].tip_chord, display.magnify),
                    6.0,
                    [1.0, 1.0, 1.0, 0.45],
                ));
            }
        }
        if let Some(s) = plan.error.as_ref().and_then(|e| e.s)
            && let Ok(l) = plan.design.path.location_at(s)
        {
            balls.push(SphereInstance {
                center: self.origin.local(l.centre),
                radius: r as f32,
                color: [1.0, 0.2, 0.2, 0.5],
            });
        }
        Renderer3d::with(rs, |g| {
            g.set_spheres(VIEW_ID, Layer::Cutters, &balls);
            g.set_lines(VIEW_ID, Layer::DynamicLines, &lines, 0);
        });
        self.dynamic_for = Some(key);
    }

    fn clear_plan(&mut self, rs: &RenderState) {
        if self.plan_for.is_none() && self.dynamic_for.is_none() {
            return;
        }
        Renderer3d::with(rs, |g| {
            g.set_lines(VIEW_ID, Layer::PathLines, &[], 0);
            g.set_lines(VIEW_ID, Layer::ExactLines, &[], 0);
            g.set_lines(VIEW_ID, Layer::DynamicLines, &[], 0);
            g.set_spheres(VIEW_ID, Layer::Markers, &[]);
            g.set_spheres(VIEW_ID, Layer::Cutters, &[]);
        });
        self.plan_for = None;
        self.dynamic_for = None;
    }

    /// The exaggeration that shows the plan's largest swept-to-chord distance as 3 % of the
    /// view's size (1 when it is already that large).
    pub fn auto_magnify(&self, plan: &Plan) -> f64 {
        let dev = plan
            .segs
            .iter()
            .flat_map(|sg| sg.samples.iter())
            .map(|x| (x.tip - x.tip_chord).length().max((x.centre - x.centre_chord).length()))
            .fold(0.0f64, f64::max);
        if dev <= MIN_EXAGGERATED_DEV_MM { 1.0 } else { (0.03 * self.radius / dev).clamp(1.0, 10_000.0).round() }
    }

    /// Where a workpiece point appears in the view's rectangle (`None` behind the eye).
    fn project(&self, p: DVec3, rect: egui::Rect) -> Option<egui::Pos2> {
        let clip = self.camera.clip_from_world(rect.width() / rect.height().max(1.0));
        let q = clip * self.origin.local_vec(p).extend(1.0);
        if q.w <= MIN_CLIP_W {
            return None;
        }
        let (x, y) = (q.x / q.w, q.y / q.w);
        Some(egui::pos2(rect.left() + (x + 1.0) * 0.5 * rect.width(), rect.top() + (1.0 - y) * 0.5 * rect.height()))
    }

    fn fit(&mut self) {
        self.camera.fit(Vec3::ZERO, self.radius as f32);
        self.fit_requested = false;
    }

    /// Draws the view into `rect`-sized space of `ui`; returns the view's rectangle.
    #[expect(clippy::too_many_arguments, reason = "the view reads the design, the plan and the panel's settings")]
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        rs: Option<&RenderState>,
        design: Option<&Design>,
        plan: Option<&Plan>,
        display: &Display,
        selected: Option<usize>,
        scale_mm: f64,
        overlay: impl FnOnce(&egui::Painter, egui::Rect, &dyn Fn(DVec3) -> Option<egui::Pos2>),
    ) -> egui::Rect {
        let (rect, response) =
            ui.allocate_exact_size(ui.available_size().max(egui::vec2(64.0, 64.0)), egui::Sense::click_and_drag());
        let Some(rs) = rs else {
            no_gpu(ui.painter(), rect);
            return rect;
        };
        if let Some(d) = design {
            self.rebuild_static(rs, d, display);
        }
        match plan {
            Some(p) => {
                self.rebuild_plan(rs, p, display, scale_mm);
                self.rebuild_dynamic(rs, p, selected, display);
            }
            None => self.clear_plan(rs),
        }
        camera_controls(&mut self.camera, ui, &response, rect, self.radius as f32);
        if self.fit_requested && design.is_some() {
            self.fit();
        }
        paint_view(ui, rect, &self.camera, VIEW_ID, BACKGROUND, true);
        let painter = ui.painter_at(rect);
        self.triad_and_scale(&painter, rect);
        overlay(&painter, rect, &|p| self.project(p, rect));
        let buttons =
            egui::Rect::from_min_size(rect.right_bottom() + egui::vec2(-140.0, -60.0), egui::vec2(130.0, 24.0));
        fit_buttons(ui, buttons, &mut self.camera, self.radius as f32, "Frame the whole path (double-click)");
        rect
    }

    fn triad_and_scale(&self, painter: &egui::Painter, rect: egui::Rect) {
        let font = egui::FontId::proportional(13.0);
        axis_triad(painter, rect.left_bottom() + egui::vec2(46.0, -46.0), 32.0, &self.camera, &font);
        let end = rect.right_bottom() + egui::vec2(-20.0, -20.0);
        scale_bar(painter, end, f64::from(self.camera.mm_per_point(rect.height())), &font);
    }
}

/// The surfaces' legend colours (S1, S2) for the overlay.
pub fn surface_color(i: usize) -> egui::Color32 {
    SURFACE_COLORS[i.min(1)]
}
