//! The NURBS & G-code tab's controls: the design path, tolerance, resolution, degree and
//! dialect, the programmed point and feed (in the side panel), the real-time update choices
//! (over the plots), and the *Simulate this program* hand-over.

use eframe::egui;

use super::NurbsPanel;
use super::plots::FeedPlot;
use super::table::Shown;
use super::work::{Point, Source};
use crate::app::panel::{Handoff, PanelContext, SIMULATION_TITLE};
use crate::app::ranges;
use crate::gcode::{Dialect, ProgramKind};
use crate::nurbs_path::Update;
use crate::report::fmt_fixed;

impl NurbsPanel {
    pub(super) fn controls(&mut self, ui: &mut egui::Ui, cx: &PanelContext<'_>) {
        self.rects.clear();
        let s = &mut self.settings;
        ui.horizontal_wrapped(|ui| {
            ui.label("Design path:");
            ui.selectable_value(&mut s.source, Source::Crease, "scene's crease")
                .on_hover_text("The current scene's ball-centre crease, as `interpolab gcode SCENE` uses it");
            let r = ui.selectable_value(&mut s.source, Source::Parabola, "parabola profile").on_hover_text(
                "The paper's parabola-like profile: y = x²/40 for x from −60 to 60 mm, z = 0 (1500 mm/min, 4 ms)",
            );
            self.rects.push(("source_parabola", r.rect));
        });
        // In the side panel: a slider or a combo box a line (egui's wrapped rows do not wrap
        // a slider), the choices between them in rows.
        ui.scope(|ui| {
            ui.spacing_mut().slider_width = 140.0;
            let r = ui
                .add(
                    egui::Slider::new(&mut s.tol_mm, ranges::NURBS_TOL_MM)
                        .logarithmic(true)
                        .text("tolerance E")
                        .suffix(" mm")
                        .custom_formatter(|v, _| fmt_fixed(v, 4)),
                )
                .on_hover_text("Every program stays within E of the design path after rounding to the resolution");
            self.rects.push(("tolerance_slider", r.rect));
            egui::ComboBox::from_id_salt("nurbs-resolution")
                .selected_text(format!("resolution {} mm", fmt_fixed(s.resolution_mm, 4)))
                .show_ui(ui, |ui| {
                    for r in [0.01, 0.001, 0.0001] {
                        ui.selectable_value(&mut s.resolution_mm, r, format!("{} mm", fmt_fixed(r, 4)));
                    }
                })
                .response
                .on_hover_text("The machine's least input increment: every written number is rounded to it");
            egui::ComboBox::from_id_salt("nurbs-degree")
                .selected_text(format!("G06.2 degree {} (P{})", s.degree, s.degree + 1))
                .show_ui(ui, |ui| {
                    for d in [3, 2, 1] {
                        ui.selectable_value(&mut s.degree, d, format!("degree {d} (order P{})", d + 1));
                    }
                });
            egui::ComboBox::from_id_salt("nurbs-dialect")
                .selected_text(format!("dialect {}", s.dialect.label()))
                .show_ui(ui, |ui| {
                    for d in Dialect::ALL {
                        ui.selectable_value(&mut s.dialect, d, d.label());
                    }
                })
                .response
                .on_hover_text(
                    "The controller the programs are written for: FANUC G06.2, Sinumerik 840D BSPLINE, LinuxCNC G5.2 (XY only); each is read back by its own reader",
                );
        });
        ui.horizontal_wrapped(|ui| {
            ui.label("programmed point:");
            ui.selectable_value(&mut s.point, Point::Centre, "ball centre");
            let r = ui
                .selectable_value(&mut s.point, Point::Tip, "ball tip")
                .on_hover_text(format!("Ball centre − R·z, R = {} mm (the scene's tool)", cx.scene.tool.radius));
            self.rects.push(("point_tip", r.rect));
        });
        ui.horizontal(|ui| {
            let default_feed = if s.source == Source::Parabola { 1500.0 } else { cx.scene.motion.feed };
            let mut feed = s.feed_mm_per_min.unwrap_or(default_feed);
            ui.spacing_mut().slider_width = 140.0;
            if ui
                .add(
                    egui::Slider::new(&mut feed, ranges::NURBS_FEED_MM_PER_MIN)
                        .logarithmic(true)
                        .text("feed F")
                        .suffix(" mm/min")
                        .custom_formatter(|v, _| fmt_fixed(v, 0)),
                )
                .on_hover_text("Feed of the programs (F word) and of the real-time interpolation")
                .changed()
            {
                s.feed_mm_per_min = Some(feed);
            }
            if s.feed_mm_per_min.is_some()
                && ui.small_button("default").on_hover_text(format!("Back to {default_feed} mm/min")).clicked()
            {
                s.feed_mm_per_min = None;
            }
        });
    }

    /// The real-time settings, over the plots.
    pub(super) fn realtime_controls(&mut self, ui: &mut egui::Ui) {
        let s = &mut self.settings;
        ui.horizontal_wrapped(|ui| {
            ui.label(egui::RichText::new("Real-time interpolation").strong()).on_hover_text(
                "The G06.2 curve as read back from its program, advanced one period Ts at a time at feed F",
            );
            ui.separator();
            ui.label("update:");
            for (u, tip) in [
                (Update::FirstOrder, "Δu = f/|C′|"),
                (Update::SecondOrder, "Δu = f/|C′| − f²(C′·C″)/(2|C′|⁴)"),
                (Update::Corrected, "second order, then one Newton step on |C(u) − C(uₖ)| = f"),
            ] {
                let r = ui.selectable_value(&mut s.update, u, u.as_str()).on_hover_text(tip);
                self.rects.push((u.as_str(), r.rect));
            }
            ui.separator();
            let r = ui.checkbox(&mut s.chord_limit, "feed limit δ").on_hover_text(
                "Lower the feed where the curvature would make a period's chord error exceed δ: f = 2√(2ρδ − δ²)",
            );
            self.rects.push(("chord_limit", r.rect));
            if s.chord_limit {
                ui.spacing_mut().slider_width = 110.0;
                let mut d_um = s.chord_tol_mm * 1000.0;
                if ui
                    .add(
                        egui::Slider::new(&mut d_um, ranges::NURBS_CHORD_TOL_UM)
                            .logarithmic(true)
                            .suffix(" µm")
                            .custom_formatter(|v, _| fmt_fixed(v, 3)),
                    )
                    .changed()
                {
                    s.chord_tol_mm = d_um / 1000.0;
                }
            }
            ui.separator();
            ui.label("plot:");
            ui.selectable_value(&mut self.feed_plot, FeedPlot::Feed, "feed (mm/min)");
            ui.selectable_value(&mut self.feed_plot, FeedPlot::Fluctuation, "|Δf/f| (log)");
        });
    }

    /// "Simulate this program": hands the shown program's text (a written crease program,
    /// or the loaded file) to the Cutting simulation tab, with the scene's surfaces as the
    /// design and the scene's ball for a program of the scene's crease.
    pub(super) fn simulate_button(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        let (text, of_scene, name) = match self.shown {
            Shown::Kind(kind) => {
                let i = ProgramKind::ALL.iter().position(|k| *k == kind).unwrap_or(0);
                let text = self.work.row(i).map(|r| r.program.text.clone());
                (text, self.settings.source == Source::Crease, format!("NURBS & G-code tab: {}", kind.label()))
            }
            Shown::Loaded => {
                let l = self.work.loaded.as_ref();
                (l.map(|l| l.text.clone()), false, l.map_or(String::new(), |l| l.name.clone()))
            }
        };
        let r = ui
            .add_enabled(text.is_some(), egui::Button::new("Simulate this program →"))
            .on_hover_text("Machine the program shown below in the Cutting simulation tab")
            .on_disabled_hover_text("No program yet");
        self.rects.push(("nurbs_simulate", r.rect));
        let asked = std::mem::take(&mut self.simulate_requested);
        if let Some(text) = text.filter(|_| r.clicked() || asked) {
            let mut options = vec![("program_text", text), ("program_name", name)];
            if of_scene {
                options.push(("design", "scene".to_owned()));
                options.push(("cutter", "scene".to_owned()));
            } else {
                options.push(("design", "auto".to_owned()));
            }
            cx.handoff = Some(Handoff { to: SIMULATION_TITLE, options, payload: None });
        }
    }
}
