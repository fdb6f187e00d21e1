//! The five-axis tab's controls (in the app's side panel): the path, Example 1's
//! before/after, the tolerance E and the root method, the machine, the tool-axis rule and
//! what the 3D view shows.

use eframe::egui;

use super::view::Swept;
use super::work::Source;
use super::{FiveAxisPanel, RuleKind, plots};
use crate::app::fmt_len;
use crate::app::ranges;
use crate::app::widgets::{PROBLEM_TEXT, section, tolerance_slider};
use crate::chords::RootMethod;
use crate::fiveaxis::MachineKind;
use crate::scene::Scene;

impl FiveAxisPanel {
    /// The tab's inputs: path, before/after, tolerance and method, machine, tool axis, display.
    pub(super) fn inputs_ui(&mut self, ui: &mut egui::Ui, scene: &Scene) {
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
        section(ui, "Machine", false, |ui| self.machine_ui(ui, scene));
        section(ui, "Tool axis", self.source != Source::Example1, |ui| self.rule_ui(ui));
        section(ui, "Display", false, |ui| {
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
                    egui::Slider::new(&mut self.display.magnify, ranges::FIVEAXIS_MAGNIFY)
                        .logarithmic(true)
                        .text("× swept − chord")
                        .clamping(egui::SliderClamping::Always),
                )
                .on_hover_text("Exaggerates how far the swept curves leave the programmed chords (colours stay true)");
            });
        });
    }

    fn tolerance_ui(&mut self, ui: &mut egui::Ui) {
        let r = tolerance_slider(ui, &mut self.tol_mm, ranges::FIVEAXIS_TOL_MM, "tolerance E");
        self.rects.push(("tolerance", r.rect));
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
            "By default each segment's error is the ball's signed error on the surfaces (the paper's δ). With this, the swept tool tip's distance from the design tip path is held within E too, as a post-processor checking the programmed point would want (interpolab steps --bound-tip).",
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
                if r.vector.iter().all(|c| c.abs() < crate::numerics::tolerance::MIN_DIRECTION_LENGTH) {
                    ui.colored_label(PROBLEM_TEXT, "The vector is zero: give a direction.");
                }
            }
        }
    }
}
