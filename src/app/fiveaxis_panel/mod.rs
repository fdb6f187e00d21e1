//! The five-axis view (seed 002): choose the path (the paper's Example 1, the crease of the
//! current scene, the NACA blade of its Table 1), the machine and the tool-axis rule, move
//! the tolerance E, and see the blocks the step selection chooses — the tool axes, the
//! programmed chords, the swept tool coloured by the ball's signed error — with the joints
//! over the path, every segment's δ = δt + δn against ±E, and the iterations of every root
//! method at this E. Example 1 has a before/after switch: the single gouging block, then the
//! inserted steps.
//!
//! The work runs between frames within a time budget ([`work::Plan::advance`]); while a new
//! plan is computed the last complete one stays on screen.

mod controls;
mod overlay;
mod plots;
mod text;
mod view;
mod work;

use std::rc::Rc;

use eframe::egui;
use web_time::Duration;

use super::budget::FRAME_BUDGET;
use super::panel::{CreaseProblem, Handoff, Panel, PanelContext, SIMULATION_TITLE, SceneCrease};
use super::ranges;
use super::widgets::{rects_json, tolerance_option};
use crate::chords::RootMethod;
use crate::crease::CreaseCurve;
use crate::fiveaxis::{Machine, MachineKind, ToolAxisRule};
use crate::scene::{MachineSpec, Scene, ToolAxisSpec, build_machine, build_tool_axis};
use view::{Display, FiveAxisView};
use work::{Design, Plan, Source};

/// How the tool axis is chosen (the editable form of [`ToolAxisRule`]).
#[derive(Clone, Copy, Debug, PartialEq)]
struct RuleEdit {
    kind: RuleKind,
    lead_deg: f64,
    tilt_deg: f64,
    vector: [f64; 3],
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum RuleKind {
    Bisector,
    Normal1,
    Fixed,
}

impl Default for RuleEdit {
    fn default() -> Self {
        Self { kind: RuleKind::Bisector, lead_deg: 0.0, tilt_deg: 0.0, vector: [0.0, 0.0, 1.0] }
    }
}

impl RuleEdit {
    fn from_rule(r: ToolAxisRule) -> Self {
        match r {
            ToolAxisRule::Normal1 { lead_rad, tilt_rad } => Self {
                kind: RuleKind::Normal1,
                lead_deg: lead_rad.to_degrees(),
                tilt_deg: tilt_rad.to_degrees(),
                ..Self::default()
            },
            ToolAxisRule::Fixed { axis } => Self { kind: RuleKind::Fixed, vector: axis.to_array(), ..Self::default() },
            ToolAxisRule::Bisector | ToolAxisRule::Interpolated { .. } => Self::default(),
        }
    }

    fn rule(&self) -> ToolAxisRule {
        match self.kind {
            RuleKind::Bisector => ToolAxisRule::Bisector,
            RuleKind::Normal1 => {
                ToolAxisRule::Normal1 { lead_rad: self.lead_deg.to_radians(), tilt_rad: self.tilt_deg.to_radians() }
            }
            RuleKind::Fixed => ToolAxisRule::Fixed { axis: glam::DVec3::from_array(self.vector) },
        }
    }
}

/// What the source's defaults were taken from (to reset machine and rule when it changes).
type DefaultsKey = (Source, Option<MachineSpec>, Option<ToolAxisSpec>);

/// The five-axis panel.
pub struct FiveAxisPanel {
    source: Source,
    before: bool,
    machine: Machine,
    rule: RuleEdit,
    tol_mm: f64,
    method: RootMethod,
    bound_tip: bool,
    display: Display,
    selected: usize,
    defaults_for: Option<DefaultsKey>,
    crease: SceneCrease,
    design: Option<Rc<Design>>,
    design_error: Option<String>,
    waiting: Option<String>,
    plan: Option<Plan>,
    previous: Option<Plan>,
    serial: u64,
    view: FiveAxisView,
    machine_note: Option<String>,
    surface_names: [&'static str; 2],
    /// Rectangles of key widgets this frame (points), published in the status.
    rects: Vec<(&'static str, egui::Rect)>,
    /// The scene computation's generation seen last.
    generation: u64,
    /// "Simulate this program" asked for by `set_option` (handed over in the next frame).
    simulate_requested: bool,
    /// The scene's feed `motion.feed` (mm/min), for the time of the crease's plan.
    scene_feed: f64,
}

impl Default for FiveAxisPanel {
    fn default() -> Self {
        Self {
            source: Source::Example1,
            before: true,
            machine: Machine::default(),
            rule: RuleEdit::default(),
            tol_mm: 0.01,
            method: RootMethod::Secant,
            bound_tip: false,
            display: Display::default(),
            selected: 0,
            defaults_for: None,
            crease: SceneCrease::default(),
            design: None,
            design_error: None,
            waiting: None,
            plan: None,
            previous: None,
            serial: 0,
            view: FiveAxisView::default(),
            machine_note: None,
            surface_names: ["", ""],
            rects: Vec::new(),
            generation: 0,
            simulate_requested: false,
            scene_feed: crate::plan::steps::DEFAULT_FEED_MM_PER_MIN,
        }
    }
}

fn source_id(s: Source) -> &'static str {
    match s {
        Source::Example1 => "example1",
        Source::Scene => "scene",
        Source::Blade => "naca2412",
    }
}

impl FiveAxisPanel {
    /// Takes the machine and rule of the source (the scene's keys for its crease) when the
    /// source or the scene's keys change.
    fn sync_defaults(&mut self, scene: &Scene) {
        let key: DefaultsKey = match self.source {
            Source::Scene => (Source::Scene, scene.machine, scene.tool_axis),
            s => (s, None, None),
        };
        if self.defaults_for.as_ref() == Some(&key) {
            return;
        }
        self.defaults_for = Some(key);
        self.reset_machine_and_rule(scene);
    }

    fn reset_machine_and_rule(&mut self, scene: &Scene) {
        self.machine_note = None;
        match self.source {
            Source::Example1 => {
                self.machine = crate::fiveaxis::example1().machine;
                self.rule = RuleEdit::default();
                self.tol_mm = crate::fiveaxis::example1().tol_mm;
            }
            Source::Blade => {
                let (m, r) = work::blade_defaults();
                self.machine = m;
                self.rule = RuleEdit::from_rule(r);
            }
            Source::Scene => {
                self.machine = scene.machine.as_ref().map(build_machine).unwrap_or_default();
                if scene.machine.is_none() {
                    self.machine_note = Some("the scene has no \"machine\": table-ac through the origin".into());
                }
                self.rule = RuleEdit::from_rule(
                    scene.tool_axis.as_ref().and_then(|t| build_tool_axis(t).ok()).unwrap_or(ToolAxisRule::Bisector),
                );
            }
        }
    }

    /// The scene's crease as a design curve, once its computation has finished.
    fn crease_curve(&mut self, cx: &PanelContext<'_>) -> Option<Rc<CreaseCurve>> {
        match self.crease.get(cx.compute) {
            Ok(curve) => {
                self.waiting = None;
                Some(curve)
            }
            Err(CreaseProblem::Waiting(w)) => {
                self.waiting = Some(w);
                None
            }
            Err(CreaseProblem::Failed(e)) => {
                self.waiting = None;
                self.design_error = Some(format!("{e}; choose Example 1 or the blade, or change the scene."));
                None
            }
        }
    }

    fn inputs(&self, generation: u64) -> work::Inputs {
        let rule = if self.source == Source::Example1 { ToolAxisRule::Bisector } else { self.rule.rule() };
        work::Inputs {
            source: self.source,
            generation: if self.source == Source::Scene { generation } else { 0 },
            machine: self.machine,
            rule,
            tol_mm: self.tol_mm,
            method: self.method,
            before: self.source == Source::Example1 && self.before,
            bound_tip: self.bound_tip,
            feed_mm_per_min: self.feed().0,
        }
    }

    /// The feed of the plans' time (mm/min) and whether it is the default (the built-in paths
    /// have no feed of their own).
    fn feed(&self) -> (f64, bool) {
        if self.source == Source::Scene {
            (self.scene_feed, false)
        } else {
            (crate::plan::steps::DEFAULT_FEED_MM_PER_MIN, true)
        }
    }

    /// Brings design and plan up to date with the inputs, then computes within the budget.
    fn update(&mut self, cx: &PanelContext<'_>, budget: Duration) -> bool {
        if self.source != Source::Scene {
            self.waiting = None;
        }
        let generation = cx.compute.generation;
        self.generation = generation;
        self.scene_feed = cx.scene.motion.feed;
        let inputs = self.inputs(generation);
        let key = (inputs.source, inputs.generation, inputs.rule);
        if self.design.as_ref().is_none_or(|d| d.key != key) {
            self.design_error = None;
            let crease = if self.source == Source::Scene { self.crease_curve(cx) } else { None };
            if self.source == Source::Scene && crease.is_none() {
                self.design = None;
                self.plan = None;
                self.previous = None;
                return false;
            }
            let source_changed = self.design.as_ref().is_none_or(|d| d.key.0 != key.0 || d.key.1 != key.1);
            match work::build_design(inputs.source, inputs.generation, inputs.rule, crease.as_deref()) {
                Ok(d) => self.design = Some(Rc::new(d)),
                Err(e) => {
                    self.design = None;
                    self.design_error = Some(format!("{e}; change the tool-axis rule or the source."));
                }
            }
            self.plan = None;
            self.previous = None;
            if source_changed {
                self.view.request_fit();
                self.selected = 0;
            }
        }
        let Some(design) = self.design.clone() else {
            return false;
        };
        if self.plan.as_ref().is_none_or(|p| p.inputs != inputs) {
            let old = self.plan.take();
            self.serial += 1;
            self.plan = Some(Plan::new(inputs, design.clone(), self.serial, old.as_ref()));
            if let Some(old) = old
                && old.shown_complete()
                && old.design.key == design.key
            {
                self.previous = Some(old);
            }
        }
        let Some(plan) = self.plan.as_mut() else {
            return false;
        };
        plan.advance(budget);
        if plan.shown_complete() {
            self.previous = None;
        }
        !plan.finished()
    }

    fn shown(&self) -> Option<&Plan> {
        match (&self.plan, &self.previous) {
            (Some(p), Some(prev)) if !p.shown_complete() => Some(prev),
            (Some(p), _) => Some(p),
            (None, prev) => prev.as_ref(),
        }
    }
}

impl FiveAxisPanel {
    /// The plans' time for the status: machine, feed, and the seconds (`null` until computed
    /// or where it failed; `before_s` only for Example 1).
    fn times_json(&self) -> serde_json::Value {
        let (feed, default) = self.feed();
        let times = self.plan.as_ref().and_then(|p| p.times.as_ref());
        let secs =
            |r: Option<&Result<crate::plan::StepsTime, String>>| r.and_then(|r| r.as_ref().ok()).map(|t| t.cycle_s);
        let error = times
            .and_then(|t| t.before.iter().chain([&t.after]).find_map(|r| r.as_ref().err().cloned()))
            .unwrap_or_default();
        serde_json::json!({
            "machine": self.machine.kind.as_str(),
            "feed_mm_per_min": feed,
            "feed_default": default,
            "before_s": secs(times.and_then(|t| t.before.as_ref())),
            "after_s": secs(times.map(|t| &t.after)),
            "error": error,
        })
    }
}

impl Panel for FiveAxisPanel {
    fn title(&self) -> &'static str {
        "5-axis steps"
    }

    fn paper(&self) -> Option<&'static str> {
        Some(super::papers::FIVE_AXIS)
    }

    fn controls(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        self.rects.clear();
        self.sync_defaults(cx.scene);
        self.inputs_ui(ui, cx.scene);
        let r = ui
            .add_enabled(self.source == Source::Scene, egui::Button::new("Simulate this program →"))
            .on_hover_text("Machine the scene's tool steps (its machine and tool-axis rule, 0.01 mm) in the Cutting simulation tab")
            .on_disabled_hover_text("The Cutting simulation runs the scene's steps: choose the scene's crease as the path");
        self.rects.push(("fa_simulate", r.rect));
        self.simulate_requested |= r.clicked();
        if self.source == Source::Scene {
            ui.separator();
            cx.scene_controls(ui);
        }
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        self.sync_defaults(cx.scene);
        self.surface_names = [cx.scene.surfaces[0].type_name(), cx.scene.surfaces[1].type_name()];
        if self.update(cx, FRAME_BUDGET) {
            ui.ctx().request_repaint();
        }
        if self.source == Source::Scene && self.waiting.is_some() {
            ui.ctx().request_repaint();
        }
        let simulate = std::mem::take(&mut self.simulate_requested) && self.source == Source::Scene;
        egui::Panel::right("fa_results").resizable(true).default_size(330.0).min_size(260.0).max_size(520.0).show(
            ui,
            |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| self.results(ui));
            },
        );
        if simulate {
            cx.handoff =
                Some(Handoff { to: SIMULATION_TITLE, options: vec![("source", "steps".to_owned())], payload: None });
        }
        egui::Panel::bottom("fa_plots").resizable(true).default_size(240.0).min_size(140.0).show(ui, |ui| {
            let Some(plan) = self.shown() else {
                ui.label("No plan yet.");
                return;
            };
            let unit = plan.design.s_unit;
            let selected = Some(self.selected);
            ui.columns(2, |cols| {
                plots::joints_plot(&mut cols[0], plan, unit, selected);
                plots::errors_plot(&mut cols[1], plan, unit, selected);
            });
        });
        if self.display.auto_magnify
            && let Some(plan) = self.shown()
        {
            self.display.magnify = self.view.auto_magnify(plan);
        }
        egui::CentralPanel::no_frame().show(ui, |ui| {
            let design = self.design.clone();
            let display = self.display;
            let selected = Some(self.selected);
            let scale = self.tol_mm;
            let mut view = std::mem::take(&mut self.view);
            let rect =
                view.ui(ui, cx.render_state, design.as_deref(), self.shown(), &display, selected, scale, |p, r, at| {
                    self.overlay(p, r, at);
                });
            self.view = view;
            self.rects.push(("view", rect));
        });
    }

    fn set_option(&mut self, key: &str, value: &str) -> Result<(), String> {
        let number = || value.parse::<f64>().map_err(|_| format!("{key}: \"{value}\" is not a number"));
        match key {
            "source" => {
                self.source = [Source::Example1, Source::Scene, Source::Blade]
                    .into_iter()
                    .find(|s| source_id(*s) == value)
                    .ok_or_else(|| format!("source: \"{value}\"; give example1, scene or naca2412"))?;
            }
            "before" => self.before = value == "true",
            // As the "Simulate this program" button: handed over in the next frame.
            "simulate" => {
                if self.source != Source::Scene {
                    return Err(
                        "simulate: the Cutting simulation runs the scene's steps; set source scene first".to_owned()
                    );
                }
                self.simulate_requested = true;
            }
            "tol_mm" => self.tol_mm = tolerance_option(key, value, &ranges::FIVEAXIS_TOL_MM)?,
            "bound_tip" => self.bound_tip = value == "true",
            "method" => {
                self.method = RootMethod::from_name(value).ok_or_else(|| {
                    format!("method: \"{value}\"; give bisection, golden, secant, illinois or anderson-bjorck")
                })?;
            }
            "machine" => {
                self.machine.kind = MachineKind::from_name(value)
                    .ok_or_else(|| format!("machine: \"{value}\" is not a machine kind"))?;
                if self.machine.kind.uses_tool_length() && self.machine.tool_length_mm <= 0.0 {
                    self.machine.tool_length_mm = 150.0;
                }
            }
            "segment" => self.selected = (number()? as usize).saturating_sub(1),
            "tilt_travel_deg" => {
                let t = number()?;
                if !(t > 0.0 && t <= 360.0) {
                    return Err(format!("tilt_travel_deg: {t}; give the travel ±t of the tilting axis, 0 < t ≤ 360"));
                }
                self.machine.limits_rad[0] = Some([-t.to_radians(), t.to_radians()]);
            }
            _ => {
                return Err(format!(
                    "no option \"{key}\"; give source, before, tol_mm, method, bound_tip, machine, tilt_travel_deg or segment"
                ));
            }
        }
        Ok(())
    }

    fn status(&self) -> serde_json::Value {
        let plan = self.shown();
        let compare: serde_json::Map<String, serde_json::Value> = self
            .plan
            .as_ref()
            .map(|p| {
                RootMethod::ALL
                    .iter()
                    .zip(&p.compare)
                    .map(|(m, r)| {
                        let v = match r {
                            work::CompareRow::Done { iterations, .. } => serde_json::json!(iterations),
                            _ => serde_json::Value::Null,
                        };
                        (m.as_str().to_owned(), v)
                    })
                    .collect()
            })
            .unwrap_or_default();
        let error = self
            .design_error
            .clone()
            .or_else(|| self.plan.as_ref().and_then(|p| p.error.as_ref()).map(|e| e.message.clone()))
            .unwrap_or_default();
        serde_json::json!({
            "source": source_id(self.source),
            "before": plan.is_some_and(|p| p.inputs.before),
            "machine": self.machine.kind.as_str(),
            "tol_mm": self.tol_mm,
            "method": self.method.as_str(),
            "bound_tip": self.bound_tip,
            // A widget changed after this frame's update counts as computing too.
            "computing": self.waiting.is_some()
                || self.plan.as_ref().is_some_and(|p| !p.finished() || p.inputs != self.inputs(self.generation)),
            "blocks": plan.map_or(0, |p| p.nodes.len()),
            "worst_delta_mm": plan.and_then(Plan::worst_delta_mm),
            "iterations": plan.map_or(0, Plan::iterations),
            "compare": compare,
            "time": self.times_json(),
            "error": error,
            "ui": rects_json(&self.rects),
        })
    }
}
