//! The "Fillet end mill" view: a finishing preset (`scene::finish::FINISH_PRESETS`)
//! machined with a fillet-end mill of the user's R and r at scallop height h and chord
//! tolerance E under one orientation strategy; its iso-scallop paths built path by path
//! within a time budget per frame (`fillet::IsoScallopSteps`, the same result as
//! `fillet::iso_scallop`), drawn over the surface coloured by strip width; the cutter at a
//! selected CC point; an inset of the normal section in a direction θ there (the surface's
//! osculating circle against the cutter's effective cutting curvature — the picture of
//! curvature matching); the comparison table on request, its rows background jobs
//! (`work::Job::advance`: threads natively, Web Workers in the browser) filled in as they
//! finish. The paths start where "Start from" says: an edge, or a curve picked by clicking
//! on the surface in the view; a click can instead select the CC point the cutter is drawn
//! at. Core and formulas: docs/fillet.md.

mod view;
pub mod work;

use eframe::egui;
use egui_plot::{Corner, Legend, Line, Plot, PlotPoints};

use super::budget::FRAME_BUDGET;
use super::panel::{FILLET_TITLE, FinishHandoff, Handoff, Panel, PanelContext, Payload, SIMULATION_TITLE};
use crate::fillet::{CcNode, effective_curvature};
use crate::scene::finish::FINISH_PRESETS;
use view::{Click, FilletView};
pub use work::{CORNER_RANGE_MM, RADIUS_RANGE_MM, SCALLOP_RANGE_UM, TOLERANCE_RANGE_MM};
use work::{Job, MAX_PICKS, Settings, StartChoice, StrategyChoice, TABLE_ROWS, table_row};

/// The cross-section plot treats a curvature gap between cutter and surface below this
/// (1/mm) as none: the scallop's half width √(2h/gap) is unbounded.
const SECTION_MIN_GAP_PER_MM: f64 = 1e-9;
/// Narrowest half width (mm) of the cross-section plot.
const SECTION_MIN_HALF_WIDTH_MM: f64 = 1e-3;

/// What a click in the 3D view does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ClickMode {
    /// Selects the CC point nearest on screen (the cutter and the inset follow).
    Select,
    /// Adds the surface point under the pointer to the start curve.
    Pick,
}

impl ClickMode {
    fn key(self) -> &'static str {
        match self {
            Self::Select => "select",
            Self::Pick => "pick",
        }
    }
}

/// Points of a section curve in the inset.
const SECTION_POINTS: usize = 121;

/// The panel.
pub struct FilletPanel {
    settings: Settings,
    job: Option<Job>,
    /// Why the settings give no job (the scene's message).
    refused: Option<String>,
    /// The settings refused last (not retried until they change).
    last_refused: Option<Settings>,
    job_id: u64,
    view: FilletView,
    /// Selected path and position along it (0 … 1).
    sel_path: usize,
    sel_along: f64,
    /// Direction of the inset's normal section from the feed direction (degrees).
    theta_deg: f64,
    /// Table requested for the next job as well.
    want_table: bool,
    /// The scallop slider's rectangle (status `ui.scallop_slider`, for end-to-end tests).
    scallop_rect: Option<egui::Rect>,
    /// The table button's rectangle (status `ui.table_button`).
    table_rect: Option<egui::Rect>,
    /// The "Simulate this program" button's rectangle (status `ui.fillet_simulate`).
    simulate_rect: Option<egui::Rect>,
    /// `set_option("simulate", "")`: hand the program over at the next frame, as the button.
    simulate_requested: bool,
    /// What a click in the view does.
    click_mode: ClickMode,
    /// The 3D view's rectangle (status `ui.fillet_view`).
    view_rect: Option<egui::Rect>,
    /// The click-mode radio buttons' rectangles (status `ui.fillet_select_mode`,
    /// `ui.fillet_pick_mode`).
    mode_rects: [Option<egui::Rect>; 2],
    /// What the last click did (status `last_click`).
    last_click: Option<String>,
}

impl Default for FilletPanel {
    fn default() -> Self {
        Self {
            settings: Settings::of_preset(0),
            scallop_rect: None,
            table_rect: None,
            simulate_rect: None,
            simulate_requested: false,
            click_mode: ClickMode::Select,
            view_rect: None,
            mode_rects: [None; 2],
            last_click: None,
            job: None,
            refused: None,
            last_refused: None,
            job_id: 0,
            view: FilletView::default(),
            sel_path: 0,
            sel_along: 0.5,
            theta_deg: 90.0,
            want_table: false,
        }
    }
}

fn parse_in(key: &str, value: &str, range: (f64, f64), unit: &str) -> Result<f64, String> {
    let v: f64 = value.trim().parse().map_err(|_| format!("{key} must be a number in {unit}, got \"{value}\""))?;
    if v.is_finite() && v >= range.0 && v <= range.1 {
        Ok(v)
    } else {
        Err(format!("{key} = {value} {unit} is outside {} … {} {unit}; give a value in that range", range.0, range.1))
    }
}

impl FilletPanel {
    /// Starts a new job when the settings changed (the old one is dropped: cancelled).
    fn sync(&mut self) {
        let s = &mut self.settings;
        s.corner_mm = s.corner_mm.min(s.radius_mm);
        if self.job.as_ref().is_some_and(|j| j.settings == self.settings) {
            return;
        }
        if self.job.is_none() && self.last_refused == Some(self.settings) {
            return;
        }
        self.job_id += 1;
        match Job::new(self.settings) {
            Ok(mut j) => {
                j.table_requested = self.want_table;
                if self.job.as_ref().is_none_or(|old| old.settings.preset != self.settings.preset) {
                    self.view.refit();
                }
                self.job = Some(j);
                self.refused = None;
                self.last_refused = None;
            }
            Err(e) => {
                self.job = None;
                self.refused = Some(e);
                self.last_refused = Some(self.settings);
            }
        }
    }

    fn selected(&self) -> Option<(usize, usize, &CcNode)> {
        let paths = self.job.as_ref()?.paths_so_far();
        let p = self.sel_path.min(paths.len().checked_sub(1)?);
        let nodes = &paths[p].nodes;
        let mut k = ((nodes.len().checked_sub(1)?) as f64 * self.sel_along.clamp(0.0, 1.0)).round() as usize;
        // A lead-in or lead-out row is not a CC point: the slider's ends select the path's
        // first and last CC points.
        if nodes.get(k)?.lead_out {
            k = if k == 0 { (k + 1).min(nodes.len() - 1) } else { k - 1 };
        }
        Some((p, k, nodes.get(k)?))
    }

    fn controls(&mut self, ui: &mut egui::Ui) {
        let s = &mut self.settings;
        ui.horizontal_wrapped(|ui| {
            ui.label("Part:");
            let name = |i: usize| FINISH_PRESETS.get(i).map_or("?", |p| p.id);
            let mut preset = s.preset;
            egui::ComboBox::from_id_salt("fillet_preset").selected_text(name(preset)).show_ui(ui, |ui| {
                for i in 0..FINISH_PRESETS.len() {
                    ui.selectable_value(&mut preset, i, name(i));
                }
            });
            if preset != s.preset {
                *s = Settings::of_preset(preset);
            }
        });
        ui.horizontal_wrapped(|ui| {
            ui.label("Start from:");
            let before = s.start;
            egui::ComboBox::from_id_salt("fillet_start").selected_text(s.start.label()).show_ui(ui, |ui| {
                for c in StartChoice::ALL {
                    ui.selectable_value(&mut s.start, c, c.label());
                }
            });
            if s.start != before && s.start == StartChoice::Picked {
                self.click_mode = ClickMode::Pick;
            }
        });
        ui.horizontal_wrapped(|ui| {
            ui.label("Click in the view:");
            let a = ui.radio_value(&mut self.click_mode, ClickMode::Select, "selects a CC point");
            let b = ui
                .radio_value(&mut self.click_mode, ClickMode::Pick, "adds a start-curve point")
                .on_hover_text("Each click on the surface adds a point; the paths start from the curve through them");
            self.mode_rects = [Some(a.rect), Some(b.rect)];
        });
        ui.horizontal_wrapped(|ui| {
            ui.label(format!("{} of {MAX_PICKS} points picked", s.n_picks));
            if ui.add_enabled(s.n_picks > 0, egui::Button::new("Clear")).clicked() {
                s.clear_picks();
            }
        });
        // In the side panel: a slider a line (egui's wrapped rows do not wrap a slider).
        ui.horizontal_wrapped(|ui| {
            ui.label("Orientation:");
            egui::ComboBox::from_id_salt("fillet_strategy").selected_text(s.strategy.label()).show_ui(ui, |ui| {
                for c in StrategyChoice::ALL {
                    ui.selectable_value(&mut s.strategy, c, c.label());
                }
            });
        });
        ui.vertical(|ui| {
            ui.add(
                egui::Slider::new(&mut s.radius_mm, RADIUS_RANGE_MM.0..=RADIUS_RANGE_MM.1)
                    .text("R (mm)")
                    .logarithmic(true),
            )
            .on_hover_text("Cutter radius");
            let r_max = s.radius_mm.min(CORNER_RANGE_MM.1);
            ui.add(egui::Slider::new(&mut s.corner_mm, CORNER_RANGE_MM.0..=r_max).text("r (mm)"))
                .on_hover_text("Corner radius: r = R is a ball, r = 0 a flat end mill");
            let r = ui.add(
                egui::Slider::new(&mut s.scallop_um, SCALLOP_RANGE_UM.0..=SCALLOP_RANGE_UM.1)
                    .text("scallop h (µm)")
                    .logarithmic(true),
            );
            self.scallop_rect = Some(r.rect);
            ui.add(
                egui::Slider::new(&mut s.tol_mm, TOLERANCE_RANGE_MM.0..=TOLERANCE_RANGE_MM.1)
                    .text("tolerance E (mm)")
                    .logarithmic(true),
            )
            .on_hover_text("Chord error of the forward step and tolerance of the gouge checks");
        });
    }

    fn summary(&mut self, ui: &mut egui::Ui) {
        let Some(job) = &self.job else {
            if let Some(e) = &self.refused {
                ui.colored_label(egui::Color32::from_rgb(240, 110, 100), e);
            }
            return;
        };
        ui.horizontal_wrapped(|ui| {
            if let Some(e) = &job.error {
                ui.colored_label(egui::Color32::from_rgb(240, 110, 100), e);
            } else if job.computing_paths() {
                ui.add(
                    egui::ProgressBar::new(job.progress() as f32)
                        .desired_width(200.0)
                        .text(format!("paths: {} so far", job.paths_so_far().len())),
                );
                ui.ctx().request_repaint();
            } else if let Some(r) = &job.result {
                let st = r.stats(job.finish.options.feed_mm_per_min);
                ui.label(format!(
                    "{} passes, {} CC points, {:.1} mm, strip {:.3} / {:.3} / {:.3} mm (min / mean / max), {:.2} min at {} mm/min, {} adjusted, {} refused; core {:.0} ms",
                    st.passes,
                    st.nodes,
                    st.length_mm,
                    st.strip_mm[0],
                    st.strip_mm[1],
                    st.strip_mm[2],
                    st.time_min,
                    job.finish.options.feed_mm_per_min,
                    st.adjusted,
                    r.refused.len(),
                    job.core_ms
                ));
                // Where the corrector could not bring the measured cusp under 1.10·h.
                if let Some(worst) = r.scallop_flags.iter().map(|f| f.scallop_mm).max_by(f64::total_cmp) {
                    ui.colored_label(
                        ui.visuals().warn_fg_color,
                        format!(
                            "The scallop stays above {:.2}·h at {} place(s), measured between neighbouring paths (the worst {:.1} µm, {:.2}·h{}): use a smaller max step or scallop height, or the matched orientation",
                            crate::fillet::paths::FLAG_ABOVE,
                            r.scallop_flags.len(),
                            worst * 1e3,
                            worst / job.finish.options.scallop_mm,
                            r.corrector_stopped_at.map_or_else(String::new, |k| format!(
                                "; the corrector stopped from path {k} on, its rebuilds past their share of the checks"
                            ))
                        ),
                    );
                }
            }
        });
    }

    /// "Simulate this program": hands the finished paths (strategy, iso-scallop layout) to
    /// the cutting simulation as the five-axis program `interpolab finish --gcode` writes,
    /// steps within the tab's tolerance E, with the finish surface as the design.
    fn simulate_button(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        let ready = self.job.as_ref().is_some_and(|j| j.result.is_some());
        let r = ui
            .add_enabled(ready, egui::Button::new("Simulate this program →"))
            .on_hover_text(
                "Machine these paths in the cutting simulation: the 5-axis program through the machine (steps within E), \
                 the fillet cutter, the finish surface as the design",
            )
            .on_disabled_hover_text("Wait for the paths to finish");
        self.simulate_rect = Some(r.rect);
        if !(r.clicked() || std::mem::take(&mut self.simulate_requested)) {
            return;
        }
        let Some(job) = &self.job else { return };
        let Some(set) = &job.result else {
            cx.error("The paths are still being built; simulate them once they are done.");
            return;
        };
        let program = crate::simulate::FinishProgram::of_paths(
            &job.finish.surface,
            &job.finish.cutter,
            &job.finish.machine,
            set,
            job.finish.options.chord_tol_mm,
        )
        .map_err(|e| e.to_string());
        match program.and_then(|p| Ok((p, job.settings.scene()?.to_json()))) {
            Ok((mut program, scene_json)) => {
                let preset = FINISH_PRESETS.get(job.settings.preset).map_or("finish", |p| p.id);
                program.label = format!("{preset}: {}", program.label);
                cx.handoff = Some(Handoff {
                    to: SIMULATION_TITLE,
                    options: vec![("source", "finish".to_owned())],
                    payload: Some(Payload::Finish(std::rc::Rc::new(FinishHandoff {
                        program,
                        scene_json,
                        scallop_mm: job.finish.options.scallop_mm,
                    }))),
                });
            }
            Err(e) => cx.error(format!("The program cannot be simulated: {e}")),
        }
    }

    fn selection(&mut self, ui: &mut egui::Ui) {
        let n_paths = self.job.as_ref().map_or(0, |j| j.paths_so_far().len());
        ui.horizontal_wrapped(|ui| {
            ui.label("CC point:");
            let mut p = self.sel_path.min(n_paths.saturating_sub(1));
            ui.add_enabled(n_paths > 1, egui::Slider::new(&mut p, 0..=n_paths.saturating_sub(1).max(1)).text("path"));
            self.sel_path = p;
            ui.add(egui::Slider::new(&mut self.sel_along, 0.0..=1.0).text("along").fixed_decimals(2));
            ui.add(egui::Slider::new(&mut self.theta_deg, 0.0..=180.0).text("θ (°) from the feed").fixed_decimals(0));
        });
    }

    /// A click in the view: a start-curve point or the selected CC point, as the mode says.
    fn click(&mut self, c: &Click) {
        let Some(job) = &self.job else { return };
        match self.click_mode {
            ClickMode::Pick => match self.view.pick_surface(job, c) {
                Some(uv) => {
                    use crate::geom::ParametricSurface;
                    let f = job.finish.surface.domain().to_file(uv);
                    if self.settings.pick([f.x, f.y]) {
                        // Picking a start curve means starting from it.
                        self.settings.start = StartChoice::Picked;
                        self.last_click = Some(format!("picked ({}, {})", f.x, f.y));
                        self.sync();
                    } else {
                        self.last_click = Some(format!("{MAX_PICKS} points are picked already; clear them first"));
                    }
                }
                None => self.last_click = Some("the click is not on the surface".to_owned()),
            },
            ClickMode::Select => match self.view.pick_node(job, c) {
                Some((p, k)) => {
                    let n = job.paths_so_far().get(p).map_or(1, |path| path.nodes.len());
                    self.sel_path = p;
                    self.sel_along = if n > 1 { k as f64 / (n - 1) as f64 } else { 0.0 };
                    self.last_click = Some(format!("selected path {p}, node {k}"));
                }
                None => self.last_click = Some("no CC point near the click".to_owned()),
            },
        }
    }

    fn inset(&self, ui: &mut egui::Ui, height: f32) {
        let (Some(job), Some((_, _, node))) = (&self.job, self.selected()) else {
            ui.label("The section appears when a path exists.");
            return;
        };
        let tool = job.finish.strategy.cutter_for(&job.finish.cutter);
        let theta = self.theta_deg.to_radians();
        let ks = node.frame.surface_form.at(theta);
        let kc = effective_curvature(&tool, &node.pose, theta);
        let h = job.finish.options.scallop_mm;
        let gap = kc - ks;
        let half = if gap > SECTION_MIN_GAP_PER_MM { (2.0 * h / gap).sqrt() } else { f64::INFINITY };
        let y_max = (1.6 * half).min(tool.radius_mm).max(SECTION_MIN_HALF_WIDTH_MM);
        // Height of a circle of curvature k through the origin, tangent to the plane.
        let arc = |k: f64, y: f64| {
            let ky = k * y;
            if ky.abs() < 1.0 { ky * y / (1.0 + (1.0 - ky * ky).sqrt()) } else { y.abs() * k.signum() }
        };
        let curve = |f: &dyn Fn(f64) -> f64| -> Vec<[f64; 2]> {
            (0..SECTION_POINTS)
                .map(|i| {
                    let y = -y_max + 2.0 * y_max * i as f64 / (SECTION_POINTS - 1) as f64;
                    [y, f(y) * 1e3]
                })
                .collect()
        };
        ui.label(format!(
            "Normal section at θ = {:.0}° (lead {:.1}°, tilt {:.1}°): surface k_s = {:.4} 1/mm, cutter κ_eff = {:.4} 1/mm, κ_eff − k_s = {:.4} 1/mm{}",
            self.theta_deg,
            node.pose.lead_rad().to_degrees(),
            node.pose.tilt_rad().to_degrees(),
            ks,
            kc,
            gap,
            if half.is_finite() { format!("; half strip at h: {half:.3} mm") } else { String::new() }
        ));
        Plot::new("fillet_section")
            .height(height)
            .legend(Legend::default().position(Corner::LeftTop))
            .x_axis_label("across, in direction θ (mm)")
            .y_axis_label("height along the normal (µm)")
            .show(ui, |pl| {
                pl.line(Line::new("surface (osculating circle)", PlotPoints::from(curve(&|y| arc(ks, y)))).width(1.8));
                pl.line(Line::new("cutter's effective profile", PlotPoints::from(curve(&|y| arc(kc, y)))).width(1.8));
                pl.line(
                    Line::new("surface + h", PlotPoints::from(curve(&|y| arc(ks, y) + h)))
                        .style(egui_plot::LineStyle::dashed_loose())
                        .width(1.0),
                );
            });
    }

    fn table(&mut self, ui: &mut egui::Ui) {
        ui.horizontal_wrapped(|ui| {
            let computing = self.job.as_ref().is_some_and(Job::computing_table);
            let has = self.job.as_ref().is_some_and(|j| j.table_requested);
            let r = ui
                .add_enabled(!has, egui::Button::new("Compute the comparison table"))
                .on_hover_text("Ten whole core runs (5 strategies × iso-scallop / iso-parametric), in the background");
            self.table_rect = Some(r.rect);
            if r.clicked() {
                self.want_table = true;
                if let Some(j) = &mut self.job {
                    j.table_requested = true;
                }
            }
            if computing {
                let done = self.job.as_ref().map_or(0, Job::rows_done);
                ui.add(
                    egui::ProgressBar::new(done as f32 / TABLE_ROWS as f32)
                        .desired_width(160.0)
                        .text(format!("{done} of {TABLE_ROWS} rows")),
                );
            }
            ui.label(if computing {
                "each row is a whole core run in the background; the view stays live and rows appear as they finish"
            } else {
                "each row is a whole core run (about as long as the paths above), so the table is computed on request"
            });
        });
        let Some(job) = &self.job else { return };
        if !job.table_requested {
            return;
        }
        egui::Grid::new("fillet_table").striped(true).num_columns(9).show(ui, |ui| {
            for h in [
                "strategy",
                "layout",
                "passes",
                "length (mm)",
                "strip min",
                "mean",
                "max (mm)",
                "time (min)",
                "wall (ms)",
            ] {
                ui.strong(h);
            }
            ui.end_row();
            for (k, row) in job.table.iter().enumerate() {
                let Some(row) = row else {
                    let (strategy, layout) = table_row(k);
                    ui.label(strategy.label());
                    ui.label(layout.name());
                    ui.weak("computing…");
                    ui.end_row();
                    continue;
                };
                ui.label(row.strategy.label());
                ui.label(row.layout.name());
                match &row.stats {
                    Ok(s) => {
                        ui.label(s.passes.to_string());
                        ui.label(format!("{:.1}", s.length_mm));
                        for w in s.strip_mm {
                            ui.label(format!("{w:.3}"));
                        }
                        ui.label(format!("{:.2}", s.time_min));
                    }
                    Err(e) => {
                        ui.label(e.to_string());
                        for _ in 0..5 {
                            ui.label("");
                        }
                    }
                }
                ui.label(format!("{:.0}", row.ms));
                ui.end_row();
            }
        });
    }
}

impl Panel for FilletPanel {
    fn title(&self) -> &'static str {
        FILLET_TITLE
    }

    fn paper(&self) -> Option<&'static str> {
        Some(super::papers::FIVE_AXIS_FINISHING)
    }

    fn controls(&mut self, ui: &mut egui::Ui, _cx: &mut PanelContext<'_>) {
        self.controls(ui);
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        self.sync();
        if let Some(j) = &mut self.job {
            // One path is the smallest step: a large surface may overshoot by one path.
            j.advance(FRAME_BUDGET);
            if j.computing_paths() {
                ui.ctx().request_repaint();
            } else if j.computing_table() {
                // The rows run elsewhere: look again soon, without drawing flat out.
                ui.ctx().request_repaint_after(super::jobs::POLL);
            }
        }
        self.sync();
        self.summary(ui);
        self.simulate_button(ui, cx);
        self.selection(ui);
        let avail = ui.available_size();
        let side = (avail.x * 0.36).clamp(260.0, 520.0);
        ui.horizontal_top(|ui| {
            let h = ui.available_height().max(200.0);
            let rect = egui::Rect::from_min_size(ui.cursor().min, egui::vec2((avail.x - side - 12.0).max(200.0), h));
            let mut view = std::mem::take(&mut self.view);
            let job = self.job.as_ref().map(|j| (j, self.job_id));
            let click = view.ui(ui, rect, cx.render_state, job, self.selected());
            self.view = view;
            self.view_rect = Some(rect);
            if let Some(c) = click {
                self.click(&c);
            }
            ui.vertical(|ui| {
                ui.set_width(side);
                egui::ScrollArea::vertical().id_salt("fillet_side").show(ui, |ui| {
                    self.inset(ui, 220.0);
                    ui.separator();
                    self.table(ui);
                });
            });
        });
    }

    fn status(&self) -> serde_json::Value {
        let s = &self.settings;
        let mut v = serde_json::json!({
            "preset": FINISH_PRESETS.get(s.preset).map(|p| p.id),
            "strategy": s.strategy.key(),
            "R_mm": s.radius_mm,
            "r_mm": s.corner_mm,
            "h_mm": s.scallop_um * crate::numerics::units::MM_PER_UM,
            "tol_mm": s.tol_mm,
            "error": self.refused,
            "start": s.start.key(),
            "picked": s.picked(),
            "click_mode": self.click_mode.key(),
            "last_click": self.last_click,
            "camera": {
                "target": self.view.camera.target.to_array(), "yaw": self.view.camera.yaw,
                "pitch": self.view.camera.pitch, "distance": self.view.camera.distance,
                "fov_y": self.view.camera.fov_y, "origin_mm": self.view.origin.0.to_array(),
            },
            "ui": super::widgets::rects_json(
                &[
                    self.scallop_rect.map(|r| ("scallop_slider", r)),
                    self.table_rect.map(|r| ("table_button", r)),
                    self.simulate_rect.map(|r| ("fillet_simulate", r)),
                    self.view_rect.map(|r| ("fillet_view", r)),
                    self.mode_rects[0].map(|r| ("fillet_select_mode", r)),
                    self.mode_rects[1].map(|r| ("fillet_pick_mode", r)),
                ]
                    .into_iter()
                    .flatten()
                    .collect::<Vec<_>>()
            ),
        });
        let Some(job) = &self.job else {
            v["computing"] = false.into();
            return v;
        };
        v["computing"] = (job.computing_paths() || job.computing_table()).into();
        v["computing_paths"] = job.computing_paths().into();
        v["progress"] = job.progress().into();
        v["paths_so_far"] = job.paths_so_far().len().into();
        v["core_ms"] = job.core_ms.into();
        v["longest_step_ms"] = job.longest_step_ms.into();
        if let Some(e) = &job.error {
            v["error"] = e.clone().into();
        }
        if let Some(r) = &job.result {
            let st = r.stats(job.finish.options.feed_mm_per_min);
            v["passes"] = st.passes.into();
            v["nodes"] = st.nodes.into();
            v["length_mm"] = st.length_mm.into();
            v["strip_mm"] = serde_json::json!({"min": st.strip_mm[0], "mean": st.strip_mm[1], "max": st.strip_mm[2]});
            v["scallop_mm"] = serde_json::json!({"mean": st.scallop_mm[0], "max": st.scallop_mm[1]});
            v["time_min"] = st.time_min.into();
            v["adjusted"] = st.adjusted.into();
            v["refused"] = r.refused.len().into();
            v["scallop_flags"] = r.scallop_flags.len().into();
            v["corrector_stopped_at_path"] = r.corrector_stopped_at.into();
            v["second_side"] = r.second_side.into();
        }
        if let Some((p, k, n)) = self.selected() {
            v["selected"] = serde_json::json!({
                "path": p, "node": k,
                "lead_deg": n.pose.lead_rad().to_degrees(), "tilt_deg": n.pose.tilt_rad().to_degrees(),
                "theta_deg": self.theta_deg,
                "k_surface_per_mm": n.frame.surface_form.at(self.theta_deg.to_radians()),
                "k_cutter_per_mm": effective_curvature(&job.finish.strategy.cutter_for(&job.finish.cutter), &n.pose, self.theta_deg.to_radians()),
            });
        }
        v["table_requested"] = job.table_requested.into();
        v["computing_table"] = job.computing_table().into();
        v["table_rows_done"] = job.rows_done().into();
        v["table_in_background"] = job.rows_in_background().into();
        v["table"] = job
            .table
            .iter()
            .flatten()
            .map(|r| match &r.stats {
                Ok(s) => serde_json::json!({
                    "strategy": r.strategy.key(), "layout": r.layout.name(), "passes": s.passes,
                    "length_mm": s.length_mm, "strip_mm": s.strip_mm, "time_min": s.time_min,
                }),
                Err(e) => {
                    serde_json::json!({"strategy": r.strategy.key(), "layout": r.layout.name(), "error": e.to_string()})
                }
            })
            .collect();
        v
    }

    fn set_option(&mut self, key: &str, value: &str) -> Result<(), String> {
        let s = &mut self.settings;
        match key {
            "preset" => {
                let i = FINISH_PRESETS
                    .iter()
                    .position(|p| p.id == value)
                    .or_else(|| value.parse::<usize>().ok().filter(|&i| i < FINISH_PRESETS.len()))
                    .ok_or_else(|| {
                        let ids: Vec<&str> = FINISH_PRESETS.iter().map(|p| p.id).collect();
                        format!("preset \"{value}\" is not one of {}", ids.join(", "))
                    })?;
                *s = Settings::of_preset(i);
            }
            "strategy" => {
                s.strategy = StrategyChoice::from_key(value).ok_or_else(|| {
                    format!("strategy \"{value}\" is not one of matched, lead5, lead10, principal, ball")
                })?;
            }
            "R" => s.radius_mm = parse_in("R", value, RADIUS_RANGE_MM, "mm")?,
            "r" => {
                let r = parse_in("r", value, CORNER_RANGE_MM, "mm")?;
                if r > s.radius_mm {
                    return Err(format!("r = {r} mm is above R = {} mm; give r ≤ R", s.radius_mm));
                }
                s.corner_mm = r;
            }
            "h" => {
                let r = (
                    SCALLOP_RANGE_UM.0 * crate::numerics::units::MM_PER_UM,
                    SCALLOP_RANGE_UM.1 * crate::numerics::units::MM_PER_UM,
                );
                s.scallop_um = parse_in("h", value, r, "mm")? * 1e3;
            }
            "E" => s.tol_mm = parse_in("E", value, TOLERANCE_RANGE_MM, "mm")?,
            "theta" => self.theta_deg = parse_in("theta", value, (0.0, 180.0), "degrees")?,
            "path" => {
                self.sel_path =
                    value.trim().parse().map_err(|_| format!("path must be a pass index, got \"{value}\""))?;
            }
            "along" => self.sel_along = parse_in("along", value, (0.0, 1.0), "(fraction)")?,
            "simulate" => self.simulate_requested = true,
            "start" => {
                s.start = StartChoice::from_key(value)
                    .ok_or_else(|| format!("start \"{value}\" is not one of first, u0, u1, v0, v1, picked"))?;
                if s.start == StartChoice::Picked {
                    self.click_mode = ClickMode::Pick;
                }
            }
            "pick" => {
                let nums: Vec<f64> = value.split(',').filter_map(|x| x.trim().parse().ok()).collect();
                let [u, v] = nums[..] else {
                    return Err(format!(
                        "pick must be \"u, v\" in the surface's parameters (file units), got \"{value}\""
                    ));
                };
                if !s.pick([u, v]) {
                    return Err(format!("{MAX_PICKS} points are picked already; clear them first (picks = clear)"));
                }
            }
            "picks" if value == "clear" => s.clear_picks(),
            "click_mode" => {
                self.click_mode = match value {
                    "select" => ClickMode::Select,
                    "pick" => ClickMode::Pick,
                    _ => return Err(format!("click_mode \"{value}\" is neither select nor pick")),
                };
            }
            "table" => {
                self.want_table = value == "true";
                if let Some(j) = &mut self.job {
                    j.table_requested = self.want_table;
                }
            }
            _ => {
                return Err(format!(
                    "this view has no option \"{key}\"; use preset, strategy, R, r, h, E (mm), theta (degrees), path, along, table, simulate, start, pick, picks, click_mode"
                ));
            }
        }
        self.sync();
        Ok(())
    }
}
