//! The tab's tool editor: each tool the program uses, its shape and size and its body (flute
//! length, shank and holder radius × length, whether it cuts at its centre) as the tables give
//! them, changed here and applied as cutter specs (`N:shape:diameter[:corner or angle]` with
//! the body words `flute=`, `shank=r:l`, `holder=r:l`, `nocentre`: the command line's
//! `--tool`) over the tool table and project. A body length not given is the simulation's
//! default, shown as "assumed"; an edited one is written into the spec. A tool keeps its
//! table's length offset (`ToolTable::set_cutter`).

use std::collections::BTreeMap;

use eframe::egui;

use crate::gcode::interp::tools::{DEFAULT_DRILL_POINT_DEG, ToolShape, parse_tool_spec};
use crate::geom::BodySpec;
use crate::jobs::user_program::ToolRow;

/// Shapes a spec can name, in the combo box's order.
const SHAPES: [&str; 5] = ["flat", "ball", "bull", "v", "drill"];

/// One tool as edited (mm and degrees).
#[derive(Clone, Debug, PartialEq)]
pub struct ToolDraft {
    /// Index in [`SHAPES`].
    shape: usize,
    /// Cutting diameter (mm).
    diameter_mm: f64,
    /// Bull nose corner radius (mm), V tip angle or drill point angle (degrees).
    extra: f64,
    /// The body lengths given (mm) and centre cutting: by the spec, or edited here.
    body: BodySpec,
}

/// Shortest body length the editor writes (mm): the spec's words take lengths above 0.
const MIN_BODY_MM: f64 = 0.01;

/// A body length's drag value (mm).
fn length(v: &mut f64) -> egui::DragValue<'_> {
    egui::DragValue::new(v).speed(0.1).range(MIN_BODY_MM..=1000.0).max_decimals(3).suffix(" mm")
}

/// A body length as the spec writes it: to the micrometre, at least [`MIN_BODY_MM`].
fn body_mm(v: f64) -> f64 {
    ((v * 1e3).round() / 1e3).max(MIN_BODY_MM)
}

impl ToolDraft {
    /// From a spec; a flat 3 mm end mill when the spec is empty or unreadable.
    fn from_spec(spec: &str) -> Self {
        let Ok(e) = parse_tool_spec(spec) else {
            return Self { shape: 0, diameter_mm: 3.0, extra: 0.0, body: BodySpec::default() };
        };
        let (shape, extra) = match e.shape {
            ToolShape::Ball => (1, 0.0),
            ToolShape::Bull { corner_radius_mm } => (2, corner_radius_mm),
            ToolShape::V { tip_angle_deg } => (3, tip_angle_deg),
            ToolShape::Drill { point_angle_deg } => (4, point_angle_deg),
            _ => (0, 0.0),
        };
        Self { shape, diameter_mm: e.diameter_mm, extra, body: e.body }
    }

    /// As a spec for tool `number`, with the body words given (as `ToolEntry::spec` writes
    /// them, so an unedited draft is its tool's spec).
    fn spec(&self, number: i32) -> String {
        let (s, d) = (SHAPES[self.shape.min(SHAPES.len() - 1)], self.diameter_mm);
        let mut spec = match self.shape {
            0 | 1 => format!("{number}:{s}:{d}"),
            _ => format!("{number}:{s}:{d}:{}", self.extra),
        };
        if !self.body.is_empty() {
            spec.push(',');
            spec.push_str(&self.body.words(","));
        }
        spec
    }

    /// The body's widgets: flute length, shank and holder radius × length (mm), and whether
    /// it cuts at its centre, each showing the length the simulation takes (`now`: the tool
    /// as read) until it is edited; an edit gives that length in the spec.
    fn body_ui(&mut self, ui: &mut egui::Ui, now: &ToolRow) {
        egui::Grid::new(("tool_body", now.number)).num_columns(2).show(ui, |ui| {
            ui.label("flutes");
            let mut f = self.body.flute_mm.unwrap_or(now.body_mm[0]);
            if ui.add(length(&mut f)).on_hover_text("flute (cutting) length from the tip").changed() {
                self.body.flute_mm = Some(body_mm(f));
            }
            ui.end_row();
            let pair = |ui: &mut egui::Ui, given: &mut Option<(f64, f64)>, now: (f64, f64), what: &str| {
                let (mut r, mut l) = given.unwrap_or(now);
                ui.horizontal(|ui| {
                    let a = ui.add(length(&mut r)).on_hover_text(format!("{what} radius"));
                    ui.label("×");
                    let b = ui.add(length(&mut l)).on_hover_text(format!("{what} length"));
                    if a.changed() || b.changed() {
                        *given = Some((body_mm(r), body_mm(l)));
                    }
                });
            };
            ui.label("shank R");
            pair(ui, &mut self.body.shank_mm, (now.body_mm[1], now.body_mm[2]), "shank (above the flutes)");
            ui.end_row();
            ui.label("holder R");
            pair(ui, &mut self.body.holder_mm, (now.body_mm[3], now.body_mm[4]), "holder (above the shank)");
            ui.end_row();
        });
        let mut centre = self.body.centre_cutting.unwrap_or(now.centre_cutting);
        if ui
            .checkbox(&mut centre, "cuts at its centre")
            .on_hover_text(
                "an end mill whose teeth stop short of the axis cannot plunge: untick it to have plunges reported",
            )
            .changed()
        {
            self.body.centre_cutting = Some(centre);
        }
    }

    /// What the extra number is, with its unit, for shapes that have one.
    fn extra_label(&self) -> Option<(&'static str, &'static str)> {
        match self.shape {
            2 => Some(("corner", " mm")),
            3 => Some(("tip", "°")),
            4 => Some(("point", "°")),
            _ => None,
        }
    }
}

/// The editor's state: a draft per tool number, kept while programs are read again.
#[derive(Debug, Default)]
pub struct ToolEditor {
    drafts: BTreeMap<i32, ToolDraft>,
}

/// What the user asked of the editor this frame.
pub enum Edit {
    /// Nothing.
    None,
    /// Use these specs (checked).
    Apply(Vec<String>),
    /// Back to the tables' tools.
    Reset,
}

impl ToolEditor {
    /// Forgets the drafts (the tables' tools again).
    pub fn clear(&mut self) {
        self.drafts.clear();
    }

    /// Takes a spec given by name (automation): its tool's draft follows it.
    pub fn take_spec(&mut self, number: i32, spec: &str) {
        self.drafts.insert(number, ToolDraft::from_spec(spec));
    }

    /// The editor for `tools` (the program's, the default cutter left out); `applied`: the
    /// specs in use, to tell whether the drafts differ from them.
    pub fn ui(&mut self, ui: &mut egui::Ui, tools: &[ToolRow], applied: &[String]) -> Edit {
        let tools: Vec<&ToolRow> = tools.iter().filter(|t| t.number >= 0).collect();
        if tools.is_empty() {
            ui.label("The program changes no tool: its moves use the default cutter.");
            return Edit::None;
        }
        let mut specs = Vec::new();
        for t in &tools {
            let d = self.drafts.entry(t.number).or_insert_with(|| ToolDraft::from_spec(&t.spec));
            ui.horizontal(|ui| {
                ui.strong(format!("T{}", t.number));
                egui::ComboBox::from_id_salt(("tool_shape", t.number))
                    .width(60.0)
                    .selected_text(SHAPES[d.shape])
                    .show_ui(ui, |ui| {
                        for (i, s) in SHAPES.iter().enumerate() {
                            if ui.selectable_value(&mut d.shape, i, *s).changed() {
                                d.extra = match i {
                                    2 => (0.1 * d.diameter_mm).max(0.1),
                                    3 => 90.0,
                                    4 => DEFAULT_DRILL_POINT_DEG,
                                    _ => 0.0,
                                };
                            }
                        }
                    });
                ui.add(
                    egui::DragValue::new(&mut d.diameter_mm).speed(0.1).range(0.01..=200.0).prefix("Ø ").suffix(" mm"),
                )
                .on_hover_text("cutting diameter");
                if let Some((what, unit)) = d.extra_label() {
                    let range = if d.shape == 2 { 0.001..=100.0 } else { 1.0..=179.0 };
                    ui.add(
                        egui::DragValue::new(&mut d.extra)
                            .speed(0.1)
                            .range(range)
                            .prefix(format!("{what} "))
                            .suffix(unit),
                    );
                }
            });
            ui.indent(("tool_body", t.number), |ui| {
                d.body_ui(ui, t);
                // The body as read (the simulation's): "assumed" until a source gives it.
                ui.add(egui::Label::new(egui::RichText::new(format!("as simulated: {}", t.body)).weak()).wrap());
            });
            specs.push(d.spec(t.number));
        }
        let mut edit = Edit::None;
        ui.horizontal(|ui| {
            // The program read gives each tool as its tables and the applied specs make it.
            let changed = specs.iter().zip(&tools).any(|(s, t)| *s != t.spec);
            if ui
                .add_enabled(changed, egui::Button::new("Apply"))
                .on_hover_text("read the program again with these cutters")
                .clicked()
            {
                edit = Edit::Apply(specs.clone());
            }
            if ui.add_enabled(!applied.is_empty(), egui::Button::new("Tables' tools")).clicked() {
                edit = Edit::Reset;
            }
        });
        edit
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A draft made from a tool's spec writes that spec back, body words included, so an
    /// unedited tool is not "changed"; an edited length is written to the micrometre and
    /// never as 0 (which the spec's reader refuses).
    #[test]
    fn a_draft_writes_its_specs_body_words_back() {
        for spec in
            ["1:flat:6", "1:flat:6,flute=10", "2:ball:4,flute=12,shank=2:30,holder=10:40,nocentre", "3:v:6:90,flute=5"]
        {
            let d = ToolDraft::from_spec(spec);
            let n = spec.split(':').next().and_then(|n| n.parse().ok()).unwrap_or(0);
            assert_eq!(d.spec(n), spec);
            let e = parse_tool_spec(spec).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(e.spec().as_deref(), Some(spec));
        }
        let mut d = ToolDraft::from_spec("1:flat:6");
        d.body.flute_mm = Some(body_mm(10.100_000_000_000_001));
        d.body.shank_mm = Some((body_mm(0.0), body_mm(40.0)));
        d.body.centre_cutting = Some(false);
        let spec = d.spec(1);
        assert_eq!(spec, "1:flat:6,flute=10.1,shank=0.01:40,nocentre");
        assert!(parse_tool_spec(&spec).is_ok(), "{spec}");
    }
}
