//! The fillet tab's 3D view: the surface shaded, the iso-scallop paths as lines coloured by
//! strip width (blue narrow → red wide, legend in mm), CC points whose orientation the gouge
//! checks adjusted as orange markers, and the cutter at the selected CC point as a line
//! drawing of its fillet-end edge (rings and generators) with its axis; the picked start
//! curve's points (magenta) and the curve the paths start from. A click (no drag) in the view
//! is handed back to the panel: [`FilletView::pick_surface`] turns it into a ray from the
//! camera ([`OrbitCamera::ray`]) and the surface point it meets (`geom::ray_hit`),
//! [`FilletView::pick_node`] into the CC node nearest on screen.

use eframe::egui;
use eframe::egui_wgpu::RenderState;
use glam::{DVec2, DVec3, Vec2, Vec3};

use super::work::Job;
use crate::app::overlay::{camera_controls, colour_bar, no_gpu, paint_view, view_frame};
use crate::fillet::CcNode;
use crate::geom::{Cutter, ParametricSurface, any_perpendicular, ray_hit};
use crate::render::geometry::{Origin, bounds, tessellate};
use crate::render::{Layer, LineSegment, OrbitCamera, Renderer3d, SphereInstance, ViewId};

/// This view's GPU id.
pub const VIEW_ID: ViewId = 4;
const BACKGROUND: [f32; 4] = [0.07, 0.08, 0.1, 1.0];
/// Surface samples a side.
const MESH_SIDE: usize = 64;
/// Segments of a ring of the cutter drawing.
const RING_SEGMENTS: usize = 48;
/// Cells a side of the grid a click's ray is tested against (then refined by Newton).
const PICK_GRID: usize = 96;
/// Farthest a CC node may appear from a click to be selected by it (points).
pub const PICK_RADIUS_POINTS: f32 = 14.0;
/// Colour of the picked points and the start curve.
const PICK_COLOR: [f32; 4] = [1.0, 0.3, 0.9, 1.0];

/// A click (press and release without a drag) in the view.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Click {
    /// Where, in normalised device coordinates ([`OrbitCamera::ndc_of`]).
    pub ndc: Vec2,
    /// The view's size (points).
    pub size: egui::Vec2,
}

impl Click {
    fn aspect(&self) -> f32 {
        self.size.x / self.size.y.max(1.0)
    }
}

/// Colour of a strip width `w` between `lo` and `hi` (mm): blue → green → red.
#[must_use]
pub fn strip_color(w: f64, lo: f64, hi: f64) -> [f32; 4] {
    let t = if hi > lo { ((w - lo) / (hi - lo)).clamp(0.0, 1.0) as f32 } else { 0.5 };
    if t < 0.5 {
        let a = t * 2.0;
        [0.15 + 0.05 * a, 0.35 + 0.45 * a, 0.95 - 0.65 * a, 1.0]
    } else {
        let a = (t - 0.5) * 2.0;
        [0.2 + 0.7 * a, 0.8 - 0.6 * a, 0.3 - 0.15 * a, 1.0]
    }
}

/// Strip width range of the paths (mm), `None` without nodes.
#[must_use]
pub fn strip_range(job: &Job) -> Option<(f64, f64)> {
    let mut r: Option<(f64, f64)> = None;
    for n in job.paths_so_far().iter().flat_map(|p| &p.nodes) {
        if n.strip_mm.is_finite() {
            r = Some(r.map_or((n.strip_mm, n.strip_mm), |(a, b)| (a.min(n.strip_mm), b.max(n.strip_mm))));
        }
    }
    r
}

/// The cutter's edge as line segments: rings of the corner torus and the flutes' cylinder,
/// eight generators, and the axis.
fn cutter_lines(o: Origin, cutter: &Cutter, tip: DVec3, axis: DVec3) -> Vec<LineSegment> {
    let a = axis.normalize_or(DVec3::Z);
    let e1 = any_perpendicular(a);
    let e2 = a.cross(e1);
    let big_r = cutter.radius_mm;
    let r = cutter.corner_radius_mm.min(big_r);
    let r0 = big_r - r;
    let flute = cutter.flute_length_mm;
    // Profile points (radius from the axis, height above the tip).
    let mut profile: Vec<(f64, f64)> = (0..=6)
        .map(|k| {
            let phi = std::f64::consts::FRAC_PI_2 * f64::from(k) / 6.0;
            (r0 + r * phi.sin(), r - r * phi.cos())
        })
        .collect();
    profile.push((big_r, flute.max(r)));
    let color = [0.9, 0.9, 1.0, 0.9];
    let at = |rad: f64, z: f64, t: f64| o.local(tip + a * z + (e1 * t.cos() + e2 * t.sin()) * rad);
    let mut lines = Vec::new();
    for &(rad, z) in &profile {
        for k in 0..RING_SEGMENTS {
            let t0 = std::f64::consts::TAU * k as f64 / RING_SEGMENTS as f64;
            let t1 = std::f64::consts::TAU * (k + 1) as f64 / RING_SEGMENTS as f64;
            lines.push(LineSegment::new(at(rad, z, t0), at(rad, z, t1), 1.2, color));
        }
    }
    for g in 0..8 {
        let t = std::f64::consts::TAU * f64::from(g) / 8.0;
        for w in profile.windows(2) {
            lines.push(LineSegment::new(at(w[0].0, w[0].1, t), at(w[1].0, w[1].1, t), 1.2, color));
        }
        lines.push(LineSegment::new(at(0.0, 0.0, t), at(r0, 0.0, t), 1.2, color));
    }
    lines.push(LineSegment::new(o.local(tip), o.local(tip + a * (flute + 2.0 * big_r)), 2.5, [1.0, 0.95, 0.3, 1.0]));
    lines
}

/// What was last uploaded.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Built {
    job_id: u64,
    paths: usize,
    done: bool,
    selected: Option<(usize, usize)>,
}

/// Camera and upload state.
pub struct FilletView {
    /// Camera.
    pub camera: OrbitCamera,
    /// The world point at the view's local origin (mm).
    pub origin: Origin,
    radius: f32,
    built: Option<Built>,
    refit: bool,
}

impl Default for FilletView {
    fn default() -> Self {
        Self { camera: OrbitCamera::default(), origin: Origin(DVec3::ZERO), radius: 50.0, built: None, refit: true }
    }
}

impl FilletView {
    /// Frames the next job's surface.
    pub fn refit(&mut self) {
        self.refit = true;
    }

    /// The surface point (parameters, internal units) a click's ray meets first, if any.
    #[must_use]
    pub fn pick_surface(&self, job: &Job, click: &Click) -> Option<DVec2> {
        let (o, d) = self.camera.ray(click.aspect(), click.ndc);
        ray_hit(&job.finish.surface, self.origin.0 + o.as_dvec3(), d.as_dvec3(), PICK_GRID).map(|h| h.uv)
    }

    /// The CC node (path, node) that appears nearest to a click, within
    /// [`PICK_RADIUS_POINTS`].
    #[must_use]
    pub fn pick_node(&self, job: &Job, click: &Click) -> Option<(usize, usize)> {
        let half = Vec2::new(click.size.x, click.size.y) * 0.5;
        let mut best: Option<(f32, usize, usize)> = None;
        for (p, path) in job.paths_so_far().iter().enumerate() {
            for (k, n) in path.nodes.iter().enumerate().filter(|(_, n)| !n.lead_out) {
                let Some(ndc) = self.camera.project(click.aspect(), self.origin.local_vec(n.frame.point)) else {
                    continue;
                };
                let dist = ((ndc - click.ndc) * half).length();
                if dist <= PICK_RADIUS_POINTS && best.is_none_or(|b| dist < b.0) {
                    best = Some((dist, p, k));
                }
            }
        }
        best.map(|(_, p, k)| (p, k))
    }

    fn upload(&mut self, rs: &RenderState, job: &Job, job_id: u64, selected: Option<(usize, usize, &CcNode)>) {
        let paths = job.paths_so_far();
        let key = Built {
            job_id,
            paths: paths.len(),
            done: !job.computing_paths(),
            selected: selected.map(|(p, n, _)| (p, n)),
        };
        if self.built == Some(key) {
            return;
        }
        let new_job = self.built.is_none_or(|b| b.job_id != job_id);
        let o = self.origin;
        if new_job {
            let mesh = tessellate(&job.finish.surface, o, MESH_SIDE, 0.0, [0.62, 0.64, 0.68, 1.0]);
            Renderer3d::with(rs, |r| r.set_mesh(VIEW_ID, Layer::Surfaces, &mesh));
        }
        let (lo, hi) = strip_range(job).unwrap_or((0.0, 1.0));
        let mut lines = Vec::new();
        let mut markers = Vec::new();
        let mark = (job.finish.cutter.radius_mm * 0.06).max(0.02) as f32;
        for p in paths {
            for w in p.nodes.windows(2) {
                let c = strip_color(0.5 * (w[0].strip_mm + w[1].strip_mm), lo, hi);
                lines.push(
                    LineSegment::new(o.local(w[0].frame.point), o.local(w[1].frame.point), 1.6, c)
                        .with_depth_bias(0.002),
                );
            }
            for n in p.nodes.iter().filter(|n| n.adjusted.is_some()) {
                markers.push(SphereInstance {
                    center: o.local(n.frame.point),
                    radius: mark,
                    color: [1.0, 0.55, 0.1, 1.0],
                });
            }
        }
        for r in job.result.as_ref().map_or(&[][..], |r| &r.refused[..]) {
            markers.push(SphereInstance { center: o.local(r.point), radius: mark, color: [0.9, 0.1, 0.1, 1.0] });
        }
        self.start_curve(job, &mut lines, &mut markers, mark);
        let mut tool = Vec::new();
        if let Some((_, _, n)) = selected {
            tool = cutter_lines(o, &job.finish.strategy.cutter_for(&job.finish.cutter), n.tip, n.axis);
            markers.push(SphereInstance {
                center: o.local(n.frame.point),
                radius: mark * 1.6,
                color: [1.0, 1.0, 0.3, 1.0],
            });
        }
        Renderer3d::with(rs, |r| {
            r.set_lines(VIEW_ID, Layer::PathLines, &lines, 0);
            r.set_lines(VIEW_ID, Layer::DynamicLines, &tool, 0);
            r.set_spheres(VIEW_ID, Layer::Markers, &markers);
        });
        self.built = Some(key);
    }

    /// The picked points as markers and, once there are 2, the curve the first path follows
    /// (the core's own polyline: sorted, continued to the edges).
    fn start_curve(&self, job: &Job, lines: &mut Vec<LineSegment>, markers: &mut Vec<SphereInstance>, mark: f32) {
        let o = self.origin;
        let picked = job.settings.picked();
        let pts: Vec<DVec2> =
            picked.iter().map(|p| crate::scene::params_from_file(&job.finish.surface, DVec2::from(*p))).collect();
        for &uv in &pts {
            markers.push(SphereInstance {
                center: o.local(job.finish.surface.point_at(uv)),
                radius: mark * 2.5,
                color: PICK_COLOR,
            });
        }
        if pts.len() < 2 {
            return;
        }
        let along = crate::fillet::paths::curve_along(&job.finish.surface, &pts, job.finish.options.direction);
        if let Ok(poly) = crate::fillet::paths::start_polyline(&job.finish.surface, &pts, along) {
            for w in poly.windows(2) {
                lines.push(
                    LineSegment::new(
                        o.local(job.finish.surface.point_at(w[0])),
                        o.local(job.finish.surface.point_at(w[1])),
                        2.4,
                        PICK_COLOR,
                    )
                    .with_depth_bias(0.004),
                );
            }
        }
    }

    /// Draws the view into `rect`; returns a click in it (press and release without a
    /// drag), for the panel to pick with.
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        rect: egui::Rect,
        rs: Option<&RenderState>,
        job: Option<(&Job, u64)>,
        selected: Option<(usize, usize, &CcNode)>,
    ) -> Option<Click> {
        let response = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        let click = response.clicked().then(|| response.interact_pointer_pos()).flatten().map(|p| Click {
            ndc: OrbitCamera::ndc_of(p.x - rect.left(), p.y - rect.top(), rect.width(), rect.height()),
            size: rect.size(),
        });
        if let Some((job, _)) = job {
            let d = job.finish.surface.domain();
            let pts = (0..=8).flat_map(|i| {
                (0..=8).map(move |j| {
                    let u = d.u.min + (d.u.max - d.u.min) * f64::from(i) / 8.0;
                    let v = d.v.min + (d.v.max - d.v.min) * f64::from(j) / 8.0;
                    (u, v)
                })
            });
            let pts: Vec<DVec3> = pts.map(|(u, v)| job.finish.surface.point_at(glam::DVec2::new(u, v))).collect();
            if let Some((c, r)) = bounds(pts) {
                self.origin = Origin(c);
                self.radius = r.max(1.0) as f32;
            }
            // Here, not at the upload: picking needs the fitted camera without a GPU too.
            if self.refit {
                self.camera.fit(Vec3::ZERO, self.radius);
                self.refit = false;
            }
        }
        let Some(rs) = rs else {
            no_gpu(ui.painter(), rect);
            return click;
        };
        camera_controls(&mut self.camera, ui, &response, rect, self.radius);
        match job {
            Some((job, id)) => self.upload(rs, job, id, selected),
            None => {
                Renderer3d::with(rs, |r| r.clear_view(VIEW_ID));
                self.built = None;
            }
        }
        paint_view(ui, rect, &self.camera, VIEW_ID, BACKGROUND, false);
        if let Some((lo, hi)) = job.and_then(|(j, _)| strip_range(j)) {
            colour_bar(
                &ui.painter_at(rect),
                rect.right_bottom() + egui::vec2(-8.0, -66.0),
                240.0,
                "strip width (orange: adjusted, red: refused)",
                &[(0.0, format!("{lo:.3} mm")), (1.0, format!("{hi:.3} mm"))],
                |t| strip_color(t, 0.0, 1.0),
                &egui::FontId::proportional(13.0),
            );
        }
        view_frame(ui, rect, &mut self.camera, self.radius, "Frame the surface");
        click
    }
}
