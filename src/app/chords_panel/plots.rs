//! The chords tab's drawing: the curve cut three ways and the chords' errors (egui_plot).

use eframe::egui;
use egui_plot::{Corner, HLine, Legend, Line, MarkerShape, Plot, PlotPoints, Points};

use super::{ChordsPanel, CurveKind, SpacingRow, spacing_index};
use crate::app::{fmt_len, ranges};

/// Smallest span (mm) of the curve's plot, so a degenerate curve still has a scale.
const MIN_PLOT_SPAN_MM: f64 = 1e-6;
/// Floor of a chord's squared length (mm²) where the distance to it divides by it: a chord
/// of two equal points does not divide by zero.
const MIN_CHORD_LEN2: f64 = 1e-300;

/// Colours of the three shown spacings (equal-error, equal-interval, equal-step).
pub(super) const SET_COLORS: [egui::Color32; 3] = [
    egui::Color32::from_rgb(120, 230, 120),
    egui::Color32::from_rgb(255, 170, 60),
    egui::Color32::from_rgb(110, 170, 255),
];
const CURVE_COLOR: egui::Color32 = egui::Color32::from_rgb(230, 230, 230);
/// The tolerance d and values over it.
pub(super) const TOL_COLOR: egui::Color32 = egui::Color32::from_rgb(235, 90, 80);

impl ChordsPanel {
    /// The curve with the three shown spacings' chords (their distance from the curve
    /// magnified), and every chord's error along the curve against d.
    pub(super) fn plots(&mut self, ui: &mut egui::Ui) {
        let Some(c) = &self.comparison else {
            ui.centered_and_justified(|ui| ui.label(self.waiting.as_deref().unwrap_or("No curve yet.")));
            return;
        };
        let p = &c.prepared;
        let curve = p.curve.as_ref();
        let (lo, hi) = curve.range();
        let dense: Vec<[f64; 2]> =
            (0..=1500).map(|k| p.project.apply(curve.point_at(lo + (hi - lo) * f64::from(k) / 1500.0))).collect();
        let extent = {
            let (mut a, mut b) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
            for q in &dense {
                for i in 0..2 {
                    a[i] = a[i].min(q[i]);
                    b[i] = b[i].max(q[i]);
                }
            }
            (b[0] - a[0]).max(b[1] - a[1]).max(MIN_PLOT_SPAN_MM)
        };
        let d = c.inputs.tol_mm;
        if self.auto_magnify {
            self.magnify =
                (0.015 * extent / d).clamp(*ranges::CHORDS_MAGNIFY.start(), *ranges::CHORDS_MAGNIFY.end()).round();
        }
        let k = self.magnify;
        let sets: Vec<(usize, &SpacingRow)> = self
            .shown_sets()
            .iter()
            .enumerate()
            .filter_map(|(i, sp)| c.rows[spacing_index(*sp)].as_ref().and_then(|r| r.as_ref().ok()).map(|r| (i, r)))
            .collect();
        let available = ui.available_size();
        let geometry_h = (available.y * 0.64).max(120.0);
        let magnified = if k > 1.0 { format!(", chords' distance from the curve ×{k:.0}") } else { String::new() };
        ui.label(egui::RichText::new(format!("{}{magnified}", p.title)).strong());
        Plot::new("ch_geometry")
            .height(geometry_h - 20.0)
            .data_aspect(1.0)
            .legend(
                Legend::default()
                    .position(Corner::RightBottom)
                    .background_alpha(0.6)
                    .text_style(egui::TextStyle::Small),
            )
            .x_axis_label(if matches!(self.inputs.kind, CurveKind::Crease) {
                "u (mm, best-fit plane)"
            } else {
                "x (mm)"
            })
            .y_axis_label(if matches!(self.inputs.kind, CurveKind::Crease) { "v (mm)" } else { "y (mm)" })
            .allow_scroll(false)
            .show(ui, |pl| {
                pl.line(Line::new("curve", PlotPoints::from(dense.clone())).color(CURVE_COLOR).width(1.2));
                for (i, row) in &sets {
                    let name = format!("{} ({} nodes)", self.shown_sets()[*i].label(), row.params.len());
                    // Each chord drawn with its distance from the arc magnified k times.
                    let mut pts = Vec::new();
                    for w in row.params.windows(2) {
                        let (a, b) = (curve.point_at(w[0]), curve.point_at(w[1]));
                        let ab = b - a;
                        let len2 = ab.length_squared().max(MIN_CHORD_LEN2);
                        for j in 0..=24 {
                            let u = w[0] + (w[1] - w[0]) * f64::from(j) / 24.0;
                            let q = curve.point_at(u);
                            let lam = ((q - a).dot(ab) / len2).clamp(0.0, 1.0);
                            let on_chord = a + ab * lam;
                            pts.push(p.project.apply(q + (on_chord - q) * k));
                        }
                    }
                    let color = SET_COLORS[*i];
                    pl.line(Line::new(name.clone(), PlotPoints::from(pts)).color(color).width(1.6));
                    let nodes: Vec<[f64; 2]> = row.params.iter().map(|s| p.project.apply(curve.point_at(*s))).collect();
                    let (shape, radius) =
                        [(MarkerShape::Circle, 4.5), (MarkerShape::Square, 3.5), (MarkerShape::Diamond, 3.0)][*i];
                    pl.points(
                        Points::new(name, PlotPoints::from(nodes))
                            .color(color)
                            .shape(shape)
                            .radius(radius)
                            .filled(*i == 0),
                    );
                }
            });
        ui.label(egui::RichText::new("every chord's error along the curve").strong());
        Plot::new("ch_errors")
            .legend(
                Legend::default()
                    .position(Corner::RightBottom)
                    .background_alpha(0.6)
                    .text_style(egui::TextStyle::Small),
            )
            .x_axis_label(p.param)
            .y_axis_label("chord error (µm)")
            .include_y(0.0)
            .include_y(1.15 * d * 1e3)
            .allow_scroll(false)
            .show(ui, |pl| {
                pl.hline(HLine::new(format!("d = {}", fmt_len(d)), d * 1e3).color(TOL_COLOR).width(1.2));
                for (i, row) in &sets {
                    let mut pts = Vec::with_capacity(2 * row.errors_mm.len());
                    for (w, e) in row.params.windows(2).zip(&row.errors_mm) {
                        pts.push([w[0], e * 1e3]);
                        pts.push([w[1], e * 1e3]);
                    }
                    pl.line(
                        Line::new(self.shown_sets()[*i].label(), PlotPoints::from(pts))
                            .color(SET_COLORS[*i])
                            .width(if *i == 0 { 2.2 } else { 1.4 })
                            .allow_band(false),
                    );
                }
            });
    }
}
