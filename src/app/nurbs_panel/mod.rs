//! The "NURBS & G-code" view: the design path (the scene's crease or seed 004's
//! parabola-like profile) with its G06.2 curve, control polygon and knots; the real-time
//! interpolation of that curve, drawn as points coloured by feed fluctuation and plotted over
//! time; seed 004's comparison of the G01, G02/G03 and G06.2 programs at the tolerance of the
//! slider; the text of the selected program with copy and download; and a G-code file loaded
//! (picked or dropped) drawn over the design with its deviation.
//!
//! Every number comes from the core (`gcode::compare_row`, `realtime_stats`,
//! `nurbs_path::interpolate_realtime`, `gcode::parse_program`, `gcode::deviation`); the three
//! programs are written as background jobs and the rest runs a step per frame after a short
//! quiet time ([`work`]), so the page stays live.
//!
//! Files: this one holds the state and the `Panel` impl; `controls` the inputs, `program` the
//! table and program column, `text` the prose, `view` / `plots` / `table` the drawing, `work`
//! the computation.

mod controls;
mod plots;
mod program;
mod table;
mod text;
mod view;
pub mod work;

use eframe::egui;
use glam::DVec3;

use super::panel::{Panel, PanelContext};
use super::platform::FileKind;
use super::ranges;
use crate::gcode::{Dialect, ProgramKind, ProgrammedPoint};
use crate::nurbs_path::Update;
use plots::FeedPlot;
use table::Shown;
use view::{NurbsView, Overlay};
use work::{DesignInput, Pending, Point, ProgramInput, RealtimeInput, Source, Wanted, Work};

/// A resolution typed within this (mm) of one of the offered ones is that one.
const RESOLUTION_MATCH_MM: f64 = 1e-12;
/// Smallest chord tolerance (mm) the panel's option takes.
const MIN_CHORD_TOL_MM: f64 = 1e-6;

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
    /// The machine the programs are timed on, a name of [`crate::plan::PRESETS`]; `None`:
    /// not timed (the time columns hidden).
    machine: Option<&'static str>,
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
            machine: Some("vmc"),
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
    /// Loaded file whose reading's end was announced (file generation).
    read_announced: u64,
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
            read_announced: 0,
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
            machine: s.machine.and_then(crate::plan::Dynamics::preset),
        })
    }

    fn handle_files(&mut self, cx: &mut PanelContext<'_>) {
        for f in std::mem::take(&mut cx.incoming) {
            match f.text {
                Err(e) => cx.error(format!("{}: {e}", f.name)),
                Ok(text) => {
                    self.work.load(&f.name, text);
                    self.shown = Shown::Loaded;
                    self.scroll_to = Some(1);
                }
            }
        }
    }

    /// Once a loaded program is read to its end (over frames): its error, or that it has
    /// nothing to compare, in the banner, and the code view at the error's line. (Judged at
    /// the load itself, before any slice was read, every program looked empty.)
    fn announce_read(&mut self, cx: &mut PanelContext<'_>) {
        let Some(l) = &self.work.loaded else { return };
        if l.reader.is_some() || self.read_announced == l.generation {
            return;
        }
        self.read_announced = l.generation;
        match &l.parsed {
            Err(e) => {
                cx.error(format!("{} is not a program this reader can follow — {e}", l.name));
                self.scroll_to = l.error_line.or(self.scroll_to);
            }
            Ok(p) if p.toolpath.cuts().next().is_none() => cx.error(format!(
                "{} has no cutting moves (G01, G02, G03 or G06.2) to draw or compare with the design path.",
                l.name
            )),
            Ok(_) => {}
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
                Some(Ok(t)) => {
                    let r = &t.row;
                    let mut row = serde_json::json!({
                        "kind": k.label(),
                        "fresh": w.is_some_and(|w| self.work.row_fresh(i, w)),
                        "path_blocks": r.path_blocks,
                        "bytes": r.bytes,
                        "deviation_mm": r.deviation_mm,
                    });
                    // The time on the machine (s), the feed moves' time (s) and mean feed
                    // (mm/min); or why it could not be planned.
                    match &t.time {
                        Some(Ok(c)) => {
                            row["time_machine"] = c.machine.clone().into();
                            row["time_s"] = c.total_s.into();
                            row["feed_s"] = c.feed_s.into();
                            row["mean_feed_mm_min"] = c.mean_feed_mm_min().into();
                        }
                        Some(Err(e)) => row["time_error"] = e.clone().into(),
                        None => {}
                    }
                    row
                }
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
            "machine": self.settings.machine,
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
        "NURBS & G-code"
    }

    fn paper(&self) -> Option<&'static str> {
        Some(super::papers::NURBS)
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
                    .find(|x| (x - r).abs() < RESOLUTION_MATCH_MM)
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
                    s.chord_tol_mm = positive(number()?)?.clamp(MIN_CHORD_TOL_MM, 0.01);
                    s.chord_limit = true;
                }
            }
            "dialect" => s.dialect = value.parse::<Dialect>().map_err(|e| e.to_string())?,
            // The machine of the time column, or none to hide it.
            "machine" => {
                s.machine = if value == "none" {
                    None
                } else {
                    Some(crate::plan::PRESETS.into_iter().find(|p| *p == value).ok_or_else(|| {
                        format!("machine: \"{value}\"; give none or one of {}", crate::plan::PRESETS.join(", "))
                    })?)
                };
            }
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
                    "no option \"{key}\"; give source, tol_mm, resolution_mm, point, update, feed_mm_per_min, chord_tol_mm, degree, dialect, machine or program"
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
        self.announce_read(cx);
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
