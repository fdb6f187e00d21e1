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
//!
//! Files: this one holds the state (inputs, the prepared curve, the comparison) and the
//! tab; `controls.rs` the side panel's widgets, `plots.rs` the drawing, `text.rs` the words
//! and the table.

mod controls;
mod plots;
mod text;

use std::rc::Rc;

use eframe::egui;
use glam::DVec3;
use web_time::Instant;

use super::panel::{CreaseProblem, Panel, PanelContext, SceneCrease};
use super::ranges;
use super::widgets::{error_text, rects_json, tolerance_option};
use crate::chords::ChordOptions;
use crate::chords::expr::{Expr, parametric_curve};
use crate::chords::planar::{Ellipse, Hyperbola, Sizing, Spacing, SpacingRow, spacing_nodes};
use crate::crease::CreaseCurve;
use crate::geom::Curve3;
use crate::geom::Parabola;
use crate::numerics::planefit::best_fit_plane;

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
    crease: SceneCrease,
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
            crease: SceneCrease::default(),
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
        self.crease.get(cx.compute).map_err(|e| match e {
            CreaseProblem::Waiting(w) | CreaseProblem::Failed(w) => w,
        })
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

    fn shown_sets(&self) -> [Spacing; 3] {
        [Spacing::EqualError, Spacing::EqualInterval(self.sizing), Spacing::EqualStep(self.sizing)]
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
        "Chords"
    }

    fn paper(&self) -> Option<&'static str> {
        Some(super::papers::CHORDS)
    }

    fn controls(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        self.inputs_ui(ui);
        if self.inputs.kind == CurveKind::Crease {
            ui.separator();
            cx.scene_controls(ui);
        }
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        if self.update(cx) {
            ui.ctx().request_repaint();
        }
        egui::Panel::right("ch_results").resizable(true).default_size(360.0).min_size(260.0).max_size(560.0).show(
            ui,
            |ui| {
                egui::ScrollArea::vertical().show(ui, |ui| {
                    if let Some(w) = &self.waiting {
                        ui.horizontal(|ui| {
                            ui.spinner();
                            ui.label(w);
                        });
                    }
                    if let Some(e) = &self.problem {
                        error_text(ui, format!("{e}. The last valid curve is shown."));
                    }
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
            "ui": rects_json(
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
            "tol_mm" => i.tol_mm = tolerance_option(key, value, &ranges::CHORDS_TOL_MM)?,
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
