//! The crease view's own controls: what its 3D view shows (the scene's inputs are the shared
//! [`crate::app::scene_controls`]).

use eframe::egui;

use super::view::ViewSettings;
use crate::app::ranges;
use crate::app::widgets::section;

/// The "Display" section: layers of the 3D view and the exaggeration of the deviation.
pub fn display(ui: &mut egui::Ui, view: &mut ViewSettings) {
    section(ui, "Display", true, |ui| {
        ui.checkbox(&mut view.cutter_side_only, "surfaces from the cutter side only");
        ui.checkbox(&mut view.show_offsets, "offset surfaces (translucent)");
        ui.checkbox(&mut view.show_iso, "iso-parameter lines");
        ui.checkbox(&mut view.show_cutters, "ball cutters along the path");
        ui.checkbox(&mut view.show_exact, "exact crease");
        ui.add(
            egui::Slider::new(&mut view.magnify, ranges::CREASE_MAGNIFY)
                .logarithmic(true)
                .text("× deviation from the exact crease"),
        );
    });
}
