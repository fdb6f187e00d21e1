//! The five-axis panel's plots and tables: the two rotary joints over the path (degrees,
//! named as the machine names them, travel limits, blocks at a limit and segments ended by
//! the 90° rotary step marked); every segment's δ = δt + δn against ±E with the swept ball's
//! error along the whole path; and the iterations of every root method at the current E.

use eframe::egui;
use egui_plot::{Corner, HLine, Legend, Line, LineStyle, MarkerShape, Plot, PlotPoints, Points, Span, VLine};

use super::view::{OVERCUT, STOCK};
use super::work::{CompareRow, Plan};
use crate::chords::RootMethod;

const TILT_COLOR: egui::Color32 = egui::Color32::from_rgb(255, 170, 60);
const C_COLOR: egui::Color32 = egui::Color32::from_rgb(110, 200, 255);
const LIMIT_COLOR: egui::Color32 = egui::Color32::from_rgb(235, 90, 80);
const DT_COLOR: egui::Color32 = egui::Color32::from_rgb(250, 210, 80);
const DN_COLOR: egui::Color32 = egui::Color32::from_rgb(190, 130, 255);
const TIP_COLOR: egui::Color32 = egui::Color32::from_rgb(150, 160, 175);
/// Past this many blocks per-block markers become lines (each marker costs a shape a frame).
const MANY_BLOCKS: usize = 300;
/// Within this many degrees of a travel limit a block counts as "at the limit".
const AT_LIMIT_DEG: f64 = 0.5;

/// At most ~2·`buckets` points keeping each bucket's lowest and highest (the envelope).
fn envelope(points: Vec<[f64; 2]>, buckets: usize) -> Vec<[f64; 2]> {
    if points.len() <= 2 * buckets {
        return points;
    }
    let per = points.len().div_ceil(buckets);
    let mut out = Vec::with_capacity(2 * buckets + 2);
    for chunk in points.chunks(per) {
        let lo = chunk.iter().copied().fold(chunk[0], |a, p| if p[1] < a[1] { p } else { a });
        let hi = chunk.iter().copied().fold(chunk[0], |a, p| if p[1] > a[1] { p } else { a });
        if lo[0] <= hi[0] {
            out.extend([lo, hi]);
        } else {
            out.extend([hi, lo]);
        }
    }
    out
}

/// Display name of a root method.
pub fn method_name(m: RootMethod) -> &'static str {
    match m {
        RootMethod::Bisection => "bisection",
        RootMethod::Golden => "golden section",
        RootMethod::Secant => "modified secant (paper)",
        RootMethod::Illinois => "Illinois",
        RootMethod::AndersonBjorck => "Anderson–Björck",
    }
}

fn spans_rotary_limited(p: &mut egui_plot::PlotUi<'_>, plan: &Plan) {
    for w in plan.nodes.windows(2).filter(|w| w[1].rotary_limited) {
        // Unnamed: a named span prints its name inside every shaded band.
        p.span(
            Span::new("", w[0].block.location.s..=w[1].block.location.s)
                .fill(egui::Color32::from_rgba_unmultiplied(255, 200, 80, 28))
                .border_width(0.0),
        );
    }
}

/// The rotary joints over the path.
pub fn joints_plot(ui: &mut egui::Ui, plan: &Plan, s_unit: &str, selected: Option<usize>) {
    let many = plan.nodes.len() > MANY_BLOCKS;
    let machine = &plan.inputs.machine;
    let names = machine.kind.axis_names();
    let mut series = [Vec::new(), Vec::new()];
    let mut at_limit = Vec::new();
    // Along each segment the joints move linearly; draw them at the swept samples so the
    // line follows s as the design parametrises it (the blocks as markers).
    for (k, w) in plan.nodes.windows(2).enumerate() {
        let (a, b) = (&w[0].block, &w[1].block);
        let n = if plan.segs.get(k).is_some() { 4 } else { 1 };
        for i in 0..=n {
            let tau = f64::from(i) / f64::from(n);
            let s = a.location.s + tau * (b.location.s - a.location.s);
            let j = a.joints.lerp(&b.joints, tau);
            for (axis, v) in series.iter_mut().enumerate() {
                v.push([s, j.rotary_rad[axis].to_degrees()]);
            }
        }
    }
    if plan.nodes.len() == 1 {
        let b = &plan.nodes[0].block;
        for (axis, v) in series.iter_mut().enumerate() {
            v.push([b.location.s, b.joints.rotary_rad[axis].to_degrees()]);
        }
    }
    let blocks: [Vec<[f64; 2]>; 2] = [0, 1].map(|axis| {
        plan.nodes.iter().map(|n| [n.block.location.s, n.block.joints.rotary_rad[axis].to_degrees()]).collect()
    });
    for n in &plan.nodes {
        for (axis, lim) in machine.limits_rad.iter().enumerate() {
            if let Some([lo, hi]) = lim {
                let v = n.block.joints.rotary_rad[axis];
                if (v - lo).to_degrees().abs() < AT_LIMIT_DEG || (hi - v).to_degrees().abs() < AT_LIMIT_DEG {
                    at_limit.push([n.block.location.s, v.to_degrees()]);
                }
            }
        }
    }
    Plot::new("fiveaxis_joints")
        .legend(Legend::default().position(Corner::LeftTop).background_alpha(0.5).text_style(egui::TextStyle::Small))
        .x_axis_label(format!("s ({s_unit}) along the path"))
        .y_axis_label("rotary axes (°)")
        .allow_scroll(false)
        .show(ui, |p| {
            spans_rotary_limited(p, plan);
            for (axis, color) in [(0, TILT_COLOR), (1, C_COLOR)] {
                let name = format!("{} (°)", names[axis]);
                p.line(
                    Line::new(name.clone(), PlotPoints::from(std::mem::take(&mut series[axis])))
                        .color(color)
                        .width(1.8),
                );
                if !many {
                    p.points(
                        Points::new(name, PlotPoints::from(blocks[axis].clone()))
                            .color(color)
                            .radius(2.5)
                            .shape(MarkerShape::Circle)
                            .filled(true),
                    );
                }
                if let Some([lo, hi]) = machine.limits_rad[axis] {
                    let label = format!("{} travel {:.0}° to {:.0}°", names[axis], lo.to_degrees(), hi.to_degrees());
                    for v in [lo, hi] {
                        p.hline(
                            HLine::new(label.clone(), v.to_degrees())
                                .color(LIMIT_COLOR.gamma_multiply(0.8))
                                .style(LineStyle::dashed_loose()),
                        );
                    }
                }
            }
            if !at_limit.is_empty() {
                p.points(
                    Points::new("block at a travel limit", PlotPoints::from(at_limit))
                        .color(LIMIT_COLOR)
                        .radius(6.0)
                        .shape(MarkerShape::Diamond)
                        .filled(false),
                );
            }
            markers(p, plan, selected);
        });
}

/// The vertical markers both plots share: where a failed plan stopped, and the middle of
/// the selected segment.
fn markers(p: &mut egui_plot::PlotUi<'_>, plan: &Plan, selected: Option<usize>) {
    if let Some(s) = plan.error.as_ref().and_then(|e| e.s) {
        p.vline(VLine::new("plan stopped here", s).color(LIMIT_COLOR).width(2.0));
    }
    if let Some(w) = selected.and_then(|k| plan.nodes.get(k..k + 2)) {
        let mid = 0.5 * (w[0].block.location.s + w[1].block.location.s);
        p.vline(VLine::new("", mid).color(egui::Color32::from_gray(200)).width(1.0));
    }
}

/// δ, δt, δn per segment (at the worst point of each) and the swept ball's error along the
/// path, in µm, against ±E.
pub fn errors_plot(ui: &mut egui::Ui, plan: &Plan, s_unit: &str, selected: Option<usize>) {
    let many = plan.nodes.len() > MANY_BLOCKS;
    let tol_um = plan.inputs.tol_mm * 1e3;
    let mut along = Vec::new();
    for (k, seg) in plan.segs.iter().enumerate() {
        let (sa, sb) = (plan.nodes[k].block.location.s, plan.nodes[k + 1].block.location.s);
        along.extend(seg.samples.iter().map(|x| [sa + x.tau * (sb - sa), x.delta_mm * 1e3]));
    }
    let (mut total, mut chord, mut nonlinear, mut tip) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for (k, w) in plan.nodes.windows(2).enumerate() {
        let (sa, sb) = (w[0].block.location.s, w[1].block.location.s);
        if let Some(r) = w[1].report {
            let s = sa + r.at_tau * (sb - sa);
            total.push([s, r.total_mm * 1e3]);
            chord.push([s, r.chord_mm * 1e3]);
            nonlinear.push([s, r.nonlinear_mm * 1e3]);
        }
        if let Some(d) = plan.tip_design_mm.get(k).filter(|d| d.is_finite()) {
            tip.push([0.5 * (sa + sb), d * 1e3]);
        }
    }
    Plot::new("fiveaxis_errors")
        .legend(Legend::default().position(Corner::LeftTop).background_alpha(0.5).text_style(egui::TextStyle::Small))
        .x_axis_label(format!("s ({s_unit}) along the path"))
        .y_axis_label("error (µm), overcut +")
        .allow_scroll(false)
        .include_y(1.2 * tol_um)
        .include_y(-1.2 * tol_um)
        .show(ui, |p| {
            spans_rotary_limited(p, plan);
            let e = crate::app::fmt_len(plan.inputs.tol_mm);
            p.hline(HLine::new(format!("±E = {e}"), tol_um).color(OVERCUT.gamma_multiply(0.8)).width(1.0));
            p.hline(HLine::new(format!("±E = {e}"), -tol_um).color(STOCK.gamma_multiply(0.9)).width(1.0));
            p.line(
                Line::new("δ(s), swept ball", PlotPoints::from(envelope(along, 2000)))
                    .color(egui::Color32::from_gray(170))
                    .width(1.0),
            );
            for (name, pts, color, shape) in [
                ("δ per segment", total, egui::Color32::WHITE, MarkerShape::Circle),
                ("δt chord part", chord, DT_COLOR, MarkerShape::Square),
                ("δn nonlinear part", nonlinear, DN_COLOR, MarkerShape::Diamond),
            ] {
                if many {
                    p.line(Line::new(name, PlotPoints::from(pts)).color(color).width(1.2).allow_band(false));
                } else {
                    p.points(
                        Points::new(name, PlotPoints::from(pts)).color(color).radius(3.0).shape(shape).filled(true),
                    );
                }
            }
            let name = "tip to design tip path (reference)";
            if many {
                p.line(
                    Line::new(name, PlotPoints::from(tip)).color(TIP_COLOR).width(1.0).style(LineStyle::dotted_dense()),
                );
            } else {
                p.points(
                    Points::new(name, PlotPoints::from(tip))
                        .color(TIP_COLOR)
                        .radius(2.5)
                        .shape(MarkerShape::Up)
                        .filled(false),
                );
            }
            markers(p, plan, selected);
        });
}

/// Iterations of every root method at the current tolerance, with bars.
pub fn iterations_table(ui: &mut egui::Ui, plan: &Plan) {
    let max = plan
        .compare
        .iter()
        .filter_map(|r| match r {
            CompareRow::Done { iterations, .. } => Some(*iterations),
            _ => None,
        })
        .max()
        .unwrap_or(1)
        .max(1);
    egui::Grid::new("fiveaxis_iterations").num_columns(4).spacing([8.0, 3.0]).striped(true).show(ui, |ui| {
        ui.label(egui::RichText::new("method").strong());
        ui.label(egui::RichText::new("iterations").strong());
        ui.label(egui::RichText::new("blocks").strong());
        ui.label("");
        ui.end_row();
        for (m, row) in RootMethod::ALL.iter().zip(&plan.compare) {
            let shown = *m == plan.inputs.method;
            let name = egui::RichText::new(method_name(*m));
            ui.label(if shown { name.strong() } else { name });
            match row {
                CompareRow::Pending => {
                    ui.label(egui::RichText::new("…").weak());
                    ui.label("");
                    ui.label("");
                }
                CompareRow::Failed(e) => {
                    ui.label(egui::RichText::new("failed").color(LIMIT_COLOR)).on_hover_text(e);
                    ui.label("");
                    ui.label("");
                }
                CompareRow::Done { iterations, nodes, ms } => {
                    ui.label(format!("{iterations}")).on_hover_text(format!("{ms:.1} ms on this device"));
                    ui.label(format!("{nodes}"));
                    let (rect, _) = ui.allocate_exact_size(egui::vec2(56.0, 10.0), egui::Sense::hover());
                    let w = rect.width() * (*iterations as f32 / max as f32);
                    let bar = egui::Rect::from_min_size(rect.min, egui::vec2(w.max(1.0), rect.height()));
                    let color =
                        if shown { egui::Color32::from_rgb(120, 200, 255) } else { egui::Color32::from_gray(140) };
                    ui.painter().rect_filled(bar, 2.0, color);
                }
            }
            ui.end_row();
        }
    });
}

/// The lesson of the iteration table, read from its numbers: whether the paper's modified
/// secant beat bisection here, and why not when it did not (Example 1: the √(8ρE) bracket
/// ignores the nonlinear error, and regula falsi keeps the far end fixed).
pub fn iterations_lesson(ui: &mut egui::Ui, plan: &Plan) {
    let count = |m: RootMethod| {
        RootMethod::ALL.iter().zip(&plan.compare).find(|(k, _)| **k == m).and_then(|(_, row)| match row {
            CompareRow::Done { iterations, .. } => Some(*iterations),
            _ => None,
        })
    };
    let (Some(bisection), Some(secant), Some(illinois)) =
        (count(RootMethod::Bisection), count(RootMethod::Secant), count(RootMethod::Illinois))
    else {
        return;
    };
    let text = if secant > bisection {
        format!(
            "Here the paper's claim fails: its modified secant needs {secant} iterations, bisection {bisection}. \
             The first bracket comes from √(8ρE), which knows nothing of the nonlinear error, so it overshoots \
             far; on a convex error function regula falsi then keeps that far end fixed and creeps toward the \
             root from one side. Bisection only halves the bracket, whatever the function. Illinois scales \
             down the kept end's value each time it stays, so the secant swings to the other side: {illinois}."
        )
    } else {
        format!(
            "The paper's order holds here: modified secant {secant} iterations against bisection's {bisection} \
             (the bracket is close to the root); Illinois, which keeps regula falsi from stalling on one end, {illinois}."
        )
    };
    ui.label(egui::RichText::new(text).small());
}
