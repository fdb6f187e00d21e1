//! What the five-axis tab draws over its 3D view (the view itself is `view.rs`).

use eframe::egui;

use super::text::signed;
use super::view::Swept;
use super::{FiveAxisPanel, view, work};
use crate::app::fmt_len;
use crate::app::widgets::{legend_entry, view_status};

impl FiveAxisPanel {
    /// Draws over the 3D view: P1, P2 and the selected segment's worst error in the scene,
    /// the legend, the colour bar of δ from −E to +E, and the status line.
    pub(super) fn overlay(
        &self,
        painter: &egui::Painter,
        rect: egui::Rect,
        at: &dyn Fn(glam::DVec3) -> Option<egui::Pos2>,
    ) {
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
        let mut entry = |color: egui::Color32, label: &str| legend_entry(painter, x, &mut y, color, label.to_owned());
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
        view_status(painter, rect, ok, status, font);
    }
}
