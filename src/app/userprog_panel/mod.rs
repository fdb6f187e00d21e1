//! The "Your program" view: a program the user brings, with its tool table, CAMotics project
//! and subroutine files, read by the interpreter and drawn as its tool path — coloured by
//! move kind, feed, tool or five-axis nonlinear error — with the interpreter's reports and
//! the reading's notes listed by line (a click shows the line and its block), a slider over
//! its blocks, and *Simulate*: the program machined with its own tools, in the background
//! (`jobs::user_program`: a thread natively, a Web Worker in the browser) with progress and
//! cancel, the stock shown coloured by which tool cut it last, and the crashes it found — the
//! shank or holder in the stock, a rapid through it, a plunge with a tool that cannot — listed
//! (a click shows the line and its block) and marked in red in both views. The same pipeline as
//! `interpolab simulate --tools/--project/--machine` (docs/user-programs.md).

mod timing;
mod tools;
mod view;

use std::rc::Rc;

use eframe::egui;

use super::jobs::{Job, Poll};
use super::panel::{Panel, PanelContext};
use super::platform::FileKind;
use crate::geom::Cutter;
use crate::jobs::JobError;
use crate::jobs::user_program::{CrashRow, Finished, ReadSummary, Request, UserProgram};
use crate::simulate::CrashKind;
use crate::simulate::canon::{KinematicsChoice, MachineSetup};
use view::PathView;

/// Title of the tab.
pub const TITLE: &str = "Your program";

/// Where a stock set in the tab comes from (shown beside it).
const STOCK_SET_HERE: &str = "set here";

/// Range of the nonlinear-error tolerance slider (mm).
pub const TOL_RANGE_MM: std::ops::RangeInclusive<f64> = 0.0005..=1.0;

/// What the path is coloured by.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ColourBy {
    /// Rapid, line, arc, spline.
    #[default]
    Kind,
    /// The programmed feed.
    Feed,
    /// The tool.
    Tool,
    /// The five-axis nonlinear error against the tolerance.
    Error,
    /// The feed each block achieves on the machine it was timed on, against its programmed
    /// feed (after *Time it*).
    Achieved,
}

impl ColourBy {
    const ALL: [Self; 5] = [Self::Kind, Self::Feed, Self::Tool, Self::Error, Self::Achieved];
    fn key(self) -> &'static str {
        match self {
            Self::Kind => "kind",
            Self::Feed => "feed",
            Self::Tool => "tool",
            Self::Error => "error",
            Self::Achieved => "achieved",
        }
    }
    fn label(self) -> &'static str {
        match self {
            Self::Kind => "move kind",
            Self::Feed => "feed",
            Self::Tool => "tool",
            Self::Error => "nonlinear error",
            Self::Achieved => "achieved feed",
        }
    }
}

/// Machine choices: automatic (as the program names it, else three axes), then the names.
fn machine_names() -> Vec<&'static str> {
    std::iter::once("auto").chain(MachineSetup::NAMES).collect()
}

/// The files and choices a run is made of.
#[derive(Clone, Debug, Default, PartialEq)]
struct Inputs {
    program: Option<(String, String)>,
    subs: Vec<(String, String)>,
    table: Option<(String, String)>,
    project: Option<(String, String)>,
    machine: usize,
    kinematics: usize,
    pitch_mm: Option<f64>,
    /// Cutters set in the tool editor (`N:shape:diameter[:x][,body words]`).
    tool_specs: Vec<String>,
}

impl Inputs {
    fn request(&self, simulate: bool) -> Option<Request> {
        let (name, text) = self.program.clone()?;
        let names = machine_names();
        Some(Request {
            name,
            text,
            files: self.subs.clone(),
            tool_table: self.table.as_ref().map(|t| t.1.clone()),
            project: self.project.as_ref().map(|p| p.1.clone()),
            tool_specs: self.tool_specs.clone(),
            default_cutter: Cutter::flat(1.5).ok()?,
            machine: (self.machine > 0).then(|| names.get(self.machine).map(|s| (*s).to_owned())).flatten(),
            kinematics: [KinematicsChoice::Auto, KinematicsChoice::Joints, KinematicsChoice::Tcp]
                .get(self.kinematics)
                .copied()
                .unwrap_or_default(),
            pitch_mm: self.pitch_mm,
            stock_mm: None,
            simulate,
        })
    }
}

/// A run under way or done.
struct Run {
    job: Option<Job<UserProgram>>,
    simulate: bool,
    inputs: Inputs,
    progress: f64,
    started_ms: f64,
    done_ms: Option<f64>,
}

/// The panel.
#[derive(Default)]
pub struct UserProgramPanel {
    inputs: Inputs,
    /// The next G-code file is a subroutine file (the button asked for one).
    expect_sub: bool,
    run: Option<Run>,
    summary: Option<Rc<ReadSummary>>,
    result: Option<Rc<Finished>>,
    error: Option<String>,
    colour: ColourBy,
    tol_mm: f64,
    /// The block picked (a message, a crash, a click in the view, the slider).
    selected: Option<usize>,
    /// The crash picked in the list (index in the result's), circled in the views while its
    /// block is the one picked.
    selected_crash: Option<usize>,
    /// Blocks drawn: the first `shown` (the slider).
    shown: Option<usize>,
    /// The stock block set here (mm: min x, y, z, max x, y, z); `None`: the project's
    /// workpiece or the automatic one. Used by Simulate; changing it does not read again.
    stock_set: Option<[f64; 6]>,
    tool_editor: tools::ToolEditor,
    /// The program timed on a machine.
    timing: timing::Timing,
    /// Readings started with new inputs (what a plan is for).
    reading: u64,
    /// The achieved feed of each block drawn (mm/min; NaN: none) and the plan
    /// ([`timing::Timing::serial`]) and block count it was made for.
    achieved: ((u64, usize), Vec<f32>),
    view: PathView,
    rects: Vec<(&'static str, egui::Rect)>,
}

impl UserProgramPanel {
    fn tol(&self) -> f64 {
        if self.tol_mm > 0.0 { self.tol_mm } else { 0.01 }
    }

    fn start(&mut self, simulate: bool) {
        let Some(mut req) = self.inputs.request(simulate) else {
            return;
        };
        req.stock_mm = self.stock_set;
        if self.run.as_ref().is_none_or(|r| r.inputs != self.inputs) {
            self.reading += 1;
        }
        self.error = None;
        if simulate {
            self.result = None;
            self.selected_crash = None;
        }
        self.run = Some(Run {
            job: Some(Job::start(req)),
            simulate,
            inputs: self.inputs.clone(),
            progress: 0.0,
            started_ms: super::platform::Platform::now_ms(),
            done_ms: None,
        });
    }

    /// A file given to the view.
    fn take_file(&mut self, kind: FileKind, name: String, text: String) {
        match kind {
            // A new table or project decides the tools again: the tab's edits go.
            FileKind::ToolTable => {
                self.inputs.table = Some((name, text));
                self.inputs.tool_specs.clear();
                self.tool_editor.clear();
            }
            FileKind::Project => {
                self.inputs.project = Some((name, text));
                self.inputs.tool_specs.clear();
                self.tool_editor.clear();
            }
            FileKind::GCode => {
                if self.expect_sub || is_subroutine_file(&text) {
                    self.inputs.subs.retain(|(n, _)| *n != name);
                    self.inputs.subs.push((name, text));
                } else {
                    self.inputs.program = Some((name, text));
                    self.summary = None;
                    self.result = None;
                    self.selected = None;
                    self.shown = None;
                    self.view.refit();
                }
                self.expect_sub = false;
            }
            FileKind::Scene => {}
        }
    }

    fn poll(&mut self, ctx: &egui::Context) {
        let Some(run) = self.run.as_mut() else {
            return;
        };
        let Some(job) = run.job.as_mut() else {
            return;
        };
        super::jobs::set_waker(ctx);
        let polled = job.poll();
        // The summary arrives in pieces (a few per frame, `Job::poll`): the path grows as
        // they come, framed as a whole from the first on.
        for piece in job.take_partials() {
            if piece.first_block == 0 {
                let fresh = self.summary.as_ref().is_none_or(|old| old.block_line.len() != piece.total_blocks);
                if fresh {
                    self.view.fit_box(piece.bounds_mm);
                    self.selected = None;
                    self.shown = None;
                }
                let mut summary = piece.summary;
                if let Some(b) = self.stock_set {
                    summary.stock_mm = b;
                    summary.stock_from = STOCK_SET_HERE.to_owned();
                }
                self.summary = Some(Rc::new(summary));
            } else if let Some(s) = self.summary.as_mut() {
                let first = piece.first_block;
                if !Rc::make_mut(s).take_piece(*piece) {
                    log::warn!("a piece of the program read (block {first} on) came out of order: left out");
                }
            }
            self.view.invalidate();
        }
        match polled {
            Poll::Running(f) => {
                run.progress = f.unwrap_or(run.progress);
                ctx.request_repaint_after(std::time::Duration::from_millis(100));
            }
            Poll::Done(out) => {
                run.job = None;
                run.progress = 1.0;
                run.done_ms = Some(super::platform::Platform::now_ms());
                match out {
                    Ok(Some(f)) => {
                        self.result = Some(Rc::new(f));
                        self.selected_crash = None;
                    }
                    Ok(None) => {}
                    Err(e) => self.error = Some(e.to_string()),
                }
                self.view.invalidate();
            }
        }
    }

    /// The stock: shown, and set here when "set the stock" is ticked (six lengths, mm).
    fn stock_controls(&mut self, ui: &mut egui::Ui) {
        let Some(s) = self.summary.clone() else { return };
        let mut set = self.stock_set.is_some();
        let r = ui.checkbox(&mut set, "set the stock");
        self.rects.push(("stock_set", r.rect));
        if set != self.stock_set.is_some() {
            let _ = self.set_stock(set.then_some(s.stock_mm));
        }
        if let Some(mut b) = self.stock_set {
            let mut changed = false;
            egui::Grid::new("userprog_stock").num_columns(3).show(ui, |ui| {
                ui.label("");
                ui.label("from");
                ui.label("to");
                ui.end_row();
                for (i, axis) in ["x", "y", "z"].into_iter().enumerate() {
                    ui.label(axis);
                    for k in [i, i + 3] {
                        let r = ui.add(egui::DragValue::new(&mut b[k]).speed(0.5).suffix(" mm").max_decimals(3));
                        changed |= r.changed();
                    }
                    ui.end_row();
                }
            });
            if changed && let Err(e) = self.set_stock(Some(b)) {
                self.error = Some(e);
            }
        }
        let b = self.summary.as_ref().map_or(s.stock_mm, |s| s.stock_mm);
        ui.label(format!(
            "stock {:.1} … {:.1} × {:.1} … {:.1} × {:.1} … {:.1} mm ({}), pitch {} mm",
            b[0],
            b[3],
            b[1],
            b[4],
            b[2],
            b[5],
            self.summary.as_ref().map_or("", |s| s.stock_from.as_str()),
            s.pitch_mm
        ));
    }

    /// Sets the stock block (`None`: the project's or the automatic one again). A block with
    /// a side of no length or a number not finite is refused with what to change; the last
    /// simulated stock stays until Simulate runs again.
    fn set_stock(&mut self, b: Option<[f64; 6]>) -> Result<(), String> {
        if let Some(b) = b {
            if let Some(bad) = b.iter().position(|v| !v.is_finite()) {
                return Err(format!(
                    "stock: the {} value is not a number; give lengths in mm",
                    ["x from", "y from", "z from", "x to", "y to", "z to"][bad]
                ));
            }
            if let Some(i) = (0..3).find(|&i| b[i] >= b[i + 3]) {
                let axis = ["x", "y", "z"][i];
                return Err(format!(
                    "stock: {axis} from {} mm is not below {axis} to {} mm; make \"to\" the larger",
                    b[i],
                    b[i + 3]
                ));
            }
        }
        let was_set = self.stock_set.is_some();
        self.stock_set = b;
        self.error = None;
        if let Some(s) = self.summary.as_mut() {
            let s = Rc::make_mut(s);
            match b {
                Some(b) => {
                    s.stock_mm = b;
                    s.stock_from = STOCK_SET_HERE.to_owned();
                }
                // Back to the reading's own stock: read again.
                None if was_set => self.run = None,
                None => {}
            }
        }
        self.view.invalidate();
        Ok(())
    }

    /// Uses these cutters (the program is read again); each spec is checked first, a bad one
    /// refused with what to write and nothing changed.
    fn set_tool_specs(&mut self, specs: Vec<String>) -> Result<(), String> {
        for s in &specs {
            crate::gcode::interp::tools::parse_tool_spec(s).map_err(|e| format!("tool {e}"))?;
        }
        self.error = None;
        self.inputs.tool_specs = specs;
        Ok(())
    }

    /// The achieved feeds against the programmed ones, for the status: blocks compared, the
    /// lowest and highest ratio over feed blocks (`null` until timed).
    fn achieved_status(&self) -> serde_json::Value {
        let Some(s) = self.summary.as_ref() else { return serde_json::Value::Null };
        if self.achieved.1.len() != s.block_kind.len() {
            return serde_json::Value::Null;
        }
        let ratios: Vec<f64> = self
            .achieved
            .1
            .iter()
            .zip(&s.block_feed)
            .zip(&s.block_kind)
            .filter(|((f, p), k)| **k != 0 && f.is_finite() && **p > 0.0)
            .map(|((f, p), _)| f64::from(*f) / f64::from(*p))
            .collect();
        serde_json::json!({
            "blocks": ratios.len(),
            "min_ratio": ratios.iter().copied().fold(f64::INFINITY, f64::min),
            "max_ratio": ratios.iter().copied().fold(0.0, f64::max),
        })
    }

    fn running(&self) -> bool {
        self.run.as_ref().is_some_and(|r| r.job.is_some())
    }

    fn file_row(ui: &mut egui::Ui, what: &str, name: Option<&str>) -> bool {
        let mut remove = false;
        ui.horizontal(|ui| {
            ui.label(format!("{what}:"));
            match name {
                Some(n) => {
                    ui.monospace(short(n));
                    remove = ui.small_button("✕").on_hover_text("leave it out").clicked();
                }
                None => {
                    ui.weak("none");
                }
            }
        });
        remove
    }

    fn files_controls(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        ui.horizontal_wrapped(|ui| {
            let r = ui.button("Open program…");
            if r.clicked() {
                self.expect_sub = false;
                cx.pick_file(FileKind::GCode);
            }
            self.rects.push(("open_program", r.rect));
            let r = ui.button("Tool table…").on_hover_text("a LinuxCNC .tbl: T, Z (length), D; the shape as the remark's first word (flat, ball, bull r=1, v90, drill)");
            if r.clicked() {
                cx.pick_file(FileKind::ToolTable);
            }
            self.rects.push(("open_table", r.rect));
            let r = ui.button("CAMotics project…").on_hover_text("its tools and workpiece");
            if r.clicked() {
                cx.pick_file(FileKind::Project);
            }
            let r = ui.button("Subroutine file…").on_hover_text("a file the program calls (o<name> call, M98)");
            if r.clicked() {
                self.expect_sub = true;
                cx.pick_file(FileKind::GCode);
            }
        });
        if Self::file_row(ui, "program", self.inputs.program.as_ref().map(|p| p.0.as_str())) {
            self.inputs.program = None;
            self.summary = None;
            self.result = None;
        }
        if Self::file_row(ui, "tool table", self.inputs.table.as_ref().map(|p| p.0.as_str())) {
            self.inputs.table = None;
        }
        if Self::file_row(ui, "project", self.inputs.project.as_ref().map(|p| p.0.as_str())) {
            self.inputs.project = None;
        }
        let mut drop_sub = None;
        for (i, (n, _)) in self.inputs.subs.iter().enumerate() {
            if Self::file_row(ui, "subroutine", Some(n)) {
                drop_sub = Some(i);
            }
        }
        if let Some(i) = drop_sub {
            self.inputs.subs.remove(i);
        }
    }

    fn machine_controls(&mut self, ui: &mut egui::Ui) {
        let names = machine_names();
        egui::ComboBox::from_label("machine")
            .selected_text(*names.get(self.inputs.machine).unwrap_or(&"auto"))
            .show_ui(ui, |ui| {
                for (i, n) in names.iter().enumerate() {
                    ui.selectable_value(&mut self.inputs.machine, i, *n);
                }
            });
        let kin = ["auto (M428/G43.4)", "joints", "TCP"];
        egui::ComboBox::from_label("rotary words")
            .selected_text(*kin.get(self.inputs.kinematics).unwrap_or(&"auto"))
            .show_ui(ui, |ui| {
                for (i, n) in kin.iter().enumerate() {
                    ui.selectable_value(&mut self.inputs.kinematics, i, *n);
                }
            });
    }

    fn numbers(&self, ui: &mut egui::Ui) {
        let Some(s) = &self.summary else {
            return;
        };
        ui.label(format!(
            "{} lines, {} blocks, {} moves; {:.2} min at the programmed feed",
            s.lines,
            s.block_line.len(),
            s.moves,
            s.feed_min
        ));
        if let Some(m) = &s.machine {
            let measured = s.block_error.iter().filter(|e| e.is_finite()).count();
            let over = s.block_error.iter().filter(|e| f64::from(**e) > self.tol()).count();
            ui.label(format!("machine {m}: {measured} blocks measured, {over} over {} mm", self.tol()));
        }
        // Rapids through stock are crashes: the Crashes section lists them by line.
        egui::Grid::new("userprog_tools").striped(true).show(ui, |ui| {
            ui.strong("tool");
            ui.strong("cutter");
            ui.strong("min");
            ui.strong("mm³");
            ui.end_row();
            for (k, t) in s.tools.iter().enumerate() {
                let c = view::tool_colour(k);
                ui.colored_label(c, if t.number < 0 { "default".to_owned() } else { format!("T{}", t.number) });
                ui.label(&t.cutter).on_hover_text(&t.source);
                ui.label(format!("{:.2}", t.feed_min));
                let v = self.result.as_ref().and_then(|r| r.removed_mm3.get(k).copied());
                ui.label(v.map_or_else(|| "–".to_owned(), |v| format!("{v:.1}")));
                ui.end_row();
            }
        });
    }

    /// The blocks of a line (the first block on it).
    fn block_of_line(&self, line: u32) -> Option<usize> {
        let s = self.summary.as_ref()?;
        s.block_line.iter().zip(&s.block_file).position(|(l, f)| *l == line && *f == 0)
    }

    fn messages(&mut self, ui: &mut egui::Ui) {
        let Some(s) = self.summary.clone() else {
            return;
        };
        if s.messages.is_empty() {
            return;
        }
        ui.strong(format!("Reports and notes ({})", s.messages.len()));
        let mut picked = None;
        // Only the rows in sight are laid out (a program may bring thousands of notes).
        let row = ui.spacing().interact_size.y;
        egui::ScrollArea::vertical().id_salt("userprog_messages").max_height(160.0).show_rows(
            ui,
            row,
            s.messages.len(),
            |ui, rows| {
                for (k, (line, text)) in s.messages.iter().enumerate().skip(rows.start).take(rows.len()) {
                    let label = if *line > 0 { format!("line {line}: {text}") } else { text.clone() };
                    let r = ui.selectable_label(false, label);
                    if k == 0 {
                        self.rects.push(("first_message", r.rect));
                    }
                    if r.clicked() && *line > 0 {
                        picked = Some(*line);
                    }
                }
            },
        );
        if let Some(line) = picked {
            self.select_line(line);
        }
    }

    /// The crashes of the last simulation: one line of counts (or that there was none) and
    /// the list, a row per crash; a click shows its block as a report's does and circles its
    /// mark.
    fn crashes(&mut self, ui: &mut egui::Ui) {
        let Some(f) = self.result.clone() else {
            return;
        };
        ui.strong(format!("Crashes ({})", f.crash_total()));
        if f.crash_total() == 0 {
            ui.colored_label(egui::Color32::from_rgb(120, 210, 120), crash_summary(&f));
            return;
        }
        super::widgets::error_text(ui, crash_summary(&f));
        let picked = self.picked_crash().and_then(|k| f.crashes.get(k).map(|c| (k, c)));
        if let Some((_, c)) = picked.or(f.crashes.first().map(|c| (0, c))) {
            ui.weak(format!("line {}: {}", c.line, crash_advice(c.kind)));
        }
        let mut clicked = None;
        let row = ui.spacing().interact_size.y;
        let s = self.summary.clone();
        egui::ScrollArea::vertical().id_salt("userprog_crashes").max_height(140.0).show_rows(
            ui,
            row,
            f.crashes.len(),
            |ui, rows| {
                for (k, c) in f.crashes.iter().enumerate().skip(rows.start).take(rows.len()) {
                    let in_sub =
                        c.block.and_then(|b| s.as_ref()?.block_file.get(b as usize).copied()).is_some_and(|f| f != 0);
                    let r = ui
                        .selectable_label(picked.is_some_and(|p| p.0 == k), crash_row_text(c, in_sub))
                        .on_hover_text(format!("{}: {}", c.kind.part(), crash_advice(c.kind)));
                    if k == 0 {
                        self.rects.push(("first_crash", r.rect));
                    }
                    if r.clicked() {
                        clicked = Some(k);
                    }
                }
            },
        );
        if let Some(k) = clicked {
            self.select_crash(k);
        }
    }

    /// Picks crash `k` of the last simulation: its block is selected (as a report's line is)
    /// and its mark circled.
    fn select_crash(&mut self, k: usize) -> bool {
        let Some(c) = self.result.as_ref().and_then(|f| f.crashes.get(k).copied()) else {
            return false;
        };
        let n = self.summary.as_ref().map_or(0, |s| s.block_line.len());
        match c.block.map(|b| b as usize).filter(|b| *b < n) {
            Some(b) => {
                self.selected = Some(b);
                self.view.invalidate();
            }
            None => self.select_line(c.line),
        }
        self.selected_crash = Some(k);
        true
    }

    /// The crash picked, while its block is the one selected (another pick leaves it).
    fn picked_crash(&self) -> Option<usize> {
        let k = self.selected_crash?;
        let c = self.result.as_ref()?.crashes.get(k)?;
        match c.block {
            Some(b) => (self.selected == Some(b as usize)).then_some(k),
            None => Some(k),
        }
    }

    /// The crashes for the status: counts per kind, the first (line, kind, tool, depth and
    /// place in mm), the deepest listed (mm), how many are listed and left out; `null` before
    /// a simulation.
    fn crash_status(&self) -> serde_json::Value {
        let Some(f) = self.result.as_ref() else { return serde_json::Value::Null };
        let mut by_kind = serde_json::Map::new();
        for k in CrashKind::ALL {
            by_kind.insert(k.name().to_owned(), f.crash_counts[k.index()].into());
        }
        let row = |c: &CrashRow| {
            serde_json::json!({
                "line": c.line, "kind": c.kind.name(), "tool": c.tool, "block": c.block,
                "depth_mm": c.depth_mm, "x_mm": c.at_mm.x, "y_mm": c.at_mm.y, "z_mm": c.at_mm.z,
            })
        };
        serde_json::json!({
            "total": f.crash_total(),
            "by_kind": by_kind,
            "listed": f.crashes.len(),
            "left_out": f.crashes_left_out(),
            "first": f.crashes.first().map(row),
            "deepest_mm": f.crashes.iter().map(|c| c.depth_mm).fold(0.0, f64::max),
            "summary": crash_summary(f),
            "picked": self.picked_crash().and_then(|k| f.crashes.get(k)).map(row),
        })
    }

    fn select_line(&mut self, line: u32) {
        // A line without a motion shows the next block after it.
        let Some(s) = &self.summary else {
            return;
        };
        let at = self
            .block_of_line(line)
            .or_else(|| s.block_line.iter().zip(&s.block_file).position(|(l, f)| *l >= line && *f == 0));
        self.selected = at;
        self.view.invalidate();
    }

    /// The text of a line of the main program.
    fn line_text(&self, line: u32) -> Option<&str> {
        let (_, text) = self.inputs.program.as_ref()?;
        text.lines().nth(line.checked_sub(1)? as usize)
    }
}

/// The crashes in one line: the count per kind and the deepest, or that there was none.
fn crash_summary(f: &Finished) -> String {
    let total = f.crash_total();
    if total == 0 {
        return "no crash: the shank and holder never met the stock, no rapid cut".to_owned();
    }
    let kinds: Vec<String> = CrashKind::ALL
        .iter()
        .filter(|k| f.crash_counts[k.index()] > 0)
        .map(|k| format!("{} {}", f.crash_counts[k.index()], k.name()))
        .collect();
    let deepest = f.crashes.iter().map(|c| c.depth_mm).fold(0.0, f64::max);
    let mut s = format!(
        "{total} {} ({}), the deepest {deepest:.3} mm into the stock",
        if total == 1 { "crash" } else { "crashes" },
        kinds.join(", ")
    );
    if f.crashes_left_out() > 0 {
        s.push_str(&format!("; the first {} listed, {} more counted", f.crashes.len(), f.crashes_left_out()));
    }
    s
}

/// A row of the crash list: line, kind, tool, depth and place, with units.
fn crash_row_text(c: &CrashRow, in_subroutine: bool) -> String {
    let tool = match c.tool {
        Some(t) if t >= 0 => format!("T{t}"),
        Some(_) => "default tool".to_owned(),
        None => "tool ?".to_owned(),
    };
    let file = if in_subroutine { " (subroutine file)" } else { "" };
    format!(
        "line {}{file}: {}, {tool}, {:.3} mm deep at ({:.3}, {:.3}, {:.3}) mm",
        c.line,
        c.kind.name(),
        c.depth_mm,
        c.at_mm.x,
        c.at_mm.y,
        c.at_mm.z
    )
}

/// What to change about a crash of this kind.
fn crash_advice(kind: CrashKind) -> &'static str {
    match kind {
        CrashKind::Shank => {
            "the shank met stock above the flutes: cut in shallower steps, or use a tool with longer flutes (its flute length in the tool editor)"
        }
        CrashKind::Holder => {
            "the holder met the stock: use a longer tool (the shank's length in the tool editor) or a slimmer holder, or stay out of deep pockets"
        }
        CrashKind::Rapid => {
            "a rapid (G0) went through stock: raise the rapid's Z above the stock, or make that move a feed (G1)"
        }
        CrashKind::Plunge => {
            "a tool that does not cut at its centre plunged: ramp or helix in below 5 degrees, pre-drill, or use a centre-cutting tool"
        }
    }
}

/// Whether a G-code text is a subroutine file: its first line of code opens an O-word
/// subroutine (`o<name> sub`).
fn is_subroutine_file(text: &str) -> bool {
    text.lines()
        .map(|l| l.split([';', '(']).next().unwrap_or("").trim().to_ascii_lowercase())
        .find(|l| !l.is_empty() && l != "%")
        .is_some_and(|l| l.starts_with("o<") && l.contains("sub") && !l.contains("call"))
}

fn short(name: &str) -> String {
    let base = name.rsplit(['/', '\\']).next().unwrap_or(name);
    if base.chars().count() > 40 {
        format!("…{}", base.chars().rev().take(38).collect::<String>().chars().rev().collect::<String>())
    } else {
        base.to_owned()
    }
}

impl Panel for UserProgramPanel {
    fn title(&self) -> &'static str {
        TITLE
    }

    fn accepts_also(&self) -> &'static [FileKind] {
        &[FileKind::GCode, FileKind::ToolTable, FileKind::Project]
    }

    fn controls(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        self.rects.clear();
        super::widgets::section(ui, "Program and tools", true, |ui| self.files_controls(ui, cx));
        if let Some(s) = self.summary.clone() {
            super::widgets::section(ui, "Tools", true, |ui| {
                match self.tool_editor.ui(ui, &s.tools, &self.inputs.tool_specs) {
                    tools::Edit::None => {}
                    tools::Edit::Apply(specs) => {
                        if let Err(e) = self.set_tool_specs(specs) {
                            self.error = Some(e);
                        }
                    }
                    tools::Edit::Reset => {
                        self.inputs.tool_specs.clear();
                        self.tool_editor.clear();
                    }
                }
            });
        }
        super::widgets::section(ui, "Machine", true, |ui| self.machine_controls(ui));
        super::widgets::section(ui, "View", true, |ui| {
            egui::ComboBox::from_label("colour by").selected_text(self.colour.label()).show_ui(ui, |ui| {
                for c in ColourBy::ALL {
                    if ui.selectable_value(&mut self.colour, c, c.label()).changed() {
                        self.view.invalidate();
                    }
                }
            });
            let mut tol = self.tol();
            let r = super::widgets::tolerance_slider(ui, &mut tol, TOL_RANGE_MM, "tolerance E");
            if (tol - self.tol()).abs() > 0.0 {
                self.tol_mm = tol;
                self.view.invalidate();
            }
            self.rects.push(("tolerance", r.rect));
        });
        // Read again when the files or choices change.
        let stale = self.run.as_ref().is_none_or(|r| r.inputs != self.inputs);
        if stale && self.inputs.program.is_some() {
            self.start(false);
        }
        self.poll(ui.ctx());
        super::widgets::section(ui, "Simulate", true, |ui| {
            ui.horizontal(|ui| {
                let running = self.running();
                let sim = self.run.as_ref().is_some_and(|r| r.simulate);
                if running {
                    let r = ui.button("Cancel");
                    self.rects.push(("cancel", r.rect));
                    if r.clicked() {
                        if let Some(run) = self.run.as_mut() {
                            run.job = None;
                        }
                        self.error = Some(JobError::Cancelled.to_string());
                    }
                    let f = self.run.as_ref().map_or(0.0, |r| r.progress) as f32;
                    ui.add(egui::ProgressBar::new(f).show_percentage().desired_width(140.0));
                } else {
                    let r = ui.add_enabled(self.inputs.program.is_some(), egui::Button::new("Simulate"));
                    self.rects.push(("simulate", r.rect));
                    if r.clicked() {
                        self.start(true);
                    }
                }
                let _ = sim;
            });
            let mut auto = self.inputs.pitch_mm.is_none();
            ui.horizontal(|ui| {
                ui.checkbox(&mut auto, "automatic pitch");
                if !auto {
                    let mut p = self.inputs.pitch_mm.unwrap_or(0.2);
                    ui.add(egui::Slider::new(&mut p, 0.02..=2.0).logarithmic(true).suffix(" mm"));
                    self.inputs.pitch_mm = Some(p);
                } else {
                    self.inputs.pitch_mm = None;
                }
            });
            self.stock_controls(ui);
        });
        if self.summary.is_some() {
            let reading = (!self.running() && self.error.is_none()).then_some(self.reading);
            let programmed = self.summary.as_ref().map(|s| s.feed_min);
            let (timing, inputs, rects) = (&mut self.timing, &self.inputs, &mut self.rects);
            super::widgets::section(ui, "Time on a machine", true, |ui| {
                let r = timing.ui(ui, reading, || inputs.request(false), programmed);
                rects.push(("time_it", r));
            });
        }
        if let Some(e) = &self.error {
            super::widgets::error_text(ui, e.clone());
        }
        self.numbers(ui);
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        // Files arrive with the view's context (read at the next frame's controls).
        for f in std::mem::take(&mut cx.incoming) {
            match f.text {
                Ok(t) => self.take_file(f.kind, f.name, t),
                Err(e) => cx.error(format!("{}: {e}", f.name)),
            }
            ui.ctx().request_repaint();
        }
        let Some(s) = self.summary.clone() else {
            let rect = ui.available_rect_before_wrap();
            let text = if self.inputs.program.is_some() {
                "reading the program…"
            } else {
                "Open a program (G-code) with its tool table or CAMotics project: it is drawn here, its reports listed, and Simulate machines it with its own tools."
            };
            ui.painter().text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                text,
                egui::FontId::proportional(15.0),
                egui::Color32::from_gray(200),
            );
            return;
        };
        let n = s.block_line.len();
        // The slider over the blocks, and the picked block's line.
        ui.horizontal(|ui| {
            let mut shown = self.shown.unwrap_or(n);
            let r = ui.add(egui::Slider::new(&mut shown, 0..=n).text("blocks shown"));
            self.rects.push(("blocks_slider", r.rect));
            if r.changed() {
                self.shown = (shown < n).then_some(shown);
                self.selected = shown.checked_sub(1);
                self.view.invalidate();
            }
        });
        if let Some(b) = self.selected.filter(|b| *b < n) {
            let (line, file) = (s.block_line[b], s.block_file[b]);
            let text = if file == 0 {
                self.line_text(line).unwrap_or("").trim().to_owned()
            } else {
                format!("(in subroutine file {file})")
            };
            let err = s.block_error[b];
            let extra = if err.is_finite() { format!("  — nonlinear error {:.4} mm", err) } else { String::new() };
            ui.monospace(format!("line {line}: {text}{extra}"));
        }
        self.messages(ui);
        self.crashes(ui);
        let rect = ui.available_rect_before_wrap();
        let (map_rect, path_rect) = if self.result.is_some() && rect.width() > 500.0 {
            let w = (rect.width() * 0.38).min(rect.height());
            (
                Some(egui::Rect::from_min_size(egui::pos2(rect.right() - w, rect.top()), egui::vec2(w, w))),
                egui::Rect::from_min_max(rect.min, egui::pos2(rect.right() - w - 8.0, rect.bottom())),
            )
        } else {
            (None, rect)
        };
        // The feeds achieved on the machine, given to the blocks drawn by their lines (once
        // per plan and reading).
        if self.achieved.0 != (self.timing.serial(), n) {
            self.achieved = (
                (self.timing.serial(), n),
                self.timing.timed().map_or_else(Vec::new, |t| {
                    crate::jobs::program_time::feeds_by_block(&s.block_line, &s.block_file, t)
                }),
            );
            self.view.invalidate();
        }
        let achieved = (!self.achieved.1.is_empty()).then_some(self.achieved.1.as_slice());
        let result = self.result.clone();
        let marks = view::CrashMarks {
            list: result.as_ref().map_or(&[][..], |f| f.crashes.as_slice()),
            selected: self.picked_crash(),
        };
        let (by, tol) = (self.colour, self.tol());
        let picked =
            self.view.ui(ui, path_rect, cx.render_state, &s, by, tol, self.selected, self.shown, achieved, marks);
        if let Some(b) = picked {
            self.selected = Some(b);
            self.view.invalidate();
        }
        self.rects.push(("path_view", path_rect));
        if let (Some(r), Some(f)) = (map_rect, self.result.clone()) {
            let picked = self.picked_crash();
            self.view.map(ui, r, &f, picked);
            self.rects.push(("stock_map", r));
        }
    }

    fn status(&self) -> serde_json::Value {
        let s = self.summary.as_ref();
        let run = self.run.as_ref();
        let over = s.map(|s| s.block_error.iter().filter(|e| f64::from(**e) > self.tol()).count());
        let worst = s.and_then(|s| {
            s.block_error
                .iter()
                .enumerate()
                .filter(|(_, e)| e.is_finite())
                .max_by(|a, b| a.1.total_cmp(b.1))
                .map(|(i, e)| serde_json::json!({ "mm": f64::from(*e), "line": s.block_line[i] }))
        });
        serde_json::json!({
            "ui": super::widgets::rects_json(&self.rects),
            "program": self.inputs.program.as_ref().map(|p| p.0.clone()),
            "tool_table": self.inputs.table.as_ref().map(|p| p.0.clone()),
            "project": self.inputs.project.as_ref().map(|p| p.0.clone()),
            "subroutines": self.inputs.subs.iter().map(|s| s.0.clone()).collect::<Vec<_>>(),
            "computing": self.running(),
            "simulating": run.is_some_and(|r| r.simulate && r.job.is_some()),
            "progress": run.map(|r| r.progress),
            "run_ms": run.and_then(|r| r.done_ms.map(|d| d - r.started_ms)),
            "error": self.error,
            "lines": s.map(|s| s.lines),
            "blocks": s.map(|s| s.block_line.len()),
            "points": s.map(|s| s.point_block.len()),
            "moves": s.map(|s| s.moves),
            "machine": s.and_then(|s| s.machine.clone()),
            "feed_min": s.map(|s| s.feed_min),
            "tools": s.map(|s| s.tools.iter().map(|t| serde_json::json!({
                "number": t.number, "cutter": t.cutter, "spec": t.spec, "body": t.body,
                "body_mm": t.body_mm, "centre_cutting": t.centre_cutting,
            })).collect::<Vec<_>>()),
            "tool_specs": self.inputs.tool_specs,
            "achieved": self.achieved_status(),
            "time": self.timing.status(),
            "messages": s.map(|s| s.messages.iter().map(|(l, t)| format!("{l}: {t}")).collect::<Vec<_>>()),
            "colour": self.colour.key(),
            "tol_mm": self.tol(),
            "over_tolerance": over,
            "worst_error": worst,
            "selected_line": self.selected.and_then(|b| s.and_then(|s| s.block_line.get(b).copied())),
            "shown": self.shown,
            "drawn_segments": self.view.drawn_segments(),
            "drawn_crash_marks": self.view.drawn_crash_marks(),
            "removed_mm3": self.result.as_ref().map(|r| r.removed_mm3.clone()),
            "stock_mm": s.map(|s| s.stock_mm),
            "stock_from": s.map(|s| s.stock_from.clone()),
            "stock_rays": self.result.as_ref().map(|r| r.map.grid.len()),
            "rapid_cuts": self.result.as_ref().map(|r| r.counters.rapid_cuts),
            "first_rapid_cut_line": self.result.as_ref().and_then(|r| r.counters.first_rapid_cut_line),
            "crashes": self.crash_status(),
            "first_crash_line": self.result.as_ref().and_then(|r| r.crashes.first()).map(|c| c.line),
        })
    }

    fn set_option(&mut self, key: &str, value: &str) -> Result<(), String> {
        // A file given by name (automation): `file:job.ngc`, `file:tools.tbl`, … with its text.
        if let Some(name) = key.strip_prefix("file:") {
            let kind = FileKind::from_name(name);
            if kind == FileKind::Scene {
                return Err(format!(
                    "{name}: give a program (.ngc, .nc, …), a tool table (.tbl) or a CAMotics project (.camotics)"
                ));
            }
            self.take_file(kind, name.to_owned(), value.to_owned());
            return Ok(());
        }
        match key {
            "colour" => {
                self.colour = ColourBy::ALL
                    .into_iter()
                    .find(|c| c.key() == value)
                    .ok_or_else(|| format!("colour \"{value}\": use kind, feed, tool or error"))?;
            }
            "tolerance" => self.tol_mm = super::widgets::tolerance_option(key, value, &TOL_RANGE_MM)?,
            "machine" => {
                self.inputs.machine = machine_names()
                    .iter()
                    .position(|n| *n == value)
                    .ok_or_else(|| format!("machine \"{value}\": use one of {}", machine_names().join(", ")))?;
            }
            "kinematics" => {
                self.inputs.kinematics = ["auto", "joints", "tcp"]
                    .iter()
                    .position(|n| *n == value)
                    .ok_or_else(|| format!("kinematics \"{value}\": use auto, joints or tcp"))?;
            }
            "simulate" => {
                if self.inputs.program.is_none() {
                    return Err("no program: open one first".to_owned());
                }
                self.start(true);
            }
            "line" => {
                let line: u32 = value.parse().map_err(|_| format!("line \"{value}\": give a line number"))?;
                self.select_line(line);
            }
            "crash" => {
                // The k-th crash listed (from 0), as a click on its row.
                let n = self.result.as_ref().map_or(0, |f| f.crashes.len());
                let k: usize =
                    value.parse().map_err(|_| format!("crash \"{value}\": give a row of the list, from 0"))?;
                if !self.select_crash(k) {
                    return Err(if self.result.is_none() {
                        "crash: no simulation yet; Simulate first".to_owned()
                    } else {
                        format!("crash {k}: the list has {n} row(s), from 0")
                    });
                }
            }
            "tool" => {
                // `N:shape:diameter[:x][,flute=…,shank=r:l,holder=r:l,nocentre]` sets tool N's
                // cutter and body; `reset`: the tables' tools.
                if value == "reset" {
                    self.inputs.tool_specs.clear();
                    self.tool_editor.clear();
                } else {
                    let e = crate::gcode::interp::tools::parse_tool_spec(value).map_err(|e| format!("tool {e}"))?;
                    let mut specs = self.inputs.tool_specs.clone();
                    let n = e.number;
                    specs.retain(|s| crate::gcode::interp::tools::parse_tool_spec(s).map_or(true, |o| o.number != n));
                    specs.push(value.to_owned());
                    self.set_tool_specs(specs)?;
                    self.tool_editor.take_spec(n, value);
                }
            }
            "time_machine" => self.timing.set_machine(value)?,
            "time_tolerance" => self.timing.set_tolerance(value)?,
            "time_limits" => self.timing.set_limits(value)?,
            "time" => self.timing.want(),
            "stock" => {
                let b = if value == "auto" {
                    None
                } else {
                    let v: Vec<f64> =
                        value.split(',').map(|x| x.trim().parse::<f64>()).collect::<Result<_, _>>().map_err(|_| {
                            format!("stock \"{value}\": give six lengths in mm (x0,y0,z0,x1,y1,z1) or auto")
                        })?;
                    Some(<[f64; 6]>::try_from(v).map_err(|_| {
                        format!("stock \"{value}\": give six lengths in mm (x0,y0,z0,x1,y1,z1) or auto")
                    })?)
                };
                self.set_stock(b)?;
            }
            "pitch" => {
                self.inputs.pitch_mm = if value == "auto" {
                    None
                } else {
                    Some(
                        value
                            .parse::<f64>()
                            .ok()
                            .filter(|p| *p > 0.0 && p.is_finite())
                            .ok_or_else(|| format!("pitch \"{value}\": give a length in mm or auto"))?,
                    )
                };
            }
            _ => {
                return Err(format!(
                    "this view has no option \"{key}\" (file:NAME, colour, tolerance, machine, kinematics, simulate, line, crash, pitch, stock, tool, time, time_machine, time_tolerance, time_limits)"
                ));
            }
        }
        self.view.invalidate();
        Ok(())
    }
}
