//! The 3D view of the crease: both surfaces with iso-parameter lines, the translucent offset
//! surfaces, the exact crease, the interpolated cutter centres, ball cutters along the path
//! and at the playback position with the contact points and normals; orbit / pan / zoom,
//! fit, an axis triad and a scale bar.

use eframe::egui;
use eframe::egui_wgpu::RenderState;
use glam::{DVec3, Vec3};

use crate::app::Playback;
use crate::app::compute::{Computation, Period};
use crate::app::overlay::{axis_triad, camera_controls, fit_buttons, no_gpu, paint_view, scale_bar};
use crate::app::widgets::{SURFACE_COLORS, legend_entry, view_status};
use crate::geom::ParametricSurface;
use crate::render::geometry::{Origin, bounds, iso_lines, tessellate};
use crate::render::{Layer, LineSegment, Mesh, OrbitCamera, Renderer3d, SphereInstance, ViewId};
use crate::scene::{Scene, SurfaceSpec};

/// What the view shows (the "Display" section of the controls).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewSettings {
    /// Translucent offset surfaces.
    pub show_offsets: bool,
    /// Iso-parameter lines on the surfaces.
    pub show_iso: bool,
    /// Translucent balls along the path.
    pub show_cutters: bool,
    /// The exact crease line.
    pub show_exact: bool,
    /// Exaggeration of the centres' deviation from the exact crease.
    pub magnify: f64,
    /// Show surfaces only from the cutter's side (the side their normal points to).
    pub cutter_side_only: bool,
}

impl Default for ViewSettings {
    fn default() -> Self {
        Self {
            show_offsets: true,
            show_iso: true,
            show_cutters: true,
            show_exact: true,
            magnify: 1.0,
            cutter_side_only: true,
        }
    }
}

fn rgba(c: egui::Color32, a: f32) -> [f32; 4] {
    [f32::from(c.r()) / 255.0, f32::from(c.g()) / 255.0, f32::from(c.b()) / 255.0, a]
}

/// Smallest distance between drawn path points, as a fraction of the scene's radius.
const DRAW_GAP: f64 = 2.5e-4;

/// Lines drawn on a surface are lifted off it by this fraction of the scene's radius, so the
/// depth test does not hide them in the surface's own triangles.
const LINE_LIFT_REL: f64 = 1e-3;

/// Where a period's centre is drawn: on the exact crease plus the deviation × `magnify`.
fn centre_drawn(p: &Period, magnify: f64) -> DVec3 {
    match p.exact {
        Some(e) if magnify > 1.0 => e + (p.row.p - e) * magnify,
        _ => p.row.p,
    }
}

/// Appends a segment from the last kept point to `p` when `p` is far enough from it (or
/// `force`), remembering which period was kept last.
fn keep(
    last: &mut Option<(usize, DVec3)>,
    k: usize,
    p: DVec3,
    gap: f64,
    force: bool,
    out: &mut Vec<LineSegment>,
    segment: impl Fn(DVec3, DVec3) -> LineSegment,
) {
    match *last {
        None => *last = Some((k, p)),
        Some((kk, _)) if kk == k => {}
        Some((_, q)) => {
            if force || (p - q).length() >= gap {
                out.push(segment(q, p));
                *last = Some((k, p));
            }
        }
    }
}

const PATH_COLOR: egui::Color32 = egui::Color32::from_rgb(120, 230, 120);
const EXACT_COLOR: egui::Color32 = egui::Color32::from_rgb(250, 250, 250);
const BACKGROUND: [f32; 4] = [0.075, 0.08, 0.095, 1.0];

/// State of the crease view.
pub struct CreaseView {
    id: ViewId,
    /// Display options.
    pub settings: ViewSettings,
    camera: OrbitCamera,
    origin: Origin,
    /// What the static layers were built from: surfaces, R', display options.
    built_for: Option<([SurfaceSpec; 2], f64, ViewSettings)>,
    /// Path layers: (generation, periods seen, magnification bits, exact shown, running).
    path_for: (u64, usize, u64, bool, bool),
    /// Last kept drawn point of the path and of the exact crease: (period, point).
    kept: [Option<(usize, DVec3)>; 2],
    path_cpu: Vec<LineSegment>,
    exact_cpu: Vec<LineSegment>,
    cutters_for: (u64, usize, bool),
    cutters_static: Vec<SphereInstance>,
    fit_requested: bool,
    scene_radius: f64,
}

impl CreaseView {
    /// A view drawing into GPU view `id`.
    #[must_use]
    pub fn new(id: ViewId) -> Self {
        Self {
            id,
            settings: ViewSettings::default(),
            camera: OrbitCamera::default(),
            origin: Origin::default(),
            built_for: None,
            path_for: (u64::MAX, 0, 1f64.to_bits(), true, true),
            kept: [None, None],
            path_cpu: Vec::new(),
            exact_cpu: Vec::new(),
            cutters_for: (u64::MAX, 0, true),
            cutters_static: Vec::new(),
            fit_requested: true,
            scene_radius: 100.0,
        }
    }

    /// Frames the scene at the next frame.
    pub fn request_fit(&mut self) {
        self.fit_requested = true;
    }

    /// Uploads the surfaces, offsets and iso-lines when the scene changed; returns whether it did.
    fn rebuild_static(&mut self, rs: &RenderState, scene: &Scene, compute: &Computation) -> bool {
        let Some(job) = &compute.job else { return false };
        let shown = ViewSettings {
            magnify: 1.0,
            show_cutters: true,
            show_exact: true,
            cutter_side_only: true,
            ..self.settings
        };
        let key = (scene.surfaces.clone(), job.r_eff_mm, shown);
        if self.built_for.as_ref() == Some(&key) {
            return false;
        }
        // Origin and size from the surfaces (sampled), so f32 stays precise near the part.
        let mut samples = Vec::new();
        for s in &job.surfaces {
            let d = s.domain();
            for i in 0..=16 {
                for j in 0..=16 {
                    let uv = glam::DVec2::new(
                        d.u.min + d.u.width() * f64::from(i) / 16.0,
                        d.v.min + d.v.width() * f64::from(j) / 16.0,
                    );
                    samples.push(s.point_at(uv));
                }
            }
        }
        let (center, radius) = bounds(samples).unwrap_or((DVec3::ZERO, 100.0));
        let origin_changed = self.built_for.as_ref().is_none_or(|(s, _, _)| *s != scene.surfaces);
        if origin_changed {
            self.origin = Origin(center);
            self.scene_radius = radius.max(1.0);
            // Positions of path layers are relative to the origin: rebuild them too.
            self.path_for.0 = u64::MAX;
            self.cutters_for.0 = u64::MAX;
        }
        let lift = LINE_LIFT_REL * self.scene_radius;
        let mut surfaces = Mesh::default();
        let mut offsets = Mesh::default();
        let mut lines = Vec::new();
        for (i, s) in job.surfaces.iter().enumerate() {
            let color = SURFACE_COLORS[i];
            surfaces.extend(&tessellate(s, self.origin, 72, 0.0, rgba(color, 1.0)));
            if self.settings.show_offsets {
                offsets.extend(&tessellate(s, self.origin, 56, job.r_eff_mm, rgba(color, 0.16)));
            }
            if self.settings.show_iso {
                let dark = rgba(color.gamma_multiply(0.45), 1.0);
                lines.extend(iso_lines(s, self.origin, 12, 96, lift, 1.2, dark));
            }
        }
        Renderer3d::with(rs, |r| {
            r.set_mesh(self.id, Layer::Surfaces, &surfaces);
            r.set_mesh(self.id, Layer::Offsets, &offsets);
            r.set_lines(self.id, Layer::StaticLines, &lines, 0);
        });
        self.built_for = Some(key);
        if self.fit_requested || origin_changed {
            self.camera.fit(Vec3::ZERO, self.scene_radius as f32);
            self.fit_requested = false;
        }
        true
    }

    fn centre_drawn(&self, p: &Period) -> DVec3 {
        centre_drawn(p, self.settings.magnify)
    }

    /// Uploads the path and the exact crease. Drawn points are kept only once they are
    /// `DRAW_GAP` of the scene's size from the last kept one (far below a pixel), so a path of
    /// 100 000 periods is drawn with a few thousand segments; the last point is always kept.
    /// The segments only grow while the path is computed, so only new ones are uploaded.
    fn update_path(&mut self, rs: &RenderState, compute: &Computation) {
        let n = compute.periods.len();
        let running = compute.running();
        let key = (compute.generation, n, self.settings.magnify.to_bits(), self.settings.show_exact, running);
        if key == self.path_for {
            return;
        }
        let same_run =
            self.path_for.0 == key.0 && self.path_for.2 == key.2 && self.path_for.3 == key.3 && self.path_for.1 <= n;
        if !same_run {
            self.path_cpu.clear();
            self.exact_cpu.clear();
            self.kept = [None, None];
        }
        let unchanged = (self.path_cpu.len(), self.exact_cpu.len());
        let from = if same_run { self.path_for.1 } else { 0 };
        let gap = DRAW_GAP * self.scene_radius;
        let (origin, magnify, show_exact) = (self.origin, self.settings.magnify, self.settings.show_exact);
        let path_color = rgba(PATH_COLOR, 1.0);
        let exact_color = rgba(EXACT_COLOR, 0.95);
        for (k, p) in compute.periods.iter().enumerate().skip(from) {
            let force = !running && k + 1 == n;
            let c = centre_drawn(p, magnify);
            keep(&mut self.kept[0], k, c, gap, force, &mut self.path_cpu, |a, b| {
                LineSegment::new(origin.local(a), origin.local(b), 3.0, path_color)
            });
            if let (true, Some(e)) = (show_exact, p.exact) {
                keep(&mut self.kept[1], k, e, gap, force, &mut self.exact_cpu, |a, b| {
                    LineSegment::new(origin.local(a), origin.local(b), 1.3, exact_color)
                });
            }
        }
        // The run ended after its last period was seen: close the drawn path at it.
        if !running && n > 0 {
            let p = &compute.periods[n - 1];
            keep(&mut self.kept[0], n - 1, centre_drawn(p, magnify), gap, true, &mut self.path_cpu, |a, b| {
                LineSegment::new(origin.local(a), origin.local(b), 3.0, path_color)
            });
            if let (true, Some(e)) = (show_exact, p.exact) {
                keep(&mut self.kept[1], n - 1, e, gap, true, &mut self.exact_cpu, |a, b| {
                    LineSegment::new(origin.local(a), origin.local(b), 1.3, exact_color)
                });
            }
        }
        let (path, exact) = (&self.path_cpu, &self.exact_cpu);
        Renderer3d::with(rs, |r| {
            r.set_lines(self.id, Layer::PathLines, path, unchanged.0);
            r.set_lines(self.id, Layer::ExactLines, exact, unchanged.1);
        });
        self.path_for = key;
    }

    fn update_cutters(&mut self, rs: &RenderState, scene: &Scene, compute: &Computation, playback: &Playback) {
        let n = compute.periods.len();
        let r_ball = scene.tool.radius as f32;
        let key = (compute.generation, n, self.settings.show_cutters);
        if key != self.cutters_for {
            let mut balls = Vec::new();
            if self.settings.show_cutters && n > 1 {
                let every = (n / 24).max(1);
                for p in compute.periods.iter().step_by(every) {
                    balls.push(SphereInstance {
                        center: self.origin.local(self.centre_drawn(p)),
                        radius: r_ball,
                        color: [0.8, 0.82, 0.86, 0.16],
                    });
                }
            }
            // The cutter at the playback position is appended every frame (below).
            self.cutters_for = key;
            self.cutters_static = balls;
        }
        let mut balls = self.cutters_static.clone();
        let mut markers = Vec::new();
        let mut dynamic = Vec::new();
        let k = (playback.k.floor() as usize).min(n.saturating_sub(1));
        if let (Some(p), Some(job)) = (compute.periods.get(k), &compute.job) {
            let c = self.centre_drawn(p);
            balls.push(SphereInstance {
                center: self.origin.local(c),
                radius: r_ball,
                color: [0.95, 0.95, 0.98, 0.55],
            });
            let dot = (0.035 * job.r_eff_mm).max(0.02) as f32;
            markers.push(SphereInstance { center: self.origin.local(c), radius: dot, color: [1.0, 1.0, 1.0, 1.0] });
            for i in 0..2 {
                let d = job.surfaces[i].derivatives_at(p.row.uv[i]);
                let color = rgba(SURFACE_COLORS[i], 1.0);
                markers.push(SphereInstance { center: self.origin.local(d.point), radius: dot * 1.4, color });
                // The contact normal runs from q_i to the centre (length R').
                dynamic.push(LineSegment::new(
                    self.origin.local(d.point),
                    self.origin.local(d.point + job.r_eff_mm * d.normal),
                    2.5,
                    color,
                ));
            }
            if let Some(next) = compute.periods.get(k + 1).or_else(|| compute.periods.get(k.saturating_sub(1))) {
                let t = (next.row.p - p.row.p).normalize_or_zero() * if k + 1 < n { 1.0 } else { -1.0 };
                dynamic.push(LineSegment::new(
                    self.origin.local(c),
                    self.origin.local(c + t * 2.0 * job.r_eff_mm),
                    2.5,
                    [1.0, 0.9, 0.3, 1.0],
                ));
            }
        }
        Renderer3d::with(rs, |r| {
            r.set_spheres(self.id, Layer::Cutters, &balls);
            r.set_spheres(self.id, Layer::Markers, &markers);
            r.set_lines(self.id, Layer::DynamicLines, &dynamic, 0);
        });
    }

    /// Draws the view into the remaining space of `ui`.
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        rs: Option<&RenderState>,
        scene: &Scene,
        compute: &Computation,
        playback: &Playback,
    ) {
        let (rect, response) =
            ui.allocate_exact_size(ui.available_size().max(egui::vec2(64.0, 64.0)), egui::Sense::click_and_drag());
        let Some(rs) = rs else {
            no_gpu(ui.painter(), rect);
            return;
        };
        let rebuilt = self.rebuild_static(rs, scene, compute);
        // A run that has just started has at most one period: no segment to draw yet. Its
        // first frame keeps the previous run's path and cutters (same scene, same origin)
        // instead of drawing the scene once more without them — during a slider drag every
        // step starts a run, and that empty frame cost SwiftShader a scene pass of its own
        // (docs/speed.md, round 8). The next frame, with the new run's periods, draws them.
        let starting = compute.running()
            && compute.periods.len() < 2
            && self.path_for.0 != compute.generation
            && self.path_for.0 != u64::MAX;
        if rebuilt || !starting {
            self.update_path(rs, compute);
            self.update_cutters(rs, scene, compute, playback);
        }

        camera_controls(&mut self.camera, ui, &response, rect, self.scene_radius as f32);

        paint_view(ui, rect, &self.camera, self.id, BACKGROUND, self.settings.cutter_side_only);
        self.overlays(ui, rect, scene, compute);
    }

    fn overlays(&mut self, ui: &mut egui::Ui, rect: egui::Rect, scene: &Scene, compute: &Computation) {
        let painter = ui.painter_at(rect);
        let font = egui::FontId::proportional(13.0);
        axis_triad(&painter, rect.left_bottom() + egui::vec2(46.0, -46.0), 32.0, &self.camera, &font);
        scale_bar(
            &painter,
            rect.right_bottom() + egui::vec2(-20.0, -24.0),
            f64::from(self.camera.mm_per_point(rect.height())),
            &font,
        );
        // Legend, top left.
        let mut y = rect.top() + 10.0;
        let x = rect.left() + 10.0;
        let mut entry = |color: egui::Color32, text: String| legend_entry(&painter, x, &mut y, color, text);
        for (i, s) in scene.surfaces.iter().enumerate() {
            entry(SURFACE_COLORS[i], format!("S{} {}", i + 1, s.type_name()));
        }
        let magnify = if self.settings.magnify > 1.0 {
            format!(" (deviation ×{:.0})", self.settings.magnify)
        } else {
            String::new()
        };
        entry(PATH_COLOR, format!("cutter centres, one per period{magnify}"));
        if self.settings.show_exact {
            entry(EXACT_COLOR, "exact crease (Newton)".to_owned());
        }
        entry(egui::Color32::from_gray(200), format!("ball R = {} mm", scene.tool.radius));
        let (ok, text) = crate::app::describe_outcome(compute);
        view_status(&painter, rect, ok, text, font);
        // Fit / reset buttons, under the status line.
        let buttons = egui::Rect::from_min_size(rect.right_top() + egui::vec2(-140.0, 32.0), egui::vec2(130.0, 24.0));
        fit_buttons(ui, buttons, &mut self.camera, self.scene_radius as f32, "Frame the whole scene (double-click)");
    }
}
