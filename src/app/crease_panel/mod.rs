//! The crease tab (seed 000): the scene's two surfaces, the interpolated cutter centres and
//! the exact crease in 3D, the playback of the cutter, the summary and the error plots.
//! Its state is the 3D view's (`view.rs`) and the plots' (`plots.rs`); its controls are the
//! shared scene controls plus what the 3D view shows (`controls.rs`). The computation it
//! draws is the app's (`app/compute.rs`), shared with every tab that uses the crease.

mod controls;
mod plots;
mod view;

use eframe::egui;

use super::ablate;
use super::panel::{Panel, PanelContext};

/// The crease tab.
pub struct CreasePanel {
    view: view::CreaseView,
    plots: plots::PlotState,
}

impl Default for CreasePanel {
    fn default() -> Self {
        Self { view: view::CreaseView::new(0), plots: plots::PlotState::default() }
    }
}

impl Panel for CreasePanel {
    fn title(&self) -> &'static str {
        "Crease interpolation"
    }

    fn paper(&self) -> Option<&'static str> {
        Some(super::papers::CREASE)
    }

    fn controls(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        cx.scene_controls(ui);
        controls::display(ui, &mut self.view.settings);
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        if !ablate::hidden(ablate::Part::Bottom) {
            egui::Panel::bottom("plots").resizable(true).default_size(260.0).min_size(140.0).show(ui, |ui| {
                plots::playback_bar(ui, cx.playback, cx.compute, cx.scene.motion.period);
                ui.separator();
                let out = plots::plots(ui, &mut self.plots, cx.compute, cx.scene, cx.playback.k);
                if let Some(r) = out.toward_end_rect {
                    cx.publish("run_toward_end", r);
                }
                if let Some(d) = out.direction {
                    cx.editor.draft.path.direction = Some(d);
                    cx.editor.asked.scene_changed = true;
                }
            });
        }
        egui::CentralPanel::no_frame().show(ui, |ui| {
            self.view.ui(ui, cx.render_state, cx.scene, cx.compute, cx.playback);
        });
    }

    fn scene_opened(&mut self) {
        self.view.request_fit();
    }
}
