//! The 3D view of the simulation tab: the machined stock's top as a shaded height-field
//! mesh (one vertex per ray, normals from the height differences), coloured by signed
//! deviation from the design (blue gouge / green within the band / red stock left) or grey
//! by height without one; the program's tool-tip path over it (moves simulated bright, the
//! rest dim); the cutter at the current move; a legend in µm.

use eframe::egui;
use eframe::egui_wgpu::RenderState;
use glam::{DVec3, Vec3};

use super::work::Job;
use crate::app::overlay::{camera_controls, colour_bar, no_gpu, paint_view, view_frame};
use crate::render::geometry::Origin;
use crate::render::{Layer, LineSegment, Mesh, MeshVertex, OrbitCamera, Renderer3d, SphereInstance, ViewId};
use crate::simulate::MoveKind;

/// This view's GPU id.
pub const VIEW_ID: ViewId = 3;
const BACKGROUND: [f32; 4] = [0.07, 0.08, 0.1, 1.0];
/// Most path segments drawn (longer programs are drawn every n-th move).
const MAX_PATH_SEGMENTS: usize = 20_000;
/// Colour of unmachined rays.
const UNCUT: [f32; 4] = [0.62, 0.62, 0.6, 1.0];

/// Most vertices a side of the drawn stock (a 512 × 512 grid is drawn every second ray:
/// a software rasteriser draws a quarter of the triangles; the screen shows no more).
pub const MAX_DRAWN_SIDE: usize = 256;
/// Most vertices a side of a keyframe drawn while a run goes on (a quarter of the triangles
/// of [`MAX_DRAWN_SIDE`]): a frame of the 256² mesh costs SwiftShader 0.27–0.37 s of CPU,
/// taken from the worker machining on a 2-core machine; the exact stock, when it arrives,
/// is drawn at the full side.
pub const RUNNING_DRAWN_SIDE: usize = 128;

/// Colour of a deviation `d_mm` for a band of `band_mm`: blue (≤ −band) → green (0) → red
/// (≥ +band).
#[must_use]
pub fn deviation_color(d_mm: f64, band_mm: f64) -> [f32; 4] {
    let t = (d_mm / band_mm).clamp(-1.0, 1.0) as f32;
    let green = [0.2, 0.75, 0.3];
    let end = if t < 0.0 { [0.15, 0.35, 0.95] } else { [0.9, 0.2, 0.15] };
    let a = t.abs();
    [green[0] + (end[0] - green[0]) * a, green[1] + (end[1] - green[1]) * a, green[2] + (end[2] - green[2]) * a, 1.0]
}

/// What was last uploaded.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Built {
    map_generation: u64,
    band_um: f64,
    applied: usize,
    origin: [u64; 3],
    /// Most vertices a side drawn.
    side: usize,
}

/// The view's camera and upload state.
pub struct SimView {
    /// Camera.
    pub camera: OrbitCamera,
    origin: Origin,
    built: Option<Built>,
    radius: f32,
    /// Refit the camera at the next upload.
    pub refit: bool,
}

impl Default for SimView {
    fn default() -> Self {
        Self { camera: OrbitCamera::default(), origin: Origin(DVec3::ZERO), built: None, radius: 50.0, refit: true }
    }
}

impl SimView {
    /// Moves the camera's target to a point of the part (mm) and zooms in on it.
    pub fn go_to(&mut self, p: DVec3) {
        self.camera.target = self.origin.local_vec(p);
        self.camera.distance = (self.radius * 0.3).max(1.0);
    }

    fn upload(&mut self, rs: &RenderState, job: &Job, band_um: f64) {
        let (Some(p), Some((map, dev))) = (&job.prepared, job.current_map()) else {
            Renderer3d::with(rs, |r| r.clear_view(VIEW_ID));
            self.built = None;
            return;
        };
        let s = p.stock_mm;
        let origin = self.origin.0;
        let side = if dev.is_none() && job.computing() { RUNNING_DRAWN_SIDE } else { MAX_DRAWN_SIDE };
        let key = Built {
            side,
            map_generation: job.map_generation,
            band_um,
            applied: job.applied(),
            origin: [origin.x.to_bits(), origin.y.to_bits(), origin.z.to_bits()],
        };
        if self.built == Some(key) {
            return;
        }
        if self.refit {
            self.camera.fit(Vec3::ZERO, self.radius);
            self.refit = false;
        }
        let o = self.origin;
        // The measured map when it is current, else the latest keyframe's heights.
        let g = map.grid;
        let (z0, z1) = (s[2], s[5]);
        let band = band_um * crate::numerics::units::MM_PER_UM;
        // At most MAX_DRAWN_SIDE vertices a side: every `step`-th ray (and the last), each
        // coloured by the largest deviation (in size) of the rays it stands for, so a gouge
        // or crest narrower than the step still shows. The numbers are every ray's.
        let step = g.nx.max(g.ny).div_ceil(side).max(1);
        let picks = |n: usize| -> Vec<usize> {
            let mut v: Vec<usize> = (0..n).step_by(step).collect();
            if v.last().is_some_and(|&l| l + 1 < n) {
                v.push(n - 1);
            }
            v
        };
        let (cols, rows) = (picks(g.nx), picks(g.ny));
        let mut mesh = Mesh::default();
        mesh.vertices.reserve(cols.len() * rows.len());
        let h = |i: usize, j: usize| map.top_mm[j * g.nx + i];
        for &j in &rows {
            for &i in &cols {
                let k = j * g.nx + i;
                let (il, ir) = (i.saturating_sub(step), (i + step).min(g.nx - 1));
                let (jl, jr) = (j.saturating_sub(step), (j + step).min(g.ny - 1));
                let dx = (h(ir, j) - h(il, j)) / (((ir - il).max(1)) as f64 * g.pitch_mm);
                let dy = (h(i, jr) - h(i, jl)) / (((jr - jl).max(1)) as f64 * g.pitch_mm);
                let n = DVec3::new(-dx, -dy, 1.0).normalize_or(DVec3::Z);
                let block_dev = dev.and_then(|d| {
                    let mut worst: Option<f64> = None;
                    for jj in j..(j + step).min(g.ny) {
                        for ii in i..(i + step).min(g.nx) {
                            if let Some(x) = d[jj * g.nx + ii]
                                && worst.is_none_or(|w| x.abs() > w.abs())
                            {
                                worst = Some(x);
                            }
                        }
                    }
                    worst
                });
                let color = if !map.machined[k] && block_dev.is_none() {
                    UNCUT
                } else if let Some(d) = block_dev {
                    deviation_color(d, band)
                } else {
                    let t = ((map.top_mm[k] - z0) / (z1 - z0).max(f64::MIN_POSITIVE)).clamp(0.0, 1.0) as f32;
                    [0.35 + 0.5 * t, 0.38 + 0.5 * t, 0.45 + 0.45 * t, 1.0]
                };
                mesh.vertices.push(MeshVertex {
                    position: o.local(DVec3::new(g.x_mm(i), g.y_mm(j), map.top_mm[k])),
                    normal: [n.x as f32, n.y as f32, n.z as f32],
                    color,
                });
            }
        }
        let nc = cols.len() as u32;
        for j in 0..rows.len().saturating_sub(1) as u32 {
            for i in 0..nc.saturating_sub(1) {
                let a = j * nc + i;
                let b = a + 1;
                let c = a + nc;
                let d = c + 1;
                mesh.indices.extend_from_slice(&[a, b, d, a, d, c]);
            }
        }
        // The path: tips at move ends, simulated part bright.
        let applied = job.applied();
        let every = (p.tips.len() / MAX_PATH_SEGMENTS).max(1);
        let mut lines = Vec::new();
        let mut k = 0;
        while k + 1 < p.tips.len() {
            let next = (k + every).min(p.tips.len() - 1);
            let rapid = p.program.moves.get(k).is_some_and(|m| m.rapid);
            let color = match (k < applied, rapid) {
                (true, false) => [1.0, 0.85, 0.2, 1.0],
                (true, true) => [0.9, 0.5, 0.9, 0.8],
                (false, _) => [0.55, 0.6, 0.7, 0.45],
            };
            // From where move k starts: a program whose passes are not linked (a finishing
            // program leaves out the rapids between them) draws no line across the gap.
            let from = p.program.moves.get(k).map_or(p.tips[k], |m| crate::jobs::simulate_run::program::ends(m)[0]);
            lines.push(LineSegment::new(o.local(from), o.local(p.tips[next]), 1.5, color).with_depth_bias(0.002));
            k = next;
        }
        // The cutter at the current move's end (its centre for a ball: tip + R along the
        // axis), drawn as a translucent sphere of radius R.
        let mut spheres = Vec::new();
        if applied > 0
            && let Some(m) = p.program.moves.get(applied - 1)
        {
            let (tip, axis) = match m.kind {
                MoveKind::Line { to, .. } => (to, DVec3::Z),
                MoveKind::Joints { machine, to, .. } => {
                    let pose = machine.pose_from_joints(&to);
                    (pose.tip_in_workpiece, pose.axis_in_workpiece.normalize_or(DVec3::Z))
                }
            };
            let r = p.cutter.radius_mm;
            spheres.push(SphereInstance {
                center: o.local(tip + axis * r),
                radius: r as f32,
                color: [0.85, 0.85, 0.95, 0.35],
            });
        }
        Renderer3d::with(rs, |r| {
            r.set_mesh(VIEW_ID, Layer::Surfaces, &mesh);
            r.set_lines(VIEW_ID, Layer::PathLines, &lines, 0);
            r.set_spheres(VIEW_ID, Layer::Cutters, &spheres);
        });
        self.built = Some(key);
    }

    /// Draws the view into `rect`; returns the button clicked, if any.
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        rect: egui::Rect,
        rs: Option<&RenderState>,
        job: Option<&Job>,
        band_um: f64,
        legend: bool,
    ) {
        let response = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        // The frame of the drawing: the stock's centre is the origin.
        if let Some(p) = job.and_then(|j| j.prepared.as_ref()) {
            let s = p.stock_mm;
            self.origin = Origin(DVec3::new((s[0] + s[3]) * 0.5, (s[1] + s[4]) * 0.5, (s[2] + s[5]) * 0.5));
            self.radius = (0.5 * DVec3::new(s[3] - s[0], s[4] - s[1], s[5] - s[2]).length()) as f32;
        }
        let Some(rs) = rs else {
            no_gpu(ui.painter(), rect);
            return;
        };
        camera_controls(&mut self.camera, ui, &response, rect, self.radius);
        match job {
            Some(job) => self.upload(rs, job, band_um),
            None => {
                Renderer3d::with(rs, |r| r.clear_view(VIEW_ID));
                self.built = None;
            }
        }
        paint_view(ui, rect, &self.camera, VIEW_ID, BACKGROUND, false);
        if legend {
            colour_bar(
                &ui.painter_at(rect),
                rect.right_bottom() + egui::vec2(-8.0, -66.0),
                240.0,
                "signed deviation from the design (grey: not machined)",
                &[(0.0, format!("−{band_um} µm gouge")), (0.5, "0".to_owned()), (1.0, format!("+{band_um} µm left"))],
                |t| deviation_color(2.0 * t - 1.0, 1.0),
                &egui::FontId::proportional(13.0),
            );
        }
        view_frame(ui, rect, &mut self.camera, self.radius, "Frame the stock");
    }
}
