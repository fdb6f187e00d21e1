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

mod plots;
mod view;
mod work;

use std::rc::Rc;

use eframe::egui;
use web_time::Duration;

use super::fmt_len;
use super::panel::{Handoff, Panel, PanelContext, SIMULATION_TITLE};
use crate::chords::RootMethod;
use crate::crease::CreaseCurve;
use crate::fiveaxis::{Machine, MachineKind, StepNode, ToolAxisRule};
use crate::scene::{MachineSpec, Scene, ToolAxisSpec, build_machine, build_tool_axis};
use view::{Display, FiveAxisView, Swept};
use work::{Design, Plan, Source};

/// Wall time per frame given to the five-axis computation: half the last frame's duration
/// within these bounds (on a slow renderer more work per frame instead of many slow frames).
const BUDGET_MIN: Duration = Duration::from_millis(10);
const BUDGET_MAX: Duration = Duration::from_millis(60);
/// Range of the tolerance slider (mm).
const TOL_RANGE: std::ops::RangeInclusive<f64> = 0.0005..=1.0;

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
    crease: Option<(u64, Result<CreaseCurve, String>)>,
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
            crease: None,
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

fn signed(mm: f64) -> String {
    // Below a picometre an error is rounding: say exact.
    if mm.abs() < 1e-9 {
        return "0 (exact to 1 pm)".to_owned();
    }
    let tag = if mm > 0.0 {
        "overcut"
    } else if mm < 0.0 {
        "stock"
    } else {
        "exact"
    };
    format!("{}{} ({tag})", if mm > 0.0 { "+" } else { "" }, fmt_len(mm))
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
    fn crease_curve(&mut self, cx: &PanelContext<'_>) -> Option<&CreaseCurve> {
        let c = cx.compute;
        if c.running() {
            self.waiting = Some(format!("waiting for the crease of the scene: {} periods so far…", c.periods.len()));
            return None;
        }
        self.waiting = None;
        if self.crease.as_ref().is_none_or(|(g, _)| *g != c.generation) {
            let built = match (&c.job, &c.outcome) {
                (_, Some(Err(e))) => Err(format!("the crease of this scene could not be computed — {e}")),
                (Some(job), _) => {
                    let rows: Vec<_> = c.periods.iter().map(|p| p.row).collect();
                    CreaseCurve::from_rows(job, &rows).ok_or_else(|| {
                        "the crease of this scene is too short to plan along (fewer than two points)".to_owned()
                    })
                }
                (None, _) => Err("the scene has no valid crease".to_owned()),
            };
            self.crease = Some((c.generation, built));
        }
        match self.crease.as_ref().map(|(_, r)| r) {
            Some(Ok(curve)) => Some(curve),
            Some(Err(e)) => {
                self.design_error = Some(format!("{e}; choose Example 1 or the blade, or change the scene."));
                None
            }
            None => None,
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
        }
    }

    /// Brings design and plan up to date with the inputs, then computes within the budget.
    fn update(&mut self, cx: &PanelContext<'_>, budget: Duration) -> bool {
        if self.source != Source::Scene {
            self.waiting = None;
        }
        let generation = cx.compute.generation;
        self.generation = generation;
        let inputs = self.inputs(generation);
        let key = (inputs.source, inputs.generation, inputs.rule);
        if self.design.as_ref().is_none_or(|d| d.key != key) {
            self.design_error = None;
            let crease = if self.source == Source::Scene { self.crease_curve(cx).cloned() } else { None };
            if self.source == Source::Scene && crease.is_none() {
                self.design = None;
                self.plan = None;
                self.previous = None;
                return false;
            }
            let source_changed = self.design.as_ref().is_none_or(|d| d.key.0 != key.0 || d.key.1 != key.1);
            match work::build_design(inputs.source, inputs.generation, inputs.rule, crease.as_ref()) {
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
            if let Some(old) = self.plan.take()
                && old.shown_complete()
                && old.design.key == design.key
            {
                self.previous = Some(old);
            }
            self.serial += 1;
            self.plan = Some(Plan::new(inputs, design, self.serial));
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

    fn controls(&mut self, ui: &mut egui::Ui, scene: &Scene) {
        ui.heading("5-axis tool steps");
        ui.label(
            egui::RichText::new(
                "Between two blocks every joint moves linearly, so rotary axes bend the tool's path. Each step is chosen so the ball's total error δ = δt + δn is exactly E (Ji et al. 2010).",
            )
            .weak(),
        );
        ui.add_space(4.0);
        ui.horizontal(|ui| {
            ui.label("path");
            let r = egui::ComboBox::from_id_salt("fa_source").selected_text(self.source.label()).width(200.0).show_ui(
                ui,
                |ui| {
                    for s in [Source::Example1, Source::Scene, Source::Blade] {
                        ui.selectable_value(&mut self.source, s, s.label());
                    }
                },
            );
            self.rects.push(("source", r.response.rect));
        });
        if self.source == Source::Example1 {
            ui.horizontal(|ui| {
                let b = ui.selectable_value(&mut self.before, true, "before: one block P1 → P2");
                let a = ui.selectable_value(&mut self.before, false, "after: steps inserted");
                self.rects.push(("before", b.rect));
                self.rects.push(("after", a.rect));
            });
        }
        ui.separator();
        self.tolerance_ui(ui);
        ui.separator();
        egui::CollapsingHeader::new(egui::RichText::new("Machine").strong()).default_open(false).show(ui, |ui| {
            self.machine_ui(ui, scene);
        });
        egui::CollapsingHeader::new(egui::RichText::new("Tool axis").strong())
            .default_open(self.source != Source::Example1)
            .show(ui, |ui| self.rule_ui(ui));
        egui::CollapsingHeader::new(egui::RichText::new("Display").strong()).default_open(false).show(ui, |ui| {
            ui.checkbox(&mut self.display.surfaces, "surfaces (translucent)");
            ui.checkbox(&mut self.display.thin_axes, "tool axes along the design path");
            ui.horizontal(|ui| {
                ui.label("swept curve of the");
                ui.selectable_value(&mut self.display.swept, Swept::Tip, "tool tip");
                ui.selectable_value(&mut self.display.swept, Swept::Centre, "ball centre");
                ui.selectable_value(&mut self.display.swept, Swept::Both, "both");
            });
            ui.horizontal(|ui| {
                ui.checkbox(&mut self.display.auto_magnify, "auto")
                    .on_hover_text("Exaggerate so the largest distance shows as 3 % of the view");
                ui.add_enabled(
                    !self.display.auto_magnify,
                    egui::Slider::new(&mut self.display.magnify, 1.0..=10_000.0)
                        .logarithmic(true)
                        .text("× swept − chord")
                        .clamping(egui::SliderClamping::Always),
                )
                .on_hover_text("Exaggerates how far the swept curves leave the programmed chords (colours stay true)");
            });
        });
    }

    fn tolerance_ui(&mut self, ui: &mut egui::Ui) {
        let mut tol = self.tol_mm;
        let r = ui.add(
            egui::Slider::new(&mut tol, TOL_RANGE)
                .logarithmic(true)
                .text("tolerance E")
                .suffix(" mm")
                .custom_formatter(|v, _| format!("{v:.4}"))
                .clamping(egui::SliderClamping::Always),
        );
        self.rects.push(("tolerance", r.rect));
        if r.changed() && tol.is_finite() {
            self.tol_mm = tol.clamp(*TOL_RANGE.start(), *TOL_RANGE.end());
        }
        let on = if self.bound_tip { "|δ| and tip distance" } else { "|δ|" };
        ui.label(egui::RichText::new(format!("E = {} on every segment's {on}", fmt_len(self.tol_mm))).weak());
        ui.horizontal(|ui| {
            ui.label("root method");
            egui::ComboBox::from_id_salt("fa_method").selected_text(plots::method_name(self.method)).show_ui(
                ui,
                |ui| {
                    for m in RootMethod::ALL {
                        ui.selectable_value(&mut self.method, m, plots::method_name(m));
                    }
                },
            );
        });
        let r = ui.checkbox(&mut self.bound_tip, "also hold the tool tip within E of its design path").on_hover_text(
            "By default each segment's error is the ball's signed error on the surfaces (seed 002's δ). With this, the swept tool tip's distance from the design tip path is held within E too, as a post-processor checking the programmed point would want (interpolab steps --bound-tip).",
        );
        self.rects.push(("bound_tip", r.rect));
    }

    fn machine_ui(&mut self, ui: &mut egui::Ui, scene: &Scene) {
        let m = &mut self.machine;
        let before_kind = m.kind;
        ui.horizontal(|ui| {
            ui.label("structure");
            egui::ComboBox::from_id_salt("fa_kind").selected_text(m.kind.as_str()).show_ui(ui, |ui| {
                for k in MachineKind::ALL {
                    ui.selectable_value(&mut m.kind, k, k.as_str());
                }
            });
        });
        if m.kind != before_kind && m.kind.uses_tool_length() && m.tool_length_mm <= 0.0 {
            m.tool_length_mm = 150.0;
        }
        let names = m.kind.axis_names();
        let what = match m.kind {
            MachineKind::TableAC => "A trunnion about X carries a C table",
            MachineKind::TableBC => "B trunnion about Y carries a C table",
            MachineKind::HeadBC => "the head: C about Z carries B about Y",
            MachineKind::HeadATableC => "the head tilts about X (A), the table turns about Z (C)",
        };
        ui.label(egui::RichText::new(what).weak());
        for (i, has) in m.kind.has_pivot().into_iter().enumerate() {
            if !has {
                continue;
            }
            let head = m.kind.uses_tool_length() && (i == 0);
            ui.label(if head {
                format!("{} axis: offset from the control point (mm)", names[i])
            } else {
                format!("{} axis passes through (mm)", names[i])
            });
            ui.horizontal(|ui| {
                let mut v = m.pivots_mm[i].to_array();
                for (c, n) in v.iter_mut().zip(["x", "y", "z"]) {
                    ui.add(egui::DragValue::new(c).speed(0.5).range(-1.0e4..=1.0e4).prefix(format!("{n} ")));
                }
                m.pivots_mm[i] = glam::DVec3::from_array(v);
            });
        }
        if m.kind.uses_tool_length() {
            ui.horizontal(|ui| {
                ui.label("tool length L");
                ui.add(egui::DragValue::new(&mut m.tool_length_mm).speed(1.0).range(1.0..=2000.0).suffix(" mm"));
            });
        }
        for i in 0..2 {
            ui.horizontal(|ui| {
                let mut limited = m.limits_rad[i].is_some();
                ui.checkbox(&mut limited, format!("{} travel", names[i]));
                let [mut lo, mut hi] = m.limits_rad[i].map_or([-120.0, 120.0], |l| l.map(f64::to_degrees));
                if limited {
                    ui.add(egui::DragValue::new(&mut lo).speed(1.0).range(-720.0..=hi - 1.0).suffix("°"));
                    ui.label("to");
                    ui.add(egui::DragValue::new(&mut hi).speed(1.0).range(lo + 1.0..=720.0).suffix("°"));
                    m.limits_rad[i] = Some([lo.to_radians(), hi.to_radians()]);
                } else {
                    m.limits_rad[i] = None;
                    ui.label(egui::RichText::new("unlimited").weak());
                }
            });
        }
        if let Some(n) = &self.machine_note {
            ui.label(egui::RichText::new(n).weak());
        }
        if ui.button("reset to the path's machine").clicked() {
            self.reset_machine_and_rule(scene);
        }
    }

    fn rule_ui(&mut self, ui: &mut egui::Ui) {
        if self.source == Source::Example1 {
            ui.label("The paper's data: the axis turns from T1 (0, 1, 0) to T2 (0.997, −0.070, 0) along the great circle as the contact point runs from P1 to P2.");
            return;
        }
        let r = &mut self.rule;
        ui.horizontal(|ui| {
            ui.selectable_value(&mut r.kind, RuleKind::Bisector, "bisector")
                .on_hover_text("(n1 + n2)/|n1 + n2| of the contact normals (n1 alone on a profile)");
            ui.selectable_value(&mut r.kind, RuleKind::Normal1, "normal1 + lead, tilt")
                .on_hover_text("n1 turned by the lead (toward the travel) and the tilt (toward t × n1)");
            ui.selectable_value(&mut r.kind, RuleKind::Fixed, "fixed");
        });
        match r.kind {
            RuleKind::Bisector => {}
            RuleKind::Normal1 => {
                ui.add(egui::Slider::new(&mut r.lead_deg, -80.0..=80.0).text("lead").suffix("°"));
                ui.add(egui::Slider::new(&mut r.tilt_deg, -80.0..=80.0).text("tilt").suffix("°"));
            }
            RuleKind::Fixed => {
                ui.horizontal(|ui| {
                    for (c, n) in r.vector.iter_mut().zip(["i", "j", "k"]) {
                        ui.add(egui::DragValue::new(c).speed(0.01).range(-1.0..=1.0).prefix(format!("{n} ")));
                    }
                });
                if r.vector.iter().all(|c| c.abs() < 1e-9) {
                    ui.colored_label(egui::Color32::from_rgb(255, 120, 110), "The vector is zero: give a direction.");
                }
            }
        }
    }

    fn summary(&mut self, ui: &mut egui::Ui) {
        let Some(plan) = self.shown() else { return };
        let stale = self.plan.as_ref().is_some_and(|p| !p.shown_complete());
        let names = plan.inputs.machine.kind.axis_names();
        egui::Grid::new("fa_summary").num_columns(2).spacing([10.0, 3.0]).striped(true).show(ui, |ui| {
            let segments = plan.nodes.len().saturating_sub(1);
            ui.label("blocks");
            ui.label(if plan.inputs.before {
                "2 (P1, P2): one segment".to_owned()
            } else if plan.design.example1.is_some() {
                format!("{} ({} inserted), {segments} segments", plan.nodes.len(), plan.nodes.len().saturating_sub(2))
            } else {
                format!("{}, {segments} segments", plan.nodes.len())
            });
            ui.end_row();
            if let Some(w) = plan.worst_delta_mm() {
                let over = w.abs() > plan.inputs.tol_mm * (1.0 + 1e-6);
                ui.label("worst δ");
                ui.label(egui::RichText::new(signed(w)).color(if over {
                    view::OVERCUT_BEYOND
                } else {
                    ui.visuals().text_color()
                }));
                ui.end_row();
            }
            if !plan.inputs.before {
                ui.label("iterations");
                ui.label(format!("{} δ evaluations ({})", plan.iterations(), plots::method_name(plan.inputs.method)));
                ui.end_row();
                let limited = plan.nodes.iter().filter(|n| n.rotary_limited).count();
                if limited > 0 {
                    ui.label("rotary step");
                    ui.label(format!(
                        "{limited} segment(s) ended by the 90° limit on {} / {} (shaded)",
                        names[0], names[1]
                    ));
                    ui.end_row();
                }
            }
            ui.label("compute");
            ui.label(format!("{:.1} ms on this device", plan.plan_ms));
            ui.end_row();
        });
        if stale {
            ui.label(egui::RichText::new("computing the new plan… (the last one is shown)").weak());
        }
    }

    fn segment_ui(&mut self, ui: &mut egui::Ui) {
        let selected = self.selected;
        let Some(plan) = self.shown() else { return };
        let segments = plan.nodes.len().saturating_sub(1);
        if segments == 0 {
            return;
        }
        let mut k = selected.min(segments - 1) + 1;
        ui.add(egui::Slider::new(&mut k, 1..=segments).text("segment").clamping(egui::SliderClamping::Always));
        let k = k - 1;
        let names = plan.inputs.machine.kind.axis_names();
        let (a, b): (&StepNode, &StepNode) = (&plan.nodes[k], &plan.nodes[k + 1]);
        egui::Grid::new("fa_segment").num_columns(2).spacing([10.0, 2.0]).striped(true).show(ui, |ui| {
            if let Some(r) = b.report {
                ui.label("δ at worst");
                ui.label(format!("{} at τ = {:.3}", signed(r.total_mm), r.at_tau));
                ui.end_row();
                ui.label("  of which δt");
                ui.label(signed(r.chord_mm));
                ui.end_row();
                ui.label("  and δn");
                ui.label(signed(r.nonlinear_mm));
                ui.end_row();
                ui.label("gouge / stock");
                let tiny = |v: f64| if v < 1e-9 { 0.0 } else { v };
                ui.label(format!("{} / {}", fmt_len(tiny(r.gouge_mm)), fmt_len(tiny(r.stock_mm))));
                ui.end_row();
                ui.label("tip off its chord");
                ui.label(fmt_len(r.tip_deviation_mm));
                ui.end_row();
            }
            if let Some(d) = plan.tip_design_mm.get(k).filter(|d| d.is_finite()) {
                ui.label("tip off design tip path");
                ui.label(fmt_len(*d)).on_hover_text(
                    "The swept tip's largest distance from the design tip path (reference: step selection bounds the ball's surface error, not this; see docs/fiveaxis.md)",
                );
                ui.end_row();
            }
            for (label, n) in [("from block", a), ("to block", b)] {
                let j = &n.block.joints;
                ui.label(label);
                ui.label(format!("X {:.3}  Y {:.3}  Z {:.3} mm", j.xyz_mm.x, j.xyz_mm.y, j.xyz_mm.z));
                ui.end_row();
                ui.label("");
                ui.label(format!(
                    "{} {:.3}°  {} {:.3}°",
                    names[0],
                    j.rotary_rad[0].to_degrees(),
                    names[1],
                    j.rotary_rad[1].to_degrees()
                ));
                ui.end_row();
            }
            if !plan.inputs.before {
                ui.label("iterations");
                ui.label(format!("{} ({} bracketing)", b.evaluations, b.bracket_evaluations));
                ui.end_row();
            }
        });
        self.selected = k;
    }

    fn overlay(&self, painter: &egui::Painter, rect: egui::Rect, at: &dyn Fn(glam::DVec3) -> Option<egui::Pos2>) {
        let font = egui::FontId::proportional(13.0);
        let text = egui::Color32::from_gray(225);
        // Labels in the scene: Example 1's P1, P2; the selected segment's worst error.
        if let Some(plan) = self.shown() {
            let label = |p: glam::DVec3, s: String, color: egui::Color32| {
                if let Some(q) = at(p).filter(|q| rect.contains(*q)) {
                    painter.circle_filled(q, 2.5, color);
                    // Near the right edge the text goes to the left of the point.
                    let (offset, align) = if q.x > rect.right() - 280.0 {
                        (egui::vec2(-6.0, -6.0), egui::Align2::RIGHT_BOTTOM)
                    } else {
                        (egui::vec2(6.0, -6.0), egui::Align2::LEFT_BOTTOM)
                    };
                    painter.text(q + offset, align, s, font.clone(), color);
                }
            };
            if let Some(ex) = plan.design.example1 {
                for (i, p) in ex.contacts.iter().enumerate() {
                    label(*p, format!("P{}", i + 1), egui::Color32::WHITE);
                }
            }
            let k = self.selected;
            if let Some(w) = plan.nodes.get(k..k + 2)
                && let Some(r) = w[1].report
            {
                let j = w[0].block.joints.lerp(&w[1].block.joints, r.at_tau);
                let pose = plan.inputs.machine.pose_from_joints(&j);
                let centre = pose.tip_in_workpiece + plan.design.path.ball_radius_mm() * pose.axis_in_workpiece;
                label(
                    centre,
                    format!("segment {}: δ = {}", k + 1, signed(r.total_mm)),
                    view::error_color(r.total_mm, plan.inputs.tol_mm).gamma_multiply(1.2),
                );
            }
        }
        let x = rect.left() + 10.0;
        let mut y = rect.top() + 10.0;
        let mut entry = |color: egui::Color32, label: &str| {
            painter.rect_filled(egui::Rect::from_min_size(egui::pos2(x, y + 3.0), egui::vec2(12.0, 10.0)), 2.0, color);
            painter.text(egui::pos2(x + 18.0, y), egui::Align2::LEFT_TOP, label, font.clone(), text);
            y += 18.0;
        };
        if let Some(d) = &self.design {
            if matches!(d.shape, work::Shape::Crease(_)) {
                for (i, name) in self.surface_names.iter().enumerate() {
                    entry(view::surface_color(i), &format!("S{} {name}", i + 1));
                }
            }
            let part = match &d.shape {
                work::Shape::Cylinder { radius_mm, .. } => Some(format!("the boss: cylinder r = {radius_mm} mm")),
                work::Shape::Extrusion(_) => Some("the blade: NACA 2412 extruded".to_owned()),
                work::Shape::Crease(_) => None,
            };
            if let Some(p) = part {
                entry(view::surface_color(0), &p);
            }
        }
        entry(view::DESIGN_CENTRE, "design path of the ball centre");
        entry(view::DESIGN_TIP, "design path of the tool tip");
        entry(view::CHORD, "programmed chords (tool tip) and blocks");
        entry(view::AXIS, "tool axis at each block");
        let swept = match self.display.swept {
            Swept::Tip => "swept tool tip",
            Swept::Centre => "swept ball centre",
            Swept::Both => "swept tip and centre",
        };
        let magnify = if self.display.magnify > 1.0 {
            format!(" (distance from chord ×{:.0})", self.display.magnify)
        } else {
            String::new()
        };
        painter.text(
            egui::pos2(x, y + 2.0),
            egui::Align2::LEFT_TOP,
            format!("{swept}{magnify}, coloured by the ball's error δ:"),
            font.clone(),
            text,
        );
        y += 22.0;
        // Colour bar from −E to +E, then the colours beyond.
        let (w, h) = (180.0, 12.0);
        let steps = 48;
        for i in 0..steps {
            let t0 = i as f32 / steps as f32;
            let d = (2.0 * f64::from(t0) - 1.0 + 1.0 / steps as f64) * self.tol_mm;
            let r = egui::Rect::from_min_size(egui::pos2(x + t0 * w, y), egui::vec2(w / steps as f32 + 0.5, h));
            painter.rect_filled(r, 0.0, view::error_color(d, self.tol_mm));
        }
        let e = fmt_len(self.tol_mm);
        let small = egui::FontId::proportional(11.5);
        painter.text(egui::pos2(x, y + h + 2.0), egui::Align2::LEFT_TOP, format!("−{e}"), small.clone(), text);
        painter.text(egui::pos2(x + w / 2.0, y + h + 2.0), egui::Align2::CENTER_TOP, "0", small.clone(), text);
        painter.text(egui::pos2(x + w, y + h + 2.0), egui::Align2::RIGHT_TOP, format!("+{e}"), small.clone(), text);
        painter.text(egui::pos2(x, y + h + 16.0), egui::Align2::LEFT_TOP, "stock", small.clone(), text);
        painter.text(egui::pos2(x + w, y + h + 16.0), egui::Align2::RIGHT_TOP, "overcut", small.clone(), text);
        let bx = x + w + 14.0;
        painter.rect_filled(
            egui::Rect::from_min_size(egui::pos2(bx, y), egui::vec2(14.0, h)),
            2.0,
            view::OVERCUT_BEYOND,
        );
        painter.text(egui::pos2(bx + 18.0, y - 1.0), egui::Align2::LEFT_TOP, "overcut > E", small.clone(), text);
        painter.rect_filled(
            egui::Rect::from_min_size(egui::pos2(bx, y + 16.0), egui::vec2(14.0, h)),
            2.0,
            view::STOCK_BEYOND,
        );
        painter.text(egui::pos2(bx + 18.0, y + 15.0), egui::Align2::LEFT_TOP, "stock > E", small, text);
        // Status, top right.
        let (ok, status) = self.status_line();
        painter.text(
            egui::pos2(rect.right() - 10.0, rect.top() + 10.0),
            egui::Align2::RIGHT_TOP,
            status,
            font,
            if ok { egui::Color32::from_gray(215) } else { egui::Color32::from_rgb(255, 120, 110) },
        );
    }

    fn status_line(&self) -> (bool, String) {
        if let Some(w) = &self.waiting {
            return (true, w.clone());
        }
        if self.design_error.is_some() {
            return (false, "no path — see the message on the left".to_owned());
        }
        let Some(plan) = &self.plan else { return (true, String::new()) };
        if plan.error.is_some() {
            return (false, format!("plan stopped after {} blocks — see the message on the left", plan.nodes.len()));
        }
        if !plan.shown_complete() {
            return (true, format!("computing… {} blocks so far", plan.nodes.len()));
        }
        let extra = if plan.finished() { "" } else { " (comparing the methods…)" };
        (
            true,
            format!(
                "{} blocks, worst δ {}{extra}",
                plan.nodes.len(),
                plan.worst_delta_mm().map_or_else(String::new, signed)
            ),
        )
    }
}

/// Example 1's numbers, before or after, in words for the lecture.
fn example1_story(ui: &mut egui::Ui, plan: &Plan) {
    let Some(ex) = plan.design.example1 else { return };
    let f = |v: glam::DVec3| format!("({:.3}, {:.3}, {:.3})", v.x, v.y, v.z);
    ui.label(
        egui::RichText::new(format!(
            "Circle r = 25 mm about Z at z = 50; P1 {} → P2 {}; T1 {} → T2 {}; ball R = 5 mm; table-ac with both axes through the origin.",
            f(ex.contacts[0]),
            f(ex.contacts[1]),
            f(ex.axes[0]),
            f(ex.axes[1])
        ))
        .weak(),
    );
    if plan.inputs.before {
        if let Some(r) = plan.nodes.get(1).and_then(|n| n.report) {
            let c: Vec<f64> = plan.nodes.iter().map(|n| n.block.joints.rotary_rad[1].to_degrees()).collect();
            ui.label(format!(
                "One block: C turns {:.2}° while the tip is 25–30 mm from the C axis. The swept ball overcuts the boss by {} at τ = {:.2} (chord part δt {}, nonlinear part δn {}); the tip leaves its chord by {}.",
                c.last().copied().unwrap_or(0.0) - c.first().copied().unwrap_or(0.0),
                fmt_len(r.total_mm),
                r.at_tau,
                signed(r.chord_mm),
                signed(r.nonlinear_mm),
                fmt_len(r.tip_deviation_mm)
            ));
        }
    } else if plan.shown_complete() && plan.error.is_none() {
        let deltas: Vec<f64> = plan.nodes.iter().filter_map(|n| n.total_mm).collect();
        let (inner, last) = deltas.split_at(deltas.len().saturating_sub(1));
        let lo = inner.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = inner.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let range = if inner.is_empty() {
            String::new()
        } else {
            format!("every segment but the last δ = {} … {}, ", signed(lo), signed(hi))
        };
        ui.label(format!(
            "The method inserts {} blocks: {range}the last {} — the gouge is gone, each segment's error is E = {}.",
            plan.nodes.len().saturating_sub(2),
            last.first().map_or_else(String::new, |d| signed(*d)),
            fmt_len(plan.inputs.tol_mm),
        ));
    }
}

impl Panel for FiveAxisPanel {
    fn title(&self) -> &'static str {
        "5-axis (seed 002)"
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        self.rects.clear();
        self.sync_defaults(cx.scene);
        self.surface_names = [cx.scene.surfaces[0].type_name(), cx.scene.surfaces[1].type_name()];
        let last_frame = Duration::from_secs_f32(ui.ctx().input(|i| i.unstable_dt).clamp(0.0, 1.0));
        if self.update(cx, (last_frame / 2).clamp(BUDGET_MIN, BUDGET_MAX)) {
            ui.ctx().request_repaint();
        }
        if self.source == Source::Scene && self.waiting.is_some() {
            ui.ctx().request_repaint();
        }
        let mut simulate = std::mem::take(&mut self.simulate_requested) && self.source == Source::Scene;
        egui::Panel::left("fa_controls").resizable(true).default_size(310.0).min_size(260.0).max_size(520.0).show(
            ui,
            |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    self.controls(ui, cx.scene);
                    let r = ui
                        .add_enabled(self.source == Source::Scene, egui::Button::new("▶ Simulate this program"))
                        .on_hover_text(
                            "Machine the scene's tool steps (its machine and tool-axis rule, 0.01 mm) in the Cutting simulation tab",
                        )
                        .on_disabled_hover_text("The Cutting simulation runs the scene's steps: choose the scene's crease as the source");
                    self.rects.push(("fa_simulate", r.rect));
                    simulate |= r.clicked();
                    ui.separator();
                    if let Some(w) = &self.waiting {
                        ui.horizontal(|ui| {
                            ui.spinner();
                            ui.label(w);
                        });
                    }
                    let error = self.design_error.clone().or_else(|| {
                        self.plan.as_ref().and_then(|p| p.error.as_ref()).map(|e| {
                            let at = e.s.map_or_else(String::new, |s| format!(" (marked on the plots at s = {s:.4})"));
                            format!("The plan stopped: {}{at}.", e.message)
                        })
                    });
                    if let Some(e) = error {
                        egui::Frame::new()
                            .fill(egui::Color32::from_rgb(80, 24, 24))
                            .inner_margin(6.0)
                            .corner_radius(4.0)
                            .show(ui, |ui| {
                                ui.colored_label(egui::Color32::WHITE, e);
                            });
                    }
                    if let Some(plan) = self.shown() {
                        example1_story(ui, plan);
                    }
                    self.summary(ui);
                    ui.separator();
                    ui.label(
                        egui::RichText::new(format!("Iterations per method at E = {}", fmt_len(self.tol_mm))).strong(),
                    );
                    if let Some(plan) = &self.plan {
                        if plan.inputs.before {
                            ui.label(egui::RichText::new("(the plans with steps inserted, as in \"after\")").weak());
                        }
                        plots::iterations_table(ui, plan);
                        plots::iterations_lesson(ui, plan);
                    }
                    ui.separator();
                    ui.label(egui::RichText::new("Selected segment").strong());
                    self.segment_ui(ui);
                });
            },
        );
        if simulate {
            cx.handoff = Some(Handoff { to: SIMULATION_TITLE, options: vec![("source", "steps".to_owned())] });
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
            "tol_mm" => {
                let t = number()?;
                if !(t > 0.0 && t.is_finite()) {
                    return Err(format!("tol_mm: {t} is not a positive length"));
                }
                self.tol_mm = t.clamp(*TOL_RANGE.start(), *TOL_RANGE.end());
            }
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
            "error": error,
            "ui": rects_json(&self.rects),
        })
    }
}

/// Widget rectangles as `{name: [x, y, w, h]}` (points) for the status element.
pub(crate) fn rects_json(rects: &[(&'static str, egui::Rect)]) -> serde_json::Value {
    rects.iter().map(|(k, r)| ((*k).to_owned(), serde_json::json!([r.min.x, r.min.y, r.width(), r.height()]))).collect()
}
