//! The five-axis tab's words: the plan's summary, the selected segment, the status line over
//! the view, and Example 1 told before and after, as in the paper.

use eframe::egui;

use super::work::Plan;
use super::{FiveAxisPanel, plots, view};
use crate::app::fmt_len;
use crate::app::widgets::error_text;
use crate::fiveaxis::StepNode;
use crate::numerics::format::fmt_num;
use crate::plan::StepsTime;

/// A worst deviation is reported over the tolerance only beyond this fraction of it: the
/// search accepts a node whose error rounds a part in a million above E.
const OVER_TOLERANCE_REL: f64 = 1e-6;

/// A signed error in words: `+5.00 µm (overcut)`, `−2.00 µm (stock)`; below a picometre
/// `0 (exact to 1 pm)`.
pub(super) fn signed(mm: f64) -> String {
    // Below a picometre an error is rounding: say exact.
    if mm.abs() < crate::numerics::tolerance::MEASUREMENT_FLOOR_MM {
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
    /// The tab's results beside its view: the wait or the problem, Example 1's story, the
    /// summary, the iterations of every method, the selected segment.
    pub(super) fn results(&mut self, ui: &mut egui::Ui) {
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
            error_text(ui, e);
        }
        if let Some(plan) = self.shown() {
            example1_story(ui, plan);
        }
        self.summary(ui);
        self.time_ui(ui);
        ui.separator();
        ui.label(egui::RichText::new(format!("Iterations per method at E = {}", fmt_len(self.tol_mm))).strong());
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
    }

    /// The plan in numbers: blocks, worst δ, iterations, compute time.
    pub(super) fn summary(&mut self, ui: &mut egui::Ui) {
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
                let over = w.abs() > plan.inputs.tol_mm * (1.0 + OVER_TOLERANCE_REL);
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

    /// The plans' time on the machine: one line "time on <machine> at F …: before X s, after
    /// Y s" (the plan's time for sources without a before/after), and the two lower bounds.
    pub(super) fn time_ui(&self, ui: &mut egui::Ui) {
        let (feed, default) = self.feed();
        let kind = self.machine.kind.as_str();
        let head = format!(
            "time on {kind} at F {} mm/min{}",
            fmt_num(feed),
            if default { " (default: this path has no feed)" } else { " (the scene's feed)" }
        );
        let times = self.plan.as_ref().and_then(|p| p.times.as_ref());
        let Some(t) = times else {
            ui.label(egui::RichText::new(format!("{head}: computing…")).weak());
            return;
        };
        let secs = |r: &Result<StepsTime, String>| match r {
            Ok(t) => format!("{:.3} s", t.cycle_s),
            Err(_) => "—".to_owned(),
        };
        let line = match &t.before {
            Some(b) => format!("{head}: before {}, after {}", secs(b), secs(&t.after)),
            None => format!("{head}: {}", secs(&t.after)),
        };
        ui.label(egui::RichText::new(line).strong()).on_hover_text(
            "Cycle time on the dynamics preset of the machine's structure (docs/feed-planning.md): each block a straight joint move programmed to take its tool-tip chord / F (inverse time, G93), every joint within its velocity, acceleration and jerk limits, junctions blended within the preset's contour tolerance.",
        );
        let bounds = |r: &Result<StepsTime, String>| match r {
            Ok(t) => format!("feed alone {:.3} s, rotary axes ≥ {:.3} s", t.feed_s, t.rotary_bound_s),
            Err(e) => e.clone(),
        };
        let detail = match &t.before {
            Some(b) => format!("before: {}; after: {}", bounds(b), bounds(&t.after)),
            None => bounds(&t.after),
        };
        ui.label(egui::RichText::new(detail).weak());
    }

    /// The selected segment (a slider picks it): its δ and parts, its blocks' joints.
    pub(super) fn segment_ui(&mut self, ui: &mut egui::Ui) {
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
                let tiny = |v: f64| if v < crate::numerics::tolerance::MEASUREMENT_FLOOR_MM { 0.0 } else { v };
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

    /// The line over the view: what is computed, or why nothing is.
    pub(super) fn status_line(&self) -> (bool, String) {
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
