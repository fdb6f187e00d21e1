//! The "NURBS & G-code (seed 004)" view: the design path (the scene's crease or seed 004's
//! parabola-like profile) with its G06.2 curve, control polygon and knots; the real-time
//! interpolation of that curve, drawn as points coloured by feed fluctuation and plotted over
//! time; seed 004's comparison of the G01, G02/G03 and G06.2 programs at the tolerance of the
//! slider; the text of the selected program with copy and download; and a G-code file loaded
//! (picked or dropped) drawn over the design with its deviation.
//!
//! Every number comes from the core (`gcode::compare_row`, `realtime_stats`,
//! `nurbs_path::interpolate_realtime`, `gcode::parse_program`, `gcode::deviation`); the work
//! runs one step per frame after a short quiet time ([`work`]), so the page stays live.

mod plots;
mod table;
mod view;
pub mod work;

use eframe::egui;
use glam::DVec3;

use super::panel::{Handoff, Panel, PanelContext, SIMULATION_TITLE};
use super::platform::FileKind;
use super::ranges;
use crate::gcode::{Dialect, ProgramKind, ProgrammedPoint, format_comparison};
use crate::nurbs_path::Update;
use crate::report::fmt_fixed;
use plots::FeedPlot;
use table::Shown;
use view::{NurbsView, Overlay};
use work::{DesignInput, Pending, Point, ProgramInput, RealtimeInput, Source, Wanted, Work};

/// A length in µm with 3 significant digits (at least 3 decimals from 1 µm), e.g. `8.268 µm`,
/// `0.0618 µm`.
pub(crate) fn um(mm: f64) -> String {
    if !mm.is_finite() {
        return "—".to_owned();
    }
    let v = mm * 1000.0;
    let a = v.abs();
    if a == 0.0 {
        "0 µm".to_owned()
    } else if a >= 100.0 {
        format!("{v:.1} µm")
    } else if a >= 1.0 {
        format!("{v:.3} µm")
    } else if a >= 1e-4 {
        let decimals = (2.0 - a.log10().floor()) as usize;
        format!("{v:.decimals$} µm")
    } else {
        format!("{v:.2e} µm")
    }
}

/// The user's choices.
#[derive(Clone, Debug, PartialEq)]
struct Settings {
    source: Source,
    tol_mm: f64,
    resolution_mm: f64,
    point: Point,
    update: Update,
    /// Feed chosen here (mm/min); `None`: the source's.
    feed_mm_per_min: Option<f64>,
    /// Chord tolerance of the feed limit (mm), when on.
    chord_tol_mm: f64,
    chord_limit: bool,
    degree: usize,
    dialect: Dialect,
}

impl Default for Settings {
    fn default() -> Self {
        Self {
            source: Source::Crease,
            tol_mm: 0.01,
            resolution_mm: 0.001,
            point: Point::Centre,
            update: Update::FirstOrder,
            feed_mm_per_min: None,
            chord_tol_mm: 0.00002,
            chord_limit: false,
            degree: 3,
            dialect: Dialect::Fanuc,
        }
    }
}

/// The panel.
pub struct NurbsPanel {
    settings: Settings,
    work: Work,
    view: NurbsView,
    feed_plot: FeedPlot,
    shown: Shown,
    scroll_to: Option<usize>,
    /// Why the design cannot be made yet (crease computing or failed).
    waiting: Option<(bool, String)>,
    /// The inputs of the last frame.
    wanted: Option<Wanted>,
    /// Loaded-file deviation already announced in the banner (file generation).
    announced: u64,
    /// Rectangles of key widgets this frame (points), published in the status.
    rects: Vec<(&'static str, egui::Rect)>,
    /// Longest single step of the work so far (ms): what one frame may cost at most.
    slowest_step_ms: f64,
    /// The plotted series.
    series: plots::Series,
    /// The last program downloaded (file name).
    downloaded: Option<String>,
    /// "Simulate this program" asked for by `set_option` (handed over in the next frame).
    simulate_requested: bool,
}

impl Default for NurbsPanel {
    fn default() -> Self {
        Self {
            settings: Settings::default(),
            work: Work::default(),
            view: NurbsView::default(),
            feed_plot: FeedPlot::Fluctuation,
            shown: Shown::Kind(ProgramKind::Nurbs),
            scroll_to: None,
            waiting: None,
            wanted: None,
            announced: 0,
            rects: Vec::new(),
            slowest_step_ms: 0.0,
            series: plots::Series::default(),
            downloaded: None,
            simulate_requested: false,
        }
    }
}

impl NurbsPanel {
    /// The inputs for this frame, or why there are none yet (`(is_progress, message)`).
    fn wanted(&self, cx: &PanelContext<'_>) -> Result<Wanted, (bool, String)> {
        let s = &self.settings;
        let (design, feed, period) = match s.source {
            Source::Parabola => (DesignInput::Parabola, 1500.0, 4.0),
            Source::Crease => {
                if cx.compute.running() {
                    return Err((
                        true,
                        format!(
                            "Waiting for the scene's crease: {} periods computed…",
                            cx.compute.periods.len().saturating_sub(1)
                        ),
                    ));
                }
                let Some(job) = &cx.compute.job else {
                    return Err((
                        false,
                        "The scene has no crease to follow (it failed to build). Fix the scene in the controls, or choose the parabola profile.".to_owned(),
                    ));
                };
                (
                    DesignInput::Crease(Box::new(job.clone()), cx.scene.name.clone()),
                    cx.scene.motion.feed,
                    cx.scene.motion.period,
                )
            }
        };
        let point = match s.point {
            Point::Centre => ProgrammedPoint::BallCentre,
            Point::Tip => ProgrammedPoint::BallTip { radius_mm: cx.scene.tool.radius },
        };
        Ok(Wanted {
            design,
            program: ProgramInput {
                tol_mm: s.tol_mm,
                resolution_mm: s.resolution_mm,
                point,
                feed_mm_per_min: s.feed_mm_per_min.unwrap_or(feed),
                degree: s.degree,
                dialect: s.dialect,
            },
            realtime: RealtimeInput {
                update: s.update,
                period_ms: period,
                chord_tol_mm: s.chord_limit.then_some(s.chord_tol_mm),
            },
        })
    }

    fn handle_files(&mut self, cx: &mut PanelContext<'_>) {
        for f in std::mem::take(&mut cx.incoming) {
            match f.text {
                Err(e) => cx.error(format!("{}: {e}", f.name)),
                Ok(text) => {
                    self.work.load(&f.name, text);
                    self.shown = Shown::Loaded;
                    self.scroll_to = Some(self.work.loaded.as_ref().and_then(|l| l.error_line).unwrap_or(1));
                    if let Some(l) = &self.work.loaded {
                        match &l.parsed {
                            Err(e) => {
                                cx.error(format!("{} is not a program this reader can follow — {e}", l.name));
                            }
                            Ok(p) if p.toolpath.cuts().next().is_none() => cx.error(format!(
                                "{} has no cutting moves (G01, G02, G03 or G06.2) to draw or compare with the design path.",
                                l.name
                            )),
                            Ok(_) => {}
                        }
                    }
                }
            }
        }
    }

    /// Announces a loaded program's deviation once it is measured.
    fn announce(&mut self, cx: &mut PanelContext<'_>) {
        let (Some(l), Some(w)) = (&self.work.loaded, &self.wanted) else { return };
        if self.announced == l.generation || !self.work.loaded_fresh(w) {
            return;
        }
        self.announced = l.generation;
        match &self.work.loaded_deviation.value {
            Some(Ok(d)) => cx.info(format!(
                "{}: deviation from the design path {} (program → design {} at line {}, design → program {}).",
                l.name,
                um(d.max_mm()),
                um(d.program_to_design_mm),
                d.program_line,
                um(d.design_to_program_mm)
            )),
            Some(Err(e)) if l.parsed.is_ok() => cx.error(format!("{}: {e}", l.name)),
            _ => {}
        }
    }

    fn controls(&mut self, ui: &mut egui::Ui, cx: &PanelContext<'_>) {
        self.rects.clear();
        let s = &mut self.settings;
        ui.horizontal_wrapped(|ui| {
            ui.label("Design path:");
            ui.selectable_value(&mut s.source, Source::Crease, "scene's crease")
                .on_hover_text("The current scene's ball-centre crease, as `interpolab gcode SCENE` uses it");
            let r = ui.selectable_value(&mut s.source, Source::Parabola, "parabola profile").on_hover_text(
                "Seed 004's parabola-like profile: y = x²/40 for x from −60 to 60 mm, z = 0 (1500 mm/min, 4 ms)",
            );
            self.rects.push(("source_parabola", r.rect));
            ui.separator();
            ui.spacing_mut().slider_width = 140.0;
            let r = ui
                .add(
                    egui::Slider::new(&mut s.tol_mm, ranges::NURBS_TOL_MM)
                        .logarithmic(true)
                        .text("tolerance E")
                        .suffix(" mm")
                        .custom_formatter(|v, _| fmt_fixed(v, 4)),
                )
                .on_hover_text("Every program stays within E of the design path after rounding to the resolution");
            self.rects.push(("tolerance_slider", r.rect));
            egui::ComboBox::from_id_salt("nurbs-resolution")
                .selected_text(format!("resolution {} mm", fmt_fixed(s.resolution_mm, 4)))
                .show_ui(ui, |ui| {
                    for r in [0.01, 0.001, 0.0001] {
                        ui.selectable_value(&mut s.resolution_mm, r, format!("{} mm", fmt_fixed(r, 4)));
                    }
                })
                .response
                .on_hover_text("The machine's least input increment: every written number is rounded to it");
            egui::ComboBox::from_id_salt("nurbs-degree")
                .selected_text(format!("G06.2 degree {} (P{})", s.degree, s.degree + 1))
                .show_ui(ui, |ui| {
                    for d in [3, 2, 1] {
                        ui.selectable_value(&mut s.degree, d, format!("degree {d} (order P{})", d + 1));
                    }
                });
            egui::ComboBox::from_id_salt("nurbs-dialect")
                .selected_text(format!("dialect {}", s.dialect.label()))
                .show_ui(ui, |ui| {
                    for d in Dialect::ALL {
                        ui.selectable_value(&mut s.dialect, d, d.label());
                    }
                })
                .response
                .on_hover_text(
                    "The controller the programs are written for: FANUC G06.2, Sinumerik 840D BSPLINE, LinuxCNC G5.2 (XY only); each is read back by its own reader",
                );
        });
        ui.horizontal_wrapped(|ui| {
            ui.label("programmed point:");
            ui.selectable_value(&mut s.point, Point::Centre, "ball centre");
            let r = ui
                .selectable_value(&mut s.point, Point::Tip, "ball tip")
                .on_hover_text(format!("Ball centre − R·z, R = {} mm (the scene's tool)", cx.scene.tool.radius));
            self.rects.push(("point_tip", r.rect));
            ui.separator();
            let default_feed = if s.source == Source::Parabola { 1500.0 } else { cx.scene.motion.feed };
            let mut feed = s.feed_mm_per_min.unwrap_or(default_feed);
            ui.spacing_mut().slider_width = 140.0;
            if ui
                .add(
                    egui::Slider::new(&mut feed, ranges::NURBS_FEED_MM_PER_MIN)
                        .logarithmic(true)
                        .text("feed F")
                        .suffix(" mm/min")
                        .custom_formatter(|v, _| fmt_fixed(v, 0)),
                )
                .on_hover_text("Feed of the programs (F word) and of the real-time interpolation")
                .changed()
            {
                s.feed_mm_per_min = Some(feed);
            }
            if s.feed_mm_per_min.is_some()
                && ui.small_button("default").on_hover_text(format!("Back to {default_feed} mm/min")).clicked()
            {
                s.feed_mm_per_min = None;
            }
        });
    }

    /// The real-time settings, over the plots.
    fn realtime_controls(&mut self, ui: &mut egui::Ui) {
        let s = &mut self.settings;
        ui.horizontal_wrapped(|ui| {
            ui.label(egui::RichText::new("Real-time interpolation").strong()).on_hover_text(
                "The G06.2 curve as read back from its program, advanced one period Ts at a time at feed F",
            );
            ui.separator();
            ui.label("update:");
            for (u, tip) in [
                (Update::FirstOrder, "Δu = f/|C′|"),
                (Update::SecondOrder, "Δu = f/|C′| − f²(C′·C″)/(2|C′|⁴)"),
                (Update::Corrected, "second order, then one Newton step on |C(u) − C(uₖ)| = f"),
            ] {
                let r = ui.selectable_value(&mut s.update, u, u.as_str()).on_hover_text(tip);
                self.rects.push((u.as_str(), r.rect));
            }
            ui.separator();
            let r = ui.checkbox(&mut s.chord_limit, "feed limit δ").on_hover_text(
                "Lower the feed where the curvature would make a period's chord error exceed δ: f = 2√(2ρδ − δ²)",
            );
            self.rects.push(("chord_limit", r.rect));
            if s.chord_limit {
                ui.spacing_mut().slider_width = 110.0;
                let mut d_um = s.chord_tol_mm * 1000.0;
                if ui
                    .add(
                        egui::Slider::new(&mut d_um, ranges::NURBS_CHORD_TOL_UM)
                            .logarithmic(true)
                            .suffix(" µm")
                            .custom_formatter(|v, _| fmt_fixed(v, 3)),
                    )
                    .changed()
                {
                    s.chord_tol_mm = d_um / 1000.0;
                }
            }
            ui.separator();
            ui.label("plot:");
            ui.selectable_value(&mut self.feed_plot, FeedPlot::Feed, "feed (mm/min)");
            ui.selectable_value(&mut self.feed_plot, FeedPlot::Fluctuation, "|Δf/f| (log)");
        });
    }

    /// One line about the work's state for the view's corner.
    fn status_line(&self) -> (bool, String) {
        if let Some(w) = &self.waiting {
            return w.clone();
        }
        let Some(w) = &self.wanted else { return (true, String::new()) };
        if let Some(Err(e)) = &self.work.design.value {
            return (false, e.clone());
        }
        match self.work.pending(w) {
            Pending::Nothing => {
                let errs = self.work.rows.iter().filter(|r| matches!(r.value, Some(Err(_)))).count();
                if errs > 0 {
                    (false, format!("{errs} program(s) could not be written — see the table"))
                } else {
                    (true, "up to date".to_owned())
                }
            }
            Pending::Waiting(_) | Pending::Working => {
                let what = if !self.work.design_fresh(w) {
                    match self.work.design_progress() {
                        Some(n) => return (true, format!("computing… design path ({n} periods of the crease)")),
                        None => "design path",
                    }
                } else if let jobs @ [_, ..] = &self.work.jobs_running()[..] {
                    // The programs are written in the background, side by side.
                    let list: Vec<String> =
                        jobs.iter().map(|(k, t)| format!("{} ({t:.1} s)", w.program.dialect.kind_label(*k))).collect();
                    return (true, format!("computing in the background… {}", list.join(", ")));
                } else if !self.work.row_fresh(0, w) {
                    "G01 program"
                } else if !self.work.row_fresh(1, w) {
                    "G02/G03 program"
                } else if !self.work.row_fresh(2, w) {
                    "G06.2 program"
                } else if !self.work.realtime_fresh(w) {
                    match self.work.realtime_progress() {
                        Some((u, k)) => {
                            return (
                                true,
                                format!("computing… real-time interpolation, {} update ({k} periods)", u.as_str()),
                            );
                        }
                        None => "real-time interpolation",
                    }
                } else {
                    "deviation of the loaded program"
                };
                (true, format!("computing… {what}"))
            }
        }
    }

    fn side(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        let w = self.wanted.clone();
        // Why nothing below is current: the crease still computing, or no design path.
        let problem = match (&self.waiting, &self.work.design.value) {
            (Some(why), _) => Some(why.clone()),
            (None, Some(Err(e))) if w.as_ref().is_some_and(|w| self.work.design_fresh(w)) => Some((false, e.clone())),
            _ => None,
        };
        if let Some((progress, text)) = problem {
            let color = if progress { egui::Color32::from_gray(200) } else { egui::Color32::from_rgb(255, 120, 110) };
            ui.label(egui::RichText::new(text).color(color));
            ui.add_space(4.0);
        }
        ui.horizontal(|ui| {
            let (tol, feed) =
                w.as_ref().map_or((self.settings.tol_mm, 0.0), |w| (w.program.tol_mm, w.program.feed_mm_per_min));
            ui.label(egui::RichText::new(format!("Programs within E = {} at F = {feed:.0} mm/min", um(tol))).strong());
            if let Some(c) = w.as_ref().and_then(|w| self.work.comparison(w))
                && ui
                    .small_button("copy table")
                    .on_hover_text("Both tables as Markdown, as `interpolab compare` prints them")
                    .clicked()
            {
                ui.ctx().copy_text(format_comparison(&c, crate::gcode::TableStyle::Markdown));
                cx.info("Comparison tables copied to the clipboard (Markdown).");
            }
        });
        table::programs_table(ui, &self.work, w.as_ref());
        ui.add_space(4.0);
        table::realtime_table(ui, &self.work, w.as_ref());
        ui.separator();
        self.gcode(ui, cx);
    }

    fn file_stem(&self, cx: &PanelContext<'_>) -> String {
        let name = match self.settings.source {
            Source::Parabola => "parabola",
            Source::Crease => cx.scene.name.as_str(),
        };
        let stem: String =
            name.chars().map(|c| if c.is_ascii_alphanumeric() { c.to_ascii_lowercase() } else { '-' }).collect();
        let stem = stem.split('-').filter(|s| !s.is_empty()).collect::<Vec<_>>().join("-");
        if stem.is_empty() { "program".to_owned() } else { stem }
    }

    fn gcode(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        ui.horizontal_wrapped(|ui| {
            ui.label(egui::RichText::new("G-code:").strong());
            for kind in ProgramKind::ALL {
                let r = ui.selectable_label(self.shown == Shown::Kind(kind), self.settings.dialect.kind_label(kind));
                self.rects.push((kind.label(), r.rect));
                if r.clicked() {
                    self.shown = Shown::Kind(kind);
                    self.scroll_to = Some(1);
                }
            }
            if let Some(l) = &self.work.loaded {
                let chars: Vec<char> = l.name.chars().collect();
                let name = if chars.len() > 28 {
                    format!("…{}", chars[chars.len() - 26..].iter().collect::<String>())
                } else {
                    l.name.clone()
                };
                if ui.selectable_label(self.shown == Shown::Loaded, name).on_hover_text(&l.name).clicked() {
                    self.shown = Shown::Loaded;
                    self.scroll_to = Some(1);
                }
            }
            ui.separator();
            let r = ui.button("Open a G-code file…").on_hover_text(
                "Read a program (.nc, .ngc, .gcode, .tap, .txt) and draw it over the design; or drop it on the page",
            );
            self.rects.push(("open_gcode", r.rect));
            if r.clicked() {
                cx.pick_file(FileKind::GCode);
            }
        });
        // The text shown and what to say about it.
        let (text, name, mark): (Option<&str>, String, Option<usize>) = match self.shown {
            Shown::Kind(kind) => {
                let i = ProgramKind::ALL.iter().position(|k| *k == kind).unwrap_or(0);
                match self.work.rows[i].ok() {
                    Some(r) => (
                        Some(r.program.text.as_str()),
                        match self.settings.dialect {
                            Dialect::Fanuc => format!("{}-{}.nc", self.file_stem(cx), kind.as_str()),
                            d => format!("{}-{d}-{}.nc", self.file_stem(cx), kind.as_str()),
                        },
                        Some(r.program.deviation.program_line),
                    ),
                    None => (None, String::new(), None),
                }
            }
            Shown::Loaded => match &self.work.loaded {
                Some(l) => (
                    Some(l.text.as_str()),
                    l.name.clone(),
                    l.error_line.or_else(|| self.work.loaded_deviation.ok().map(|d| d.program_line)),
                ),
                None => (None, String::new(), None),
            },
        };
        let mut go_to = None;
        let mut close = false;
        let mut saved = None;
        ui.horizontal_wrapped(|ui| {
            let enabled = text.is_some();
            if ui
                .add_enabled(enabled, egui::Button::new("Copy"))
                .on_hover_text("Copy the program text to the clipboard")
                .clicked()
                && let Some(t) = text
            {
                ui.ctx().copy_text(t.to_owned());
                cx.info(format!("{name} copied to the clipboard ({} bytes).", t.len()));
            }
            let r = ui.add_enabled(enabled, egui::Button::new("Download")).on_hover_text(format!("Save as {name}"));
            self.rects.push(("download", r.rect));
            if r.clicked()
                && let Some(t) = text
            {
                cx.save_text(&name, t);
                saved = Some(name.clone());
            }
            if let Some(m) = mark
                && ui
                    .small_button(format!("go to line {m}"))
                    .on_hover_text("The line of the largest deviation, or of the reader's error")
                    .clicked()
            {
                go_to = Some(m);
            }
            close = self.shown == Shown::Loaded && ui.small_button("close file").clicked();
        });
        self.about_shown(ui);
        let scroll_to = go_to.or(self.scroll_to);
        match text {
            Some(t) => table::code_view(ui, t, mark, scroll_to),
            None => {
                let msg = match self.shown {
                    Shown::Loaded => "No file loaded.".to_owned(),
                    Shown::Kind(kind) => {
                        let i = ProgramKind::ALL.iter().position(|k| *k == kind).unwrap_or(0);
                        match &self.work.rows[i].value {
                            Some(Err(e)) => e.clone(),
                            _ => "computing…".to_owned(),
                        }
                    }
                };
                ui.label(egui::RichText::new(msg).weak().italics());
            }
        }
        self.scroll_to = None;
        if saved.is_some() {
            self.downloaded = saved;
        }
        if close {
            self.work.unload();
            self.shown = Shown::Kind(ProgramKind::Nurbs);
        }
    }

    /// "Simulate this program": hands the shown program's text (a written crease program,
    /// or the loaded file) to the Cutting simulation tab, with the scene's surfaces as the
    /// design and the scene's ball for a program of the scene's crease.
    fn simulate_button(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        let (text, of_scene, name) = match self.shown {
            Shown::Kind(kind) => {
                let i = ProgramKind::ALL.iter().position(|k| *k == kind).unwrap_or(0);
                let text = self.work.rows[i].ok().map(|r| r.program.text.clone());
                (text, self.settings.source == Source::Crease, format!("NURBS & G-code tab: {}", kind.label()))
            }
            Shown::Loaded => {
                let l = self.work.loaded.as_ref();
                (l.map(|l| l.text.clone()), false, l.map_or(String::new(), |l| l.name.clone()))
            }
        };
        let r = ui
            .add_enabled(text.is_some(), egui::Button::new("Simulate this program →"))
            .on_hover_text("Machine the program shown below in the Cutting simulation tab")
            .on_disabled_hover_text("No program yet");
        self.rects.push(("nurbs_simulate", r.rect));
        let asked = std::mem::take(&mut self.simulate_requested);
        if let Some(text) = text.filter(|_| r.clicked() || asked) {
            let mut options = vec![("program_text", text), ("program_name", name)];
            if of_scene {
                options.push(("design", "scene".to_owned()));
                options.push(("cutter", "scene".to_owned()));
            } else {
                options.push(("design", "auto".to_owned()));
            }
            cx.handoff = Some(Handoff { to: SIMULATION_TITLE, options });
        }
    }

    /// A line about the shown program: its size and deviation, or the reader's complaints.
    fn about_shown(&self, ui: &mut egui::Ui) {
        let red = egui::Color32::from_rgb(255, 120, 110);
        let yellow = egui::Color32::from_rgb(240, 200, 90);
        match self.shown {
            Shown::Kind(kind) => {
                let i = ProgramKind::ALL.iter().position(|k| *k == kind).unwrap_or(0);
                if let Some(r) = self.work.rows[i].ok() {
                    ui.label(format!(
                        "{}: {} path blocks, {} lines, {} bytes; deviation after rounding {} (program → design largest at line {}).",
                        kind.label(),
                        r.path_blocks,
                        r.program.parsed.lines,
                        r.bytes,
                        um(r.deviation_mm),
                        r.program.deviation.program_line
                    ));
                }
            }
            Shown::Loaded => {
                let Some(l) = &self.work.loaded else { return };
                match &l.parsed {
                    Err(e) => {
                        ui.label(egui::RichText::new(format!("{}: {e}", l.name)).color(red));
                    }
                    Ok(p) => {
                        let s = crate::gcode::summarize(&p.toolpath);
                        ui.label(format!(
                            "{}: {} lines, {} path blocks (G01 {}, G02 {}, G03 {}, G06.2 curves {}), cutting length {:.3} mm.",
                            l.name,
                            p.lines,
                            p.path_blocks(),
                            s.moves[1],
                            s.moves[2],
                            s.moves[3],
                            s.moves[4],
                            s.cut_length_mm
                        ));
                        match &self.work.loaded_deviation.value {
                            Some(Ok(d)) => {
                                let point = l.point.map_or("the panel's programmed point", |p| match p {
                                    ProgrammedPoint::BallCentre => "ball centre (from its header)",
                                    ProgrammedPoint::BallTip { .. } => "ball tip (from its header)",
                                });
                                ui.label(
                                    egui::RichText::new(format!(
                                        "Deviation from the design path: {} — program → design {} (line {}), design → program {}; gaps at the ends {} / {}. Point: {point}.",
                                        um(d.max_mm()),
                                        um(d.program_to_design_mm),
                                        d.program_line,
                                        um(d.design_to_program_mm),
                                        um(d.start_gap_mm),
                                        um(d.end_gap_mm)
                                    ))
                                    .color(view::LOADED_COLOR),
                                );
                            }
                            Some(Err(e)) => {
                                ui.label(egui::RichText::new(e).color(red));
                            }
                            None => {
                                ui.label(egui::RichText::new("measuring the deviation…").weak().italics());
                            }
                        }
                        if !p.unsupported.is_empty() {
                            let list: Vec<String> = p
                                .unsupported
                                .iter()
                                .take(6)
                                .map(|u| format!("line {}: {} ({})", u.line, u.word, u.reason))
                                .collect();
                            let more = if p.unsupported.len() > 6 {
                                format!(" and {} more", p.unsupported.len() - 6)
                            } else {
                                String::new()
                            };
                            ui.label(
                                egui::RichText::new(format!(
                                    "Not modelled, effect left out: {}{more}",
                                    list.join("; ")
                                ))
                                .color(yellow),
                            );
                        }
                    }
                }
            }
        }
    }

    fn overlay(&self) -> Overlay {
        match self.shown {
            Shown::Kind(ProgramKind::Lines) => Overlay::Row(0),
            Shown::Kind(ProgramKind::Arcs) => Overlay::Row(1),
            Shown::Kind(ProgramKind::Nurbs) => Overlay::None,
            Shown::Loaded => Overlay::Loaded,
        }
    }

    /// The panel's state for tests and assistive tools (published in the app's status).
    fn status_value(&self) -> serde_json::Value {
        let w = self.wanted.as_ref();
        let rows: Vec<serde_json::Value> = ProgramKind::ALL
            .iter()
            .enumerate()
            .map(|(i, k)| match &self.work.rows[i].value {
                Some(Ok(r)) => serde_json::json!({
                    "kind": k.label(),
                    "fresh": w.is_some_and(|w| self.work.row_fresh(i, w)),
                    "path_blocks": r.path_blocks,
                    "bytes": r.bytes,
                    "deviation_mm": r.deviation_mm,
                }),
                Some(Err(e)) => serde_json::json!({ "kind": k.label(), "error": e }),
                None => serde_json::json!({ "kind": k.label() }),
            })
            .collect();
        let realtime: Vec<serde_json::Value> = self.work.realtime.ok().map_or_else(Vec::new, |rt| {
            rt.stats
                .iter()
                .map(|s| serde_json::json!({ "update": s.update.as_str(), "periods": s.periods, "max_fluctuation": s.max_fluctuation }))
                .collect()
        });
        let loaded = self.work.loaded.as_ref().map(|l| {
            serde_json::json!({
                "name": l.name,
                "error": l.parsed.as_ref().err(),
                "unsupported": l.parsed.as_ref().map_or(0, |p| p.unsupported.len()),
                "deviation_mm": self.work.loaded_deviation.ok().map(|d| d.max_mm()),
                "deviation_line": self.work.loaded_deviation.ok().map(|d| d.program_line),
            })
        });
        let (ok, status) = self.status_line();
        let done = w.is_some_and(|w| self.work.pending(w) == Pending::Nothing);
        serde_json::json!({
            "source": match self.settings.source { Source::Crease => "crease", Source::Parabola => "parabola" },
            "tol_mm": self.settings.tol_mm,
            "done": done,
            "computing": !done,
            "status": status,
            "status_ok": ok,
            "design_mm": self.work.design.ok().map(|d| d.length_mm),
            "rows": rows,
            "realtime": realtime,
            "loaded": loaded,
            "slowest_step_ms": self.slowest_step_ms,
            "downloaded": self.downloaded,
            "program": match self.shown {
                Shown::Kind(k) => k.as_str(),
                Shown::Loaded => "loaded",
            },
            "worst_px": self.view.worst_on_screen.map(|p| [p.x, p.y]),
            "ui": self.rects.iter().map(|(k, r)| ((*k).to_owned(), serde_json::json!([r.min.x, r.min.y, r.width(), r.height()]))).collect::<serde_json::Map<_, _>>(),
        })
    }
}

impl Panel for NurbsPanel {
    fn title(&self) -> &'static str {
        "NURBS & G-code (seed 004)"
    }

    fn accepts(&self) -> Option<FileKind> {
        Some(FileKind::GCode)
    }

    fn status(&self) -> serde_json::Value {
        self.status_value()
    }

    fn set_option(&mut self, key: &str, value: &str) -> Result<(), String> {
        let s = &mut self.settings;
        let number = || value.parse::<f64>().map_err(|_| format!("{key}: \"{value}\" is not a number"));
        let positive = |x: f64| {
            if x.is_finite() && x > 0.0 { Ok(x) } else { Err(format!("{key}: {x} is not a positive number")) }
        };
        match key {
            // As the "Simulate this program" button: handed over in the next frame.
            "simulate" => self.simulate_requested = true,
            "source" => {
                s.source = match value {
                    "crease" => Source::Crease,
                    "parabola" => Source::Parabola,
                    _ => return Err(format!("source: \"{value}\"; give crease or parabola")),
                }
            }
            // The slider's range, as a user could set it.
            "tol_mm" => {
                s.tol_mm = positive(number()?)?.clamp(*ranges::NURBS_TOL_MM.start(), *ranges::NURBS_TOL_MM.end())
            }
            "resolution_mm" => {
                let r = number()?;
                s.resolution_mm = [0.01, 0.001, 0.0001]
                    .into_iter()
                    .find(|x| (x - r).abs() < 1e-12)
                    .ok_or_else(|| format!("resolution_mm: {r}; give 0.01, 0.001 or 0.0001"))?;
            }
            "point" => {
                s.point = match value {
                    "centre" => Point::Centre,
                    "tip" => Point::Tip,
                    _ => return Err(format!("point: \"{value}\"; give centre or tip")),
                }
            }
            "update" => {
                s.update = Update::ALL
                    .into_iter()
                    .find(|u| u.as_str() == value)
                    .ok_or_else(|| format!("update: \"{value}\"; give first, second or corrected"))?;
            }
            "feed_mm_per_min" => {
                s.feed_mm_per_min = if value == "default" {
                    None
                } else {
                    Some(
                        positive(number()?)?
                            .clamp(*ranges::NURBS_FEED_MM_PER_MIN.start(), *ranges::NURBS_FEED_MM_PER_MIN.end()),
                    )
                };
            }
            "chord_tol_mm" => {
                if value == "off" {
                    s.chord_limit = false;
                } else {
                    s.chord_tol_mm = positive(number()?)?.clamp(1e-6, 0.01);
                    s.chord_limit = true;
                }
            }
            "dialect" => s.dialect = value.parse::<Dialect>().map_err(|e| e.to_string())?,
            "degree" => {
                s.degree = match value {
                    "1" => 1,
                    "2" => 2,
                    "3" => 3,
                    _ => return Err(format!("degree: \"{value}\"; give 1, 2 or 3")),
                }
            }
            "program" => {
                self.shown = match value {
                    "g01" => Shown::Kind(ProgramKind::Lines),
                    "arcs" => Shown::Kind(ProgramKind::Arcs),
                    "nurbs" => Shown::Kind(ProgramKind::Nurbs),
                    "loaded" if self.work.loaded.is_some() => Shown::Loaded,
                    _ => return Err(format!("program: \"{value}\"; give g01, arcs, nurbs or loaded (after a file)")),
                }
            }
            _ => {
                return Err(format!(
                    "no option \"{key}\"; give source, tol_mm, resolution_mm, point, update, feed_mm_per_min, chord_tol_mm, degree, dialect or program"
                ));
            }
        }
        Ok(())
    }

    fn controls(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        self.controls(ui, cx);
        self.simulate_button(ui, cx);
        if self.settings.source == Source::Crease {
            ui.separator();
            cx.scene_controls(ui);
        }
    }

    fn ui(&mut self, ui: &mut egui::Ui, cx: &mut PanelContext<'_>) {
        self.handle_files(cx);
        match self.wanted(cx) {
            Ok(w) => {
                self.waiting = None;
                if let DesignInput::Crease(job, _) = &w.design {
                    self.work.note_scene(job, cx.scene);
                }
                self.work.want(&w);
                let t0 = web_time::Instant::now();
                // Steps until the frame budget is used; one program per step at most.
                loop {
                    let t = web_time::Instant::now();
                    if !self.work.step(&w) {
                        break;
                    }
                    self.slowest_step_ms = self.slowest_step_ms.max(t.elapsed().as_secs_f64() * 1000.0);
                    if t0.elapsed() > crate::app::budget::FRAME_BUDGET {
                        break;
                    }
                }
                match self.work.pending(&w) {
                    Pending::Nothing => {}
                    Pending::Waiting(d) => ui.ctx().request_repaint_after(d),
                    // Programs written in the background: look again now and then.
                    Pending::Working if self.work.waiting_on_jobs() => {
                        ui.ctx().request_repaint_after(crate::app::jobs::POLL);
                    }
                    Pending::Working => ui.ctx().request_repaint(),
                }
                self.wanted = Some(w);
            }
            Err(why) => {
                self.waiting = Some(why);
                self.wanted = None;
                ui.ctx().request_repaint_after(web_time::Duration::from_millis(100));
            }
        }
        self.announce(cx);

        let feed = self.wanted.as_ref().map_or(0.0, |w| w.program.feed_mm_per_min);
        let chord = self.wanted.as_ref().and_then(|w| w.realtime.chord_tol_mm);
        let tol = self.settings.tol_mm;
        egui::Panel::bottom("nurbs-plots").resizable(true).default_size(230.0).min_size(140.0).show(ui, |ui| {
            self.realtime_controls(ui);
            let rt = self.work.realtime.ok().map(|r| (self.work.realtime.generation, r));
            plots::plots(ui, &mut self.series, self.feed_plot, rt, feed, tol, chord);
        });
        let max_side = (ui.available_width() - 300.0).max(320.0);
        let side = egui::Panel::right("nurbs-side")
            .resizable(true)
            .default_size(560.0)
            .min_size(320.0)
            .max_size(max_side)
            .show(ui, |ui| {
                ui.set_max_width(ui.available_width());
                self.side(ui, cx);
            });
        // The rest, left of the side panel: layer switches and the 3D view.
        let mut central = ui.available_rect_before_wrap();
        central.max.x = central.max.x.min(side.response.rect.min.x - 4.0);
        let mut cui =
            ui.new_child(egui::UiBuilder::new().max_rect(central).layout(egui::Layout::top_down(egui::Align::Min)));
        cui.horizontal_wrapped(|ui| {
            let s = &mut self.view.show;
            ui.label("show:");
            ui.checkbox(&mut s.design, "design");
            ui.checkbox(&mut s.curve, "G06.2 curve");
            ui.checkbox(&mut s.polygon, "control polygon");
            ui.checkbox(&mut s.knots, "knots");
            ui.checkbox(&mut s.points, "interpolated points");
            ui.checkbox(&mut s.program, "selected / loaded program");
        });
        let rect = cui.available_rect_before_wrap();
        let rect = egui::Rect::from_min_size(rect.min, rect.size().max(egui::vec2(64.0, 64.0)));
        let offset = self.wanted.as_ref().map_or(DVec3::ZERO, |w| w.program.point.offset());
        let status = self.status_line();
        self.rects.push(("view", rect));
        let drawn = view::Drawn { work: &self.work, overlay: self.overlay(), offset, status };
        self.view.ui(&mut cui, rect, cx.render_state, drawn);
    }
}
