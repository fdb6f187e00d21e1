//! The chords tab's controls (in the app's side panel): the curve and its numbers, the
//! tolerance d, how the uniform spacings are sized, the plot's magnification.

use eframe::egui;

use super::text::intro;
use super::{ChordsPanel, CurveKind};
use crate::app::ranges;
use crate::app::widgets::tolerance_slider;
use crate::chords::planar::Sizing;

impl ChordsPanel {
    /// The curve and its numbers, the tolerance d, the sizing of the uniform spacings and the
    /// magnification of the plot.
    pub(super) fn inputs_ui(&mut self, ui: &mut egui::Ui) {
        intro(ui);
        let i = &mut self.inputs;
        ui.horizontal(|ui| {
            ui.label("curve");
            let r =
                egui::ComboBox::from_id_salt("ch_curve").selected_text(i.kind.label()).width(210.0).show_ui(ui, |ui| {
                    for k in CurveKind::ALL {
                        ui.selectable_value(&mut i.kind, k, k.label());
                    }
                });
            self.curve_rect = Some(r.response.rect);
        });
        let num = |ui: &mut egui::Ui, label: &str, v: &mut f64, speed: f64, suffix: &str| {
            ui.horizontal(|ui| {
                ui.label(label);
                ui.add(
                    egui::DragValue::new(v)
                        .speed(speed)
                        .range(-ranges::CHORDS_NUMBER_ABS_MAX..=ranges::CHORDS_NUMBER_ABS_MAX)
                        .suffix(suffix),
                );
            });
        };
        match i.kind {
            CurveKind::Parabola => {
                num(ui, "a", &mut i.parabola[0], 0.001, " 1/mm");
                num(ui, "x from", &mut i.parabola[1], 0.5, " mm");
                num(ui, "x to", &mut i.parabola[2], 0.5, " mm");
            }
            CurveKind::Hyperbola => {
                num(ui, "k", &mut i.hyperbola[0], 5.0, " mm²");
                num(ui, "x from", &mut i.hyperbola[1], 0.5, " mm");
                num(ui, "x to", &mut i.hyperbola[2], 0.5, " mm");
            }
            CurveKind::Ellipse => {
                num(ui, "a", &mut i.ellipse[0], 0.5, " mm");
                num(ui, "b", &mut i.ellipse[1], 0.5, " mm");
                num(ui, "t from", &mut i.ellipse[2], 1.0, "°");
                num(ui, "t to", &mut i.ellipse[3], 1.0, "°");
            }
            CurveKind::Typed => {
                for (label, text) in [("x(t) =", &mut i.x_text), ("y(t) =", &mut i.y_text)] {
                    ui.horizontal(|ui| {
                        ui.label(label);
                        ui.add(egui::TextEdit::singleline(text).desired_width(230.0).font(egui::TextStyle::Monospace));
                    });
                }
                ui.horizontal(|ui| {
                    ui.label("t from");
                    ui.add(
                        egui::TextEdit::singleline(&mut i.t0_text).desired_width(70.0).font(egui::TextStyle::Monospace),
                    );
                    ui.label("to");
                    ui.add(
                        egui::TextEdit::singleline(&mut i.t1_text).desired_width(70.0).font(egui::TextStyle::Monospace),
                    );
                });
                ui.label(
                    egui::RichText::new("mm; numbers, t, pi, + − * / ^, ( ), sin cos tan exp ln sqrt abs (radians)")
                        .weak()
                        .small(),
                );
            }
            CurveKind::Crease => {
                ui.label(
                    egui::RichText::new(
                        "The ball-centre crease of the scene, a space curve: its chords are found and measured in 3D; the plot shows it projected onto its best-fit plane.",
                    )
                    .weak(),
                );
            }
        }
        ui.separator();
        let r = tolerance_slider(ui, &mut i.tol_mm, ranges::CHORDS_TOL_MM, "tolerance d");
        self.tol_rect = Some(r.rect);
        ui.horizontal(|ui| {
            ui.label("uniform spacings sized");
            ui.selectable_value(&mut self.sizing, Sizing::MinRadius, "by ρ_min (the article's)")
                .on_hover_text("chord L = 2√(2ρ_min·d − d²) at the smallest radius of curvature");
            ui.selectable_value(&mut self.sizing, Sizing::Widest, "widest within d")
                .on_hover_text("the widest uniform spacing whose every chord stays within d (searched)");
        });
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.auto_magnify, "auto")
                .on_hover_text("Magnify so that d shows as about 1.5 % of the curve's size");
            ui.add_enabled(
                !self.auto_magnify,
                egui::Slider::new(&mut self.magnify, ranges::CHORDS_MAGNIFY).logarithmic(true).text("× chord error"),
            );
        });
    }
}
