//! The chords tab's words: what seed 003 does, and the comparison as a table.

use eframe::egui;

use super::plots::{SET_COLORS, TOL_COLOR};
use super::{ChordsPanel, spacing_index};
use crate::app::fmt_len;
use crate::chords::planar::Spacing;

/// What the tab is about, over its controls.
pub(super) fn intro(ui: &mut egui::Ui) {
    ui.heading("Equal-error chords");
    ui.label(
            egui::RichText::new(
                "Straight chords between nodes on a curve. The article this tab follows puts the nodes so that every chord deviates from the curve by exactly the tolerance d, and compares it with constant parameter steps and constant chord lengths.",
            )
            .weak(),
        );
}

impl ChordsPanel {
    /// The comparison: nodes, worst error and step of each spacing, and the time it took.
    pub(super) fn table(&self, ui: &mut egui::Ui) {
        let Some(c) = &self.comparison else { return };
        let d = c.inputs.tol_mm;
        egui::Grid::new("ch_table").num_columns(4).spacing([8.0, 3.0]).striped(true).show(ui, |ui| {
            for h in ["spacing", "nodes", "worst error", "step"] {
                ui.label(egui::RichText::new(h).strong());
            }
            ui.end_row();
            for sp in Spacing::ALL {
                let shown = self.shown_sets().iter().position(|s| *s == sp);
                ui.horizontal(|ui| {
                    let (rect, _) = ui.allocate_exact_size(egui::vec2(10.0, 10.0), egui::Sense::hover());
                    if let Some(k) = shown {
                        ui.painter().rect_filled(rect, 2.0, SET_COLORS[k]);
                    }
                    let label = egui::RichText::new(sp.label());
                    ui.label(if shown.is_some() { label } else { label.weak() });
                });
                match &c.rows[spacing_index(sp)] {
                    None => {
                        ui.label(egui::RichText::new("…").weak());
                        ui.label("");
                        ui.label("");
                    }
                    Some(Err(e)) => {
                        ui.label(egui::RichText::new("failed").color(TOL_COLOR)).on_hover_text(e);
                        ui.label("");
                        ui.label("");
                    }
                    Some(Ok(row)) => {
                        ui.label(format!("{}", row.params.len()));
                        let w = row.worst_mm();
                        let over = w > d * (1.0 + crate::numerics::tolerance::ROUNDING_REL);
                        ui.label(
                            egui::RichText::new(format!("{}{}", fmt_len(w), if over { " > d" } else { "" }))
                                .color(if over { TOL_COLOR } else { ui.visuals().text_color() }),
                        );
                        ui.label(match sp {
                            Spacing::EqualError => "—".to_owned(),
                            Spacing::EqualInterval(_) => format!("Δ{} = {:.4}", c.prepared.param_symbol(), row.step),
                            Spacing::EqualStep(_) => format!("L = {:.4} mm", row.step),
                        });
                    }
                }
                ui.end_row();
            }
        });
        let done = c.rows.iter().filter(|r| r.is_some()).count();
        if done < c.rows.len() {
            ui.label(egui::RichText::new(format!("computing… {done} of {}", c.rows.len())).weak());
        } else {
            ui.label(egui::RichText::new(format!("computed in {:.1} ms on this device", c.ms)).weak());
        }
    }
}
