//! The chords view (seed 003): a plane curve cut by straight chords three ways — every chord
//! deviating by exactly the tolerance d (equal-error), constant parameter steps
//! (equal-interval) and constant chord lengths (equal-step), the last two sized as seed 003
//! does (from the smallest radius of curvature) or as wide as stays within d — with the
//! node counts, the worst errors and every chord's error along the curve.
//!
//! Curves: the parabola y = a·x², the hyperbola x·y = k, the ellipse, any parametric curve
//! typed as x(t), y(t) (the core's `chords::expr`), and the crease of the current scene. The
//! crease is a space curve: its chords are computed and measured in 3D, and drawn projected
//! onto the crease's best-fit plane (the plane of its two principal directions).
//!
//! Each spacing is computed on its own frame, so the page never waits for all five.

use std::rc::Rc;

use eframe::egui;
use egui_plot::{Corner, HLine, Legend, Line, MarkerShape, Plot, PlotPoints, Points};
use glam::DVec3;
use web_time::Instant;

use super::fmt_len;
use super::panel::{Panel, PanelContext};
use crate::chords::ChordOptions;
use crate::chords::expr::{Expr, parametric_curve};
use crate::chords::planar::{Ellipse, Hyperbola, Sizing, Spacing, SpacingRow, spacing_nodes};
use crate::crease::CreaseCurve;
use crate::geom::Curve3;
use crate::geom::Parabola;
use crate::numerics::planefit::best_fit_plane;

/// Range of the tolerance slider (mm).
const TOL_RANGE: std::ops::RangeInclusive<f64> = 0.001..=1.0;

/// Which curve.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum CurveKind {
    Parabola,
    Hyperbola,
    Ellipse,
    Typed,
    Crease,
}

impl CurveKind {
    const ALL: [Self; 5] = [Self::Parabola, Self::Hyperbola, Self::Ellipse, Self::Typed, Self::Crease];

    fn label(self) -> &'static str {
        match self {
            Self::Parabola => "parabola y = a·x²",
            Self::Hyperbola => "hyperbola x·y = k",
            Self::Ellipse => "ellipse (a·cos t, b·sin t)",
            Self::Typed => "parametric x(t), y(t) (typed)",
            Self::Crease => "crease of the current scene",
        }
    }

    fn id(self) -> &'static str {
        match self {
            Self::Parabola => "parabola",
            Self::Hyperbola => "hyperbola",
            Self::Ellipse => "ellipse",
            Self::Typed => "typed",
            Self::Crease => "crease",
        }
    }
}

/// The editable inputs.
#[derive(Clone, Debug, PartialEq)]
struct Inputs {
    kind: CurveKind,
    tol_mm: f64,
    parabola: [f64; 3],
    hyperbola: [f64; 3],
    ellipse: [f64; 4],
    x_text: String,
    y_text: String,
    t0_text: String,
    t1_text: String,
    generation: u64,
}

impl Default for Inputs {
    fn default() -> Self {
        Self {
            kind: CurveKind::Parabola,
            tol_mm: 0.05,
            parabola: [0.025, 0.0, 60.0],
            hyperbola: [400.0, 5.0, 80.0],
            ellipse: [60.0, 30.0, 0.0, 90.0],
            x_text: "(40 + 6*cos(5*t))*cos(t)".into(),
            y_text: "(40 + 6*cos(5*t))*sin(t)".into(),
            t0_text: "0".into(),
            t1_text: "2*pi".into(),
            generation: 0,
        }
    }
}

/// The curve being cut: the core curve, its title, how it is drawn (2D coordinates of
/// 3D points) and the parameter's name.
struct Prepared {
    curve: Rc<dyn Curve3>,
    title: String,
    project: Projection,
    param: &'static str,
}

/// 3D → plot coordinates: the identity on (x, y) for plane curves, the best-fit plane for
/// the crease.
#[derive(Clone, Copy, Debug)]
struct Projection {
    origin: DVec3,
    u: DVec3,
    v: DVec3,
}

impl Projection {
    const XY: Self = Self { origin: DVec3::ZERO, u: DVec3::X, v: DVec3::Y };

    fn apply(&self, p: DVec3) -> [f64; 2] {
        let d = p - self.origin;
        [d.dot(self.u), d.dot(self.v)]
    }

    /// The plane through the centroid spanned by the two largest principal directions of the
    /// points ([`best_fit_plane`]).
    fn best_fit(points: &[DVec3]) -> Self {
        let fit = best_fit_plane(points);
        Self { origin: fit.origin, u: fit.u, v: fit.v }
    }
}

/// The five rows of the comparison, computed one per frame.
struct Comparison {
    inputs: Inputs,
    prepared: Rc<Prepared>,
    rows: Vec<Option<Result<SpacingRow, String>>>,
    ms: f64,
}

const SET_COLORS: [egui::Color32; 3] = [
    egui::Color32::from_rgb(120, 230, 120),
    egui::Color32::from_rgb(255, 170, 60),
    egui::Color32::from_rgb(110, 170, 255),
];
const CURVE_COLOR: egui::Color32 = egui::Color32::from_rgb(230, 230, 230);
const TOL_COLOR: egui::Color32 = egui::Color32::from_rgb(235, 90, 80);

/// The chords panel.
pub struct ChordsPanel {
    inputs: Inputs,
    sizing: Sizing,
    magnify: f64,
    auto_magnify: bool,
    prepared: Option<Rc<Prepared>>,
    prepared_for: Option<Inputs>,
    problem: Option<String>,
    waiting: Option<String>,
    crease: Option<(u64, Result<Rc<CreaseCurve>, String>)>,
    comparison: Option<Comparison>,
    tol_rect: Option<egui::Rect>,
    plot_rect: Option<egui::Rect>,
    curve_rect: Option<egui::Rect>,
}

impl Default for ChordsPanel {
    fn default() -> Self {
        Self {
            inputs: Inputs::default(),
            sizing: Sizing::MinRadius,
            magnify: 1.0,
            auto_magnify: true,
            prepared: None,
            prepared_for: None,
            problem: None,
            waiting: None,
            crease: None,
            comparison: None,
            tol_rect: None,
            plot_rect: None,
            curve_rect: None,
        }
    }
}

/// A constant typed as an expression (`2*pi`).
fn constant(text: &str, what: &str) -> Result<f64, String> {
    let e = Expr::parse(text).map_err(|e| format!("{what}, {e}"))?;
    let v = e.eval(0.0);
    if text.contains('t') && Expr::parse(text).is_ok_and(|e| (e.eval(1.0) - v).abs() > 0.0) {
        return Err(format!("{what} must be a number, not depend on t"));
    }
    if v.is_finite() { Ok(v) } else { Err(format!("{what} is not a finite number")) }
}

fn spacing_index(s: Spacing) -> usize {
    Spacing::ALL.iter().position(|x| *x == s).unwrap_or(0)
}

impl ChordsPanel {
    fn crease(&mut self, cx: &PanelContext<'_>) -> Result<Rc<CreaseCurve>, String> {
        let c = cx.compute;
        if c.running() {
            return Err(format!("waiting for the crease of the scene: {} periods so far…", c.periods.len()));
        }
        if self.crease.as_ref().is_none_or(|(g, _)| *g != c.generation) {
            let built = match (&c.job, &c.outcome) {
                (_, Some(Err(e))) => Err(format!("the crease of this scene could not be computed — {e}")),
                (Some(job), _) => {
                    let rows: Vec<_> = c.periods.iter().map(|p| p.row).collect();
                    CreaseCurve::from_rows(job, &rows)
                        .map(Rc::new)
                        .ok_or_else(|| "the crease of this scene has fewer than two points".to_owned())
                }
                (None, _) => Err("the scene has no valid crease".to_owned()),
            };
            self.crease = Some((c.generation, built));
        }
        self.crease.as_ref().map_or_else(|| Err("no crease".to_owned()), |(_, r)| r.clone())
    }

    /// The curve for the inputs, or what is wrong with them.
    fn prepare(&mut self, cx: &PanelContext<'_>) -> Result<Prepared, String> {
        let i = &self.inputs;
        match i.kind {
            CurveKind::Parabola => {
                let [a, x0, x1] = i.parabola;
                if x0 >= x1 {
                    return Err(format!("x from {x0} to {x1} mm is empty; make the first x smaller than the last"));
                }
                if a == 0.0 {
                    return Err("a = 0 is a straight line (one chord); give a ≠ 0, e.g. 0.025".into());
                }
                Ok(Prepared {
                    curve: Rc::new(Parabola { a, x0, x1, z: 0.0 }),
                    title: format!("parabola y = {a}·x², {x0} ≤ x ≤ {x1} mm"),
                    project: Projection::XY,
                    param: "x (mm)",
                })
            }
            CurveKind::Hyperbola => {
                let [k, x0, x1] = i.hyperbola;
                if k <= 0.0 {
                    return Err(format!("k = {k} mm²: give k > 0, e.g. 400"));
                }
                if !(x0 > 0.0 && x1 > x0) {
                    return Err(format!("x from {x0} to {x1} mm: give 0 < first x < last x"));
                }
                Ok(Prepared {
                    curve: Rc::new(Hyperbola { k, x0, x1 }),
                    title: format!("hyperbola x·y = {k} mm², {x0} ≤ x ≤ {x1} mm"),
                    project: Projection::XY,
                    param: "x (mm)",
                })
            }
            CurveKind::Ellipse => {
                let [a, b, t0, t1] = i.ellipse;
                if !(a > 0.0 && b > 0.0) {
                    return Err(format!("semi-axes {a} and {b} mm: give both > 0"));
                }
                if t0 >= t1 {
                    return Err(format!("t from {t0}° to {t1}° is empty; make the first angle smaller"));
                }
                Ok(Prepared {
                    curve: Rc::new(Ellipse { a, b, t0: t0.to_radians(), t1: t1.to_radians() }),
                    title: format!("ellipse {a} × {b} mm, {t0}° ≤ t ≤ {t1}°"),
                    project: Projection::XY,
                    param: "t (rad)",
                })
            }
            CurveKind::Typed => {
                let t0 = constant(&i.t0_text, "t0")?;
                let t1 = constant(&i.t1_text, "t1")?;
                let c = parametric_curve(&i.x_text, &i.y_text, t0, t1).map_err(|e| e.to_string())?;
                Ok(Prepared {
                    curve: Rc::new(c),
                    title: format!("x(t) = {}, y(t) = {}, {t0:.4} ≤ t ≤ {t1:.4}", i.x_text, i.y_text),
                    project: Projection::XY,
                    param: "t",
                })
            }
            CurveKind::Crease => {
                let curve = self.crease(cx)?;
                let (a, b) = curve.range();
                let pts: Vec<DVec3> = (0..=400).map(|k| curve.point_at(a + (b - a) * f64::from(k) / 400.0)).collect();
                let project = Projection::best_fit(&pts);
                Ok(Prepared {
                    title: format!("ball-centre crease of \"{}\" ({:.1} mm long)", cx.scene.name, b - a),
                    curve,
                    project,
                    param: "s (mm, chord length)",
                })
            }
        }
    }

    fn update(&mut self, cx: &PanelContext<'_>) -> bool {
        self.inputs.generation = if self.inputs.kind == CurveKind::Crease { cx.compute.generation } else { 0 };
        let running = self.inputs.kind == CurveKind::Crease && cx.compute.running();
        if self.prepared_for.as_ref() != Some(&self.inputs) || running {
            self.prepared_for = Some(self.inputs.clone());
            self.waiting = None;
            match self.prepare(cx) {
                Ok(p) => {
                    self.problem = None;
                    self.prepared = Some(Rc::new(p));
                }
                Err(e) if e.starts_with("waiting") => {
                    self.waiting = Some(e);
                    self.prepared = None;
                    self.prepared_for = None;
                    self.comparison = None;
                }
                Err(e) => {
                    // Keep the last good curve on screen; say what is wrong with the new one.
                    self.problem = Some(e);
                }
            }
        }
        let Some(prepared) = self.prepared.clone() else { return running };
        let stale = self.comparison.as_ref().is_none_or(|c| {
            !Rc::ptr_eq(&c.prepared, &prepared) || c.inputs.tol_mm.to_bits() != self.inputs.tol_mm.to_bits()
        });
        if stale {
            self.comparison = Some(Comparison {
                inputs: self.inputs.clone(),
                prepared,
                rows: vec![None; Spacing::ALL.len()],
                ms: 0.0,
            });
        }
        let Some(c) = self.comparison.as_mut() else { return running };
        // One spacing per frame, the equal-error nodes and the shown sizing first.
        let order = [
            Spacing::EqualError,
            Spacing::EqualInterval(self.sizing),
            Spacing::EqualStep(self.sizing),
            Spacing::EqualInterval(other(self.sizing)),
            Spacing::EqualStep(other(self.sizing)),
        ];
        if let Some(sp) = order.into_iter().find(|s| c.rows[spacing_index(*s)].is_none()) {
            let t0 = Instant::now();
            let row = spacing_nodes(c.prepared.curve.as_ref(), c.inputs.tol_mm, sp, &ChordOptions::default())
                .map_err(|e| e.to_string());
            c.ms += t0.elapsed().as_secs_f64() * 1e3;
            c.rows[spacing_index(sp)] = Some(row);
        }
        running || c.rows.iter().any(Option::is_none)
    }

    fn controls(&mut self, ui: &mut egui::Ui) {
        ui.heading("Equal-error chords");
        ui.label(
            egui::RichText::new(
                "Straight chords between nodes on a curve. Seed 003 puts the nodes so that every chord deviates from the curve by exactly the tolerance d, and compares it with constant parameter steps and constant chord lengths.",
            )
            .weak(),
        );
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
                ui.add(egui::DragValue::new(v).speed(speed).range(-1.0e5..=1.0e5).suffix(suffix));
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
        let mut tol = i.tol_mm;
        let r = ui.add(
            egui::Slider::new(&mut tol, TOL_RANGE)
                .logarithmic(true)
                .text("tolerance d")
                .suffix(" mm")
                .custom_formatter(|v, _| format!("{v:.4}"))
                .clamping(egui::SliderClamping::Always),
        );
        self.tol_rect = Some(r.rect);
        if r.changed() && tol.is_finite() {
            i.tol_mm = tol.clamp(*TOL_RANGE.start(), *TOL_RANGE.end());
        }
        ui.horizontal(|ui| {
            ui.label("uniform spacings sized");
            ui.selectable_value(&mut self.sizing, Sizing::MinRadius, "by ρ_min (seed 003)")
                .on_hover_text("chord L = 2√(2ρ_min·d − d²) at the smallest radius of curvature");
            ui.selectable_value(&mut self.sizing, Sizing::Widest, "widest within d")
                .on_hover_text("the widest uniform spacing whose every chord stays within d (searched)");
        });
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.auto_magnify, "auto")
                .on_hover_text("Magnify so that d shows as about 1.5 % of the curve's size");
            ui.add_enabled(
                !self.auto_magnify,
                egui::Slider::new(&mut self.magnify, 1.0..=100_000.0).logarithmic(true).text("× chord error"),
            );
        });
    }

    fn table(&self, ui: &mut egui::Ui) {
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
                        let over = w > d * (1.0 + 1e-9);
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

    fn shown_sets(&self) -> [Spacing; 3] {
        [Spacing::EqualError, Spacing::EqualInterval(self.sizing), Spacing::EqualStep(self.sizing)]
    }

    fn plots(&mut self, ui: &mut egui::Ui) {
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
            (b[0] - a[0]).max(b[1] - a[1]).max(1e-6)
        };
        let d = c.inputs.tol_mm;
        if self.auto_magnify {
            self.magnify = (0.015 * extent / d).clamp(1.0, 100_000.0).round();
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
                        let len2 = ab.length_squared().max(1e-300);
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

fn other(s: Sizing) -> Sizing {
    match s {
        Sizing::MinRadius => Sizing::Widest,
        Sizing::Widest => Sizing::MinRadius,
    }
}

impl Prepared {
    fn param_symbol(&self) -> &'static str {
        match self.param {
            "x (mm)" => "x",
            "t (rad)" | "t" => "t",
            _ => "s",
        }
    }
}

impl Panel for ChordsPanel {
    fn title(&self) -> &'static str {
        "Chords (seed 003)"
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        if self.update(cx) {
            ui.ctx().request_repaint();
        }
        egui::Panel::left("ch_controls").resizable(true).default_size(330.0).min_size(260.0).max_size(520.0).show(
            ui,
            |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    self.controls(ui);
                    if let Some(w) = &self.waiting {
                        ui.horizontal(|ui| {
                            ui.spinner();
                            ui.label(w);
                        });
                    }
                    if let Some(e) = &self.problem {
                        egui::Frame::new()
                            .fill(egui::Color32::from_rgb(80, 24, 24))
                            .inner_margin(6.0)
                            .corner_radius(4.0)
                            .show(ui, |ui| {
                                ui.colored_label(egui::Color32::WHITE, format!("{e}. The last valid curve is shown."));
                            });
                    }
                    ui.separator();
                    self.table(ui);
                });
            },
        );
        let r = egui::CentralPanel::default().show(ui, |ui| self.plots(ui));
        self.plot_rect = Some(r.response.rect);
    }

    fn status(&self) -> serde_json::Value {
        let rows: serde_json::Map<String, serde_json::Value> = self
            .comparison
            .as_ref()
            .map(|c| {
                Spacing::ALL
                    .iter()
                    .zip(&c.rows)
                    .map(|(sp, r)| {
                        let v = match r {
                            Some(Ok(row)) => {
                                serde_json::json!({ "nodes": row.params.len(), "worst_mm": row.worst_mm() })
                            }
                            Some(Err(e)) => serde_json::json!({ "error": e }),
                            None => serde_json::Value::Null,
                        };
                        (sp.label().to_owned(), v)
                    })
                    .collect()
            })
            .unwrap_or_default();
        // The plane the curve is drawn in (its normal; +Z for plane curves).
        let normal = self.comparison.as_ref().map(|c| {
            let n = c.prepared.project.u.cross(c.prepared.project.v);
            [n.x, n.y, n.z]
        });
        serde_json::json!({
            "curve": self.inputs.kind.id(),
            "plot_plane_normal": normal,
            "tol_mm": self.inputs.tol_mm,
            // A widget changed after this frame's update counts as computing too.
            "computing": self.waiting.is_some()
                || self.comparison.as_ref().is_none_or(|c| c.rows.iter().any(Option::is_none))
                || self.prepared_for.as_ref() != Some(&self.inputs)
                || self.comparison.as_ref().is_some_and(|c| c.inputs.tol_mm.to_bits() != self.inputs.tol_mm.to_bits()),
            "rows": rows,
            "error": self.problem.clone().unwrap_or_default(),
            "ui": super::fiveaxis_panel::rects_json(
                &[("tolerance", self.tol_rect), ("plots", self.plot_rect), ("curve", self.curve_rect)]
                    .into_iter()
                    .filter_map(|(k, r)| r.map(|r| (k, r)))
                    .collect::<Vec<_>>()
            ),
        })
    }

    fn set_option(&mut self, key: &str, value: &str) -> Result<(), String> {
        let i = &mut self.inputs;
        let number = || value.parse::<f64>().map_err(|_| format!("{key}: \"{value}\" is not a number"));
        match key {
            "curve" => {
                i.kind = CurveKind::ALL
                    .into_iter()
                    .find(|k| k.id() == value)
                    .ok_or_else(|| format!("curve: \"{value}\"; give parabola, hyperbola, ellipse, typed or crease"))?;
            }
            "x" => i.x_text = value.to_owned(),
            "y" => i.y_text = value.to_owned(),
            "t0" => i.t0_text = value.to_owned(),
            "t1" => i.t1_text = value.to_owned(),
            "a" => i.parabola[0] = number()?,
            "tol_mm" => {
                let t = number()?;
                if !(t > 0.0 && t.is_finite()) {
                    return Err(format!("tol_mm: {t} is not a positive length"));
                }
                i.tol_mm = t.clamp(*TOL_RANGE.start(), *TOL_RANGE.end());
            }
            "sizing" => {
                self.sizing = match value {
                    "min-radius" => Sizing::MinRadius,
                    "widest" => Sizing::Widest,
                    _ => return Err(format!("sizing: \"{value}\"; give min-radius or widest")),
                }
            }
            _ => return Err(format!("no option \"{key}\"; give curve, x, y, t0, t1, a, tol_mm or sizing")),
        }
        Ok(())
    }
}
