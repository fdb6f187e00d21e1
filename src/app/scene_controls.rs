//! The scene's controls, shared by every tab that shows the scene or its crease: the scene
//! picker (presets, open, save, share link), every input of the scene with its unit and the
//! interpolation method. Widgets edit the *draft* scene in [`SceneEditor`]; the app validates
//! it with the core and restarts the crease's computation.

use eframe::egui;

use super::ranges;
use super::widgets::{SURFACE_COLORS, error_frame, section};
use super::{fmt_len, is_seed000};
use crate::crease::{InterpOptions, Method};
use crate::scene::{Orientation, PRESETS, Scene, SceneError, SurfaceSpec};

/// The scene being edited and what the user asked of it this frame (the app acts on it after
/// the panels have drawn).
pub struct SceneEditor {
    /// The scene as the widgets edit it (may be invalid).
    pub draft: Scene,
    /// Why the draft is not applied, if it is invalid.
    pub error: Option<SceneError>,
    /// The crease's interpolation method and options.
    pub opts: InterpOptions,
    /// The preset the scene is, if it is one.
    pub preset: Option<usize>,
    /// Requests of this frame.
    pub asked: Asked,
}

/// What the user asked of the scene this frame.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Asked {
    /// Any value of the draft changed.
    pub scene_changed: bool,
    /// The interpolation options changed (method, exact feed).
    pub options_changed: bool,
    /// Open this preset.
    pub preset: Option<usize>,
    /// Open a scene file.
    pub open: bool,
    /// Save the scene.
    pub save: bool,
    /// Copy a share link.
    pub share: bool,
}

impl SceneEditor {
    /// An editor of `scene`.
    pub fn new(scene: &Scene) -> Self {
        Self {
            draft: scene.clone(),
            error: None,
            opts: InterpOptions::default(),
            preset: preset_of(scene),
            asked: Asked::default(),
        }
    }
}

/// The index of the preset equal to `scene`, if any.
pub fn preset_of(scene: &Scene) -> Option<usize> {
    PRESETS.iter().position(|p| Scene::from_json(p.json).ok().as_ref() == Some(scene))
}

/// Display title of preset `i` (its scene name).
pub fn preset_title(i: usize) -> String {
    Scene::from_json(PRESETS[i].json).map_or_else(|_| PRESETS[i].id.to_owned(), |s| s.name)
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
        ui.add(egui::DragValue::new(v).speed(0.05).range(min..=ranges::LENGTH_MAX_MM).suffix(" mm")).changed()
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

/// The scene picker: the presets, open, save and share link (their rectangles are published
/// as `open_button`, `save_button` and `share_button`).
fn picker(ui: &mut egui::Ui, ed: &mut SceneEditor, rects: &mut Vec<(&'static str, egui::Rect)>) {
    let label = ed.preset.map_or_else(|| "(custom scene)".to_owned(), preset_title);
    egui::ComboBox::from_id_salt("preset")
        .selected_text(label)
        .width(ui.available_width().min(300.0))
        .show_ui(ui, |ui| {
            for i in 0..PRESETS.len() {
                if ui.selectable_label(ed.preset == Some(i), preset_title(i)).clicked() {
                    ed.asked.preset = Some(i);
                }
            }
        })
        .response
        .on_hover_text("Example scenes (examples/*.json)");
    ui.horizontal_wrapped(|ui| {
        if super::platform::Platform::can_pick_files() {
            let open = ui.button("Open…").on_hover_text("Open a scene file (or drop one on the window)");
            rects.push(("open_button", open.rect));
            ed.asked.open |= open.clicked();
        }
        let save = ui.button("Save").on_hover_text("Download the current scene as JSON");
        rects.push(("save_button", save.rect));
        ed.asked.save |= save.clicked();
        let share = ui.button("Share link").on_hover_text("Copy a link that opens this exact scene");
        rects.push(("share_button", share.rect));
        ed.asked.share |= share.clicked();
    });
}

/// Draws the scene's controls: the picker, the draft's error, every input of the scene and
/// the interpolation method. `sense` is the unit sense of travel of the present run at its
/// start (for the Path section's "reverse"); the feed slider's rectangle is published as
/// `feed_slider`.
pub fn scene_controls(
    ui: &mut egui::Ui,
    ed: &mut SceneEditor,
    sense: Option<[f64; 3]>,
    rects: &mut Vec<(&'static str, egui::Rect)>,
) {
    ui.label(egui::RichText::new("Scene").heading());
    picker(ui, ed, rects);
    let mut c = false;
    let draft = &mut ed.draft;
    if let Some(e) = &ed.error {
        error_frame(ui, |ui| {
            ui.label(egui::RichText::new(format!("⚠ Not applied: {e}")).color(egui::Color32::WHITE));
            ui.label(
                egui::RichText::new("The last valid scene is still shown.").color(egui::Color32::LIGHT_GRAY).small(),
            );
        });
    }
    section(ui, "Motion", true, |ui| {
        let feed = slider(ui, &mut draft.motion.feed, ranges::FEED_MM_PER_MIN, " mm/min", "feed F", true);
        c |= feed.changed();
        rects.push(("feed_slider", feed.rect));
        c |= slider(ui, &mut draft.motion.period, ranges::PERIOD_MS, " ms", "period Ts", true).changed();
        let f = draft.feed_per_period_mm();
        ui.label(format!("feed per period f = F·Ts = {f:.5} mm"));
    });
    section(ui, "Tool", true, |ui| {
        c |= slider(ui, &mut draft.tool.radius, ranges::BALL_RADIUS_MM, " mm", "ball radius R", true).changed();
        c |= slider(ui, &mut draft.tool.allowance, ranges::ALLOWANCE_MM, " mm", "allowance C", false).changed();
        ui.label(format!("centre offset R' = R + C = {:.4} mm", draft.effective_radius_mm()));
    });
    section(ui, "Tolerance", true, |ui| {
        c |= slider(ui, &mut draft.tolerance.t1, ranges::SURFACE_TOL_MM, " mm", "T1 on S1", true).changed();
        c |= slider(ui, &mut draft.tolerance.t2, ranges::SURFACE_TOL_MM, " mm", "T2 on S2", true).changed();
        c |= slider(ui, &mut draft.tolerance.share, ranges::TOL_SHARE, "", "share b", false).changed();
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
            c |=
                ui.add(egui::DragValue::new(&mut draft.path.max_steps).range(ranges::MAX_PERIODS).speed(100)).changed();
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
        let opts = &mut ed.opts;
        let before = *opts;
        ui.radio_value(&mut opts.method, Method::Seed000, "the paper's: track, correct, re-solve (no iteration)");
        ui.radio_value(&mut opts.method, Method::Exact, "exact: Newton onto the crease (reference)");
        if is_seed000(opts) {
            ui.checkbox(&mut opts.exact_feed, "rescale each step to exactly f (eq. 2)");
        }
        ed.asked.options_changed |= *opts != before;
    });
    ed.asked.scene_changed |= c;
}
