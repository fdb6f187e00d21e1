//! The left panel: every input of the scene with its unit, the interpolation method and the
//! display options. Widgets edit a *draft* scene; the app validates it with the core.

use eframe::egui;

use super::view3d::ViewSettings;
use super::{fmt_len, is_seed000};
use crate::crease::{InterpOptions, Method};
use crate::scene::{Orientation, Scene, SceneError, SurfaceSpec};

/// What the user changed this frame.
#[derive(Clone, Copy, Debug, Default)]
pub struct ControlsOutput {
    /// Any scene value.
    pub scene_changed: bool,
    /// The interpolation options (method, exact feed).
    pub options_changed: bool,
    /// Where the feed slider is (published for end-to-end tests).
    pub feed_rect: Option<egui::Rect>,
}

fn section(ui: &mut egui::Ui, title: &str, open: bool, add: impl FnOnce(&mut egui::Ui)) {
    egui::CollapsingHeader::new(egui::RichText::new(title).strong()).default_open(open).show(ui, add);
}

fn slider(
    ui: &mut egui::Ui,
    value: &mut f64,
    range: std::ops::RangeInclusive<f64>,
    suffix: &str,
    text: &str,
    log: bool,
) -> egui::Response {
    ui.add(
        egui::Slider::new(value, range)
            .logarithmic(log)
            .suffix(suffix)
            .text(text)
            .clamping(egui::SliderClamping::Always),
    )
}

fn vec3(ui: &mut egui::Ui, label: &str, v: &mut [f64; 3]) -> bool {
    let mut changed = false;
    ui.horizontal(|ui| {
        ui.label(label);
        for (c, name) in v.iter_mut().zip(["x", "y", "z"]) {
            changed |= ui.add(egui::DragValue::new(c).speed(0.1).prefix(format!("{name} ")).suffix(" mm")).changed();
        }
    });
    changed
}

fn length(ui: &mut egui::Ui, label: &str, v: &mut f64, min: f64) -> bool {
    ui.horizontal(|ui| {
        ui.label(label);
        ui.add(egui::DragValue::new(v).speed(0.05).range(min..=1.0e4).suffix(" mm")).changed()
    })
    .inner
}

fn orientation(ui: &mut egui::Ui, id: (&str, usize), o: &mut Orientation) -> bool {
    let before = *o;
    ui.horizontal(|ui| {
        ui.label("cutter side");
        egui::ComboBox::from_id_salt(id).selected_text(o.as_str()).show_ui(ui, |ui| {
            ui.selectable_value(o, Orientation::Outward, "outward");
            ui.selectable_value(o, Orientation::Inward, "inward");
        });
    });
    *o != before
}

fn surface_ui(ui: &mut egui::Ui, i: usize, s: &mut SurfaceSpec) -> bool {
    let mut c = false;
    ui.label(egui::RichText::new(format!("S{} — {}", i + 1, s.type_name())).color(if i == 0 {
        SURFACE_COLORS[0]
    } else {
        SURFACE_COLORS[1]
    }));
    match s {
        SurfaceSpec::Plane { origin, .. } => c |= vec3(ui, "origin", origin),
        SurfaceSpec::Cylinder { origin, radius, normal, .. } => {
            c |= length(ui, "radius ρ", radius, 0.01);
            c |= vec3(ui, "axis point", origin);
            c |= orientation(ui, ("orient", i), normal);
        }
        SurfaceSpec::Sphere { center, radius, normal, .. } => {
            c |= length(ui, "radius ρ", radius, 0.01);
            c |= vec3(ui, "centre", center);
            c |= orientation(ui, ("orient", i), normal);
        }
        SurfaceSpec::Torus { center, major_radius, minor_radius, normal, .. } => {
            c |= length(ui, "major radius R0", major_radius, 0.02);
            c |= length(ui, "minor radius r0", minor_radius, 0.01);
            c |= vec3(ui, "centre", center);
            c |= orientation(ui, ("orient", i), normal);
        }
        SurfaceSpec::Nurbs { degree, points, weights, flip_normal, .. } => {
            let n_v = points.first().map_or(0, Vec::len);
            ui.label(format!(
                "degree {}×{}, {}×{} control points, {}",
                degree[0],
                degree[1],
                points.len(),
                n_v,
                if weights.is_some() { "rational" } else { "non-rational" }
            ));
            c |= ui.checkbox(flip_normal, "flip the normal (cutter on the other side)").changed();
        }
    }
    c
}

/// Display colours of S1 and S2 (also used by the 3D view).
pub const SURFACE_COLORS: [egui::Color32; 2] =
    [egui::Color32::from_rgb(105, 155, 230), egui::Color32::from_rgb(236, 160, 72)];

/// Draws the panel. `sense` is the unit sense of travel of the present run at its start
/// (for the Path section's "reverse").
pub fn controls(
    ui: &mut egui::Ui,
    draft: &mut Scene,
    error: Option<&SceneError>,
    opts: &mut InterpOptions,
    view: &mut ViewSettings,
    sense: Option<[f64; 3]>,
) -> ControlsOutput {
    let mut out = ControlsOutput::default();
    let mut c = false;
    if let Some(e) = error {
        egui::Frame::new().fill(egui::Color32::from_rgb(80, 24, 24)).inner_margin(6.0).corner_radius(4.0).show(
            ui,
            |ui| {
                ui.label(egui::RichText::new(format!("⚠ Not applied: {e}")).color(egui::Color32::WHITE));
                ui.label(
                    egui::RichText::new("The last valid scene is still shown.")
                        .color(egui::Color32::LIGHT_GRAY)
                        .small(),
                );
            },
        );
    }
    section(ui, "Motion", true, |ui| {
        let feed = slider(ui, &mut draft.motion.feed, 10.0..=60_000.0, " mm/min", "feed F", true);
        c |= feed.changed();
        out.feed_rect = Some(feed.rect);
        c |= slider(ui, &mut draft.motion.period, 0.1..=50.0, " ms", "period Ts", true).changed();
        let f = draft.feed_per_period_mm();
        ui.label(format!("feed per period f = F·Ts = {f:.5} mm"));
    });
    section(ui, "Tool", true, |ui| {
        c |= slider(ui, &mut draft.tool.radius, 0.2..=25.0, " mm", "ball radius R", true).changed();
        c |= slider(ui, &mut draft.tool.allowance, -1.0..=3.0, " mm", "allowance C", false).changed();
        ui.label(format!("centre offset R' = R + C = {:.4} mm", draft.effective_radius_mm()));
    });
    section(ui, "Tolerance", true, |ui| {
        c |= slider(ui, &mut draft.tolerance.t1, 1e-5..=0.5, " mm", "T1 on S1", true).changed();
        c |= slider(ui, &mut draft.tolerance.t2, 1e-5..=0.5, " mm", "T2 on S2", true).changed();
        c |= slider(ui, &mut draft.tolerance.share, 0.01..=1.0, "", "share b", false).changed();
        ui.label(format!(
            "interpolation may use b·T1 = {}, b·T2 = {}",
            fmt_len(draft.tolerance.share * draft.tolerance.t1),
            fmt_len(draft.tolerance.share * draft.tolerance.t2)
        ));
    });
    section(ui, "Surfaces", false, |ui| {
        for (i, s) in draft.surfaces.iter_mut().enumerate() {
            c |= surface_ui(ui, i, s);
            ui.add_space(4.0);
        }
    });
    section(ui, "Path", false, |ui| {
        c |= vec3(ui, "start", &mut draft.path.start);
        let mut has_end = draft.path.end.is_some();
        if ui
            .checkbox(&mut has_end, "stop near an end point")
            .on_hover_text(
                "path.end: the run stops at the crease point nearest it. Without it the run goes until the crease closes, leaves a surface's domain or max periods are run.",
            )
            .changed()
        {
            draft.path.end = has_end.then_some(draft.path.end.unwrap_or(draft.path.start));
            c = true;
        }
        if let Some(end) = &mut draft.path.end {
            c |= vec3(ui, "end", end);
        }
        ui.horizontal(|ui| {
            ui.label("sense of travel");
            ui.label(match draft.path.direction {
                None => "n1 × n2 (default)".to_owned(),
                Some(d) => format!("along [{:.3}, {:.3}, {:.3}]", d[0], d[1], d[2]),
            });
        });
        ui.horizontal(|ui| {
            let current = draft.path.direction.or(sense);
            let reverse = ui
                .add_enabled(current.is_some(), egui::Button::new("reverse"))
                .on_hover_text("Sets path.direction against the present sense of travel at the start");
            if reverse.clicked()
                && let Some(d) = current
            {
                draft.path.direction = Some(crate::crease::reversed_direction(d.into()));
                c = true;
            }
            if draft.path.direction.is_some()
                && ui.button("n1 × n2").on_hover_text("Removes path.direction: the sense of n1 × n2").clicked()
            {
                draft.path.direction = None;
                c = true;
            }
        });
        ui.horizontal(|ui| {
            ui.label("max periods");
            c |= ui.add(egui::DragValue::new(&mut draft.path.max_steps).range(1..=2_000_000).speed(100)).changed();
        });
        let mut name = draft.name.clone();
        ui.horizontal(|ui| {
            ui.label("name");
            if ui.text_edit_singleline(&mut name).changed() {
                draft.name = name;
                c = true;
            }
        });
    });
    section(ui, "Interpolation", true, |ui| {
        let before = *opts;
        ui.radio_value(&mut opts.method, Method::Seed000, "seed 000: track, correct, re-solve (no iteration)");
        ui.radio_value(&mut opts.method, Method::Exact, "exact: Newton onto the crease (reference)");
        if is_seed000(opts) {
            ui.checkbox(&mut opts.exact_feed, "rescale each step to exactly f (eq. 2)");
        }
        out.options_changed = *opts != before;
    });
    section(ui, "Display", true, |ui| {
        ui.checkbox(&mut view.cutter_side_only, "surfaces from the cutter side only");
        ui.checkbox(&mut view.show_offsets, "offset surfaces (translucent)");
        ui.checkbox(&mut view.show_iso, "iso-parameter lines");
        ui.checkbox(&mut view.show_cutters, "ball cutters along the path");
        ui.checkbox(&mut view.show_exact, "exact crease");
        ui.add(
            egui::Slider::new(&mut view.magnify, 1.0..=1.0e6)
                .logarithmic(true)
                .text("× deviation from the exact crease"),
        );
    });
    out.scene_changed = c;
    out
}
